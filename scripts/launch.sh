#!/usr/bin/env bash
# Development launcher: starts a chosen subset of the daemons on this host, all on one LCM URL
# with one config directory, waits until they report ready, and stops them all on SIGINT /
# SIGTERM (or as soon as one of them dies). Spread the daemons over hosts by starting a subset
# on each (README "Network and hosts"), e.g.
#   host A:  scripts/launch.sh --url "$URL" --map config/scenarios/narrow_minimal.yaml \
#              obstacle_distance_server band_source
#   host B:  scripts/launch.sh --url "$URL" situation_assessor path_assessor dialogue_manager
#   with URL='udpm://239.255.76.67:7667?ttl=1&recv_buf_size=4194304' on every host.
# A deployment uses the systemd units of config/systemd instead.
#
#   scripts/launch.sh [--url URL] [--config-dir DIR] [--map FILE] [--log-dir DIR]
#                     [--state-dir DIR] DAEMON...
#   DAEMON: a daemon of config/system.yaml (`scripts/coopnav system daemons`) or world_sim, or
#           "all" for every daemon (not world_sim).
#   --url: default $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0 (this host only).
#   --config-dir: DIR/<daemon>.yaml (default config/).
#   --map: the map (or scenario) of the distance server and the band source (their map_file).
#   --log-dir: DIR/<daemon>.log (default runs/launch-<UTC>).
#   --state-dir: restart journals in DIR (one per run: give a fresh directory each time); the
#                distance server has no state to journal.
#   COOPNAV_DAEMON_ARGS_<daemon>: extra arguments of that daemon (word-split), e.g. --set k=v;
#   world_sim needs --set scenario=FILE there.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

url="${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}"
cfg="$COOPNAV_ROOT/config" map="" logs="" state=""
names=()
# The daemons and their command lines come from config/system.yaml (scripts/coopnav system).
coopnav=("$COOPNAV_ROOT/scripts/coopnav" system)
mapfile -t all < <("${coopnav[@]}" daemons)
mapfile -t known < <("${coopnav[@]}" daemons --with-world)
while [ $# -gt 0 ]; do
  case "$1" in
    --url | --config-dir | --map | --log-dir | --state-dir) coopnav_need_value launch.sh "$1" $# ;;&
    --url) url="$2"; shift 2 ;;
    --config-dir) cfg="$2"; shift 2 ;;
    --map) map="$2"; shift 2 ;;
    --log-dir) logs="$2"; shift 2 ;;
    --state-dir) state="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^[^#]/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "launch.sh: unknown option $1" >&2; exit 2 ;;
    all) names+=("${all[@]}"); shift ;;
    *) names+=("$1"); shift ;;
  esac
done
if [ "${#names[@]}" -eq 0 ]; then
  echo "launch.sh: name the daemons to start (or all); --help" >&2
  exit 2
fi
for d in "${names[@]}"; do
  [[ " ${known[*]} " == *" $d "* ]] ||
    { echo "launch.sh: no daemon '$d' (config/system.yaml: ${known[*]})" >&2; exit 2; }
  bin="$("${coopnav[@]}" binary "$d")"
  [ -x "$bin" ] || { echo "launch.sh: $bin missing: build first (cmake --build build)" >&2; exit 2; }
  [ -f "$cfg/$d.yaml" ] || { echo "launch.sh: no config $cfg/$d.yaml" >&2; exit 2; }
done
[ -z "$map" ] || [ -f "$map" ] || { echo "launch.sh: no map file '$map'" >&2; exit 2; }
[ -z "$map" ] || map="$(cd "$(dirname "$map")" && pwd)/$(basename "$map")"
export LCM_DEFAULT_URL="$url"

# Where multicast goes from here. ttl=0 stays on this host (lib.sh adds the route on lo if
# there is none); across hosts the route must name the NIC the other hosts are on.
case "$url" in
  *ttl=0*) coopnav_ensure_multicast ;;
  *)
    if ! via="$(ip route get 239.255.76.67 2>/dev/null | grep -o 'dev [^ ]*')"; then
      echo "launch.sh: no multicast route: ip route add 224.0.0.0/4 dev <NIC of the robot's" \
        "network> (README \"Network and hosts\")" >&2
      exit 1
    fi
    echo "launch.sh: multicast leaves this host on ${via#dev }"
    [ "$via" != "dev lo" ] ||
      echo "launch.sh: warning: the multicast route is on lo; other hosts will not hear" >&2
    ;;
esac

[ -n "$logs" ] || logs="$COOPNAV_ROOT/runs/launch-$(date -u +%Y%m%d-%H%M%S)"
mkdir -p "$logs"
[ -z "$state" ] || mkdir -p "$state"

# Background children of a non-interactive shell ignore SIGINT: they are stopped by SIGTERM
# (coopnav_stop_all), on any exit.
coopnav_trap coopnav_stop_all EXIT
coopnav_trap 'echo "launch.sh: stopping"; exit 130' INT
coopnav_trap 'echo "launch.sh: stopping"; exit 143' TERM

declare -A pid_of=()
for d in "${names[@]}"; do
  # Its binary, config, map (the daemons that read one; not the world, whose scenario is
  # COOPNAV_DAEMON_ARGS_world_sim's) and journal (the daemons that keep state).
  opts=(--config-dir "$cfg")
  [ -z "$map" ] || [ "$d" = world_sim ] || opts+=(--scenario "$map")
  [ -z "$state" ] || opts+=(--state-dir "$state")
  mapfile -t cmd < <("${coopnav[@]}" command "$d" "${opts[@]}")
  extra_var="COOPNAV_DAEMON_ARGS_$d"
  extra=()
  read -r -a extra <<<"${!extra_var:-}"
  coopnav_spawn "$logs/$d.log" "${cmd[@]}" "${extra[@]}" --lcm-url "$url"
  pid_of[$d]="${COOPNAV_PIDS[-1]}"
done
ready=()
for d in "${names[@]}"; do [ "$d" = world_sim ] || ready+=("$d"); done
# A daemon that dies at start (a bad config, a bad map, a port taken) is reported at once with
# its exit status and the end of its log, not after the 30 s of wait-ready.
if [ "${#ready[@]}" -gt 0 ]; then
  wrc=0
  coopnav_wait_ready_watching pid_of "$logs" \
    "$COOPNAV_BUILD_DIR/tools/coopnav_ctl" wait-ready "${ready[@]}" --timeout-s 30 || wrc=$?
  if [ "$wrc" -ne 0 ]; then
    echo "launch.sh: not ready; logs in $logs" >&2
    for d in "${ready[@]}"; do tail -3 "$logs/$d.log" | sed "s/^/  $d: /" >&2; done
    exit 1
  fi
fi
echo "launch.sh: running ${names[*]} on $url (logs in $logs); ctrl-C stops them"

# Until a signal, or until one of them exits: then the others are stopped too.
rc=0
wait -n "${COOPNAV_PIDS[@]}" || rc=$?
gone=""
for d in "${names[@]}"; do kill -0 "${pid_of[$d]}" 2>/dev/null || gone="$d"; done
# world_sim ends by itself at the end of its scenario (exit 0): the run is over.
if [ "$gone" = world_sim ] && [ "$rc" -eq 0 ]; then
  echo "launch.sh: world_sim finished its scenario; stopping the others"
  exit 0
fi
echo "launch.sh: $gone exited (status $rc; $logs/$gone.log); stopping the others" >&2
[ "$rc" -ne 0 ] || rc=1
exit "$rc"
