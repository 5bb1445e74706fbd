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
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// Step k needs `participant` to have acknowledged step k + offset (offset 0 or -1), and, for
/// each of `channels`, to have been received (noteReceived) as many messages of that step as the
/// ack counts: a lost datagram holds the step until the world re-publishes it (docs/lockstep.md).
struct StepRequirement {
  std::string participant;
  int offset{0};
  std::vector<std::string> channels{};
  /// Never wait for this participant before it was heard from, whatever wait_for_unseen says
  /// (world_sim for a daemon that may also run without it: replay, tests).
  bool optional_until_seen{false};
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
  /// as rejected, and the gate goes on (it never reaches an unrelated handler). Inside accept(),
  /// work is only queued: it runs once the input is stored.
  void submit(std::int64_t step, Work work);

  /// An input counted for the gate: notes it (noteReceived) and, unless it is a repeat, calls
  /// `store()`, then runs what became runnable, whether store() returned or threw. Returns false
  /// for a repeat (nothing stored). Free-running inputs (step < 0) are always stored.
  template <class Store>
  bool accept(const std::string& participant, const std::string& channel, std::int64_t step,
              const std::string& key, Store&& store) {
    if (!noteReceived(participant, channel, step, key)) return false;
    struct Release {
      StepGate& g;
      ~Release() {
        if (--g.holding_ == 0) g.drain();
      }
    };
    ++holding_;
    Release release{*this};
    store();
    return true;
  }

  /// Feeds an acknowledgement (the gate's own subscription calls this; tests may too).
  /// `counts`: messages per channel the participant published for the step (empty = unknown).
  /// Throws RejectedMessage for a step more than limits.max_pending_steps from the peer's acks
  /// so far, until limits.time_resync_messages such acks agree (a new run).
  void onAck(const std::string& participant, std::int64_t step,
             const std::map<std::string, int>& counts = {});

  /// Notes a message of `participant` on `channel` for `step`, identified by `key` (e.g. the
  /// human id). Returns false when that message was already noted (a repeat: handle it once).
  /// Does not run queued work: call poke() once the message is stored (or use accept()).
  bool noteReceived(const std::string& participant, const std::string& channel, std::int64_t step,
                    const std::string& key);
  /// Runs what became runnable (after noteReceived and storing the message).
  void poke() { drain(); }

  /// An extra condition of a step: returns what is missing ("" = nothing). Checked with the
  /// requirements; covered by the same timeout.
  void setCondition(std::function<std::string(std::int64_t step)> condition) {
    condition_ = std::move(condition);
  }

  /// Latest step acknowledged by `participant`; -1 if none.
  std::int64_t lastAck(const std::string& participant) const;
  std::size_t pending() const { return queue_.size(); }
  /// What step `step` still waits for ("" = nothing), for log lines.
  std::string missing(std::int64_t step) const { return missingFor(step); }

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
    /// The acked steps' sequence: an ack far off it (a forged step 2^50) is refused, or every
    /// real input after it would count as a late repeat; a new run is followed after a few acks.
    std::optional<JumpGuard> ack_steps;
    bool present{false};
    /// Per step: the ack's counts per channel; and the keys of the messages noted per channel.
    std::map<std::int64_t, std::map<std::string, int>> acked_counts;
    std::map<std::int64_t, std::map<std::string, std::set<std::string>>> received;
  };
  void prune(Peer& p);
  std::string missingFor(std::int64_t step) const;
  void runItem(Pending& item, bool degraded, const std::string& missing);
  void drain();

  Runtime& runtime_;
  StepGateOptions options_;
  std::map<std::string, Peer> peers_;
  std::deque<Pending> queue_;
  bool draining_{false};
  int holding_{0};  ///< inside accept(): submitted work waits until the input is stored
  std::function<std::string(std::int64_t)> condition_;
};

}  // namespace coopnav
