#pragma once
/// @file Lockstep ordering between daemons (README "Lockstep"): a daemon acts on step k only once
/// the upstream participants it depends on have acknowledged the step it needs (k for same-step
/// inputs, k-1 for outputs that take effect at the next step). Keying work to acknowledged steps
/// makes the result independent of which publisher's datagram arrives first, which is what makes
/// a lockstep run and its log replay repeat to the last digit.
///
/// Liveness: a participant that stays silent for `timeout` (wall clock, a liveness matter only)
/// is marked absent and the work runs degraded; the participant is present again with its next
/// ack. A participant never heard from is not waited for unless `wait_for_unseen` (the world
/// simulator, whose participants are required from the first step).

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/runtime.hpp"

namespace coopnav {

/// Step k needs `participant` to have acknowledged step k + offset (offset 0 or -1).
struct StepRequirement {
  std::string participant;
  int offset{0};
};

struct StepGateOptions {
  std::vector<StepRequirement> requirements;
  std::chrono::milliseconds timeout{2000};
  bool wait_for_unseen{false};
};

class StepGate {
 public:
  /// `degraded` is true when the work ran without every requirement met; `missing` names who.
  using Work = std::function<void(bool degraded, const std::string& missing)>;

  /// Subscribes to the step-ack channel and adds a liveness timer on `runtime`.
  StepGate(Runtime& runtime, StepGateOptions options);

  /// Runs `work` now if step < 0 (free-running) or the step's requirements are met, else queues
  /// it; queued work runs in submission order. An exception thrown by work is logged and counted
  /// as rejected, and the gate goes on (it never reaches an unrelated handler).
  void submit(std::int64_t step, Work work);

  /// Feeds an acknowledgement (the gate's own subscription calls this; tests may too).
  void onAck(const std::string& participant, std::int64_t step);

  /// Latest step acknowledged by `participant`; -1 if none.
  std::int64_t lastAck(const std::string& participant) const;
  std::size_t pending() const { return queue_.size(); }

  /// Runs the head of the queue if it has waited longer than the timeout (called by the timer;
  /// public so tests can drive it with a fake clock).
  void checkTimeouts(std::chrono::steady_clock::time_point now);

 private:
  struct Pending {
    std::int64_t step;
    Work work;
    std::chrono::steady_clock::time_point since;
  };
  struct Peer {
    std::int64_t last_ack{-1};
    bool present{false};
  };
  std::string missingFor(std::int64_t step) const;
  void runItem(Pending& item, bool degraded, const std::string& missing);
  void drain();

  Runtime& runtime_;
  StepGateOptions options_;
  std::map<std::string, Peer> peers_;
  std::deque<Pending> queue_;
  bool draining_{false};
};

}  // namespace coopnav
