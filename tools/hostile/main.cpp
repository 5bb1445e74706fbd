// coopnav_hostile: the hostile publisher (docs/bad-inputs.md "Hostile publisher").
//
//   coopnav_hostile --list
//   coopnav_hostile --lcm-url URL --probe NAME [--pid PID ...] [--rss-cap-mib N ...]
//   coopnav_hostile --lcm-url URL --watch --pid PID ... [--expect-state S] [--expect-detail TEXT]
//   coopnav_hostile --lcm-url URL --watch --pid PID --await-stopping
//
// --probe sends one attack to the daemon(s) it targets (started by the caller, found by --pid or,
// without it, by name from their status) and checks the documented answer on the bus; then every
// target must still run and send a status, and its resident memory must have stayed under
// --rss-cap-mib all along (one per --pid, or one for all; polled every 50 ms). --watch reads the
// next status of each process; with --await-stopping it prints "ready" once it hears the process,
// then waits for its final STOPPING status (the caller sends the stop signal in between).
// Output: "status ..." and "rss ..." lines per daemon, then "answer: ...", "rss_mib: A/B" (each
// target's peak, in --pid order) and "verdict: ok|FAIL"; exit 0 when ok, 1 when not, 2 on bad
// usage.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "bus.hpp"
#include "probes.hpp"
#include "runtime/log.hpp"

namespace coopnav::hostile {
namespace {

struct Options {
  std::string lcm_url;
  std::string probe;
  bool list{false};
  bool watch{false};
  std::vector<int> pids;
  std::vector<double> rss_caps_mib;
  double timeout_s{10.0};
  std::string expect_state;
  std::string expect_detail;
  bool await_stopping{false};
};

/// Prints every target's status and memory; false (with the reason) if one is gone or over the
/// cap.
bool reportTargets(Bus& bus, const Options& o, std::string* why) {
  bool ok = true;
  std::string rss_list;
  for (std::size_t i = 0; i < bus.watched().size(); ++i) {
    const Watched& w = bus.watched()[i];
    const double cap_mib = o.rss_caps_mib.empty()       ? 0.0
                           : o.rss_caps_mib.size() == 1 ? o.rss_caps_mib.front()
                                                        : o.rss_caps_mib.at(i);
    if (w.status) std::printf("status %s\n", describe(*w.status).c_str());
    const double max_mib = static_cast<double>(w.rss_max_kb) / 1024.0;
    const auto now_kb = rssKb(w.pid);
    std::printf("rss %s pid=%d max_mib=%.1f now_mib=%.1f\n", w.name.c_str(), w.pid, max_mib,
                now_kb ? static_cast<double>(*now_kb) / 1024.0 : -1.0);
    char mib[32];
    std::snprintf(mib, sizeof mib, "%s%.1f", rss_list.empty() ? "" : "/", max_mib);
    rss_list += mib;
    if (!alive(w.pid)) {
      ok = false;
      *why += " " + w.name + " (pid " + std::to_string(w.pid) + ") is gone;";
    }
    if (cap_mib > 0.0 && max_mib > cap_mib) {
      ok = false;
      char buf[160];
      std::snprintf(buf, sizeof buf, " %s RSS %.1f MiB over the cap of %.0f MiB;", w.name.c_str(),
                    max_mib, cap_mib);
      *why += buf;
    }
  }
  std::printf("rss_mib: %s\n", rss_list.c_str());
  return ok;
}

int finish(bool ok, const std::string& answer) {
  std::printf("answer: %s\nverdict: %s\n", answer.c_str(), ok ? "ok" : "FAIL");
  std::fflush(stdout);
  return ok ? 0 : 1;
}

int runProbe(const Options& o) {
  const Probe* p = findProbe(o.probe);
  if (!p) {
    std::fprintf(stderr, "coopnav_hostile: no probe '%s' (--list)\n", o.probe.c_str());
    return 2;
  }
  Bus bus(o.lcm_url, o.pids, std::vector<std::string>(p->daemons.begin(), p->daemons.end()));
  if (!bus.waitReady(o.timeout_s)) {
    std::string why;
    reportTargets(bus, o, &why);
    return finish(false, "no status from every target within " + std::to_string(o.timeout_s) +
                             " s before the attack");
  }
  const Outcome out = p->run(bus);
  bool ok = out.ok;
  std::string why;
  if (p->fresh_status_after) {
    const std::int64_t end_utime = wallUtime();
    for (const auto& w : bus.watched()) {
      if (!bus.statusAfter(w, end_utime, 5.0)) {
        ok = false;
        why += " no status from " + w.name + " within 5 s after the attack;";
      }
    }
  }
  if (!reportTargets(bus, o, &why)) ok = false;
  return finish(ok, out.answer + (why.empty() ? "" : " |" + why));
}

int runWatch(const Options& o) {
  if (o.pids.empty()) {
    std::fprintf(stderr, "coopnav_hostile: --watch needs --pid\n");
    return 2;
  }
  Bus bus(o.lcm_url, o.pids, {});
  if (!bus.waitReady(o.timeout_s)) return finish(false, "no status within the timeout");
  std::string answer;
  bool ok = true;
  if (o.await_stopping) {
    auto& w = bus.watched().front();
    std::printf("ready\n");
    std::fflush(stdout);
    const auto t0 = Clock::now();
    const bool stopping = bus.spinUntil(
        [&] { return w.status && w.status->state == daemon_status_t::STATE_STOPPING; },
        o.timeout_s);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s %.0f ms after ready",
                  stopping ? "final status STOPPING" : "no final status", ms);
    answer = buf;
    ok = stopping;
  } else {
    const std::int64_t now = wallUtime();
    for (auto& w : bus.watched()) {
      const auto s = bus.statusAfter(w, now, o.timeout_s);
      if (!s) {
        ok = false;
        answer += "no fresh status from pid " + std::to_string(w.pid) + "; ";
        continue;
      }
      if (!o.expect_state.empty() && o.expect_state != stateName(s->state)) {
        ok = false;
        answer += w.name + " is " + stateName(s->state) + ", not " + o.expect_state + "; ";
      }
      if (!o.expect_detail.empty() && s->detail.find(o.expect_detail) == std::string::npos) {
        ok = false;
        answer += w.name + " detail does not name \"" + o.expect_detail + "\"; ";
      }
    }
    if (ok) answer = "status as expected";
  }
  std::string why;
  if (!o.await_stopping && !reportTargets(bus, o, &why)) ok = false;
  return finish(ok, answer + why);
}

}  // namespace
}  // namespace coopnav::hostile

int main(int argc, char** argv) {
  coopnav::hostile::Options o;
  CLI::App app{
      "Hostile publisher: sends one attack of docs/bad-inputs.md to running coopnav daemons and "
      "checks their documented answer (test/e2e/hostile_test.sh).",
      "coopnav_hostile"};
  app.add_option("--lcm-url", o.lcm_url, "bus of the daemons under test");
  app.add_flag("--list", o.list, "list the probes, one line each");
  app.add_option("--probe", o.probe, "the probe to run");
  app.add_flag("--watch", o.watch, "read the next status of --pid (no attack)");
  app.add_option("--pid", o.pids, "pid of a target daemon (repeatable; default: by name)");
  app.add_option("--rss-cap-mib", o.rss_caps_mib,
                 "fail if a target's VmRSS passes this [MiB] (one per --pid, or one for all)");
  app.add_option("--timeout-s", o.timeout_s, "wait this long for a first status [s]");
  app.add_option("--expect-state", o.expect_state, "--watch: RUNNING, DEGRADED, ...");
  app.add_option("--expect-detail", o.expect_detail, "--watch: text the status detail holds");
  app.add_flag("--await-stopping", o.await_stopping,
               "--watch: print \"ready\", then wait for the final STOPPING status");
  double flood_s = 2.0;
  app.add_option("--flood-s", flood_s, "how long each flood_* probe floods [s] (default 2)")
      ->check(CLI::Range(0.1, 3600.0));
  CLI11_PARSE(app, argc, argv);
  using namespace coopnav::hostile;
  setFloodSeconds(flood_s);
  if (o.list) {
    for (const auto& p : probes()) {
      std::string targets;
      for (const char* d : p.daemons) targets += (targets.empty() ? "" : ",") + std::string(d);
      std::printf("%-28s %-40s %s -> %s\n", p.name, targets.c_str(), p.attack, p.expected);
    }
    return 0;
  }
  // The tool's own runtime logs a warning per message it cannot decode: not its business here.
  coopnav::setLogLevel("error");
  try {
    if (o.watch) return runWatch(o);
    if (!o.probe.empty()) return runProbe(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "coopnav_hostile: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr, "coopnav_hostile: give --list, --probe NAME or --watch (--help)\n");
  return 2;
}
