#include "obstacle_distance_server_node.hpp"

#include <algorithm>
#include <string>

#include "coopnav/distance_reply_t.hpp"
#include "maps/map_loader.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {
const std::string kReplyPrefix = channels::kDistanceReplyPrefix;
}  // namespace

void ObstacleDistanceServerConfig::resolvePaths(const std::string& base_dir) {
  map.resolvePaths(base_dir);
  write_bt_path = resolvePath(base_dir, write_bt_path);
}

ObstacleDistanceServerNode::ObstacleDistanceServerNode(const Config& config, Runtime& runtime)
    : config_(config), runtime_(runtime) {
  LoadedField loaded = loadDistanceField(config_.map);
  LoadedMap& map = loaded.map;
  field_ = std::move(loaded.field);
  try {
    if (!config_.write_bt_path.empty()) writeBt(*map.tree, config_.write_bt_path);
  } catch (const MapLoadError& e) {
    throw StartupError(e.what());
  }
  const auto& g = field_->grid();
  const std::string detail = "map " + config_.map.map_file + " " + std::to_string(g.width()) + "x" +
                             std::to_string(g.height()) + " @ " + std::to_string(g.resolution_m()) +
                             " m";
  log().info("obstacle_distance_server: {}, {} occupied cells, octree {} leaves", detail,
             g.count(CellState::kOccupied), map.tree ? map.tree->getNumLeafNodes() : 0);
  runtime_.setRunning(detail);
  // Unlimited queue: a request/reply server must never drop a queued request silently.
  runtime_.subscribe<distance_request_t>(
      channels::kDistanceRequest,
      [this](const distance_request_t& m, std::int64_t) { onRequest(m); }, 0);
}

void ObstacleDistanceServerNode::onRequest(const distance_request_t& msg) {
  if (msg.reply_channel.empty() || msg.reply_channel.size() > 63)
    throw RejectedMessage("request " + std::to_string(msg.request_id) +
                          " has no usable reply_channel");
  // Replies go only to reply channels: a request naming another channel (COOPNAV_STATUS, a
  // daemon's input) would make this server publish a distance_reply_t onto it for whoever asked.
  if (msg.reply_channel.compare(0, kReplyPrefix.size(), kReplyPrefix) != 0)
    throw RejectedMessage("request " + std::to_string(msg.request_id) + " names reply_channel '" +
                          msg.reply_channel + "', which does not start with " + kReplyPrefix);
  std::vector<DistanceQuery> queries;
  try {
    queries = queriesFromLcm(msg);
  } catch (const RejectedMessage& e) {
    // Tell the client why instead of letting it time out, then count the rejection.
    distance_reply_t reply;
    reply.utime = msg.utime;
    reply.request_id = msg.request_id;
    reply.status = distance_reply_t::STATUS_BAD_REQUEST;
    reply.error = e.what();
    reply.num_results = 0;
    runtime_.publish(msg.reply_channel, reply);
    throw;
  }
  std::vector<DistanceResult> results;
  results.reserve(queries.size());
  for (auto q : queries) {
    q.max_range_m = std::min(q.max_range_m, config_.max_range_cap_m);
    results.push_back(answerQuery(*field_, q));
  }
  runtime_.publish(msg.reply_channel, toLcm(msg.utime, msg.request_id, results));
}

}  // namespace coopnav
