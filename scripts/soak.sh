#!/usr/bin/env bash
# Soak: every daemon for a long run at a multiple of the nominal message rates; fails if a daemon's
# resident memory grows more than 5 % after warm-up, if its backlog or its lag behind the inputs
# grows, or if it dies.
#
#   scripts/soak.sh [--minutes N] [--rate-factor F] [--out DIR] [--no-build]
#
# Default: 10 minutes at 10x. The pipeline (obstacle_distance_server, band_source,
# situation_assessor, path_assessor, dialogue_manager) runs free-running on a bus of its own, fed by
# build/tools/coopnav_soak: agent states every 0.1 s of message time published every 0.1 s / F of
# wall time (100 Hz at 10x, time compressed like world_sim's real-time mode, so the band source
# plans and publishes bands at 100 Hz too), goals every second of message time; an endless
# corridor encounter in which a new human (new id) meets the shuttling robot every 20 s of message
# time, so per-human state comes and goes. world_sim cannot share that bus (its agent states would
# mix with the feeder's): it runs its own scenario in real-time mode at F x on a second bus
# (physics at 20 Hz x F, agent states at 10 Hz x F) and is watched for memory and counters.
# coopnav_soak samples every daemon's VmRSS (/proc/<pid>/status, pid from its status message) and
# status (received / dropped / rejected, backlog = inputs found waiting at one wake-up) every
# 5 s, and prints the table; samples go to DIR/soak.csv, daemon logs to DIR/*.log.
#
# Warm-up: the first 20 % of the run (allocator pools, per-human maps, caches fill up); RSS growth
# and lag growth are measured from its end to the end of the run.
#
# Recorded figures of the full run (10 min, 10x, RelWithDebInfo, 2-core machine shared with other
# jobs): see docs/soak.md.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

minutes=10
factor=10
out=""
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes="$2"; shift 2 ;;
    --rate-factor) factor="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "soak.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast

# Our own ports unless the caller (ctest) gave one; world_sim's bus is 100 ports above.
url="${LCM_DEFAULT_URL:-udpm://239.255.76.67:7791?ttl=0&recv_buf_size=4194304}"
if [[ "$url" =~ ^(udpm://[0-9.]+:)([0-9]+)(.*)$ ]]; then
  side_url="${BASH_REMATCH[1]}$((BASH_REMATCH[2] + 100))${BASH_REMATCH[3]}"
else
  echo "soak.sh: cannot derive a second bus from '$url'" >&2
  exit 2
fi
out="${out:-$COOPNAV_ROOT/runs/soak-$(date -u +%Y%m%dT%H%M%SZ)}"
mkdir -p "$out"
duration_s=$(awk -v m="$minutes" 'BEGIN { printf "%.1f", m * 60 }')
warmup_s=$(awk -v m="$minutes" 'BEGIN { printf "%.1f", m * 60 * 0.2 }')
# World time of the side scenario: the whole run at F x, with margin; the robot gets no commands.
sim_limit_s=$(awk -v m="$minutes" -v f="$factor" \
  'BEGIN { t = m * 60 * f * 1.5 + 60; printf "%.1f", (t < 86400 ? t : 86400) }')
scenario="$out/world_sim_soak.yaml"
cat >"$scenario" <<EOF
name: soak
seed: 7
time_limit_s: $sim_limit_s
map:
  walls:
    - {x0_m: -1.0, y0_m: -0.1, x1_m: 32.0, y1_m: -0.1, thickness_m: 0.2}
    - {x0_m: -1.0, y0_m: 6.1, x1_m: 32.0, y1_m: 6.1, thickness_m: 0.2}
    - {x0_m: -1.0, y0_m: -0.1, x1_m: -1.0, y1_m: 6.1, thickness_m: 0.2}
    - {x0_m: 32.0, y0_m: -0.1, x1_m: 32.0, y1_m: 6.1, thickness_m: 0.2}
rates: {physics_hz: 20, publish_hz: 10}
lockstep: {enabled: false}
robot:
  start: {x_m: 3.0, y_m: 3.0, theta_rad: 0.0}
  goal: {x_m: 27.0, y_m: 3.0, theta_rad: 0.0}
humans:
  - {id: 1, start: {x_m: 27.5, y_m: 3.0, theta_rad: 3.14159}, goal: {x_m: 2.5, y_m: 3.0},
     behaviour: social_force, speed_m_s: 1.0}
  - {id: 2, start: {x_m: 27.5, y_m: 1.5, theta_rad: 3.14159}, goal: {x_m: 2.5, y_m: 4.5},
     behaviour: oblivious, speed_m_s: 0.8}
EOF

cfg="$COOPNAV_ROOT/config"
coopnav_trap coopnav_stop_all EXIT
# The pipeline's daemons (config/system.yaml), free-running on their configs (no map argument:
# each config's own).
mapfile -t daemons < <("$COOPNAV_ROOT/scripts/coopnav" system daemons)
for d in "${daemons[@]}"; do
  coopnav_spawn "$out/$d.log" "$(coopnav_bin "$d")" -c "$cfg/$d.yaml" --lcm-url "$url" \
    --log-level warn
done
coopnav_spawn "$out/world_sim.log" "$(coopnav_bin world_sim)" -c "$cfg/world_sim.yaml" \
  --lcm-url "$side_url" --log-level warn --set "scenario=$scenario" --set mode=real_time \
  --set "real_time_factor=$factor" --set exit_at_end=false
"$COOPNAV_BUILD_DIR/tools/coopnav_ctl" --lcm-url "$url" wait-ready "${daemons[@]}" \
  --timeout-s 60 >/dev/null

echo "soak: ${minutes} min at ${factor}x; output in $out"
rc=0
"$COOPNAV_BUILD_DIR/tools/coopnav_soak" --lcm-url "$url" --side-url "$side_url" \
  --duration-s "$duration_s" --rate-factor "$factor" --warmup-s "$warmup_s" \
  --csv "$out/soak.csv" \
  "${daemons[@]/#/--daemon=}" --daemon world_sim | tee "$out/soak.txt" ||
  rc=$?
# A daemon that died during the run is a failure even if its last samples looked fine.
for p in "${COOPNAV_PIDS[@]}"; do
  if ! kill -0 "$p" 2>/dev/null; then
    echo "soak: process $p died during the run (logs in $out)" >&2
    rc=1
  fi
done
exit "$rc"
