// world_sim's subscriptions: COOPNAV_STATUS, COOPNAV_ROBOT_CMD, COOPNAV_UTTERANCE, COOPNAV_BANDS.
#include "lcm_paths.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  ChannelInput in;
  if (!splitChannel(data, size, 4, &in)) return 0;
  switch (in.channel) {
    case 0:
      daemonStatus(in);
      break;
    case 1:
      velocityCommand(in);
      break;
    case 2:
      utterance(in);
      break;
    default:
      bands(in);
      break;
  }
  return 0;
}
