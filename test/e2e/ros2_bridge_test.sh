#!/usr/bin/env bash
# The loop closed through DDS (issue 45): narrow_minimal with the robot's ROS 2 side standing in
# for a real robot. Two LCM buses: world_sim and coopnav_robot_side on the "robot" bus (the
# simulated base and its sensors), the five daemons and coopnav_ros2_bridge on the "pipeline"
# bus; between them only DDS: robot_side publishes /odom (odom frame, origin at the robot's start
# pose, which the bridge is configured with), /tracked_agents and /goal_pose from the world and
# applies /cmd_vel as the world's robot command. world_sim runs free (real time) and gives no
# human goal (a robot's tracker knows none: the band source infers it). What the simulated people
# perceive of the robot besides its body (its band, its words) robot_side passes from the
# pipeline's bus to the world (--sim-cues-from): on a robot they see it and hear it.
# Checks: the run reaches the decisions of the LCM-only run (the golden transcript of
# narrow_minimal: what is said each round and the dock / resume); the utterances and the markers
# arrive on the DDS side; then, in a second run, SIGKILL of band_source while the robot drives
# makes the watchdog put zero on /cmd_vel within cmd_timeout_s (+ one watchdog period + slack).
# All DDS on the loopback interface (test/dds/cyclonedds_loopback.xml) in domain 74.
# Skipped (77) when the bridge was not built (no Cyclone DDS).
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap, coopnav_spawn, coopnav_stop_all
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
bridge="$COOPNAV_BUILD_DIR/daemons/ros2_bridge/coopnav_ros2_bridge"
robot_side="$COOPNAV_BUILD_DIR/test/coopnav_robot_side"
if [ ! -x "$bridge" ] || [ ! -x "$robot_side" ]; then
  echo "SKIP: coopnav_ros2_bridge / coopnav_robot_side not built (no Cyclone DDS)"
  exit 77
fi
export CYCLONEDDS_URI="file://$src/test/dds/cyclonedds_loopback.xml"
domain=74
tmp="$(mktemp -d)"
coopnav_trap 'coopnav_stop_all; rm -rf "$tmp"' EXIT
base="${COOPNAV_TEST_PORT_BASE:-20000}"
robot_bus="udpm://239.255.76.67:$base?ttl=0&recv_buf_size=4194304"
pipe_bus="udpm://239.255.76.67:$((base + 1))?ttl=0&recv_buf_size=4194304"
scenario="$src/config/scenarios/narrow_minimal.yaml"
cfg="$src/config"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
# The robot's start pose in narrow_minimal: the odom frame's origin in the map.
ox=11.0 oy=1.575 oyaw=0.0
cmd_timeout_s=0.5

start_pipeline() {  # the five daemons and the bridge on the pipeline bus
  local d args
  for d in obstacle_distance_server band_source situation_assessor path_assessor dialogue_manager; do
    args=(-c "$cfg/$d.yaml")
    case "$d" in obstacle_distance_server | band_source) args+=(--set "map_file=$scenario") ;; esac
    coopnav_spawn "$tmp/$d.log" "$(coopnav_bin "$d")" "${args[@]}" --lcm-url "$pipe_bus"
    if [ "$d" = band_source ]; then band_pid=$!; fi
  done
  coopnav_spawn "$tmp/ros2_bridge.log" "$bridge" -c "$cfg/ros2_bridge.yaml" --lcm-url "$pipe_bus" \
    --set "domain_id=$domain" --set "odom_to_map_x_m=$ox" --set "odom_to_map_y_m=$oy" \
    --set "odom_to_map_yaw_rad=$oyaw" --set "cmd_timeout_s=$cmd_timeout_s"
  "$ctl" --lcm-url "$pipe_bus" wait-ready obstacle_distance_server band_source situation_assessor \
    path_assessor dialogue_manager ros2_bridge --timeout-s 60 ||
    { tail -5 "$tmp"/*.log; echo "FAIL: the pipeline did not come up"; exit 1; }
}

# ---- 1. the whole scenario through DDS ----
band_pid=0
coopnav_spawn "$tmp/record.log" "$COOPNAV_BUILD_DIR/tools/coopnav_record" -f -c 'COOPNAV_.*' \
  --lcm-url "$pipe_bus" "$tmp/pipeline.lcm"
start_pipeline
coopnav_spawn "$tmp/robot_side.out" "$robot_side" --lcm-url "$robot_bus" --domain "$domain" \
  --odom-origin "$ox" "$oy" "$oyaw" --sim-cues-from "$pipe_bus"
sleep 1  # DDS discovery between robot_side and the bridge (volatile topics)
rc=0
"$(coopnav_bin world_sim)" -c "$cfg/world_sim.yaml" --set "scenario=$scenario" \
  --set mode=real_time --set publish_human_goals=false --lcm-url "$robot_bus" \
  >"$tmp/world_sim.log" 2>&1 || rc=$?
coopnav_wait_recorded "$tmp/pipeline.lcm"
coopnav_stop_all
tail -2 "$tmp/world_sim.log"
"$ctl" transcript "$tmp/pipeline.lcm" --scenario narrow_minimal >"$tmp/transcript.txt" || true
grep -E "SAY|ACTION|SIM" "$tmp/transcript.txt" || true
echo "robot side: $(grep -c '^CMD' "$tmp/robot_side.out" || true) /cmd_vel," \
  "$(grep -c '^UTTERANCE' "$tmp/robot_side.out" || true) utterances, $(grep '^MARKERS' "$tmp/robot_side.out" || true)"
grep '^UTTERANCE' "$tmp/robot_side.out" || true
fail=0
if [ "$rc" -ne 0 ]; then
  echo "FAIL: world_sim exited $rc"; tail -5 "$tmp/world_sim.log"; fail=1
fi
# The decisions: each round's speech act and the robot actions, in order, as in the golden run.
decisions() { grep -oE 'SAY [A-Z_]+|ACTION [A-Z_]+' "$1" | tr '\n' ' '; }
want="$(decisions "$src/test/data/golden/narrow_minimal.transcript")"
got="$(decisions "$tmp/transcript.txt")"
echo "decisions LCM-only (golden): $want"
echo "decisions through DDS:       $got"
if [ "$want" != "$got" ]; then echo "FAIL: the decisions differ from the LCM-only run"; fail=1; fi
# What was said reached the DDS side, word for word, in order.
grep -oE 'SAY [A-Z_]+ "[^"]*"' "$tmp/transcript.txt" | sed -E 's/^SAY [A-Z_]+ "(.*)"$/\1/' \
  >"$tmp/said_lcm.txt" || true
sed -n 's/^UTTERANCE //p' "$tmp/robot_side.out" >"$tmp/said_dds.txt"
if [ ! -s "$tmp/said_dds.txt" ] || ! diff "$tmp/said_lcm.txt" "$tmp/said_dds.txt"; then
  echo "FAIL: the utterances on /coopnav/utterance are not those said"; fail=1
fi
markers="$(sed -n 's/^MARKERS //p' "$tmp/robot_side.out")"
if [ "${markers:-0}" -lt 10 ] || ! grep -q '^MARKER cp_h 1' "$tmp/robot_side.out"; then
  echo "FAIL: /coopnav/markers: ${markers:-0} arrays, CP_h of human 1 drawn: $(grep -c '^MARKER cp_h' "$tmp/robot_side.out" || true)"
  fail=1
fi

# ---- 2. the watchdog: band_source killed while the robot drives ----
COOPNAV_PIDS=()
start_pipeline
coopnav_spawn "$tmp/robot_side2.out" "$robot_side" --lcm-url "$robot_bus" --domain "$domain" \
  --odom-origin "$ox" "$oy" "$oyaw" --sim-cues-from "$pipe_bus"
sleep 1
"$(coopnav_bin world_sim)" -c "$cfg/world_sim.yaml" --set "scenario=$scenario" \
  --set mode=real_time --set publish_human_goals=false --lcm-url "$robot_bus" \
  >"$tmp/world_sim2.log" 2>&1 &
sim=$!
# Until the robot is commanded to move (a nonzero /cmd_vel), then 1 s more.
for _ in $(seq 1 100); do
  if awk '$1 == "CMD" && ($3 > 0.05 || $3 < -0.05) { found = 1 } END { exit !found }' \
    "$tmp/robot_side2.out"; then break; fi
  sleep 0.1
done
sleep 1
kill -KILL "$band_pid"
sleep $(awk -v t="$cmd_timeout_s" 'BEGIN { print t + 1.5 }')
kill -TERM "$sim" 2>/dev/null || true
wait "$sim" 2>/dev/null || true
coopnav_stop_all
# The last nonzero command, and the first zero after it: within cmd_timeout_s + a period + slack.
python3 - "$tmp/robot_side2.out" "$cmd_timeout_s" <<'PY' || fail=1
import sys
cmds = [l.split() for l in open(sys.argv[1]) if l.startswith("CMD ")]
timeout = float(sys.argv[2])
moving = [i for i, c in enumerate(cmds) if abs(float(c[2])) > 1e-9 or abs(float(c[4])) > 1e-9]
if not moving:
    print("FAIL: the robot was never commanded to move"); sys.exit(1)
last = moving[-1]
zeros = [c for c in cmds[last + 1:] if all(float(x) == 0.0 for x in c[2:5])]
if not zeros:
    print(f"FAIL: no zero /cmd_vel after the last command ({len(cmds)} commands)"); sys.exit(1)
gap = float(zeros[0][1]) - float(cmds[last][1])
print(f"watchdog: zero on /cmd_vel {gap:.3f} s after the last command (cmd_timeout_s {timeout})")
if gap > timeout + 0.05 + 0.25:
    print("FAIL: the watchdog was late"); sys.exit(1)
PY
grep -q "zero on /cmd_vel" "$tmp/ros2_bridge.log" ||
  { echo "FAIL: the bridge did not log the watchdog"; fail=1; }
if [ "$fail" -ne 0 ]; then
  for f in "$tmp"/*.log; do echo "--- $f"; tail -3 "$f"; done
  exit 1
fi
echo "ros2_bridge: all checks pass"
