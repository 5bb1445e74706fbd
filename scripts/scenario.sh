# One scenario run with every daemon as its own process: the launch that scripts/run.sh (the
# paper's experiment) and scripts/faults.sh (kills, an absent distance server, message loss)
# share. Sourced after lib.sh, not executed.
#
#   coopnav_run_scenario SCENARIO.yaml DIR PORT
#     Starts the recorder (DIR/<name>.lcm, tools/record), the distance server, the band source, the assessors
#     and the dialogue manager, waits until they are ready, runs world_sim in lockstep and stops
#     everything. Returns world_sim's exit code (DIR/world_sim.log). Every process logs to
#     DIR/<process>.log (appended to when a daemon is started again).
#
# Knobs (variables set by the caller; all optional):
#   COOPNAV_ABSENT="d1 d2"      daemons not started at all (e.g. obstacle_distance_server)
#   COOPNAV_STATE=1             every daemon gets --state-dir DIR/state (restart journal)
#   COOPNAV_LOSS=0.1            each daemon on a port of its own, joined by coopnav_lossy_relay
#                               dropping that fraction of every forwarded message (seed
#                               COOPNAV_LOSS_SEED); the logger and the scripts hear everything
#   COOPNAV_PROFILE=calibrated  the profile (default paper; paper, calibrated or forecast): the
#                               config files the daemons run (coopnav_profile_suffix below)
#   COOPNAV_NETNS_PREFIX=P      every process on a host of its own: the network namespace
#                               P-<name> (P-recorder: the recorder and the scripts' coopnav_ctl),
#                               made by scripts/netns.sh (scripts/multihost.sh); the URL has ttl=1
#                               so that multicast leaves the host. With COOPNAV_LOSS each host
#                               gets its own relay between its process (a host-local port) and
#                               the network, or, when COOPNAV_NETNS_NETEM holds netem's other
#                               arguments (e.g. "delay 20ms 5ms"), netem on every link instead
#                               (the recorder's excepted, as the relay spares it)
#   COOPNAV_DAEMON_ARGS_<name>  extra arguments of that daemon or of world_sim (word-split),
#                               e.g. --set k=v
#   coopnav_scenario_hook       a function run while world_sim runs (in the foreground of the
#                               script, world_sim in the background): faults.sh kills there
#   coopnav_scenario_after_hook a function run after world_sim ended, before the daemons are
#                               stopped (faults.sh checks that none of them died)
# After the launch, COOPNAV_DAEMON_PID[<name>] holds each daemon's pid and coopnav_start_daemon
# NAME starts one again with the same command line.

COOPNAV_DAEMONS=(obstacle_distance_server band_source situation_assessor path_assessor
  dialogue_manager)
declare -A COOPNAV_DAEMON_PID=()
declare -A COOPNAV_DAEMON_URL=()

# LCM URL of a process of the current run: the shared one, or with loss its own port.
coopnav_daemon_url() {
  local url="${COOPNAV_DAEMON_URL[$1]:-}"
  echo "${url:-$LCM_DEFAULT_URL}"
}

# What runs a process of the run on its host: _cn_on is empty on one host, else
# `ip netns exec P-<name>` (COOPNAV_NETNS_PREFIX).
_cn_on=()
_cn_host() {  # NAME
  _cn_on=()
  if [ -n "${COOPNAV_NETNS_PREFIX:-}" ]; then _cn_on=(ip netns exec "$COOPNAV_NETNS_PREFIX-$1"); fi
}

# A named profile (COOPNAV_PROFILE) is a set of config files: config/<daemon>_<suffix>.yaml.
#   paper       the paper's: every daemon's own config/<daemon>.yaml
#   calibrated  config/path_assessor_calibrated.yaml (CM's γ, τ and side rule fitted on real
#               walkers); the dialogue manager acts on its assessments
#   forecast    config/dialogue_manager_forecast.yaml (round 2 and the stand-offs judge the
#               person by the forecast p_contributing, not by CM) on the paper's path assessment
#               (config/path_assessor_forecast.yaml is the forecast's model file, not a profile)
coopnav_profile_suffix() {  # DAEMON: "" or "_<profile>"
  case "${COOPNAV_PROFILE:-paper}:$1" in
    calibrated:path_assessor) echo _calibrated ;;
    forecast:dialogue_manager) echo _forecast ;;
  esac
}
coopnav_profile_assessment() {  # the path assessment profile the run's path assessor publishes
  case "${COOPNAV_PROFILE:-paper}" in
    calibrated) echo calibrated ;;
    *) echo paper ;;
  esac
}

coopnav_start_daemon() {  # NAME
  local d="$1" args=()
  case "$d" in
    obstacle_distance_server | band_source)
      args=(-c "$_cn_cfg/$d.yaml" --set "map_file=$_cn_scenario") ;;
    path_assessor)
      args=(-c "$_cn_cfg/path_assessor$(coopnav_profile_suffix path_assessor).yaml") ;;
    dialogue_manager)
      args=(-c "$_cn_cfg/dialogue_manager$(coopnav_profile_suffix dialogue_manager).yaml"
        --set "assessment_profile=$(coopnav_profile_assessment)") ;;
    *) args=(-c "$_cn_cfg/$d.yaml") ;;
  esac
  # The distance server keeps no state across requests: nothing to journal.
  if [ "${COOPNAV_STATE:-0}" = 1 ] && [ "$d" != obstacle_distance_server ]; then
    args+=(--state-dir "$_cn_dir/state")
  fi
  local extra_var="COOPNAV_DAEMON_ARGS_$d"
  local extra=()
  read -r -a extra <<<"${!extra_var:-}"
  _cn_host "$d"
  "${_cn_on[@]}" "$(coopnav_bin "$d")" "${args[@]}" "${extra[@]}" --lcm-url "$(coopnav_daemon_url "$d")" \
    >>"$_cn_dir/$d.log" 2>&1 &
  COOPNAV_DAEMON_PID[$d]=$!
  COOPNAV_PIDS+=($!)
}

coopnav_run_scenario() {  # SCENARIO DIR PORT
  _cn_scenario="$1"
  _cn_dir="$2"
  _cn_cfg="$COOPNAV_ROOT/config"
  local port="$3" name ctl rc=0 d
  name="$(basename "$_cn_scenario" .yaml)"
  ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
  mkdir -p "$_cn_dir"
  echo "$_cn_scenario" >"$_cn_dir/scenario.path"  # replay.sh finds the map through it
  # ttl=0 keeps multicast on the host; across hosts (COOPNAV_NETNS_PREFIX) it must leave it.
  local ttl=0 netem_on=0
  if [ -n "${COOPNAV_NETNS_PREFIX:-}" ]; then ttl=1; fi
  export LCM_DEFAULT_URL="udpm://239.255.76.67:$port?ttl=$ttl&recv_buf_size=4194304"
  COOPNAV_DAEMON_PID=()
  COOPNAV_DAEMON_URL=()
  if [ -n "${COOPNAV_LOSS:-}" ] && [ -n "${COOPNAV_NETNS_PREFIX:-}" ]; then
    if [ -n "${COOPNAV_NETNS_NETEM:-}" ]; then
      # The kernel drops and delays on every link; the recorder's link is spared, as the relay
      # spares the logger (a log that lacks a message is a wrong transcript, not a lossy run).
      declare -F coopnav_netns_netem >/dev/null || source "$COOPNAV_ROOT/scripts/netns.sh"
      coopnav_netns_netem "$COOPNAV_NETNS_PREFIX" on \
        "loss $(awk -v l="$COOPNAV_LOSS" 'BEGIN { printf "%g%%", 100 * l }') $COOPNAV_NETNS_NETEM" \
        recorder || { echo "coopnav: netem refused on $COOPNAV_NETNS_PREFIX-*" >&2; return 1; }
      netem_on=1
    else
      # No netem: on each host a relay between its process (a host-local port: ttl=0 stays in
      # the namespace) and the network drops that fraction of what goes out and of what comes
      # in, i.e. of each of the two links a message between two hosts crosses. Seeds differ per
      # host: the relay's decisions depend on the seed, its endpoints and the message only.
      local priv="udpm://239.255.76.67:$((port + 1))?ttl=0&recv_buf_size=4194304" seed
      seed="${COOPNAV_LOSS_SEED:-1}"
      for d in "${COOPNAV_DAEMONS[@]}" world_sim; do
        COOPNAV_DAEMON_URL[$d]="$priv"
        _cn_host "$d"
        coopnav_spawn "$_cn_dir/relay_$d.log" "${_cn_on[@]}" \
          "$COOPNAV_BUILD_DIR/tools/coopnav_lossy_relay" --endpoint "$priv" \
          --endpoint "$LCM_DEFAULT_URL" --loss "$COOPNAV_LOSS" --seed "$seed"
        seed=$((seed + 1))
      done
    fi
  elif [ -n "${COOPNAV_LOSS:-}" ]; then
    # Every process on a port of its own; the relay joins them (lossless towards the logger and
    # the scripts, which stay on the shared URL).
    local p=$((port + 1)) eps=()
    for d in "${COOPNAV_DAEMONS[@]}" world_sim; do
      COOPNAV_DAEMON_URL[$d]="udpm://239.255.76.67:$p?ttl=0&recv_buf_size=4194304"
      eps+=(--endpoint "${COOPNAV_DAEMON_URL[$d]}")
      p=$((p + 1))
    done
    coopnav_spawn "$_cn_dir/relay.log" "$COOPNAV_BUILD_DIR/tools/coopnav_lossy_relay" \
      "${eps[@]}" --lossless "$LCM_DEFAULT_URL" --loss "$COOPNAV_LOSS" \
      --seed "${COOPNAV_LOSS_SEED:-1}"
  fi
  if [ -n "${COOPNAV_NETNS_PREFIX:-}" ]; then
    # coopnav_record (lib.sh) on the recorder's host.
    _cn_host recorder
    coopnav_spawn "$_cn_dir/record.log" "${_cn_on[@]}" "$COOPNAV_BUILD_DIR/tools/coopnav_record" \
      -f -c 'COOPNAV_.*' --lcm-url "$LCM_DEFAULT_URL" "$_cn_dir/$name.lcm"
  else
    coopnav_record "$_cn_dir/$name.lcm" 'COOPNAV_.*' "$_cn_dir/record.log"
  fi
  local ready=()
  for d in "${COOPNAV_DAEMONS[@]}"; do
    case " ${COOPNAV_ABSENT:-} " in *" $d "*) continue ;; esac
    coopnav_start_daemon "$d"
    ready+=("$d")
  done
  _cn_host recorder  # the scripts listen where the recorder does
  # A daemon that stops at start (a bad scenario as its map, a bad config) is said at once.
  if ! coopnav_wait_ready_watching COOPNAV_DAEMON_PID "$_cn_dir" \
    "${_cn_on[@]}" "$ctl" wait-ready "${ready[@]}" --timeout-s 60; then
    echo "coopnav: daemons did not come up for $name; see $_cn_dir/*.log" >&2
    coopnav_stop_all
    if [ "$netem_on" = 1 ]; then coopnav_netns_netem "$COOPNAV_NETNS_PREFIX" off; fi
    return 1
  fi
  sleep 0.3  # the recorder subscribes before the first step
  local sim_extra=()
  read -r -a sim_extra <<<"${COOPNAV_DAEMON_ARGS_world_sim:-}"
  _cn_host world_sim
  "${_cn_on[@]}" "$(coopnav_bin world_sim)" -c "$_cn_cfg/world_sim.yaml" \
    --set "scenario=$_cn_scenario" "${sim_extra[@]}" --lcm-url "$(coopnav_daemon_url world_sim)" \
    >"$_cn_dir/world_sim.log" 2>&1 &
  local sim=$!
  if declare -F coopnav_scenario_hook >/dev/null; then coopnav_scenario_hook "$name" || true; fi
  wait "$sim" || rc=$?
  coopnav_wait_recorded "$_cn_dir/$name.lcm"
  if declare -F coopnav_scenario_after_hook >/dev/null; then coopnav_scenario_after_hook "$name"; fi
  coopnav_stop_all
  if [ "$netem_on" = 1 ]; then coopnav_netns_netem "$COOPNAV_NETNS_PREFIX" off; fi
  return "$rc"
}

# Why a recorded run counts as failed although it ran to its end: a contact (whoever caused
# it), a standstill or the time limit. Prints the reason and returns 1; returns 0 for a run that
# reached every goal without contact. Reads the run's summary.json (coopnav_ctl summarize).
coopnav_run_outcome_failure() {  # SUMMARY.json
  python3 - "$1" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1]))["scenarios"][0]
except (OSError, ValueError, KeyError, IndexError) as ex:
    print(f"no readable summary ({ex})")
    sys.exit(1)
state, contact = s.get("final_state"), s.get("contact")
reasons = []
if s.get("collision") or contact:
    c = contact if isinstance(contact, dict) else {}
    fault = "robot at fault" if c.get("robot_at_fault") else "robot not at fault"
    reasons.append(f"contact with human {c.get('human_id', '?')} at t = {c.get('t_s')} s ({fault})")
if state in ("STANDSTILL", "TIME_LIMIT"):
    reasons.append(f"{state} at t = {s.get('sim_time_s')} s")
elif state != "GOAL_REACHED" and not reasons:
    reasons.append(f"final state {state}")
if reasons:
    print("; ".join(reasons) + (f": {s['detail']}" if s.get("detail") else ""))
    sys.exit(1)
PY
}
