#!/usr/bin/env bash
# The laser and /people through DDS, in closed loop (issue 45): unmapped_box_encounter (a box the
# robot's map does not hold, in a corridor, and a person walking the way round it) with the robot's
# ROS 2 side on Cyclone DDS, as in e2e_ros2_bridge_test but with the humans on /people
# (people_msgs/People, the bridge's humans_from: people) instead of /tracked_agents, and the
# world's simulated laser on /scan (sensor_msgs/LaserScan, best effort). The world's bus and the
# pipeline's are joined only by DDS.
# Checks: the scans robot_side wrote on /scan reach the pipeline's COOPNAV_SCAN unchanged (the
# same stamp, rays and ranges), most of them; the person of /people is in the pipeline's agent
# states (id from the name); the robot, seeing the box only through the forwarded scan, neither
# touches it nor the person, and reaches its goal.
# All DDS on the loopback interface (test/dds/cyclonedds_loopback.xml) in domain 75.
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
domain=75
tmp="$(mktemp -d)"
coopnav_trap 'coopnav_stop_all; rm -rf "$tmp"' EXIT
base="${COOPNAV_TEST_PORT_BASE:-20000}"
robot_bus="udpm://239.255.76.67:$base?ttl=0&recv_buf_size=4194304"
pipe_bus="udpm://239.255.76.67:$((base + 1))?ttl=0&recv_buf_size=4194304"
scenario="$src/test/data/scenarios/unmapped_box_encounter.yaml"
cfg="$src/config"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
ox=11.0 oy=1.575 oyaw=0.0  # the robot's start pose: the odom frame's origin in the map

for d in obstacle_distance_server band_source situation_assessor path_assessor dialogue_manager; do
  args=(-c "$cfg/$d.yaml")
  case "$d" in obstacle_distance_server | band_source) args+=(--set "map_file=$scenario") ;; esac
  coopnav_spawn "$tmp/$d.log" "$(coopnav_bin "$d")" "${args[@]}" --lcm-url "$pipe_bus"
done
coopnav_spawn "$tmp/ros2_bridge.log" "$bridge" -c "$cfg/ros2_bridge.yaml" --lcm-url "$pipe_bus" \
  --set "domain_id=$domain" --set "odom_to_map_x_m=$ox" --set "odom_to_map_y_m=$oy" \
  --set "odom_to_map_yaw_rad=$oyaw" --set humans_from=people
"$ctl" --lcm-url "$pipe_bus" wait-ready obstacle_distance_server band_source situation_assessor \
  path_assessor dialogue_manager ros2_bridge --timeout-s 60 ||
  { tail -5 "$tmp"/*.log; echo "FAIL: the pipeline did not come up"; exit 1; }
coopnav_spawn "$tmp/robot_side.out" "$robot_side" --lcm-url "$robot_bus" --domain "$domain" \
  --odom-origin "$ox" "$oy" "$oyaw" --sim-cues-from "$pipe_bus" --people --echo-pipeline
sleep 1  # DDS discovery between robot_side and the bridge (volatile topics)
rc=0
"$(coopnav_bin world_sim)" -c "$cfg/world_sim.yaml" --set "scenario=$scenario" \
  --set mode=real_time --set publish_human_goals=false --lcm-url "$robot_bus" \
  >"$tmp/world_sim.log" 2>&1 || rc=$?
sleep 0.5
coopnav_stop_all

fail=0
check() {  # check LABEL CONDITION...
  local label=$1; shift
  if "$@"; then echo "ok   $label"; else echo "FAIL $label"; fail=1; fi
}
out="$tmp/robot_side.out"
grep "ended at\|min robot" "$tmp/world_sim.log" || true
check "world_sim exited 0 (rc $rc)" [ "$rc" -eq 0 ]

# The scans: every PIPE_SCAN line (COOPNAV_SCAN from the bridge) equals the SCAN line robot_side
# wrote with that stamp; best effort may lose a few, not most.
written=$(grep -c '^SCAN ' "$out" || true)
forwarded=$(grep -c '^PIPE_SCAN ' "$out" || true)
mismatched=$(awk '$1 == "SCAN" { s[$2] = $3 " " $4 " " $5 }
  $1 == "PIPE_SCAN" { if (!($2 in s) || s[$2] != $3 " " $4 " " $5) bad++ }
  END { print bad + 0 }' "$out")
echo "scans: $written written on /scan, $forwarded on the pipeline's COOPNAV_SCAN, $mismatched differ"
check "scans were written (${written:-0})" [ "${written:-0}" -ge 50 ]
check "most reach COOPNAV_SCAN (${forwarded:-0} of ${written:-0})" \
  [ $((forwarded * 10)) -ge $((written * 9)) ]
check "each forwarded scan equals the one written" [ "$mismatched" -eq 0 ]

# The person of /people: in the pipeline's agent states, as human 1.
with_person=$(grep -c '^PIPE_HUMANS [0-9]* 1$' "$out" || true)
echo "pipeline agent states with human 1 (from /people): $with_person"
check "the person of /people is in the agent states" [ "${with_person:-0}" -ge 20 ]

# The loop: the box only through the forwarded scan, the person only through /people.
ended="$(grep -o "ended at .*" "$tmp/world_sim.log" | tail -1)"
clear="$(sed -n 's/.*min robot clearance to the unmapped obstacles \([-0-9.]*\) m.*/\1/p' \
  "$tmp/world_sim.log" | tail -1)"
check "the robot reached its goal ($ended)" grep -q "robot reached its goal" <<<"$ended"
check "no contact with the person" grep -q "no robot-human contact" "$tmp/world_sim.log"
check "clearance to the box > 0 (${clear:-none} m)" \
  awk -v x="$clear" 'BEGIN { exit !(x != "" && x > 0) }'

if [ "$fail" -ne 0 ]; then
  for f in "$tmp"/*.log; do echo "--- $f"; tail -3 "$f"; done
  exit 1
fi
echo "ros2_bridge scan and people: all checks pass"
