#pragma once
/// @file The caps every daemon puts on what a bus peer can make it hold or do: one struct, read
/// under the key `limits` of every daemon's config, its in-class values the only defaults. The
/// table of these keys, their defaults and what each bounds is in docs/bad-inputs.md ("Caps").
///
/// Why caps at all: a peer on the bus is not trusted to be well-behaved (a broken tracker, a
/// stale log replayed into a live run, a hostile publisher). Every message's work and every
/// piece of state a message can create is bounded here, so that a daemon's memory and time stay
/// within what the robot's computer has whatever it is sent.

#include <cstddef>
#include <cstdint>
#include <string>

#include "config/config.hpp"

namespace coopnav {

struct InputLimits {
  /// [s] A message stamped more than this after the time the daemon has from earlier messages is
  /// rejected and does not move that time (a clock pinned at INT64_MAX would drop everything
  /// after it). 60 s: far beyond any pause of a live run or a lockstep step (0.1 s).
  double max_time_jump_s{60.0};
  /// Consecutive messages that agree with each other but not with the daemon's time (a jump
  /// over max_time_jump_s either way) after which the daemon takes their time as its own: a new
  /// run, a restarted simulator, or a clock that one bad message had set.
  int time_resync_messages{3};
  /// Per-id state (humans, reference paths, dialogue threads) kept at most for this many ids;
  /// beyond it the least recently heard id is forgotten first. 256 = 4x the wire's 64 humans.
  int max_ids{256};
  /// [s] Per-id state not refreshed for this long (message time) is forgotten.
  double forget_after_s{60.0};
  /// Lockstep steps ahead of the last completed one that a step gate keeps inputs for; a
  /// message for a step further ahead is rejected (a run advances one step at a time).
  int max_pending_steps{256};
  /// [bytes] Longest text from a message (a reason, a name) a daemon keeps or logs; longer text
  /// is cut with "...". Logged text is escaped (control characters as \xNN) in any case.
  int max_text_bytes{1024};
  std::size_t maxTextBytes() const { return static_cast<std::size_t>(max_text_bytes); }
  /// Log lines per second one line's pattern (its text with digits removed) may write; the rest
  /// are counted and reported once a second as "suppressed N lines like: ...".
  int log_lines_per_s{20};
  /// [MiB] Restart journal (--state-dir) size beyond which the journal stops growing: the daemon
  /// says so (DEGRADED) and a restart after that point loses its state, never the disk.
  int journal_max_mib{256};
  /// Messages one subscription keeps waiting while the daemon is busy with earlier ones; beyond
  /// it the oldest waiting message of that channel is dropped, counted in `dropped` and named in
  /// a log line once a second (runtime.hpp). The oldest: on a state channel a newer message
  /// supersedes it, a lockstep step it held is re-published by the world (docs/lockstep.md
  /// "Loss and restarts"), and a request's client has most likely given up on it. A subscription
  /// may ask for fewer (Runtime::subscribe's queue_capacity).
  int queue_messages{256};
  /// [MiB] Bytes one subscription keeps waiting, with the same oldest-first drop; one message of
  /// any size is always kept (a channel's largest valid message must get through).
  int queue_mib{4};
  std::size_t queueBytes() const { return static_cast<std::size_t>(queue_mib) << 20U; }

  template <class V>
  void visit(V& v) {
    v("max_time_jump_s", max_time_jump_s, Range{0.001, 1e6});
    v("time_resync_messages", time_resync_messages, Range{2, 1000});
    v("max_ids", max_ids, Range{1, 100000});
    v("forget_after_s", forget_after_s, Range{0.1, 1e6});
    v("max_pending_steps", max_pending_steps, Range{1, 100000});
    v("max_text_bytes", max_text_bytes, Range{16, 1 << 20});
    v("log_lines_per_s", log_lines_per_s, Range{1, 100000});
    v("journal_max_mib", journal_max_mib, Range{1, 1 << 20});
    v("queue_messages", queue_messages, Range{1, 1000000});
    v("queue_mib", queue_mib, Range{1, 4096});
  }
};

/// `text` from a message cut to at most `max_bytes` bytes ("..." included) at a UTF-8 character
/// boundary: what a daemon keeps or publishes on of a peer's text (limits.max_text_bytes).
inline std::string keptText(std::string text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  static constexpr char kEllipsis[] = "...";
  std::size_t n = max_bytes >= sizeof kEllipsis - 1 ? max_bytes - (sizeof kEllipsis - 1) : 0;
  while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0u) == 0x80u) --n;  // continuation
  text.resize(n);
  return text + kEllipsis;
}

}  // namespace coopnav
