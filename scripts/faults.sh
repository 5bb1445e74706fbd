#!/usr/bin/env bash
# Fault runs of the paper's scenarios (README "Faults"). For each scenario:
#   clean    one run as scripts/run.sh does it: the reference decisions;
#   kill     for each daemon, kill -9 at a random step (seeded, printed) and start it again
#            with its restart journal; the run must complete, no daemon may die on its own,
#            the decisions must be the clean ones or the transcript must say they are degraded,
#            and there must be no dock the clean run did not have;
#   absent   the distance server absent for the whole run: the run completes without a
#            collision, the transcript says why the predicates are unknown, and every dock is a
#            precautionary one ("degraded: precautionary dock", dialogue_manager README);
#   loss     10 % of every message between every two processes dropped (coopnav_lossy_relay):
#            the decisions must be the clean ones.
# Decisions: the transcript's SAY, ACTION, RECORDER, FINAL CM and SIM lines (UNKNOWN notes count
# situations, which a loaded machine's distance-server timeouts may change; they are shown).
# Prints one line per run and a table; writes everything under OUT (default runs/faults-<UTC>).
#
#   scripts/faults.sh [--out DIR] [--no-build] [--seed N] [--loss P]
#                     [--scenarios "open_minimal ..."] [--kill "band_source ..."]
#                     [--kills-per-scenario N] [--no-absent] [--no-loss] [--no-kill]
#                     [--loss-seed N] [--absent-in "narrow_minimal ..."]
#   --kills-per-scenario N: N daemons per scenario (the --kill list in turn across scenarios);
#   default: every daemon in every scenario.
#   --loss-seed N: the relay's seed of every loss run (default: drawn from --seed).
#   --absent-in LIST: the absent run only for these scenarios (default: every one).
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
source "$COOPNAV_ROOT/scripts/scenario.sh"

out="" build=1 seed="${COOPNAV_FAULT_SEED:-20261201}" loss=0.1
scen_list="open_facilitating open_minimal narrow_facilitating narrow_minimal"
kill_list="${COOPNAV_DAEMONS[*]}"
kills_per=0 do_absent=1 do_loss=1 do_kill=1 loss_seed="" absent_in=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out | --seed | --loss | --loss-seed | --absent-in | --scenarios | --kill | \
      --kills-per-scenario) coopnav_need_value faults.sh "$1" $# ;;&
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --seed) seed="$2"; shift 2 ;;
    --loss) loss="$2"; shift 2 ;;
    --loss-seed) loss_seed="$2"; shift 2 ;;
    --absent-in) absent_in="$2"; shift 2 ;;
    --scenarios) scen_list="$2"; shift 2 ;;
    --kill) kill_list="$2"; shift 2 ;;
    --kills-per-scenario) kills_per="$2"; shift 2 ;;
    --no-absent) do_absent=0; shift ;;
    --no-loss) do_loss=0; shift ;;
    --no-kill) do_kill=0; shift ;;
    -h|--help) sed -n '2,/^[^#]/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "faults.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast
[ -n "$out" ] || out="$COOPNAV_ROOT/runs/faults-$(date -u +%Y%m%d-%H%M%S)"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
port="${COOPNAV_FAULT_PORT_BASE:-7700}"
RANDOM="$seed"  # the kill steps and the relay's seeds follow from it
echo "faults: seed $seed, output $out"

coopnav_trap coopnav_stop_all EXIT
coopnav_trap 'coopnav_stop_all; exit 130' INT TERM

# A restarted band source rebuilds its planner memory by planning every recorded step again: the
# peers' step gates and the world wait for it instead of going on degraded. Liveness only.
patient_args() {
  COOPNAV_DAEMON_ARGS_world_sim=""
  COOPNAV_DAEMON_ARGS_band_source="--set step_gate_timeout_s=60"
  COOPNAV_DAEMON_ARGS_situation_assessor="--set gate_timeout_ms=60000"
  COOPNAV_DAEMON_ARGS_path_assessor="--set gate_timeout_ms=60000"
  COOPNAV_DAEMON_ARGS_dialogue_manager="--set gate_timeout_ms=60000"
}
plain_args() {
  COOPNAV_DAEMON_ARGS_world_sim=""
  COOPNAV_DAEMON_ARGS_band_source=""
  COOPNAV_DAEMON_ARGS_situation_assessor=""
  COOPNAV_DAEMON_ARGS_path_assessor=""
  COOPNAV_DAEMON_ARGS_dialogue_manager=""
}

# decisions FILE: what the robot said and did, the final CMs and the end of the run. UNKNOWN
# notes (first occurrence of a reason, with a count) and restart notes are not decisions; they
# are shown beside the verdict.
decisions() { grep -E '  (SAY|ACTION|RECORDER|FINAL CM|SIM) ' "$1" || true; }

crashed=""
check_alive() {  # after world_sim: every daemon still running (the killed one: its restart)
  local d
  crashed=""
  for d in "${!COOPNAV_DAEMON_PID[@]}"; do
    kill -0 "${COOPNAV_DAEMON_PID[$d]}" 2>/dev/null || crashed+=" $d"
  done
}

kill_daemon="" kill_step=0
kill_hook() {
  # When the world has published step K: kill -9, then start the daemon again at once.
  "$ctl" wait-step world_sim --step "$kill_step" --timeout-s 300 >/dev/null 2>&1 || return 0
  kill -9 "${COOPNAV_DAEMON_PID[$kill_daemon]}" 2>/dev/null || true
  wait "${COOPNAV_DAEMON_PID[$kill_daemon]}" 2>/dev/null || true
  echo "   killed $kill_daemon (-9) at step $kill_step; starting it again"
  coopnav_start_daemon "$kill_daemon"
}

# run_one KIND SCENARIO DIR: one run, its transcript, and the check against the clean one.
results=()
fail=0
run_one() {
  local kind="$1" name="$2" dir="$3" scen="$COOPNAV_ROOT/config/scenarios/$2.yaml" rc=0
  # The kind's first word: clean, kill, absent or loss (kind itself names the daemon, the seed).
  local class="${1%% *}"
  if [ "${kind#kill}" != "$kind" ]; then
    # A restarted band source re-plans every journaled step before it answers: on a loaded
    # machine that can take longer than the scenario's 20 s step timeout. The world waits longer
    # (liveness only); the map path is made absolute for the copy.
    mkdir -p "$dir/scenario"
    sed -e "s|^\(  *step_timeout_s:\).*|\1 180|" \
      -e "s|file: \.\./maps/|file: $COOPNAV_ROOT/config/maps/|" "$scen" >"$dir/scenario/$name.yaml"
    scen="$dir/scenario/$name.yaml"
  fi
  crashed=""
  coopnav_progress_run "$name $kind"
  coopnav_run_scenario "$scen" "$dir" "$port" || rc=$?
  port=$((port + 10))
  local verdict="" detail=""
  if [ "$rc" -ne 0 ]; then
    coopnav_progress_end /dev/null
    verdict="FAIL"
    detail="world_sim exit $rc: $(tail -1 "$dir/world_sim.log")"
  else
    "$ctl" transcript "$dir/$name.lcm" --scenario "$name" >"$dir/transcript.txt"
    coopnav_progress_end "$dir/transcript.txt"
    decisions "$dir/transcript.txt" >"$dir/decisions.txt"
    local sim
    sim="$(grep -o '  SIM [A-Z_]*' "$dir/transcript.txt" | tail -1 | sed 's/  SIM //')"
    if [ "$kind" = clean ]; then
      verdict="ok"
    elif [ -n "$crashed" ]; then
      verdict="FAIL"
      detail="died on its own:$crashed"
    elif [ "$sim" = PARTICIPANT_TIMEOUT ] || [ "$sim" = COLLISION ] || [ -z "$sim" ]; then
      verdict="FAIL"
      detail="run ended ${sim:-without a sim status}"
    else
      local clean_dir="$out/$name/clean"
      local new_docks
      # A precautionary dock (an input unknown near the crossing) says so; it is degraded, not
      # false. Any other dock the clean run did not have is false.
      new_docks="$(comm -13 <(grep -o 'human [0-9]*.*ACTION DOCK' "$clean_dir/decisions.txt" |
        sed 's/t_cross=[^ ]* //' | sort -u) <(grep 'ACTION DOCK' "$dir/decisions.txt" |
        grep -v 'degraded: precautionary dock' | grep -o 'human [0-9]*.*ACTION DOCK' |
        sed 's/t_cross=[^ ]* //' | sort -u))"
      # (No grep -q after a pipe: with pipefail the writer's SIGPIPE would read as no match.)
      if [ "$class" = absent ] && grep 'ACTION DOCK' "$dir/decisions.txt" |
        grep -v 'degraded: precautionary dock' >/dev/null; then
        verdict="FAIL"
        detail="docked without the distance server, not as a precaution"
      elif [ "$class" = absent ] && ! grep -q 'distance server' "$dir/transcript.txt"; then
        verdict="FAIL"
        detail="the transcript does not say the distance server is missing"
      elif [ -n "$new_docks" ]; then
        verdict="FAIL"
        detail="a dock the clean run did not have: $new_docks"
      elif cmp -s "$clean_dir/decisions.txt" "$dir/decisions.txt"; then
        verdict="same"
      elif [ "$class" = loss ]; then
        verdict="FAIL"
        detail="decisions differ from the clean run's under message loss"
      elif grep -q -E '  degraded: |UNKNOWN .*distance server' "$dir/transcript.txt"; then
        # Decisions differ, and the transcript says why (a restart without state, the
        # distance server not answering within its bound, a precautionary dock).
        verdict="degraded"
        detail="$(grep -m1 -o -E '  degraded: .*|degraded: precautionary dock|distance server[^"]*' \
          "$dir/transcript.txt" | sed 's/^  //')"
        if grep -q 'degraded: precautionary dock' "$dir/decisions.txt" &&
          [ "${detail#degraded: precautionary}" = "$detail" ]; then
          detail="precautionary dock ($(grep -m1 -o 't=[0-9.]*s  human [0-9]*  t_cross=[^ ]*' \
            <(grep 'ACTION DOCK.*precautionary' "$dir/decisions.txt"))); $detail"
        fi
      elif [ "$class" = absent ]; then
        verdict="degraded"
        detail="predicates unknown without the distance server"
      else
        verdict="FAIL"
        detail="decisions differ and the transcript does not say why"
      fi
      if [ "$verdict" != FAIL ] && [ "$verdict" != same ]; then :; fi
    fi
  fi
  [ "$verdict" = FAIL ] && fail=1
  local restart_lines
  restart_lines="$(grep -E '  (RESTART |degraded: )' "$dir/transcript.txt" 2>/dev/null | head -3 |
    sed 's/^/      /' || true)"
  printf '   %-20s %-34s %-9s %s\n' "$name" "$kind" "$verdict" "$detail"
  [ -n "$restart_lines" ] && echo "$restart_lines"
  if [ "$kind" != clean ] && [ "$verdict" != same ] && [ -f "$dir/decisions.txt" ]; then
    diff "$out/$name/clean/decisions.txt" "$dir/decisions.txt" | head -8 | sed 's/^/      /' || true
  fi
  if [ "$kind" != clean ] && [ -f "$dir/transcript.txt" ] &&
    grep -q 'distance server' "$dir/transcript.txt" &&
    ! grep -q 'distance server' "$out/$name/clean/transcript.txt"; then
    echo "      note: the distance server did not answer within its bound at some step (UNKNOWN in the transcript)"
  fi
  results+=("$(printf '%-20s %-34s %-9s %s' "$name" "$kind" "$verdict" "$detail")")
}

read -r -a kill_daemons <<<"$kill_list"
runs=0
for name in $scen_list; do
  runs=$((runs + 1))
  if [ "$do_kill" -eq 1 ]; then
    runs=$((runs + (kills_per > 0 ? kills_per : ${#kill_daemons[@]})))
  fi
  if [ "$do_absent" -eq 1 ] && { [ -z "$absent_in" ] || [[ " $absent_in " == *" $name "* ]]; }; then
    runs=$((runs + 1))
  fi
  runs=$((runs + do_loss))
done
coopnav_progress_start "$runs"
ki=0
for name in $scen_list; do
  echo "== $name"
  unset -f coopnav_scenario_hook coopnav_scenario_after_hook
  COOPNAV_STATE=0 COOPNAV_ABSENT="" COOPNAV_LOSS=""
  plain_args
  run_one clean "$name" "$out/$name/clean"
  last_step="$(grep -o 'SIM [A-Z_]*  step [0-9]*' "$out/$name/clean/transcript.txt" |
    grep -o '[0-9]*$' || echo 100)"

  if [ "$do_kill" -eq 1 ]; then
    n="${#kill_daemons[@]}"
    [ "$kills_per" -gt 0 ] && n="$kills_per"
    for _ in $(seq 1 "$n"); do
      kill_daemon="${kill_daemons[$((ki % ${#kill_daemons[@]}))]}"
      ki=$((ki + 1))
      # A step inside the run, away from its very first and last steps.
      kill_step=$((5 + RANDOM % (last_step > 15 ? last_step - 10 : 5)))
      COOPNAV_STATE=1 COOPNAV_ABSENT="" COOPNAV_LOSS=""
      patient_args
      coopnav_scenario_hook() { kill_hook; }
      coopnav_scenario_after_hook() { check_alive; }
      run_one "kill $kill_daemon @ step $kill_step" "$name" "$out/$name/kill_$kill_daemon"
      unset -f coopnav_scenario_hook coopnav_scenario_after_hook
    done
  fi
  if [ "$do_absent" -eq 1 ] && { [ -z "$absent_in" ] || [[ " $absent_in " == *" $name "* ]]; }; then
    COOPNAV_STATE=0 COOPNAV_ABSENT="obstacle_distance_server" COOPNAV_LOSS=""
    plain_args
    # Every answer is missing anyway: one short attempt per step instead of the default 150 ms
    # bound changes how long each step waits (67 s -> ~12 s a run), never what is decided.
    COOPNAV_DAEMON_ARGS_situation_assessor="--set distance_timeout_ms=20 --set distance_attempts=1"
    coopnav_scenario_after_hook() { check_alive; }
    run_one "absent obstacle_distance_server" "$name" "$out/$name/absent_distance_server"
    unset -f coopnav_scenario_after_hook
  fi
  if [ "$do_loss" -eq 1 ]; then
    COOPNAV_STATE=0 COOPNAV_ABSENT="" COOPNAV_LOSS="$loss" COOPNAV_LOSS_SEED="${loss_seed:-$RANDOM}"
    plain_args
    # The server is there in a loss run: its bounded wait is 400 ms, in ten attempts, so that a
    # lost request or reply is asked again in time (a late answer to an earlier attempt still
    # counts) and a slow answer on a loaded machine is not taken for an absent server.
    COOPNAV_DAEMON_ARGS_situation_assessor="--set distance_timeout_ms=40 --set distance_attempts=10"
    # Most steps lose a message somewhere (9 in 10 are published again): re-publish sooner than
    # the default 0.25 s, or the run spends its time waiting (0.05 s: ~50 s a run, 0.02 s: ~30 s;
    # wall clock only, the results do not depend on it).
    COOPNAV_DAEMON_ARGS_world_sim="--set retransmit_period_s=0.02"
    coopnav_scenario_after_hook() { check_alive; }
    run_one "loss $loss (relay seed $COOPNAV_LOSS_SEED)" "$name" "$out/$name/loss"
    unset -f coopnav_scenario_after_hook
    COOPNAV_LOSS=""
  fi
done

echo
echo "faults: seed $seed"
printf '%s\n' "${results[@]}" | tee "$out/faults.txt"
if [ "$fail" -eq 0 ]; then
  echo "faults: all runs complete; decisions the same or explicitly degraded; no false dock"
else
  echo "faults: FAILURES above (logs under $out)"
fi
exit "$fail"
