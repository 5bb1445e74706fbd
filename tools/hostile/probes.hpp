#pragma once
/// @file The hostile publisher's probes: each sends one attack of docs/bad-inputs.md ("Hostile
/// publisher") to the daemon(s) it targets and checks, on the bus, the documented answer. What
/// only the caller can see (exit codes, stop times, log files) test/e2e/hostile_test.sh checks.

#include <string>
#include <vector>

#include "bus.hpp"

namespace coopnav::hostile {

struct Outcome {
  bool ok{false};
  std::string answer;  ///< what the daemon did, in a few words (or why it is not the documented)
};

struct Probe {
  const char* name;
  std::vector<const char*> daemons;  ///< the daemons it targets (started by the caller)
  const char* attack;                ///< what it sends
  const char* expected;              ///< the documented answer it checks
  /// After the attack every target must send a status within 5 s (it is not hung). Off for the
  /// backlog probes: their point is the stop signal the caller sends while the backlog drains.
  bool fresh_status_after{true};
  Outcome (*run)(Bus& bus);
};

/// Every probe, in the order test/e2e/hostile_test.sh runs them.
const std::vector<Probe>& probes();
const Probe* findProbe(const std::string& name);
/// [s] How long each flood_* probe floods (default 2; --flood-s).
void setFloodSeconds(double s);

}  // namespace coopnav::hostile
