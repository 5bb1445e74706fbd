#include "runtime/step_gate.hpp"

#include <algorithm>

#include "coopnav/step_ack_t.hpp"
#include "runtime/log.hpp"

namespace coopnav {

StepGate::StepGate(Runtime& runtime, StepGateOptions options)
    : runtime_(runtime), options_(std::move(options)) {
  for (const auto& r : options_.requirements) {
    if (r.offset > 0 || r.offset < -1)
      throw std::invalid_argument("step requirement offset must be 0 or -1 for " + r.participant);
    peers_[r.participant].present = options_.wait_for_unseen && !r.optional_until_seen;
  }
  runtime_.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& ack, std::int64_t) {
    std::map<std::string, int> counts;
    const auto n = std::min(ack.output_channels.size(), ack.output_counts.size());
    // A count the gate would wait for that no participant can publish in one step (negative, or
    // INT32_MAX) holds the step until its timeout, every step it is sent for: refused whole.
    // Every output of a step is per human (at most a few each), so limits.max_ids bounds it.
    const int max_count = runtime_.limits().max_ids;
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t c = ack.output_counts[i];
      if (c < 0 || c > max_count)
        throw RejectedMessage("step ack of " + keptText(ack.participant, 64) + " for step " +
                              std::to_string(ack.step) + " counts " + std::to_string(c) +
                              " messages on " + keptText(ack.output_channels[i], 64) +
                              " (possible: 0 to " + std::to_string(max_count) +
                              ", limits.max_ids)");
      counts[ack.output_channels[i]] = c;
    }
    if (ack.participant == "world_sim" && runtime_.name() != "world_sim")
      runtime_.noteWorldAck(ack.step);
    onAck(ack.participant, ack.step, counts);
  });
  runtime_.addTimer(std::chrono::milliseconds(50),
                    [this] { checkTimeouts(std::chrono::steady_clock::now()); });
}

void StepGate::submit(std::int64_t step, Work work) {
  if (step < 0 && queue_.empty() && holding_ == 0) {
    Pending item{step, std::move(work), std::chrono::steady_clock::now()};
    runItem(item, false, "");
    return;
  }
  queue_.push_back({step, std::move(work), std::chrono::steady_clock::now()});
  if (holding_ == 0) drain();
}

namespace {
/// Steps of counts and received keys kept behind a peer's latest ack (a repeat older than that
/// is of a step long done).
constexpr std::int64_t kKeepSteps = 64;
}  // namespace

void StepGate::prune(Peer& p) {
  const std::int64_t keep_from = p.last_ack - kKeepSteps;
  while (!p.acked_counts.empty() && p.acked_counts.begin()->first < keep_from)
    p.acked_counts.erase(p.acked_counts.begin());
  while (!p.received.empty() && p.received.begin()->first < keep_from)
    p.received.erase(p.received.begin());
}

bool StepGate::noteReceived(const std::string& participant, const std::string& channel,
                            std::int64_t step, const std::string& key) {
  if (step < 0) return true;  // free-running: no repeats to tell apart
  auto it = peers_.find(participant);
  if (it == peers_.end()) return true;
  Peer& p = it->second;
  if (step < p.last_ack - kKeepSteps) return false;  // long done: a late repeat
  // A run advances one step at a time: inputs far ahead of what the peer acknowledged, or of
  // more future steps than a run can have in flight, are no run's (limits.max_pending_steps).
  const std::int64_t max_ahead = runtime_.limits().max_pending_steps;
  if (p.last_ack >= 0 && step > p.last_ack + max_ahead)
    throw RejectedMessage("step " + std::to_string(step) + " of " + participant + " is more than " +
                          std::to_string(max_ahead) + " steps after its last ack " +
                          std::to_string(p.last_ack) + " (limits.max_pending_steps)");
  auto step_it = p.received.find(step);
  if (step_it == p.received.end()) {
    if (static_cast<std::int64_t>(p.received.size()) >= max_ahead + kKeepSteps) {
      // A peer that never acknowledged (a log replay, a peer not started) prunes nothing: its
      // oldest steps go. A peer that acks holds only its in-flight steps here: more is a flood.
      if (p.last_ack >= 0)
        throw RejectedMessage("inputs of " + std::to_string(p.received.size()) + " steps of " +
                              participant + " are held already (limits.max_pending_steps)");
      p.received.erase(p.received.begin());
    }
    step_it = p.received.emplace(step, std::map<std::string, std::set<std::string>>{}).first;
  }
  auto& keys = step_it->second[channel];
  if (keys.count(key)) return false;
  // A step's messages are one per key (human) and channel: the wire bounds the keys.
  if (keys.size() >= 4096) throw RejectedMessage("more than 4096 inputs on " + channel);
  keys.insert(key);
  return true;
}

void StepGate::onAck(const std::string& participant, std::int64_t step,
                     const std::map<std::string, int>& counts) {
  auto it = peers_.find(participant);
  if (it == peers_.end()) return;  // not one we depend on
  Peer& p = it->second;
  if (step >= 0) {
    const InputLimits& limits = runtime_.limits();
    if (!p.ack_steps) p.ack_steps.emplace(limits.max_pending_steps, limits.time_resync_messages);
    switch (p.ack_steps->offer(step)) {
      case JumpGuard::Verdict::kJump:
        throw RejectedMessage("step ack " + std::to_string(step) + " from " + participant +
                              " is more than " + std::to_string(limits.max_pending_steps) +
                              " steps from its acks so far (" + std::to_string(p.last_ack) +
                              ", limits.max_pending_steps)");
      case JumpGuard::Verdict::kResynced:
        log().warn("{}: {} acknowledges steps from {} on (was at {}): a new run", runtime_.name(),
                   participant, step, p.last_ack);
        p.last_ack = step;
        p.acked_counts.clear();
        p.received.clear();
        break;
      case JumpGuard::Verdict::kAccepted:
      case JumpGuard::Verdict::kBackwards:
        break;
    }
  }
  if (step >= 0 && !counts.empty()) p.acked_counts[step] = counts;
  if (step > p.last_ack) {
    p.last_ack = step;
    prune(p);
  }
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
    if (needed < 0 || !p.present) continue;
    std::string what;
    if (p.last_ack < needed) {
      what = r.participant + " (step " + std::to_string(needed) + ")";
    } else if (!r.channels.empty()) {
      // Acknowledged: are all of its messages of that step here? Unknown counts (an older
      // peer, or the ack of a step long gone) cannot be checked and do not hold the step.
      const auto ac = p.acked_counts.find(needed);
      if (ac != p.acked_counts.end()) {
        const auto rc = p.received.find(needed);
        for (const auto& ch : r.channels) {
          const auto want = ac->second.find(ch);
          const int wanted = want == ac->second.end() ? 0 : want->second;
          int got = 0;
          if (rc != p.received.end()) {
            const auto g = rc->second.find(ch);
            if (g != rc->second.end()) got = static_cast<int>(g->second.size());
          }
          if (got < wanted) {
            what += (what.empty() ? "" : ", ") + r.participant + " " + ch + " of step " +
                    std::to_string(needed) + " (" + std::to_string(got) + "/" +
                    std::to_string(wanted) + ")";
          }
        }
      }
    }
    if (what.empty()) continue;
    if (!missing.empty()) missing += ", ";
    missing += what;
  }
  if (condition_) {
    const std::string c = condition_(step);
    if (!c.empty()) missing += (missing.empty() ? "" : ", ") + c;
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
  if (draining_ || holding_ > 0) return;  // work may publish and re-enter through a local ack
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
