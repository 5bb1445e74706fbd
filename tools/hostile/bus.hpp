#pragma once
/// @file The hostile publisher's side of the bus: publishing at a bounded byte rate (a flood that
/// overruns the kernel's socket buffer only measures the buffer), and watching the daemons under
/// test: their status messages, resident memory and CPU time, while any probe runs.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/daemon_status_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav::hostile {

using Clock = std::chrono::steady_clock;

/// Wall-clock time [us since the epoch]: the stamp daemons put in their status messages.
std::int64_t wallUtime();

/// VmRSS of a process [kB] from /proc/<pid>/status; nullopt when it is gone.
std::optional<long> rssKb(int pid);
/// User + system CPU time of a process [s] from /proc/<pid>/stat; nullopt when it is gone.
std::optional<double> cpuSeconds(int pid);
/// The process exists and is no zombie.
bool alive(int pid);

/// One daemon under test: its name and pid (from its status), latest status, memory peak.
struct Watched {
  std::string name;
  int pid{0};
  std::optional<daemon_status_t> status;  ///< latest status of this pid
  long rss_max_kb{0};                     ///< highest VmRSS polled since the watch began
};

class Bus {
 public:
  /// Watches the processes in `pids`; when empty, the first process heard of each of `names`.
  Bus(const std::string& lcm_url, std::vector<int> pids, std::vector<std::string> names);

  Runtime& runtime() { return runtime_; }

  /// Publishes and then, if ahead of `bytes_per_s`, waits (handling messages) to keep the rate.
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    runtime_.publish(channel, msg);
    pace(static_cast<std::size_t>(msg.getEncodedSize()));
  }
  /// Byte rate of publish() [bytes/s]; 0 = as fast as possible.
  void setRate(double bytes_per_s);
  std::int64_t publishedBytes() const { return bytes_; }

  /// Handles messages and polls memory for `ms` of wall time.
  void spin(int ms);
  /// Spins until `done()` or `timeout_s` passed; returns done().
  bool spinUntil(const std::function<bool()>& done, double timeout_s);

  /// Waits until every watched daemon has sent a status (its pid is then known).
  bool waitReady(double timeout_s);
  /// A status of `w` stamped after `after_utime`, waiting up to `timeout_s`.
  std::optional<daemon_status_t> statusAfter(const Watched& w, std::int64_t after_utime,
                                             double timeout_s);

  std::vector<Watched>& watched() { return watched_; }
  /// The watched daemon of this name (nullptr if none).
  Watched* find(const std::string& name);

 private:
  void onStatus(const daemon_status_t& s);
  void pollMemory();
  void pace(std::size_t bytes);

  Runtime runtime_;
  std::vector<Watched> watched_;
  bool by_pid_{false};
  double bytes_per_s_{0.0};
  std::int64_t bytes_{0};
  Clock::time_point rate_start_{Clock::now()};
  std::int64_t rate_bytes_{0};
  Clock::time_point next_poll_{Clock::now()};
};

/// One line of a status for the reports: state, counters, backlog, detail.
std::string describe(const daemon_status_t& s);
/// "RUNNING", "DEGRADED", ... of daemon_status_t::STATE_*.
const char* stateName(std::int8_t state);

}  // namespace coopnav::hostile
