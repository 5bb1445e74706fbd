#include "runtime/step_node.hpp"

#include "runtime/log.hpp"

namespace coopnav {

StepNode::StepNode(Runtime& runtime, StepNodeOptions options)
    : runtime_(runtime),
      options_(std::move(options)),
      gate_(runtime,
            StepGateOptions{options_.requirements, options_.timeout, options_.wait_for_unseen}),
      outputs_(runtime),
      step_guard_(runtime.limits().max_pending_steps, runtime.limits().time_resync_messages) {}

bool StepNode::repeated(std::int64_t step, const std::vector<std::uint8_t>& bytes) {
  if (options_.repeat == StepNodeOptions::Repeat::kStepNumber) {
    const bool same = step == last_opened_;
    switch (step_guard_.offer(step)) {
      case JumpGuard::Verdict::kJump:
        throw RejectedMessage("step " + std::to_string(step) + " is more than " +
                              std::to_string(runtime_.limits().max_pending_steps) +
                              " steps from the last opened " + std::to_string(last_opened_) +
                              " (limits.max_pending_steps)");
      case JumpGuard::Verdict::kBackwards:
        return true;
      case JumpGuard::Verdict::kResynced:
        log().warn("{}: steps go on from {} (last opened {}): a new run", runtime_.name(), step,
                   last_opened_);
        last_opened_ = step;
        return false;
      case JumpGuard::Verdict::kAccepted:
        break;
    }
    if (same) return true;
    last_opened_ = step;
    return false;
  }
  // FNV-1a: a repeat is the same bytes (the publisher re-sent its kept answer).
  std::uint64_t hash = 1469598103934665603ull;
  for (const auto b : bytes) hash = (hash ^ b) * 1099511628211ull;
  const auto seen = opened_hash_.find(step);
  if (seen != opened_hash_.end() && seen->second == hash) return true;
  opened_hash_[step] = hash;
  while (opened_hash_.size() > 64) opened_hash_.erase(opened_hash_.begin());
  if (step > last_opened_) last_opened_ = step;
  return false;
}

void StepNode::answerRepeat(std::int64_t step) {
  outputs_.republishRecent(step);
  runtime_.countDropped();  // not computed again: counted as a stale input
}

void StepNode::finished(std::uint64_t serial) {
  if (serial < first_serial_ || serial - first_serial_ >= unacked_.size()) return;
  unacked_[static_cast<std::size_t>(serial - first_serial_)].finished = true;
  while (!unacked_.empty() && unacked_.front().finished) {
    const Unacked u = unacked_.front();
    unacked_.pop_front();
    ++first_serial_;
    outputs_.ack(u.utime, u.step);
  }
}

void StepNode::schedule(std::int64_t step, std::int64_t utime, Work work) {
  auto run = [this, step, utime, work = std::move(work)](bool degraded,
                                                         const std::string& missing) {
    Step s;
    s.state_ = std::make_shared<Step::State>();
    s.state_->node = this;
    s.state_->node_alive = alive_;
    s.state_->serial = first_serial_ + unacked_.size();
    if (step >= 0) {
      unacked_.push_back({step, utime, false});
    } else {
      s.state_->finished = true;  // free-running: nobody waits for an ack
    }
    s.state_->step = step;
    s.state_->utime = utime;
    s.state_->degraded = degraded;
    s.state_->missing = missing;
    if (work) work(s);
  };
  gate_.submit(step, std::move(run));
}

}  // namespace coopnav
