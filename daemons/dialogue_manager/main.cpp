#include "dialogue_manager_node.hpp"
#include "runtime/daemon_main.hpp"

int main(int argc, char** argv) {
  return coopnav::runDaemon<coopnav::DialogueManagerNode>(
      argc, argv, "dialogue_manager",
      "Dialogue manager: the decision pipeline of paper §II-D per human. Reads COOPNAV_SITUATION, "
      "COOPNAV_PATH_ASSESSMENT and COOPNAV_AGENT_STATES; publishes COOPNAV_UTTERANCE, "
      "COOPNAV_ROBOT_ACTION and COOPNAV_PATH_ASSESSOR_CONTROL; acknowledges lockstep steps.");
}
