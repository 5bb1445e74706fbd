// coopnav_ctl: small commands the scripts and users need, in C++ so they start in milliseconds.
//   coopnav_ctl wait-ready NAME... [--timeout-s S] [--announce]  wait for each daemon's status
//   message (--announce: print "listening" once subscribed, so the daemons can start after)
//   coopnav_ctl wait-step NAME --log LOG | --step K [--timeout-s S]  wait until NAME acknowledged
//   LOG's last step (or step K)
//   coopnav_ctl query --nearest X Y | --side X Y NX NY | --ray X Y DX DY ... [--range-m R]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <set>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "ctl_commands.hpp"
#include "distance_client/distance_client.hpp"
#include "logfile/log_reader.hpp"
#include "runtime/log.hpp"
#include "runtime/runtime.hpp"
#include "trace.hpp"

namespace coopnav {
namespace {

int waitReady(const std::string& url, const std::vector<std::string>& names, double timeout_s,
              bool announce) {
  Runtime rt("coopnav_ctl", url);
  std::set<std::string> missing(names.begin(), names.end());
  rt.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.state == daemon_status_t::STATE_RUNNING || s.state == daemon_status_t::STATE_DEGRADED)
      missing.erase(s.name);
  });
  // The socket is joined (Runtime's constructor) and the subscription made: a launcher that
  // starts the daemons after this line hears each one's first status, sent the moment it is
  // ready, instead of the next one a status period later.
  if (announce) std::cout << "listening" << std::endl;
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
  while (!missing.empty() && std::chrono::steady_clock::now() < end) rt.spinFor(20);
  if (!missing.empty()) {
    std::string list;
    for (const auto& m : missing) list += " " + m;
    std::cerr << "coopnav_ctl: no status within " << timeout_s << " s from:" << list << "\n";
    return 1;
  }
  return 0;
}

// A replay is over when the last participant has finished the log's last step: waiting for
// its acknowledgement, not for a quiet period, is what makes it hold on a loaded machine.
// With a step instead of a log: until NAME acknowledged that step (faults.sh kills a daemon when
// the world has reached a chosen step).
int waitStep(const std::string& url, const std::string& name, const std::string& log_path,
             std::int64_t step, double timeout_s) {
  Runtime rt("coopnav_ctl", url);
  std::int64_t acked = -1;
  rt.subscribe<step_ack_t>(channels::kStepAck, [&](const step_ack_t& a, std::int64_t) {
    if (a.participant == name) acked = std::max(acked, a.step);
  });
  std::int64_t last = step;
  if (!log_path.empty()) {
    const ctl::RunLog run = ctl::readRunLog(log_path);
    for (const auto& s : run.agent_states) last = std::max(last, s.step);
  }
  if (last < 0) {
    std::cerr << "coopnav_ctl wait-step: no lockstep agent states in " << log_path << "\n";
    return 1;
  }
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
  while (acked < last && std::chrono::steady_clock::now() < end) rt.spinFor(20);
  if (acked < last) {
    std::cerr << "coopnav_ctl wait-step: " << name << " acknowledged step " << acked
              << ", not the log's last step " << last << ", within " << timeout_s << " s\n";
    return 1;
  }
  return 0;
}

int query(const std::string& url, const std::vector<double>& nearest,
          const std::vector<double>& side, const std::vector<double>& ray, double range_m) {
  std::vector<DistanceQuery> qs;
  for (std::size_t i = 0; i + 1 < nearest.size(); i += 2)
    qs.push_back({DistanceQueryKind::kNearest, {nearest[i], nearest[i + 1]}, {0, 0}, range_m});
  for (std::size_t i = 0; i + 3 < side.size(); i += 4)
    qs.push_back(
        {DistanceQueryKind::kSide, {side[i], side[i + 1]}, {side[i + 2], side[i + 3]}, range_m});
  for (std::size_t i = 0; i + 3 < ray.size(); i += 4)
    qs.push_back(
        {DistanceQueryKind::kRay, {ray[i], ray[i + 1]}, {ray[i + 2], ray[i + 3]}, range_m});
  if (qs.empty()) {
    std::cerr << "coopnav_ctl query: give at least one --nearest, --side or --ray\n";
    return 2;
  }
  DistanceClient::Options o;
  o.timeout = std::chrono::milliseconds(500);
  const auto out = DistanceClient::querySync(url, qs, o);
  if (!out.ok) {
    std::cerr << "coopnav_ctl query: " << out.error << "\n";
    return 1;
  }
  static const char* kinds[] = {"NEAREST", "SIDE", "RAY"};
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const auto& q = qs[i];
    const auto& r = out.results[i];
    std::printf("%-7s p=(%.3f, %.3f) v=(%.3f, %.3f) -> %s d=%.3f m obstacle=(%.3f, %.3f)\n",
                kinds[static_cast<int>(q.kind)], q.point.x(), q.point.y(), q.vector.x(),
                q.vector.y(), toString(r.status), r.distance_m, r.obstacle.x(), r.obstacle.y());
  }
  return 0;
}

}  // namespace
}  // namespace coopnav

int main(int argc, char** argv) {
  CLI::App app{"coopnav command-line tools"};
  app.require_subcommand(1);
  std::string url;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL)");

  auto* wait = app.add_subcommand("wait-ready", "wait until each named daemon reports status");
  std::vector<std::string> names;
  double timeout_s = 30.0;
  wait->add_option("names", names)->required();
  wait->add_option("--timeout-s", timeout_s);
  bool announce = false;
  wait->add_flag("--announce", announce, "print a line once listening (start the daemons then)");

  auto* wait_step = app.add_subcommand(
      "wait-step", "wait until a daemon acknowledged the last lockstep step of a log, or --step");
  std::string step_name, step_log;
  std::int64_t step_number = -1;
  double step_timeout_s = 120.0;
  wait_step->add_option("name", step_name)->required();
  auto* log_opt = wait_step->add_option("--log", step_log)->check(CLI::ExistingFile);
  wait_step->add_option("--step", step_number, "a step number instead of a log's last step")
      ->excludes(log_opt);
  wait_step->add_option("--timeout-s", step_timeout_s);

  auto* q = app.add_subcommand("query", "ask the obstacle distance server and print the answers");
  std::vector<double> nearest, side, ray;
  double range_m = 10.0;
  q->add_option("--nearest", nearest, "X Y (repeatable)")->expected(2)->take_all();
  q->add_option("--side", side, "X Y NX NY (repeatable)")->expected(4)->take_all();
  q->add_option("--ray", ray, "X Y DX DY (repeatable)")->expected(4)->take_all();
  q->add_option("--range-m", range_m);

  coopnav::addCtlCommands(app);
  coopnav::ctl::TraceCommand trace(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; any bad command line 2, as every coopnav program.
    return app.exit(e) == 0 ? 0 : 2;
  }
  coopnav::setLogLevel("warn");
  try {
    if (*wait) return coopnav::waitReady(url, names, timeout_s, announce);
    if (*wait_step) return coopnav::waitStep(url, step_name, step_log, step_number, step_timeout_s);
    if (*q) return coopnav::query(url, nearest, side, ray, range_m);
    if (trace) return trace.run();
    return coopnav::runCtlCommands(app, url);
  } catch (const std::exception& e) {
    std::cerr << "coopnav_ctl: " << e.what() << "\n";
    return 1;
  }
}
