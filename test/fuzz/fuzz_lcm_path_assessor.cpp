// path_assessor's subscriptions: COOPNAV_REFERENCE_PATHS, COOPNAV_PATH_ASSESSOR_CONTROL,
// COOPNAV_AGENT_STATES, and COOPNAV_STEP_ACK (its lockstep gate).
#include "lcm_paths.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  ChannelInput in;
  if (!splitChannel(data, size, 4, &in)) return 0;
  switch (in.channel) {
    case 0:
      referencePaths(in);
      break;
    case 1:
      pathAssessorControl(in);
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
