#include "runtime/message_clock.hpp"

#include <cmath>

#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

// a - b without overflow (values span all of int64): as a double, exact enough for a comparison
// with a jump limit far below 2^53.
double gap(std::int64_t a, std::int64_t b) {
  return static_cast<double>(a) - static_cast<double>(b);
}

}  // namespace

JumpGuard::JumpGuard(std::int64_t max_jump, int resync_messages)
    : max_jump_(max_jump < 0 ? 0 : max_jump),
      resync_messages_(resync_messages < 1 ? 1 : resync_messages) {}

JumpGuard::Verdict JumpGuard::offer(std::int64_t value) {
  if (!now_) {
    now_ = value;
    return Verdict::kAccepted;
  }
  const double limit = static_cast<double>(max_jump_);
  if (std::fabs(gap(value, *now_)) <= limit) {
    candidate_.reset();
    candidate_count_ = 0;
    if (value < *now_) return Verdict::kBackwards;
    now_ = value;
    return Verdict::kAccepted;
  }
  // Off the position: does it continue the run of off-position values?
  const bool continues = candidate_ && value >= *candidate_ && gap(value, *candidate_) <= limit;
  candidate_count_ = continues ? candidate_count_ + 1 : 1;
  candidate_ = value;
  if (candidate_count_ >= resync_messages_) {
    now_ = value;
    candidate_.reset();
    candidate_count_ = 0;
    return Verdict::kResynced;
  }
  return Verdict::kJump;
}

MessageClock::MessageClock(double max_jump_s, int resync_messages)
    : JumpGuard(static_cast<std::int64_t>(std::llround(max_jump_s * 1e6)), resync_messages) {}

std::string MessageClock::describe(std::int64_t utime) const {
  if (!now()) return "utime " + std::to_string(utime) + " (no clock yet)";
  const double gap_s = gap(utime, *now()) * 1e-6;
  return "utime " + std::to_string(utime) + " is " + std::to_string(std::fabs(gap_s)) + " s " +
         (gap_s >= 0.0 ? "after" : "before") + " the clock " + std::to_string(*now());
}

bool MessageClock::take(std::int64_t utime, const std::string& what,
                        const std::function<void()>& on_resync) {
  switch (offer(utime)) {
    case Verdict::kJump:
      throw RejectedMessage(what + ": " + describe(utime) + " (over limits.max_time_jump_s)");
    case Verdict::kResynced:
      if (on_resync) on_resync();
      return true;
    case Verdict::kBackwards:
      return false;
    case Verdict::kAccepted:
      return true;
  }
  return true;
}

}  // namespace coopnav
