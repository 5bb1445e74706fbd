#include "bus.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

namespace coopnav::hostile {

std::int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::optional<long> rssKb(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return std::nullopt;
}

std::optional<double> cpuSeconds(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string all;
  if (!std::getline(f, all)) return std::nullopt;
  // Fields after the command name (in parentheses, which may hold spaces): state is field 3,
  // utime and stime fields 14 and 15 [clock ticks].
  const auto close = all.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream rest(all.substr(close + 2));
  std::string field;
  long utime_ticks = 0, stime_ticks = 0;
  for (int k = 3; k <= 15 && rest >> field; ++k) {
    if (k == 14) utime_ticks = std::stol(field);
    if (k == 15) stime_ticks = std::stol(field);
  }
  return static_cast<double>(utime_ticks + stime_ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

bool alive(int pid) {
  if (pid <= 0 || ::kill(pid, 0) != 0) return false;
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string all;
  std::getline(f, all);
  const auto close = all.rfind(')');
  return close != std::string::npos && close + 2 < all.size() && all[close + 2] != 'Z';
}

Bus::Bus(const std::string& lcm_url, std::vector<int> pids, std::vector<std::string> names)
    : runtime_("coopnav_hostile", lcm_url), by_pid_(!pids.empty()) {
  if (by_pid_) {
    for (const int pid : pids) watched_.push_back(Watched{"", pid, std::nullopt, 0});
  } else {
    for (const auto& n : names) watched_.push_back(Watched{n, 0, std::nullopt, 0});
  }
  runtime_.subscribe<daemon_status_t>(
      channels::kStatus, [this](const daemon_status_t& s, std::int64_t) { onStatus(s); });
}

void Bus::onStatus(const daemon_status_t& s) {
  for (auto& w : watched_) {
    const bool match =
        by_pid_ ? s.pid == w.pid : (s.name == w.name && (w.pid == 0 || s.pid == w.pid));
    if (!match) continue;
    w.pid = s.pid;
    w.name = s.name;
    w.status = s;
  }
}

void Bus::pollMemory() {
  const auto now = Clock::now();
  if (now < next_poll_) return;
  next_poll_ = now + std::chrono::milliseconds(50);
  for (auto& w : watched_) {
    if (w.pid <= 0) continue;
    if (const auto kb = rssKb(w.pid)) w.rss_max_kb = std::max(w.rss_max_kb, *kb);
  }
}

void Bus::setRate(double bytes_per_s) {
  bytes_per_s_ = bytes_per_s;
  rate_start_ = Clock::now();
  rate_bytes_ = 0;
}

void Bus::pace(std::size_t bytes) {
  bytes_ += static_cast<std::int64_t>(bytes);
  rate_bytes_ += static_cast<std::int64_t>(bytes);
  pollMemory();
  if (bytes_per_s_ <= 0.0) {
    runtime_.spinFor(0);
    return;
  }
  const auto due =
      rate_start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                        static_cast<double>(rate_bytes_) / bytes_per_s_));
  // Below a millisecond ahead: go on (the next message catches up); else wait, reading the bus.
  const auto ahead = due - Clock::now();
  if (ahead > std::chrono::milliseconds(1)) {
    spin(static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(ahead).count()));
  } else {
    runtime_.spinFor(0);
  }
}

void Bus::spin(int ms) {
  const auto end = Clock::now() + std::chrono::milliseconds(ms);
  do {
    pollMemory();
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
    runtime_.spinFor(static_cast<int>(std::clamp<long>(left.count(), 0, 20)));
  } while (Clock::now() < end);
}

bool Bus::spinUntil(const std::function<bool()>& done, double timeout_s) {
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(timeout_s));
  while (!done()) {
    if (Clock::now() >= end) return done();
    spin(5);
  }
  return true;
}

bool Bus::waitReady(double timeout_s) {
  return spinUntil(
      [&] {
        return std::all_of(watched_.begin(), watched_.end(),
                           [](const Watched& w) { return w.status.has_value(); });
      },
      timeout_s);
}

std::optional<daemon_status_t> Bus::statusAfter(const Watched& w, std::int64_t after_utime,
                                                double timeout_s) {
  const auto fresh = [&] { return w.status && w.status->utime > after_utime; };
  if (!spinUntil(fresh, timeout_s)) return std::nullopt;
  return w.status;
}

Watched* Bus::find(const std::string& name) {
  for (auto& w : watched_)
    if (w.name == name) return &w;
  return nullptr;
}

const char* stateName(std::int8_t state) {
  switch (state) {
    case daemon_status_t::STATE_STARTING:
      return "STARTING";
    case daemon_status_t::STATE_RUNNING:
      return "RUNNING";
    case daemon_status_t::STATE_DEGRADED:
      return "DEGRADED";
    case daemon_status_t::STATE_STOPPING:
      return "STOPPING";
    default:
      return "UNKNOWN";
  }
}

std::string describe(const daemon_status_t& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%s pid=%d state=%s received=%lld dropped=%lld rejected=%lld published=%lld "
                "backlog=%d",
                s.name.c_str(), s.pid, stateName(s.state), static_cast<long long>(s.received),
                static_cast<long long>(s.dropped), static_cast<long long>(s.rejected),
                static_cast<long long>(s.published), s.backlog);
  std::string detail = s.detail.substr(0, 160);
  for (char& c : detail)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  return std::string(buf) + " detail=\"" + detail + "\"";
}

}  // namespace coopnav::hostile
