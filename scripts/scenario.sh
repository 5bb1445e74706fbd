# One scenario run for a bash script of your own (no script of the tree launches runs itself now):
# a thin shell over `scripts/coopnav run-one`
# (tools/exp/coopnav_exp/run.py's run_one, which every launcher shares; config/system.yaml lists
# the daemons). Sourced after lib.sh, not executed.
#
#   coopnav_run_scenario SCENARIO.yaml DIR PORT
#     Starts the recorder (DIR/<name>.lcm), the daemons of config/system.yaml, waits until they
#     are ready, runs world_sim in lockstep and stops everything. Returns world_sim's exit code
#     (1: the daemons did not come up). Every process logs to DIR/<process>.log.
#
# Knobs (variables set by the caller; all optional; `scripts/coopnav run-one --help`):
#   COOPNAV_ABSENT="d1 d2"      daemons not started at all (e.g. obstacle_distance_server)
#   COOPNAV_STATE=1             every journaling daemon gets --state-dir DIR/state
#   COOPNAV_LOSS=0.1            each process on a port of its own, joined by coopnav_lossy_relay
#                               dropping that fraction of every message (seed COOPNAV_LOSS_SEED)
#   COOPNAV_PROFILE=calibrated  the assessment profile (config/system.yaml's profiles)
#   COOPNAV_NETNS_PREFIX=P      every process on a host of its own, the namespace P-<name>
#                               (scripts/netns.sh); COOPNAV_NETNS_NETEM: netem instead of relays
#   COOPNAV_DAEMON_ARGS_<name>  extra arguments of that daemon or of world_sim (word-split)
#   coopnav_scenario_hook       a function run while world_sim runs (in the foreground of the
#                               script, the run in the background), with LCM_DEFAULT_URL the
#                               run's bus (exported: it stays after the run, as it always did)
# COOPNAV_DAEMONS: the daemons' names in start order, from config/system.yaml.

mapfile -t COOPNAV_DAEMONS < <("$COOPNAV_ROOT/scripts/coopnav" system daemons)
[ "${#COOPNAV_DAEMONS[@]}" -gt 0 ] || { echo "coopnav: no daemons from config/system.yaml" >&2; return 1; }

coopnav_run_scenario() {  # SCENARIO DIR PORT
  local started="$2/.world_started" pid rc=0
  mkdir -p "$2"
  rm -f "$started"
  "$COOPNAV_ROOT/scripts/coopnav" run-one "$1" "$2" "$3" --world-started "$started" &
  pid=$!
  COOPNAV_PIDS+=("$pid")
  if declare -F coopnav_scenario_hook >/dev/null; then
    while [ ! -e "$started" ] && kill -0 "$pid" 2>/dev/null; do sleep 0.1; done
    if [ -e "$started" ]; then
      # The hook hears the run's bus (e.g. coopnav_ctl wait-step), as the run's processes do.
      LCM_DEFAULT_URL="$(cat "$started")"
      export LCM_DEFAULT_URL
      coopnav_scenario_hook "$(basename "$1" .yaml)" || true
    fi
  fi
  wait "$pid" || rc=$?
  rm -f "$started"
  return "$rc"
}
