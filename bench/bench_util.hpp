#pragma once
// Shared by the benchmarks: percentiles, child processes, and the bare LCM echo every latency
// figure is compared with (the same bytes through the same host stack, no decoding).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/sim_status_t.hpp"

namespace coopnav::bench {

/// Nearest-rank percentile, q in [0, 1]; NaN for no samples.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(i == 0 ? 0 : i - 1, v.size() - 1)];
}

/// Starts args[0] with args; its stderr goes to `log_path` (and stdout away) when given.
inline pid_t spawnProcess(const std::vector<std::string>& args, const std::string& log_path = "") {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!log_path.empty()) {
      if (FILE* f = std::freopen(log_path.c_str(), "w", stderr)) (void)f;
      if (FILE* f = std::freopen("/dev/null", "w", stdout)) (void)f;
    }
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

/// Forks a bare echo on `url`: whatever arrives on `request` is republished on `reply`.
inline pid_t startEcho(const std::string& url, const std::string& request,
                       const std::string& reply) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    lcm::LCM l(url);
    struct Echo {
      lcm::LCM* l;
      std::string reply;
      void onMessage(const lcm::ReceiveBuffer* rb, const std::string&) {
        l->publish(reply, rb->data, rb->data_size);
      }
    } e{&l, reply};
    l.subscribe(request, &Echo::onMessage, &e);
    while (true) l.handleTimeout(1000);
  }
  return pid;
}

/// The daemons of one run on `url` for `scenario` (distance server, band source, both assessors,
/// dialogue manager; the configs of config/), each logging to `log_prefix`_<daemon>.log. Returns
/// (daemon, pid) in start order.
inline std::vector<std::pair<std::string, pid_t>> startDaemons(const std::string& build_dir,
                                                               const std::string& source_dir,
                                                               const std::string& url,
                                                               const std::string& scenario,
                                                               const std::string& log_prefix) {
  const std::string cfg = source_dir + "/config/";
  auto exe = [&](const std::string& d) { return build_dir + "/daemons/" + d + "/coopnav_" + d; };
  std::vector<std::pair<std::string, pid_t>> out;
  for (const char* d : {"obstacle_distance_server", "band_source", "situation_assessor",
                        "path_assessor", "dialogue_manager"}) {
    std::vector<std::string> args{exe(d), "-c", cfg + d + ".yaml", "--lcm-url", url};
    if (std::string(d) == "obstacle_distance_server" || std::string(d) == "band_source")
      args.insert(args.end(), {"--set", "map_file=" + scenario});
    out.emplace_back(d, spawnProcess(args, log_prefix + "_" + d + ".log"));
  }
  return out;
}

/// What every whole-system benchmark watches on the bus: which daemons reported status (ready),
/// and the simulator's end (its final state and simulated time). Derived observers add their own
/// channels; subscribe these two with watchRun.
struct RunObserver {
  std::map<std::string, bool> ready;
  bool done{false};
  double sim_end_s{0.0};
  int final_state{-1};
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const coopnav::daemon_status_t* m) {
    ready[m->name] = true;
  }
  void onSim(const lcm::ReceiveBuffer*, const std::string&, const coopnav::sim_status_t* m) {
    if (m->state != coopnav::sim_status_t::STATE_RUNNING) {
      done = true;
      final_state = m->state;
      sim_end_s = static_cast<double>(m->utime) * 1e-6;
    }
  }
};
inline void watchRun(lcm::LCM& lcm, RunObserver& obs) {
  lcm.subscribe(coopnav::channels::kStatus, &RunObserver::onStatus, &obs);
  lcm.subscribe(coopnav::channels::kSimStatus, &RunObserver::onSim, &obs);
}

/// CPU time (user + system) a live process has used so far [s]; NaN when it cannot be read.
inline double cpuSeconds(pid_t pid) {
  FILE* f = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
  if (!f) return std::nan("");
  char buf[4096];
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = '\0';
  // Fields after the command name (in parentheses, which may hold spaces): utime is the 14th
  // field of the line, the 12th after the closing parenthesis.
  const char* p = std::strrchr(buf, ')');
  if (!p) return std::nan("");
  unsigned long long utime = 0, stime = 0;
  if (std::sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &utime, &stime) !=
      2)
    return std::nan("");
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

}  // namespace coopnav::bench
