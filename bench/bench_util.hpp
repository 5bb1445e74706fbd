#pragma once
// Shared by the benchmarks: percentiles, child processes, and the bare LCM echo every latency
// figure is compared with (the same bytes through the same host stack, no decoding).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

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

}  // namespace coopnav::bench
