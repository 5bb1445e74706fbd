#include "runtime/daemon_main.hpp"
#include "situation_assessor_node.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::SituationAssessorNode>(
      argc, argv, "situation_assessor",
      "Situation assessor (paper §II-B): per bands message and human, the crossing info, d_h, "
      "d_OH, d_OR, d_HR and the three predicates (COOPNAV_BANDS -> COOPNAV_SITUATION).");
}
