#pragma once
/// @file Restart journal (docs/lockstep.md "Loss and restarts"): every message a daemon receives
/// on a journaled channel is appended to `<state_dir>/<name>.journal` before it is handled. A
/// daemon killed (-9) and started again with the same state dir hands the recorded messages to
/// its own handlers, in the recorded order, with publishing muted: its logic runs on message
/// contents and stamps only, so it rebuilds exactly the state it had (its step gates, decisions,
/// recorders, planner memory and cached step outputs), then goes on live. The world simulator
/// re-publishes the step it waits on, and the daemon answers it from its rebuilt cache.
///
/// One journal per run: the launching script gives every run a fresh state dir. A write is one
/// write(2) of a whole record, so a kill leaves at most a cut-off last record, which is ignored.
/// Record: "CNJ1" | u32 channel length | u32 data length | i64 recv_utime | channel | data.
///
/// The journal is capped (limits.journal_max_mib): at the cap it ends with a "full" record and
/// grows no more; the daemon says so (DEGRADED), and a restart from it knows that its state is
/// lost rather than rebuilding a partial one.

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/runtime.hpp"

namespace coopnav {

class Journal {
 public:
  /// Opens (creates) the journal of `runtime.name()` in `state_dir` and reads what it holds.
  /// Throws std::runtime_error when the directory or file cannot be used.
  Journal(Runtime& runtime, const std::string& state_dir);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Replays the records read at open through the runtime's subscriptions, muted, then starts
  /// recording live messages. Returns the number of records replayed (0: a fresh start). When
  /// some were replayed, the runtime is marked restarted-and-recovered.
  std::size_t replayAndRecord();

  const std::string& path() const { return path_; }

 private:
  struct Record {
    std::string channel;
    std::vector<std::uint8_t> data;
    std::int64_t recv_utime{0};
  };
  /// Records one received message, or ends the journal when it would pass the cap.
  void append(const std::string& channel, const void* data, std::size_t size,
              std::int64_t recv_utime);
  void writeRecord(const std::string& channel, const void* data, std::size_t size,
                   std::int64_t recv_utime);

  Runtime& runtime_;
  std::string path_;
  int fd_{-1};
  std::vector<Record> records_;
  bool write_failed_{false};
  bool full_{false};  ///< ends with the "full" record: no replay, no more records
  std::uint64_t size_bytes_{0};
};

}  // namespace coopnav
