// obstacle_distance_server's subscription: COOPNAV_DIST_REQ. The whole request path of
// ObstacleDistanceServerNode::onRequest: reply-channel check, queriesFromLcm, the range cap and
// answerQuery on a real map (the narrow corridor scenario's walls), and the reply it publishes
// (BAD_REQUEST with the reason, or the results), which must encode and be readable by a client.
#include <algorithm>
#include <memory>
#include <string>

#include "coopnav/channels.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "lcm_paths.hpp"
#include "maps/map_loader.hpp"
#include "obstacle_distance_server_node.hpp"

namespace {

using namespace coopnav;

const GridDistanceField& field() {
  static const std::unique_ptr<GridDistanceField> f = [] {
    LoadedMap map = loadMap(COOPNAV_SOURCE_DIR "/config/scenarios/narrow_minimal.yaml");
    return std::make_unique<GridDistanceField>(std::move(map.grid), UnknownPolicy::kObstacle);
  }();
  return *f;
}

void checkResult(const DistanceQuery& q, const DistanceResult& r) {
  if (r.status == DistanceStatus::kOk) {
    if (!std::isfinite(r.distance_m) || r.distance_m < 0.0 || !r.obstacle.allFinite())
      fuzz::fail("distance: an OK result is not a finite distance >= 0 with a finite point");
    if (q.kind != DistanceQueryKind::kNearest && r.distance_m > q.max_range_m + 1.0)
      fuzz::fail("distance: an OK result lies beyond the query's range");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const double max_range_cap_m = ObstacleDistanceServerConfig{}.max_range_cap_m;
  static const GridDistanceField& map = field();
  fuzz::ChannelInput in{0, data, size};
  distance_request_t msg;
  if (!fuzz::decodeLikeDaemon(in, &msg)) return 0;
  // As onRequest: a reply channel LCM cannot name, or one outside COOPNAV_DIST_REP_*, is rejected
  // without a reply.
  static const std::string kReplyPrefix = channels::kDistanceReplyPrefix;
  if (msg.reply_channel.size() > 63 ||
      msg.reply_channel.compare(0, kReplyPrefix.size(), kReplyPrefix) != 0)
    return 0;
  std::vector<DistanceQuery> queries;
  try {
    queries = queriesFromLcm(msg);
  } catch (const RejectedMessage& e) {
    distance_reply_t reply{};
    reply.utime = msg.utime;
    reply.request_id = msg.request_id;
    reply.status = distance_reply_t::STATUS_BAD_REQUEST;
    reply.error = e.what();
    reply.num_results = 0;
    (void)fuzz::reencode(reply);
    return 0;
  }
  std::vector<DistanceResult> results;
  for (auto q : queries) {
    q.max_range_m = std::min(q.max_range_m, max_range_cap_m);
    results.push_back(answerQuery(map, q));
    checkResult(q, results.back());
  }
  const distance_reply_t reply = fuzz::reencode(toLcm(msg.utime, msg.request_id, results));
  try {
    if (resultsFromLcm(reply).size() != queries.size())
      fuzz::fail("distance: the reply does not answer every query");
  } catch (const RejectedMessage&) {
    fuzz::fail("distance: a client rejects the server's reply");
  }
  return 0;
}
