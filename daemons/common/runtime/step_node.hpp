#pragma once
/// @file The one lockstep harness of a daemon that answers steps (docs/lockstep.md). A node says
/// what its inputs are and what step k computes; the harness does the protocol around it:
///
/// - the message that opens step k (`open`): a repeat (the world re-published the step because
///   somebody missed an answer) re-sends the kept outputs and acks of steps k-1 and k and is never
///   computed again; a message that does not convert still has its step acknowledged in turn;
/// - the inputs a step waits for (`input`): noted per (participant, channel, step, key) so that a
///   repeat is applied once and the gate can count them against the publisher's ack;
/// - gating on the peers' acks (StepGate) and running the step's work in step order;
/// - the step's outputs (`Step::publish`), kept for re-publication, and its ack, sent on every
///   path: when the work finishes, throws, or hands its Step on and drops it later;
/// - restarts: the runtime's journal replays recorded inputs through the same handlers, muted.
///
/// A node is then `inputs of step k -> outputs of step k`, plus its free-running handlers.

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_gate.hpp"
#include "runtime/step_outputs.hpp"

namespace coopnav {

struct StepNodeOptions {
  /// What step k waits for (StepGate): peers' acks of k or k-1 and their counted messages.
  std::vector<StepRequirement> requirements;
  /// [wall clock] how long a step waits for a silent peer before it runs degraded (liveness).
  std::chrono::milliseconds timeout{2000};
  /// Wait for peers never heard from (the world simulator: its participants are required).
  bool wait_for_unseen{false};
  /// How a repeated opening message is recognised. kStepNumber: any message of a step already
  /// opened. kSameBytes: the same bytes for the same step (a node whose opening messages may
  /// legitimately go back in step, e.g. the situation assessor, which assesses every bands
  /// message it is given in arrival order).
  enum class Repeat { kStepNumber, kSameBytes };
  Repeat repeat{Repeat::kStepNumber};
};

class StepNode {
 public:
  /// One step being answered. Publish the step's outputs through it; the step is finished by
  /// finish() or, at the latest, when the last handle to it goes away, so no path through a node
  /// can leave a step unanswered. Copies share the step (a node that completes a step later,
  /// after a request/reply, keeps a copy). Acks go out in the order the steps were scheduled, each
  /// with the counts of what its step published: a consumer that sees the ack of k has every ack
  /// before it, whatever finished first.
  class Step {
   public:
    std::int64_t step() const { return state_->step; }
    std::int64_t utime() const { return state_->utime; }
    /// The step ran without every requirement met (a peer timed out); `missing()` says what.
    bool degraded() const { return state_->degraded; }
    const std::string& missing() const { return state_->missing; }

    template <class Msg>
    void publish(const std::string& channel, const Msg& msg) {
      state_->node->outputs_.publish(state_->step, channel, msg);
    }
    /// Acknowledges now (idempotent).
    void finish() { state_->finish(); }

   private:
    friend class StepNode;
    struct State {
      StepNode* node{nullptr};
      std::weak_ptr<int> node_alive;
      std::int64_t step{-1};
      std::int64_t utime{0};
      std::uint64_t serial{0};  ///< place among the node's unacknowledged steps
      bool degraded{false};
      std::string missing;
      bool finished{false};
      void finish() {
        if (finished) return;
        finished = true;
        // A step still held when its node goes away (shutdown) was not answered: no ack.
        if (node_alive.lock()) node->finished(serial);
      }
      ~State() { finish(); }
    };
    std::shared_ptr<State> state_;
  };

  using Work = std::function<void(Step&)>;

  StepNode(Runtime& runtime, StepNodeOptions options);

  /// The message that opens step `msg.step` (Msg has `step` and `utime`; its participant and
  /// channel are noted as an input when a requirement counts them). A repeat re-sends the kept
  /// answers, is counted as dropped and returns. Otherwise `prepare()` converts and validates and
  /// returns the step's work (an empty Work: nothing to compute, the step is only acknowledged);
  /// when it throws (RejectedMessage, DroppedMessage), the step is still acknowledged in its
  /// turn and the exception goes on to the runtime, which counts and logs it.
  template <class Msg, class Prepare>
  void open(const std::string& participant, const std::string& channel, const Msg& msg,
            Prepare&& prepare);

  /// An input of step `step` from `participant` on `channel`, identified by `key` (e.g. the
  /// human id). A repeat is not stored again and is counted as dropped; with `answer_repeat` (the
  /// world's message: its repeat means somebody downstream still waits) the kept answers are
  /// re-sent. `store()` files
  /// the input and may schedule() the step; whatever it does (returns or throws), what became
  /// runnable runs afterwards. Free-running inputs (step -1) are always stored.
  template <class Store>
  void input(const std::string& participant, const std::string& channel, std::int64_t step,
             const std::string& key, Store&& store, bool answer_repeat = false);

  /// Queues the work of step `step` (stamped `utime`): it runs once the step's requirements are
  /// met (at once when free-running), in submission order, and the step is acknowledged after.
  void schedule(std::int64_t step, std::int64_t utime, Work work);

  /// Runs what became runnable (after an input the node stores outside input(), e.g. goals).
  void poke() { gate_.poke(); }

  /// An extra condition of a step ("" = met), covered by the same timeout.
  void setCondition(std::function<std::string(std::int64_t step)> condition) {
    gate_.setCondition(std::move(condition));
  }
  /// Latest step acknowledged by `participant`; -1 if none.
  std::int64_t lastAck(const std::string& participant) const { return gate_.lastAck(participant); }
  /// Steps whose work waits for its requirements.
  std::size_t pending() const { return gate_.pending(); }
  /// Highest step opened; -1 if none.
  std::int64_t lastOpened() const { return last_opened_; }

 private:
  /// True when the opening message of `step` (its encoding `bytes`) was handled before.
  bool repeated(std::int64_t step, const std::vector<std::uint8_t>& bytes);
  /// The kept answers of a repeated step go out again; counted as a dropped input.
  void answerRepeat(std::int64_t step);
  /// The step `serial` is finished: acknowledges it and every finished one queued behind it.
  void finished(std::uint64_t serial);

  struct Unacked {
    std::int64_t step;
    std::int64_t utime;
    bool finished;
  };

  Runtime& runtime_;
  StepNodeOptions options_;
  StepGate gate_;
  StepOutputs outputs_;
  std::int64_t last_opened_{-1};
  /// kStepNumber: the opened steps' sequence; a step far from it is refused, not taken as the
  /// newest (one message of step 2^62 would make every later step a repeat).
  JumpGuard step_guard_;
  std::map<std::int64_t, std::uint64_t> opened_hash_;  ///< kSameBytes: per step, its bytes' hash
  std::deque<Unacked> unacked_;    ///< lockstep steps started and not yet acknowledged, in order
  std::uint64_t first_serial_{0};  ///< serial of unacked_.front()
  std::shared_ptr<int> alive_{std::make_shared<int>(0)};  ///< Steps outliving the node see it
};

// ---- template implementation ----

template <class Msg, class Prepare>
void StepNode::open(const std::string& participant, const std::string& channel, const Msg& msg,
                    Prepare&& prepare) {
  const std::int64_t step = msg.step;
  if (step < -1) throw RejectedMessage("step " + std::to_string(step) + " is neither -1 nor >= 0");
  if (step >= 0) {
    std::vector<std::uint8_t> bytes;
    if (options_.repeat == StepNodeOptions::Repeat::kSameBytes) {
      bytes.resize(static_cast<std::size_t>(msg.getEncodedSize()));
      msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    }
    if (repeated(step, bytes)) {
      answerRepeat(step);
      return;
    }
    // A run has one step in flight, a few when a peer is slow: a queue beyond the cap is a flood.
    if (static_cast<std::int64_t>(gate_.pending()) >= runtime_.limits().max_pending_steps)
      throw RejectedMessage(std::to_string(gate_.pending()) +
                            " steps wait already (limits.max_pending_steps)");
    gate_.noteReceived(participant, channel, step, "open");
  }
  Work work;
  try {
    work = prepare();
  } catch (...) {
    schedule(step, msg.utime, nullptr);
    throw;
  }
  if (work || step >= 0) schedule(step, msg.utime, std::move(work));
}

template <class Store>
void StepNode::input(const std::string& participant, const std::string& channel, std::int64_t step,
                     const std::string& key, Store&& store, bool answer_repeat) {
  if (step < -1) throw RejectedMessage("step " + std::to_string(step) + " is neither -1 nor >= 0");
  if (gate_.accept(participant, channel, step, key, std::forward<Store>(store))) return;
  if (answer_repeat) {
    answerRepeat(step);
  } else {
    runtime_.countDropped();
  }
}

}  // namespace coopnav
