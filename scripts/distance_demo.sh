#!/usr/bin/env bash
# Starts the obstacle distance server on the default map (config/obstacle_distance_server.yaml)
# and prints its answers to a few sample queries through the text spy: a quick look at the first
# daemon working over real LCM. Usage: scripts/distance_demo.sh   (builds first if needed)
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
coopnav_install_deps
coopnav_build
coopnav_ensure_multicast
# Our own port, host-local: never mixes with a running system.
export LCM_DEFAULT_URL="${COOPNAV_DEMO_URL:-udpm://239.255.76.67:7690?ttl=0}"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"

"$(coopnav_bin obstacle_distance_server)" -c "$COOPNAV_ROOT/config/obstacle_distance_server.yaml" \
  --log-level warn &
server=$!
coopnav_trap 'kill "$server" 2>/dev/null; wait "$server" 2>/dev/null || true' EXIT
"$ctl" wait-ready obstacle_distance_server --timeout-s 30

echo "== sample queries on open.pgm (6 m upper corridor at y 3.5..9.5, 2.25 m lower corridor)"
"$COOPNAV_ROOT/scripts/textspy.sh" --channel 'COOPNAV_DIST_(REQ|REP_.*)' --count 2 --timeout-s 20 &
spy=$!
sleep 1.5  # the JVM needs a moment before it listens
# Centre of the upper corridor: nearest wall, the wall on its left (+y) side, free length ahead.
"$ctl" query --nearest 10 6.5 --side 10 6.5 0 1 --ray 10 6.5 1 0 --range-m 20
wait "$spy" || true
