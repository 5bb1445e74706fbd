// band_source's subscriptions: COOPNAV_AGENT_STATES, COOPNAV_GOALS, COOPNAV_ROBOT_ACTION.
#include "lcm_paths.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  ChannelInput in;
  if (!splitChannel(data, size, 3, &in)) return 0;
  switch (in.channel) {
    case 0:
      agentStates(in);
      break;
    case 1:
      goals(in);
      break;
    default:
      robotAction(in);
      break;
  }
  return 0;
}
