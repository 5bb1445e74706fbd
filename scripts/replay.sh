#!/usr/bin/env bash
# Replays a recorded run into FRESH assessors and a fresh dialogue manager and prints their
# transcript again. Only the world's side of the log is played (agent states, goals, bands,
# reference paths, sim status) with lcm-logplayer, on a host-local port of its own; the replayed
# daemons' outputs are recorded to OUT_DIR/replay.lcm. Their step gates (docs/lockstep.md) keep
# the recorded ordering, so the transcript is the recorded one.
#
#   scripts/replay.sh LOG [--map MAP_OR_SCENARIO] [--speed S] [--out-dir DIR] [--no-build]
#   MAP defaults to the scenario recorded next to the log by run.sh (scenario.path).
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

log="" map="" speed="1.0" outdir="" build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --map) map="$2"; shift 2 ;;
    --speed) speed="$2"; shift 2 ;;
    --out-dir) outdir="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "replay.sh: unknown option $1" >&2; exit 2 ;;
    *) log="$1"; shift ;;
  esac
done
[ -n "$log" ] && [ -f "$log" ] || { echo "replay.sh: give a recorded .lcm log" >&2; exit 2; }
log="$(cd "$(dirname "$log")" && pwd)/$(basename "$log")"
if [ -z "$map" ] && [ -f "$(dirname "$log")/scenario.path" ]; then
  map="$(cat "$(dirname "$log")/scenario.path")"
fi
[ -n "$map" ] && [ -f "$map" ] || { echo "replay.sh: no map; pass --map FILE" >&2; exit 2; }
# Daemons resolve relative paths against their config file's folder: give them an absolute one.
map="$(cd "$(dirname "$map")" && pwd)/$(basename "$map")"
[ -n "$outdir" ] || outdir="$(mktemp -d)"
mkdir -p "$outdir"

if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast
export LCM_DEFAULT_URL="udpm://239.255.76.67:${COOPNAV_REPLAY_PORT:-7689}?ttl=0&recv_buf_size=4194304"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"

coopnav_trap coopnav_stop_all EXIT

# The recorder first: it is listening by the time the daemons are ready (a loaded machine can
# take a while to start it).
coopnav_record "$outdir/replay.lcm" 'COOPNAV_.*' "$outdir/record.log"
# The daemons a replay starts afresh, with their run's command lines (config/system.yaml).
mapfile -t replayed < <("$COOPNAV_ROOT/scripts/coopnav" system daemons --replayed)
for d in "${replayed[@]}"; do
  mapfile -t cmd < <("$COOPNAV_ROOT/scripts/coopnav" system command "$d" --scenario "$map")
  coopnav_spawn "$outdir/$d.log" "${cmd[@]}"
done
"$ctl" wait-ready "${replayed[@]}" --timeout-s 60 >/dev/null
sleep 0.5
# Listening before the first message goes out: done = the dialogue manager (the last stage) has
# acknowledged the log's last step, however long a loaded machine takes to get there.
"$ctl" wait-step dialogue_manager --log "$log" --timeout-s 300 &
waiter=$!
lcm-logplayer -s "$speed" -l "$LCM_DEFAULT_URL" \
  -e 'COOPNAV_(AGENT_STATES|GOALS|BANDS|REFERENCE_PATHS|SIM_STATUS)' "$log" \
  >"$outdir/lcm-logplayer.log" 2>&1
wait "$waiter" || echo "replay.sh: the replay did not reach the log's last step" >&2
coopnav_wait_recorded "$outdir/replay.lcm"
coopnav_stop_all
"$ctl" transcript "$outdir/replay.lcm"
