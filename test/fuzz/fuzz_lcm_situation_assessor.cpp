// situation_assessor's subscriptions: COOPNAV_REFERENCE_PATHS, COOPNAV_BANDS, and its distance
// client's reply channel (COOPNAV_DIST_REP_<client>).
#include "lcm_paths.hpp"

namespace {

// The distance client's reply path: resultsFromLcm, and a reply the server would build from the
// accepted results must be accepted too.
void distanceReply(const coopnav::fuzz::ChannelInput& in) {
  using namespace coopnav;
  distance_reply_t msg;
  if (!fuzz::decodeLikeDaemon(in, &msg)) return;
  try {
    const std::vector<DistanceResult> results = resultsFromLcm(msg);
    const distance_reply_t back = fuzz::reencode(toLcm(msg.utime, msg.request_id, results));
    (void)resultsFromLcm(back);
  } catch (const RejectedMessage&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  ChannelInput in;
  if (!splitChannel(data, size, 3, &in)) return 0;
  switch (in.channel) {
    case 0:
      referencePaths(in);
      break;
    case 1:
      bands(in);
      break;
    default:
      distanceReply(in);
      break;
  }
  return 0;
}
