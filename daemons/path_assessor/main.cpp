#include "path_assessor_node.hpp"
#include "runtime/daemon_main.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::PathAssessorNode>(
      argc, argv, "path_assessor",
      "Human path assessor (paper §II-C): per human, the contribution array CA, its discounted "
      "mean CM and IsContributing (COOPNAV_AGENT_STATES -> COOPNAV_PATH_ASSESSMENT).");
}
