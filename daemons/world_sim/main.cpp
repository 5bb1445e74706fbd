#include "runtime/daemon_main.hpp"
#include "world_sim_node.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::WorldSimNode>(
      argc, argv, "world_sim",
      "World simulator: runs a scenario (robot from COOPNAV_ROBOT_CMD, simulated humans), "
      "publishes COOPNAV_AGENT_STATES / COOPNAV_GOALS / COOPNAV_SIM_STATUS, in lockstep with its "
      "participants (COOPNAV_STEP_ACK) or in real time.");
}
