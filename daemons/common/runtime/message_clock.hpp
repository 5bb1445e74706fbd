#pragma once
/// @file The time (or step) a daemon has from its messages, guarded against jumps
/// (docs/bad-inputs.md "Caps").

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace coopnav {

/// A sequence position advanced by messages (a utime, a step number). A value a little behind it
/// is "backwards" (reordered or repeated: the caller drops it); one more than `max_jump` away
/// either way is a discontinuity and does not move it, unless `resync_messages` in a row agree
/// with each other (each at or after the previous, within max_jump of it): then their value is
/// taken. So one message stamped INT64_MAX cannot stop a daemon, and a new run or a restarted
/// simulator that starts again from zero is followed after a few messages.
class JumpGuard {
 public:
  enum class Verdict {
    kAccepted,   ///< the position is now this value (or it was equal)
    kResynced,   ///< taken as the new position after resync_messages agreeing messages
    kBackwards,  ///< behind the position by at most max_jump: drop
    kJump,       ///< more than max_jump away either way and not (yet) agreed on: reject
  };

  JumpGuard(std::int64_t max_jump, int resync_messages);

  /// Offers one message's value; the position moves only on kAccepted / kResynced.
  Verdict offer(std::int64_t value);

  /// The position, if any message was accepted.
  std::optional<std::int64_t> now() const { return now_; }

 private:
  std::int64_t max_jump_;
  int resync_messages_;
  std::optional<std::int64_t> now_;
  std::optional<std::int64_t> candidate_;  ///< the latest off-position value of the current run
  int candidate_count_{0};
};

/// A daemon's logic time, advanced by message utimes, with jumps over `max_jump_s` refused.
class MessageClock : public JumpGuard {
 public:
  MessageClock(double max_jump_s, int resync_messages);

  /// Text for a log line or an exception: "utime U is N s after / before the clock C".
  std::string describe(std::int64_t utime) const;

  /// The one verdict switch of every daemon: offers the utime of a message (`what` names it in
  /// the error). A jump is rejected: throws RejectedMessage "<what>: <describe> (over
  /// limits.max_time_jump_s)", so one message stamped INT64_MAX cannot become the time base. A
  /// resync calls `on_resync` (a new time line: the caller forgets or restamps what it kept on
  /// the old one). Returns true when the message is at or after the clock (or resynced it),
  /// false when it is a little behind it (reordered or repeated: the caller uses or drops it).
  bool take(std::int64_t utime, const std::string& what,
            const std::function<void()>& on_resync = {});
};

}  // namespace coopnav
