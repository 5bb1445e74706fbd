// dialogue_manager's subscriptions: COOPNAV_SITUATION, COOPNAV_PATH_ASSESSMENT,
// COOPNAV_AGENT_STATES, COOPNAV_STEP_ACK.
#include "lcm_paths.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  ChannelInput in;
  if (!splitChannel(data, size, 4, &in)) return 0;
  switch (in.channel) {
    case 0:
      situation(in);
      break;
    case 1:
      pathAssessment(in);
      break;
    case 2:
      agentStates(in);
      break;
    default:
      stepAck(in);
      break;
  }
  return 0;
}
