#!/usr/bin/env bash
# The daemons across hosts (README "Network and hosts"), with Linux network namespaces for hosts:
# every process of a run (the five daemons, world_sim, the recorder) on a host of its own, one
# NIC each (a veth) on a switch (a bridge in a namespace of its own; scripts/netns.sh), LCM
# multicast routed on the NIC with ttl=1, as a robot's computers on one subnet would run them.
# Nothing of it reaches this machine's own network namespace or its other LCM runs. Checks:
#   1. single host vs. hosts: the paper's four scenarios run as scripts/run.sh runs them (one
#      host, ttl=0), then each process on its own host: the transcripts must be byte-identical;
#   2. loss: each scenario again with every link lossy (default 5 % and 20 ms +- 5 ms delay per
#      link, netem; where the kernel has no netem, a coopnav_lossy_relay on every host drops the
#      same fraction of what goes out and of what comes in, without delay: the output says which);
#      the decisions must be the clean run's (scripts/faults.sh's loss check, which this reuses:
#      the transcript's SAY, ACTION, RECORDER, FINAL CM and SIM lines);
#   3. a host drops off: in one scenario (narrow_minimal) the path assessor's cable is pulled at
#      the switch once the world has passed step K, halfway between round 1 and round 2 of the
#      single-host run (on a busy machine the pull lands some steps later: the SIM line says
#      where the world stopped). The world must end the run (SIM PARTICIPANT_TIMEOUT naming
#      path_assessor, after the scenario's step_timeout_s, 20 s) rather than go on without it,
#      the dialogue manager must log the step it ran without the path assessor (its status says
#      DEGRADED), and what the robot said and did until then must be the single-host run's.
#   4. the recipe of README "Network and hosts": scripts/launch.sh on three hosts (the distance
#      server and the band source on one, the assessors and the dialogue manager on another,
#      world_sim on a third), the same scenario: its transcript must be the single-host one.
# Needs root (network namespaces); where they cannot be made it prints "SKIP: <reason>" and exits
# 77. Namespaces are named cnmh<pid>-<host> and removed on any exit (and at the next start if a
# run was killed before its trap ran). Writes everything under OUT (default
# runs/multihost-<UTC>): single/ (run.sh's), hosts/ (faults.sh's clean and loss runs),
# dropoff/, launch/, multihost.txt (the verdicts and wall times).
#
#   scripts/multihost.sh [--out DIR] [--no-build] [--scenarios "open_minimal ..."]
#                        [--loss-scenarios "narrow_minimal ..."] [--no-loss] [--loss P]
#                        [--delay "20ms 5ms"] [--loss-seed N] [--dropoff-scenario NAME]
#                        [--no-dropoff] [--no-launch] [--port-base N]
#   --loss-scenarios: the loss pass on these only (default: every scenario of --scenarios).
#   --port-base N: the single-host runs use ports N..N+3 of this machine (default 9100, or
#   COOPNAV_MULTIHOST_PORT_BASE); the hosts' ports are their own.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
source "$COOPNAV_ROOT/scripts/scenario.sh"
source "$COOPNAV_ROOT/scripts/netns.sh"

out="" build=1 loss=0.05 delay="20ms 5ms" loss_seed=33 do_loss=1 do_dropoff=1 do_launch=1
scen_list="open_facilitating open_minimal narrow_facilitating narrow_minimal"
loss_list="" dropoff_scen="narrow_minimal"
port_base="${COOPNAV_MULTIHOST_PORT_BASE:-9100}"
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --scenarios) scen_list="$2"; shift 2 ;;
    --loss-scenarios) loss_list="$2"; shift 2 ;;
    --no-loss) do_loss=0; shift ;;
    --loss) loss="$2"; shift 2 ;;
    --delay) delay="$2"; shift 2 ;;
    --loss-seed) loss_seed="$2"; shift 2 ;;
    --dropoff-scenario) dropoff_scen="$2"; shift 2 ;;
    --no-dropoff) do_dropoff=0; shift ;;
    --no-launch) do_launch=0; shift ;;
    --port-base) port_base="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^[^#]/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "multihost.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$loss_list" ] || loss_list="$scen_list"
[ "$do_loss" -eq 1 ] || loss_list=""
for s in $scen_list $dropoff_scen; do
  [ -f "$COOPNAV_ROOT/config/scenarios/$s.yaml" ] ||
    { echo "multihost.sh: no scenario config/scenarios/$s.yaml" >&2; exit 2; }
done

# Before building: a machine that cannot make namespaces skips at once.
prefix="cnmh$$"
coopnav_netns_reap_stale
if ! reason="$(coopnav_netns_check "$prefix")"; then
  echo "SKIP: $reason"
  exit 77
fi
if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast  # the single-host runs, on this machine's own namespace
[ -n "$out" ] || out="$COOPNAV_ROOT/runs/multihost-$(date -u +%Y%m%d-%H%M%S)"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
hosts=("${COOPNAV_DAEMONS[@]}" world_sim recorder)

# Whatever happens (failure, ctrl-C, kill), the daemons stop and the namespaces go.
coopnav_trap 'coopnav_stop_all; coopnav_netns_down "$prefix"' EXIT
coopnav_trap 'exit 130' INT
coopnav_trap 'exit 143' TERM

results=()
fail=0
note() { results+=("$*"); echo "$*"; }
# run_wall DIR: a run's wall time, from its start (scenario.path, written first) to world_sim's
# last log line.
run_wall() {
  awk -v a="$(stat -c %.3Y "$1/scenario.path")" -v b="$(stat -c %.3Y "$1/world_sim.log")" \
    'BEGIN { printf "%.1f", b - a }'
}
since() { awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.0f", b - a }'; }

echo "multihost: output $out; hosts are namespaces $prefix-{$(IFS=,; echo "${hosts[*]}")}"

# 1a. One host: scripts/run.sh itself, on ports of this machine.
echo "== single host (scripts/run.sh)"
paths=()
for s in $scen_list; do paths+=("$COOPNAV_ROOT/config/scenarios/$s.yaml"); done
t0="$EPOCHREALTIME"
if ! COOPNAV_RUN_PORT_BASE="$port_base" bash "$COOPNAV_ROOT/scripts/run.sh" --no-build \
  --out "$out/single" "${paths[@]}" >"$out/single.out" 2>&1; then
  tail -20 "$out/single.out"
  echo "multihost: FAIL: the single-host runs failed (see $out/single.out)"
  exit 1
fi
note "single host: $(since "$t0") s for $(echo "$scen_list" | wc -w) scenarios"

# 1b + 2. Every process on its own host: scripts/faults.sh's clean runs, then its loss runs
# (only the loss check: no kills, which need the scripts to reach the hosts, no absent server).
coopnav_netns_up "$prefix" "${hosts[@]}"
loss_mode=""
if [ -n "$loss_list" ]; then
  if tc_err="$(ip netns exec "$prefix-world_sim" tc qdisc add dev eth0 root netem loss 5% \
    delay 20ms 5ms 2>&1)"; then
    ip netns exec "$prefix-world_sim" tc qdisc del dev eth0 root
    loss_mode="netem"
    export COOPNAV_NETNS_NETEM="delay $delay"
    note "loss pass: netem on both ends of every link but the recorder's: loss $loss, delay $delay"
  else
    loss_mode="relay"
    unset COOPNAV_NETNS_NETEM
    note "loss pass: coopnav_lossy_relay on every host but the recorder's, loss $loss on the way" \
      "out and on the way in, no delay (the kernel refused netem: ${tc_err//$'\n'/ })"
  fi
fi
no_loss_list=""
for s in $scen_list; do
  [[ " $loss_list " == *" $s "* ]] || no_loss_list+=" $s"
done
hosts_fail=0
faults_pass() {  # LIST EXTRA_ARGS... : faults.sh on the hosts (its exit code)
  local list="$1"
  shift
  COOPNAV_NETNS_PREFIX="$prefix" COOPNAV_FAULT_PORT_BASE=$((port_base + 10)) \
    bash "$COOPNAV_ROOT/scripts/faults.sh" --no-build --out "$out/hosts" --no-kill --no-absent \
    --scenarios "$list" "$@"
}
echo "== each process on its own host (scripts/faults.sh: clean runs, loss runs)"
t0="$EPOCHREALTIME"
if [ -n "${no_loss_list# }" ]; then
  faults_pass "${no_loss_list# }" --no-loss | tee "$out/hosts_no_loss.out" || hosts_fail=1
fi
if [ -n "$loss_list" ]; then
  faults_pass "$loss_list" --loss "$loss" --loss-seed "$loss_seed" | tee "$out/hosts_loss.out" ||
    hosts_fail=1
fi
[ "$hosts_fail" -eq 0 ] || fail=1
note "hosts: $(since "$t0") s for $(echo "$scen_list" | wc -w) clean runs and" \
  "$(echo "$loss_list" | wc -w) loss runs"

echo "== verdicts"
for s in $scen_list; do
  a="$out/single/$s/transcript.txt" b="$out/hosts/$s/clean/transcript.txt"
  if [ -f "$a" ] && [ -f "$b" ] && cmp -s "$a" "$b"; then
    note "$(printf '%-20s %-28s %-9s wall %s s (one host %s s)' "$s" "hosts vs one host" same \
      "$(run_wall "$out/hosts/$s/clean")" "$(run_wall "$out/single/$s")")"
  else
    fail=1
    note "$(printf '%-20s %-28s %-9s %s' "$s" "hosts vs one host" FAIL \
      "the transcripts differ (or one is missing)")"
    [ -f "$a" ] && [ -f "$b" ] && diff "$a" "$b" | head -10 | sed 's/^/      /'
  fi
  if [[ " $loss_list " == *" $s "* ]]; then
    # faults.sh's own verdict line of this loss run: "same" (and nothing after it), else FAIL
    # and why.
    line="$(grep -E "^$s +loss " "$out/hosts/faults.txt" 2>/dev/null | head -1 | sed 's/  */ /g')"
    v=FAIL
    case "$line" in *" same" | *" same ") v=same ;; esac
    [ "$v" = same ] || fail=1
    if [ "$v" = same ]; then
      line="wall $(run_wall "$out/hosts/$s/loss") s"
    else
      line="${line:-no verdict from faults.sh}"
    fi
    note "$(printf '%-20s %-28s %-9s %s' "$s" "hosts, loss $loss ($loss_mode)" "$v" "$line")"
  fi
done

# The single-host run of the drop-off and recipe scenario, when --scenarios did not include it.
ref="$out/single/$dropoff_scen/transcript.txt"
if { [ "$do_dropoff" -eq 1 ] || [ "$do_launch" -eq 1 ]; } && [ ! -f "$ref" ]; then
  COOPNAV_RUN_PORT_BASE=$((port_base + 4)) bash "$COOPNAV_ROOT/scripts/run.sh" --no-build \
    --out "$out/single" "$COOPNAV_ROOT/config/scenarios/$dropoff_scen.yaml" >>"$out/single.out" 2>&1
fi

# 3. A host drops off: the path assessor's cable pulled between round 1 and round 2.
if [ "$do_dropoff" -eq 1 ]; then
  echo "== a host drops off ($dropoff_scen: the path assessor's cable pulled)"
  # K: halfway between round 1 and round 2 of the single-host run (steps are 0.1 s of simulated
  # time, world_sim's publish_hz): the path assessor is recording CA for round 2 then.
  round_t() { grep -m1 -o "^t=[0-9.]*s .*(round $1" "$ref" | sed 's/^t=\([0-9.]*\)s.*/\1/' || true; }
  r1="$(round_t 1)" r2="$(round_t 2)"
  drop_step=100
  if [ -n "$r1" ] && [ -n "$r2" ]; then
    drop_step="$(awk -v a="$r1" -v b="$r2" 'BEGIN { printf "%d", (a + b) * 5 }')"
  fi
  dir="$out/dropoff"
  drop_hook() {
    # Once the world has acknowledged step K, the path assessor's host leaves the network.
    ip netns exec "$prefix-recorder" "$ctl" wait-step world_sim --step "$drop_step" \
      --timeout-s 300 >/dev/null 2>&1 || return 0
    coopnav_netns_cable "$prefix" path_assessor down
    echo "   cable of the path assessor's host pulled after step $drop_step"
  }
  coopnav_scenario_hook() { drop_hook; }
  t0="$EPOCHREALTIME"
  rc=0
  COOPNAV_NETNS_PREFIX="$prefix" coopnav_run_scenario \
    "$COOPNAV_ROOT/config/scenarios/$dropoff_scen.yaml" "$dir" $((port_base + 90)) || rc=$?
  unset -f coopnav_scenario_hook
  coopnav_netns_cable "$prefix" path_assessor up
  t_drop="$(since "$t0")"
  "$ctl" transcript "$dir/$dropoff_scen.lcm" --scenario "$dropoff_scen" >"$dir/transcript.txt" ||
    true
  sim="$(grep '  SIM ' "$dir/transcript.txt" | tail -1 || true)"
  # What the robot said and did (faults.sh's decisions without the FINAL CM and SIM lines, which
  # end the run where the world stopped).
  said() { grep -E '  (SAY|ACTION|RECORDER) ' "$1" || true; }
  n="$(said "$dir/transcript.txt" | wc -l)"
  detail=""
  if [ "${sim#*PARTICIPANT_TIMEOUT}" = "$sim" ] || [ "${sim#*path_assessor}" = "$sim" ]; then
    detail="the run did not end with a participant timeout naming path_assessor: ${sim:-no SIM line}"
  elif ! grep -q 'ran without .*path_assessor' "$dir/dialogue_manager.log"; then
    detail="the dialogue manager's log does not say it ran without the path assessor"
  elif ! cmp -s <(said "$ref" | head -n "$n") <(said "$dir/transcript.txt"); then
    # The run's decisions must be the first ones of the single-host run: none that the missing
    # path assessor changed (the dialogue manager's degraded step included).
    detail="decisions differ from the single-host run's: $(diff <(said "$ref" | head -n "$n") \
      <(said "$dir/transcript.txt") | grep -m1 '^>' || true)"
  fi
  if [ -z "$detail" ]; then
    v=ok
    detail="world_sim exit $rc after $t_drop s; ${sim#*  SIM }"
  else
    v=FAIL
    fail=1
  fi
  note "$(printf '%-20s %-28s %-9s %s' "$dropoff_scen" "path_assessor drops off @ $drop_step" "$v" \
    "$detail")"
  # What the rest of the system said about it (README "Network and hosts").
  grep -h -E 'ran without|waited .* for path_assessor' "$dir/dialogue_manager.log" | head -3 |
    sed 's/^/      dialogue_manager: /' || true
  awk -v k="$drop_step" '{ t = substr($1, 3) + 0 } t * 10 >= k - 0.5' "$dir/transcript.txt" |
    sed 's/^/      transcript: /' | head -8
fi

# 4. The recipe (README "Network and hosts"): scripts/launch.sh on three of the hosts, the
# distance server and the band source on one, the assessors and the dialogue manager on
# another, world_sim on a third; the recorder on its own. The transcript must be the
# single-host one.
if [ "$do_launch" -eq 1 ]; then
  echo "== the recipe: scripts/launch.sh on three hosts ($dropoff_scen)"
  dir="$out/launch"
  scen="$COOPNAV_ROOT/config/scenarios/$dropoff_scen.yaml"
  url="udpm://239.255.76.67:$((port_base + 80))?ttl=1&recv_buf_size=4194304"
  launch=(bash "$COOPNAV_ROOT/scripts/launch.sh" --url "$url")
  mkdir -p "$dir"
  t0="$EPOCHREALTIME"
  coopnav_spawn "$dir/record.log" ip netns exec "$prefix-recorder" \
    "$COOPNAV_BUILD_DIR/tools/coopnav_record" -f -c 'COOPNAV_.*' --lcm-url "$url" \
    "$dir/$dropoff_scen.lcm"
  coopnav_spawn "$dir/host_a.out" ip netns exec "$prefix-band_source" "${launch[@]}" \
    --map "$scen" --log-dir "$dir/host_a" obstacle_distance_server band_source
  coopnav_spawn "$dir/host_b.out" ip netns exec "$prefix-dialogue_manager" "${launch[@]}" \
    --log-dir "$dir/host_b" situation_assessor path_assessor dialogue_manager
  rc=0
  ip netns exec "$prefix-recorder" "$ctl" --lcm-url "$url" wait-ready "${COOPNAV_DAEMONS[@]}" \
    --timeout-s 60 >"$dir/wait-ready.log" 2>&1 || rc=$?
  if [ "$rc" -eq 0 ]; then
    COOPNAV_DAEMON_ARGS_world_sim="--set scenario=$scen" ip netns exec "$prefix-world_sim" \
      "${launch[@]}" --log-dir "$dir/host_c" world_sim >"$dir/host_c.out" 2>&1 || rc=$?
    coopnav_wait_recorded "$dir/$dropoff_scen.lcm"
  fi
  coopnav_stop_all  # SIGTERM: each launcher stops its daemons
  "$ctl" transcript "$dir/$dropoff_scen.lcm" --scenario "$dropoff_scen" >"$dir/transcript.txt" ||
    true
  if [ "$rc" -eq 0 ] && cmp -s "$ref" "$dir/transcript.txt"; then
    v=same
    detail="wall $(since "$t0") s"
  else
    v=FAIL
    fail=1
    detail="launch.sh exit $rc (see $dir); the transcript $(cmp -s "$ref" "$dir/transcript.txt" &&
      echo is || echo is not) the single-host one"
  fi
  note "$(printf '%-20s %-28s %-9s %s' "$dropoff_scen" "launch.sh on three hosts" "$v" "$detail")"
fi

echo
printf '%s\n' "${results[@]}" >"$out/multihost.txt"
if [ "$fail" -eq 0 ]; then
  echo "multihost: all checks pass (output $out)"
else
  echo "multihost: FAILURES above (output $out)"
fi
exit "$fail"
