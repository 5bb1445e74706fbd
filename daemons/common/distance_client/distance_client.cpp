#include "distance_client/distance_client.hpp"

#include <unistd.h>

#include "runtime/log.hpp"

namespace coopnav {

DistanceClient::DistanceClient(Runtime& runtime, const std::string& client_name, Options options)
    : runtime_(runtime), options_(options) {
  // The server answers only on channels that start with the prefix, and LCM takes at most 63
  // bytes: a long client name is cut, never the prefix or the pid that makes the channel this
  // process's own.
  const std::string prefix = channels::kDistanceReplyPrefix;
  const std::string suffix = "_" + std::to_string(::getpid());
  const std::size_t room = kMaxChannelBytes - prefix.size() - suffix.size();
  reply_channel_ = prefix + client_name.substr(0, room) + suffix;
  // Unique per process and attempt: pid in the high bits.
  next_id_ = (static_cast<std::int64_t>(::getpid()) << 32) + 1;
  // Not journaled: answers to this process's own requests mean nothing to a restarted one.
  runtime_.subscribe<distance_reply_t>(
      reply_channel_, [this](const distance_reply_t& m, std::int64_t) { onReply(m); }, 0, false);
  runtime_.addTimer(std::chrono::milliseconds(10), [this] { checkTimeouts(); });
}

std::int64_t DistanceClient::query(const std::vector<DistanceQuery>& queries, std::int64_t utime,
                                   Callback done) {
  const std::int64_t id = next_id_++;
  Pending p;
  p.first_id = id;
  p.queries = queries;
  p.utime = utime;
  p.done = std::move(done);
  auto& slot = pending_[id] = std::move(p);
  send(id, slot);
  return id;
}

void DistanceClient::send(std::int64_t id, Pending& p) {
  ++p.attempts_used;
  p.deadline = std::chrono::steady_clock::now() + options_.timeout;
  runtime_.publish(channels::kDistanceRequest, toLcm(p.utime, id, reply_channel_, p.queries));
}

void DistanceClient::onReply(const distance_reply_t& msg) {
  auto it = pending_.find(msg.request_id);
  // A late answer to an earlier attempt of a request still pending answers it: the same
  // queries (a lost or slow datagram must not turn into "unknown" when an answer did come).
  for (auto a = retried_.find(msg.request_id); it == pending_.end() && a != retried_.end();
       a = retried_.find(a->second))
    it = pending_.find(a->second);
  if (it == pending_.end()) throw DroppedMessage("stale or unknown distance reply id");
  Pending p = std::move(it->second);
  pending_.erase(it);
  Outcome o;
  o.attempts_used = p.attempts_used;
  if (msg.status != distance_reply_t::STATUS_OK) {
    o.error = "distance server: " + msg.error;
  } else {
    try {
      o.results = resultsFromLcm(msg);
      o.ok = o.results.size() == p.queries.size();
      if (!o.ok) o.error = "distance server answered a different number of results";
    } catch (const RejectedMessage& e) {
      o.error = std::string("bad reply: ") + e.what();
    }
  }
  p.done(o);
}

void DistanceClient::checkTimeouts() {
  const auto now = std::chrono::steady_clock::now();
  std::vector<std::int64_t> expired;
  for (auto& [id, p] : pending_)
    if (now >= p.deadline) expired.push_back(id);
  for (std::int64_t id : expired) {
    Pending p = std::move(pending_[id]);
    pending_.erase(id);
    if (p.attempts_used < options_.attempts) {
      const std::int64_t fresh = next_id_++;
      retried_[id] = fresh;
      while (retried_.size() > kMaxRetried) retried_.erase(retried_.begin());
      auto& slot = pending_[fresh] = std::move(p);
      send(fresh, slot);
    } else {
      Outcome o;
      o.attempts_used = p.attempts_used;
      o.error = "no reply from the distance server after " + std::to_string(p.attempts_used) +
                " attempts of " + std::to_string(options_.timeout.count()) + " ms";
      p.done(o);
    }
  }
}

DistanceClient::Outcome DistanceClient::querySync(const std::string& lcm_url,
                                                  const std::vector<DistanceQuery>& queries,
                                                  Options options) {
  Runtime rt("distance_client", lcm_url);
  DistanceClient client(rt, "sync", options);
  Outcome result;
  bool done = false;
  client.query(queries, 0, [&](const Outcome& o) {
    result = o;
    done = true;
  });
  const auto limit = options.timeout * (options.attempts + 1);
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done && std::chrono::steady_clock::now() < end) rt.spinFor(5);
  if (!done) result.error = "no reply (client loop ended)";
  return result;
}

}  // namespace coopnav
