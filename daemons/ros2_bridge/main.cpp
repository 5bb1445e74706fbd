#include "ros2_bridge_node.hpp"
#include "runtime/daemon_main.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::Ros2BridgeNode>(
      argc, argv, "ros2_bridge",
      "ROS 2 bridge on Cyclone DDS (no ROS needed): /odom (or AMCL's pose), /tracked_agents or "
      "/people, /goal_pose and /scan -> COOPNAV_AGENT_STATES, COOPNAV_GOALS, COOPNAV_SCAN; "
      "COOPNAV_ROBOT_CMD -> /cmd_vel with a watchdog (zero after cmd_timeout_s without a "
      "command); COOPNAV_BANDS, COOPNAV_SITUATION, COOPNAV_UTTERANCE -> /coopnav/markers "
      "(rviz2) and /coopnav/utterance.");
}
