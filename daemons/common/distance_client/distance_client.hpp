#pragma once
/// @file Client of the obstacle distance server: request/reply over LCM with a timeout and retries
/// (each attempt a fresh request id; a late reply to an earlier attempt of a pending request
/// answers it, replies to finished requests are ignored).
///
/// Asynchronous use inside a daemon (shares the daemon's Runtime and loop):
///   DistanceClient client(runtime, "situation_assessor", {});
///   client.query(queries, utime, [](const DistanceClient::Outcome& o) { ... });
/// Synchronous use (tools, tests): DistanceClient::querySync(url, queries, options).

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "runtime/runtime.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

class DistanceClient {
 public:
  struct Options {
    std::chrono::milliseconds timeout{200};  ///< per attempt
    int attempts{3};                         ///< total attempts before giving up
  };
  struct Outcome {
    bool ok{false};
    std::vector<DistanceResult> results;  ///< one per query when ok
    std::string error;                    ///< why not ok: timeout, server error text, ...
    int attempts_used{0};
  };
  using Callback = std::function<void(const Outcome&)>;

  /// LCM's longest channel name.
  static constexpr std::size_t kMaxChannelBytes = 63;

  /// `client_name` makes the reply channel COOPNAV_DIST_REP_<client_name>_<pid> (the name cut to
  /// fit 63 bytes): the server answers only on channels with that prefix.
  DistanceClient(Runtime& runtime, const std::string& client_name, Options options);

  /// Sends a batch (1..MAX_QUERIES); `done` runs exactly once: on the reply or after the last
  /// attempt timed out. Returns the request id of the first attempt.
  std::int64_t query(const std::vector<DistanceQuery>& queries, std::int64_t utime, Callback done);

  /// Requests in flight.
  std::size_t pending() const { return pending_.size(); }

  /// Blocking helper on its own LCM instance.
  static Outcome querySync(const std::string& lcm_url, const std::vector<DistanceQuery>& queries,
                           Options options);

  const std::string& replyChannel() const { return reply_channel_; }

 private:
  struct Pending {
    std::int64_t first_id{0};
    std::vector<DistanceQuery> queries;
    std::int64_t utime{0};
    Callback done;
    int attempts_used{0};
    std::chrono::steady_clock::time_point deadline;
  };
  void send(std::int64_t id, Pending& p);
  void onReply(const distance_reply_t& msg);
  void checkTimeouts();

  Runtime& runtime_;
  Options options_;
  std::string reply_channel_;
  std::int64_t next_id_;
  std::map<std::int64_t, Pending> pending_;  // keyed by the current attempt's id
  /// Earlier attempt id -> the id that replaced it (bounded: only recent ones matter).
  std::map<std::int64_t, std::int64_t> retried_;
  static constexpr std::size_t kMaxRetried = 256;
};

}  // namespace coopnav
