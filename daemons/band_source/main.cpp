#include "band_source_node.hpp"
#include "runtime/daemon_main.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::BandSourceNode>(
      argc, argv, "band_source",
      "Band source: CoHAN-style dual time-elastic band planner. Plans the robot's band and one "
      "anticipated band per human from COOPNAV_AGENT_STATES and COOPNAV_GOALS, follows "
      "COOPNAV_ROBOT_ACTION (dock / resume), publishes COOPNAV_BANDS, COOPNAV_REFERENCE_PATHS "
      "and COOPNAV_ROBOT_CMD.");
}
