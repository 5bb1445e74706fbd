#include "common/step_gate.hpp"

#include "common/log.hpp"
#include "coopnav/step_ack_t.hpp"

namespace coopnav {

StepGate::StepGate(Runtime& runtime, StepGateOptions options)
    : runtime_(runtime), options_(std::move(options)) {
  for (const auto& r : options_.requirements) {
    if (r.offset > 0 || r.offset < -1)
      throw std::invalid_argument("step requirement offset must be 0 or -1 for " + r.participant);
    peers_[r.participant].present = options_.wait_for_unseen;
  }
  runtime_.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& ack, std::int64_t) {
    onAck(ack.participant, ack.step);
  });
  runtime_.addTimer(std::chrono::milliseconds(50),
                    [this] { checkTimeouts(std::chrono::steady_clock::now()); });
}

void StepGate::submit(std::int64_t step, Work work) {
  if (step < 0 && queue_.empty()) {
    Pending item{step, std::move(work), std::chrono::steady_clock::now()};
    runItem(item, false, "");
    return;
  }
  queue_.push_back({step, std::move(work), std::chrono::steady_clock::now()});
  drain();
}

void StepGate::onAck(const std::string& participant, std::int64_t step) {
  auto it = peers_.find(participant);
  if (it == peers_.end()) return;  // not one we depend on
  Peer& p = it->second;
  if (step > p.last_ack) p.last_ack = step;
  if (!p.present) {
    p.present = true;
    log().info("{}: {} acknowledges steps (now at {})", runtime_.name(), participant, step);
  }
  drain();
}

std::int64_t StepGate::lastAck(const std::string& participant) const {
  auto it = peers_.find(participant);
  return it == peers_.end() ? -1 : it->second.last_ack;
}

std::string StepGate::missingFor(std::int64_t step) const {
  if (step < 0) return "";
  std::string missing;
  for (const auto& r : options_.requirements) {
    const Peer& p = peers_.at(r.participant);
    const std::int64_t needed = step + r.offset;
    if (needed < 0 || !p.present || p.last_ack >= needed) continue;
    if (!missing.empty()) missing += ", ";
    missing += r.participant + " (step " + std::to_string(needed) + ")";
  }
  return missing;
}

void StepGate::runItem(Pending& item, bool degraded, const std::string& missing) {
  // Queued work runs outside the handler that submitted it: an exception must neither escape
  // into an unrelated handler nor leave draining_ set (that would stall the gate for good).
  try {
    item.work(degraded, missing);
  } catch (const std::exception& e) {
    runtime_.countRejected();
    log().error("{}: work of step {} failed: {}", runtime_.name(), item.step, e.what());
  }
}

void StepGate::drain() {
  if (draining_) return;  // work may publish and re-enter through a local ack
  draining_ = true;
  while (!queue_.empty() && missingFor(queue_.front().step).empty()) {
    Pending item = std::move(queue_.front());
    queue_.pop_front();
    runItem(item, false, "");
  }
  draining_ = false;
}

void StepGate::checkTimeouts(std::chrono::steady_clock::time_point now) {
  if (queue_.empty() || draining_) return;
  Pending& head = queue_.front();
  if (now - head.since < options_.timeout) return;
  const std::string missing = missingFor(head.step);
  if (missing.empty()) {
    drain();
    return;
  }
  log().warn("{}: step {} waited {} ms for {}; running degraded and no longer waiting for them",
             runtime_.name(), head.step, options_.timeout.count(), missing);
  for (const auto& r : options_.requirements) {
    Peer& p = peers_.at(r.participant);
    const std::int64_t needed = head.step + r.offset;
    if (needed >= 0 && p.present && p.last_ack < needed) p.present = false;
  }
  Pending item = std::move(head);
  queue_.pop_front();
  draining_ = true;
  runItem(item, true, missing);
  draining_ = false;
  // Later items were queued behind it; the absent peers no longer hold them back.
  for (auto& q : queue_) q.since = now;
  drain();
}

}  // namespace coopnav
