#pragma once
/// @file SIGINT / SIGTERM of the command-line tools (relay, recorder): a flag their poll loops
/// check between timeouts. The daemons use Runtime's signal self-pipe instead; these tools wake
/// every 200 ms anyway, and their shutdown has nothing to interrupt.

#include <csignal>

namespace coopnav::tools {

inline volatile std::sig_atomic_t g_stop_requested = 0;

inline void installStopSignals() {
  struct sigaction sa {};
  sa.sa_handler = [](int) { g_stop_requested = 1; };
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

inline bool stopRequested() { return g_stop_requested != 0; }

}  // namespace coopnav::tools
