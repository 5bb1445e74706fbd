// coopnav_ctl's bus operations (command.hpp): what the launchers ask of a running system.
//   wait-ready NAME... [--timeout-s S] [--announce]      each daemon's first status message
//     (--announce: print "listening" once subscribed, so that the daemons can be started after)
//   wait-step NAME --log LOG | --step K [--timeout-s S]  NAME acknowledged LOG's last step (or K)
//   query --nearest X Y | --side X Y NX NY | --ray X Y DX DY ... [--range-m R]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <set>

#include "command.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "distance_client/distance_client.hpp"
#include "logfile/log_reader.hpp"
#include "runtime/runtime.hpp"

namespace coopnav::ctl {
namespace {

std::chrono::steady_clock::time_point deadlineAfter(double timeout_s) {
  return std::chrono::steady_clock::now() +
         std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
}

class WaitReadyCommand final : public Command {
 public:
  explicit WaitReadyCommand(CLI::App& sub) {
    sub.add_option("names", names_)->required();
    sub.add_option("--timeout-s", timeout_s_);
    sub.add_flag("--announce", announce_, "print a line once listening (start the daemons then)");
  }

  int run(const std::string& url) override {
    Runtime rt("coopnav_ctl", url);
    std::set<std::string> missing(names_.begin(), names_.end());
    rt.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
      if (s.state == daemon_status_t::STATE_RUNNING || s.state == daemon_status_t::STATE_DEGRADED)
        missing.erase(s.name);
    });
    // The socket is joined (Runtime's constructor) and the subscription made: a launcher that
    // starts the daemons after this line hears each one's first status, sent the moment it is
    // ready, instead of the next one a status period later.
    if (announce_) std::cout << "listening" << std::endl;
    const auto end = deadlineAfter(timeout_s_);
    while (!missing.empty() && std::chrono::steady_clock::now() < end) rt.spinFor(20);
    if (!missing.empty()) {
      std::string list;
      for (const auto& m : missing) list += " " + m;
      std::cerr << "coopnav_ctl: no status within " << timeout_s_ << " s from:" << list << "\n";
      return 1;
    }
    return 0;
  }

 private:
  std::vector<std::string> names_;
  double timeout_s_{30.0};
  bool announce_{false};
};

// A replay is over when the last participant has finished the log's last step: waiting for
// its acknowledgement, not for a quiet period, is what makes it hold on a loaded machine.
// With a step instead of a log: until NAME acknowledged that step (a fault run kills a daemon
// when the world has reached a chosen step).
class WaitStepCommand final : public Command {
 public:
  explicit WaitStepCommand(CLI::App& sub) {
    sub.add_option("name", name_)->required();
    auto* log_opt = sub.add_option("--log", log_)->check(CLI::ExistingFile);
    sub.add_option("--step", step_, "a step number instead of a log's last step")
        ->excludes(log_opt);
    sub.add_option("--timeout-s", timeout_s_);
  }

  int run(const std::string& url) override {
    Runtime rt("coopnav_ctl", url);
    std::int64_t acked = -1;
    rt.subscribe<step_ack_t>(channels::kStepAck, [&](const step_ack_t& a, std::int64_t) {
      if (a.participant == name_) acked = std::max(acked, a.step);
    });
    std::int64_t last = step_;
    if (!log_.empty()) {
      const RunLog run = readRunLog(log_);
      for (const auto& s : run.agent_states) last = std::max(last, s.step);
    }
    if (last < 0) {
      std::cerr << "coopnav_ctl wait-step: no lockstep agent states in " << log_ << "\n";
      return 1;
    }
    const auto end = deadlineAfter(timeout_s_);
    while (acked < last && std::chrono::steady_clock::now() < end) rt.spinFor(20);
    if (acked < last) {
      std::cerr << "coopnav_ctl wait-step: " << name_ << " acknowledged step " << acked
                << ", not the log's last step " << last << ", within " << timeout_s_ << " s\n";
      return 1;
    }
    return 0;
  }

 private:
  std::string name_;
  std::string log_;
  std::int64_t step_{-1};
  double timeout_s_{120.0};
};

class QueryCommand final : public Command {
 public:
  explicit QueryCommand(CLI::App& sub) {
    sub.add_option("--nearest", nearest_, "X Y (repeatable)")->expected(2)->take_all();
    sub.add_option("--side", side_, "X Y NX NY (repeatable)")->expected(4)->take_all();
    sub.add_option("--ray", ray_, "X Y DX DY (repeatable)")->expected(4)->take_all();
    sub.add_option("--range-m", range_m_);
  }

  int run(const std::string& url) override {
    std::vector<DistanceQuery> qs;
    for (std::size_t i = 0; i + 1 < nearest_.size(); i += 2)
      qs.push_back({DistanceQueryKind::kNearest, {nearest_[i], nearest_[i + 1]}, {0, 0}, range_m_});
    for (std::size_t i = 0; i + 3 < side_.size(); i += 4)
      qs.push_back({DistanceQueryKind::kSide,
                    {side_[i], side_[i + 1]},
                    {side_[i + 2], side_[i + 3]},
                    range_m_});
    for (std::size_t i = 0; i + 3 < ray_.size(); i += 4)
      qs.push_back(
          {DistanceQueryKind::kRay, {ray_[i], ray_[i + 1]}, {ray_[i + 2], ray_[i + 3]}, range_m_});
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

 private:
  std::vector<double> nearest_, side_, ray_;
  double range_m_{10.0};
};

}  // namespace

void addBusCommands(CLI::App& app, CommandTable& table) {
  addCommand<WaitReadyCommand>(app, table, "wait-ready",
                               "wait until each named daemon reports status");
  addCommand<WaitStepCommand>(
      app, table, "wait-step",
      "wait until a daemon acknowledged the last lockstep step of a log, or --step");
  addCommand<QueryCommand>(app, table, "query",
                           "ask the obstacle distance server and print the answers");
}

}  // namespace coopnav::ctl
