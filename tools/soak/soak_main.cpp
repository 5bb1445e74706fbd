// coopnav_soak: the feeder and the monitor of scripts/soak.sh.
//
// Feeder: free-running inputs of an endless corridor encounter at `rate_factor` times the nominal
// rate, time-compressed like world_sim's real-time mode: agent states every 0.1 s of message time
// (10 Hz nominal), published every 0.1 s / rate_factor of wall time, and the goals every second of
// message time. The robot shuttles along the 6 m corridor of open.pgm; every 20 s of message time
// a new human (a new tracker id) walks towards it, steps aside and leaves: the per-human state of
// the daemons comes and goes as on a real robot, so a leak per interaction shows up as growth.
//
// Monitor: every `sample_s` of wall time, each daemon's resident set (VmRSS of /proc/<pid>/status,
// pid from its status message) and its status counters; its lag (message time of the newest
// input fed minus the daemon's last_logic_utime) and its backlog (status field). After the run:
// a table, per-sample CSV, and the verdict: RSS growth after warm-up > max_rss_growth, or a median
// lag or backlog over the last third of the run above the first third's, fails (exit 1).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/goals_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kMessagePeriod_s = 0.1;  // nominal agent-states period (10 Hz)
constexpr double kPass_s = 20.0;          // one robot pass along the corridor [s of message time]
constexpr double kHumanWalk_s = 14.0;     // a human is in the scene this long per pass
constexpr double kCorridorY_m = 6.5;
constexpr double kWestX_m = 6.5;
constexpr double kEastX_m = 20.5;
constexpr double kRobotSpeed_m_s = 0.7;
constexpr double kHumanSpeed_m_s = 1.0;
constexpr std::int64_t kEpoch_us = 1'000'000'000;

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double theta, double vx,
                    double vy, double radius) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = theta;
  a.vx_m_s = vx;
  a.vy_m_s = vy;
  a.radius_m = radius;
  return a;
}

/// The scene at message time t_s (open loop: the inputs do not depend on the daemons' outputs,
/// so a soak run is the same whatever the machine's speed).
struct Scene {
  agent_states_t states;
  goals_t goals;
};

Scene sceneAt(std::int64_t k) {
  const double t_s = static_cast<double>(k) * kMessagePeriod_s;
  const auto pass = static_cast<std::int64_t>(std::floor(t_s / kPass_s));
  const double tau_s = t_s - static_cast<double>(pass) * kPass_s;
  const bool eastward = pass % 2 == 0;
  const double dir = eastward ? 1.0 : -1.0;
  const double robot_start_x = eastward ? kWestX_m : kEastX_m;
  const double robot_goal_x = eastward ? kEastX_m : kWestX_m;
  const double robot_x =
      robot_start_x + dir * std::min(kRobotSpeed_m_s * tau_s, kEastX_m - kWestX_m);
  Scene s;
  s.states.utime = kEpoch_us + k * 100'000;
  s.states.step = -1;
  s.states.robot = agent(0, agent_state_t::KIND_ROBOT, robot_x, kCorridorY_m, eastward ? 0.0 : M_PI,
                         dir * kRobotSpeed_m_s, 0.0, 0.34);
  goal_t rg{};
  rg.agent_id = 0;
  rg.kind = agent_state_t::KIND_ROBOT;
  rg.x_m = robot_goal_x;
  rg.y_m = kCorridorY_m;
  rg.theta_rad = std::numeric_limits<double>::quiet_NaN();
  s.goals.utime = s.states.utime;
  s.goals.goals.push_back(rg);
  if (tau_s < kHumanWalk_s) {
    // Human 1 + pass walks head-on; from 4 s to 8 s it moves 0.6 m aside (to alternating sides).
    const auto id = static_cast<std::int32_t>(1 + pass);
    const double side = pass % 4 < 2 ? 1.0 : -1.0;
    const double shift = 0.6 * std::clamp((tau_s - 4.0) / 4.0, 0.0, 1.0);
    const double vy = (tau_s > 4.0 && tau_s < 8.0) ? side * 0.15 : 0.0;
    const double hx = robot_goal_x - dir * kHumanSpeed_m_s * tau_s;
    s.states.humans.push_back(agent(id, agent_state_t::KIND_HUMAN, hx, kCorridorY_m + side * shift,
                                    eastward ? M_PI : 0.0, -dir * kHumanSpeed_m_s, vy, 0.3));
    goal_t hg{};
    hg.agent_id = id;
    hg.kind = agent_state_t::KIND_HUMAN;
    hg.x_m = robot_start_x;
    hg.y_m = kCorridorY_m;
    hg.theta_rad = std::numeric_limits<double>::quiet_NaN();
    s.goals.goals.push_back(hg);
  }
  s.states.num_humans = static_cast<std::int16_t>(s.states.humans.size());
  s.goals.num_goals = static_cast<std::int16_t>(s.goals.goals.size());
  return s;
}

/// Median of `v`; NaN when empty.
double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// VmRSS of a process [kB]; nullopt when it is gone.
std::optional<long> rssKb(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return std::nullopt;
}

struct Sample {
  double wall_s{0.0};
  long rss_kb{0};
  daemon_status_t status;
  double lag_s{std::numeric_limits<double>::quiet_NaN()};  // [s of message time]
};

struct Options {
  std::string lcm_url;
  std::string side_url;  // a second bus whose daemons are only watched (world_sim)
  double duration_s{600.0};
  double rate_factor{10.0};
  double warmup_s{120.0};
  double sample_s{5.0};
  double max_rss_growth{0.05};
  double max_lag_growth_s{1.0};  // [wall s]
  std::vector<std::string> daemons;
  std::string csv_path;
};

int run(const Options& o) {
  Runtime rt("coopnav_soak", o.lcm_url);
  std::unique_ptr<Runtime> side;
  std::map<std::string, daemon_status_t> latest;
  auto on_status = [&](const daemon_status_t& s, std::int64_t) { latest[s.name] = s; };
  rt.subscribe<daemon_status_t>(channels::kStatus, on_status);
  if (!o.side_url.empty()) {
    side = std::make_unique<Runtime>("coopnav_soak", o.side_url);
    side->subscribe<daemon_status_t>(channels::kStatus, on_status);
  }
  std::map<std::string, std::vector<Sample>> samples;
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(kMessagePeriod_s / o.rate_factor));
  const auto start = Clock::now();
  auto next_msg = start;
  auto next_sample = start + std::chrono::milliseconds(static_cast<long>(o.sample_s * 1000));
  std::int64_t k = 0;
  std::int64_t fed_utime = -1;
  long late_messages = 0;
  while (true) {
    const auto now = Clock::now();
    const double wall_s = std::chrono::duration<double>(now - start).count();
    if (wall_s >= o.duration_s) break;
    if (now >= next_msg) {
      const Scene scene = sceneAt(k);
      if (k % 10 == 0) rt.publish(channels::kGoals, scene.goals);
      rt.publish(channels::kAgentStates, scene.states);
      fed_utime = scene.states.utime;
      ++k;
      next_msg += period;
      // The feeder itself fell behind (a loaded machine): keep the rate, do not burst.
      if (Clock::now() > next_msg + 10 * period) {
        ++late_messages;
        next_msg = Clock::now();
      }
    }
    if (now >= next_sample) {
      next_sample += std::chrono::milliseconds(static_cast<long>(o.sample_s * 1000));
      for (const auto& name : o.daemons) {
        const auto it = latest.find(name);
        if (it == latest.end()) continue;
        Sample s;
        s.wall_s = wall_s;
        s.status = it->second;
        s.rss_kb = rssKb(it->second.pid).value_or(-1);
        if (it->second.last_logic_utime >= kEpoch_us && fed_utime >= 0)
          s.lag_s = static_cast<double>(fed_utime - it->second.last_logic_utime) * 1e-6;
        samples[name].push_back(s);
      }
    }
    const auto wait = std::min(next_msg, next_sample) - Clock::now();
    const int wait_ms =
        static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(wait).count());
    rt.spinFor(std::max(0, wait_ms));
    if (side) side->spinFor(0);
  }
  const double fed_s = std::chrono::duration<double>(Clock::now() - start).count();

  if (!o.csv_path.empty()) {
    std::ofstream csv(o.csv_path);
    csv << "daemon,wall_s,rss_kb,received,dropped,rejected,published,backlog,lag_s\n";
    for (const auto& [name, v] : samples)
      for (const auto& s : v)
        csv << name << ',' << s.wall_s << ',' << s.rss_kb << ',' << s.status.received << ','
            << s.status.dropped << ',' << s.status.rejected << ',' << s.status.published << ','
            << s.status.backlog << ',' << s.lag_s << '\n';
  }

  std::printf("soak: %.0f s at %.1fx (%ld agent-states messages, %.1f/s; feeder late %ld times)\n",
              fed_s, o.rate_factor, static_cast<long>(k), static_cast<double>(k) / fed_s,
              late_messages);
  std::printf("%-26s %9s %9s %8s %9s %10s %8s %8s %9s %9s %8s\n", "daemon", "rss0_kB", "rss1_kB",
              "growth", "rssmax_kB", "recv/s", "dropped", "rejected", "lag0_s", "lag1_s",
              "backlog");
  bool ok = true;
  for (const auto& name : o.daemons) {
    const auto it = samples.find(name);
    if (it == samples.end() || it->second.size() < 2) {
      std::printf("%-26s no status / process seen: FAIL\n", name.c_str());
      ok = false;
      continue;
    }
    const auto& v = it->second;
    // Warm-up: allocator pools, maps and caches fill in the first minutes; compare after it.
    const auto w =
        std::find_if(v.begin(), v.end(), [&](const Sample& s) { return s.wall_s >= o.warmup_s; });
    const Sample& first = w == v.end() ? v.front() : *w;
    const Sample& last = v.back();
    long rss_max = 0;
    const double span_s = last.wall_s - first.wall_s;
    // Lag and backlog are noisy on a loaded machine (one late sample means nothing): a queue that
    // grows shows as a higher median over the last third of the run than over the first.
    std::vector<double> lag_a, lag_b, backlog_a, backlog_b;
    for (const auto& s : v) {
      if (s.wall_s < first.wall_s) continue;
      rss_max = std::max(rss_max, s.rss_kb);
      const bool in_a = s.wall_s <= first.wall_s + span_s / 3.0;
      const bool in_b = s.wall_s >= last.wall_s - span_s / 3.0;
      if (in_a) backlog_a.push_back(s.status.backlog);
      if (in_b) backlog_b.push_back(s.status.backlog);
      if (std::isfinite(s.lag_s) && in_a) lag_a.push_back(s.lag_s);
      if (std::isfinite(s.lag_s) && in_b) lag_b.push_back(s.lag_s);
    }
    const double lag0 = median(lag_a), lag1 = median(lag_b);
    const double backlog0 = median(backlog_a), backlog1 = median(backlog_b);
    const double growth =
        first.rss_kb > 0 ? static_cast<double>(last.rss_kb - first.rss_kb) / first.rss_kb : 0.0;
    const double recv_rate =
        span_s > 0.0 ? static_cast<double>(last.status.received - first.status.received) / span_s
                     : 0.0;
    std::vector<std::string> why;
    if (last.rss_kb <= 0) why.push_back("process gone");
    if (growth > o.max_rss_growth) why.push_back("RSS grew");
    // A lag that keeps growing is a queue that keeps growing (inputs handled later and later).
    // In wall time: at 10x one slow planning cycle under load is already a second of message time.
    if (std::isfinite(lag0) && std::isfinite(lag1) &&
        (lag1 - lag0) / o.rate_factor > o.max_lag_growth_s)
      why.push_back("lag grew");
    if (backlog1 > std::max(2.0 * backlog0, backlog0 + 10.0)) why.push_back("backlog grew");
    std::string verdict = "ok";
    if (!why.empty()) {
      verdict = "FAIL:";
      for (const auto& y : why) verdict += " " + y;
      ok = false;
    }
    std::printf("%-26s %9ld %9ld %7.2f%% %9ld %10.1f %8lld %8lld %9.2f %9.2f %3.0f->%-3.0f %s\n",
                name.c_str(), first.rss_kb, last.rss_kb, 100.0 * growth, rss_max, recv_rate,
                static_cast<long long>(last.status.dropped),
                static_cast<long long>(last.status.rejected), lag0, lag1, backlog0, backlog1,
                verdict.c_str());
  }
  std::printf("soak: %s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace coopnav

int main(int argc, char** argv) {
  coopnav::Options o;
  CLI::App app{
      "Feeds the coopnav daemons free-running inputs at a multiple of the nominal rate "
      "and watches their memory, counters, lag and backlog (scripts/soak.sh).",
      "coopnav_soak"};
  app.add_option("--lcm-url", o.lcm_url, "bus of the pipeline daemons (fed and watched)");
  app.add_option("--side-url", o.side_url, "bus of daemons only watched (world_sim)");
  app.add_option("--duration-s", o.duration_s, "wall seconds to run")->check(CLI::PositiveNumber);
  app.add_option("--rate-factor", o.rate_factor, "multiple of the nominal 10 Hz input rate")
      ->check(CLI::Range(0.1, 100.0));
  app.add_option("--warmup-s", o.warmup_s, "wall seconds before RSS and lag are compared");
  app.add_option("--sample-s", o.sample_s, "wall seconds between samples")
      ->check(CLI::Range(0.5, 600.0));
  app.add_option("--max-rss-growth", o.max_rss_growth, "allowed RSS growth after warm-up (0.05)");
  app.add_option("--max-lag-growth-s", o.max_lag_growth_s,
                 "allowed growth of a daemon's median lag behind the inputs [wall s]");
  app.add_option("--daemon", o.daemons, "name of a daemon to watch (repeatable)")->required();
  app.add_option("--csv", o.csv_path, "write every sample here");
  CLI11_PARSE(app, argc, argv);
  try {
    return coopnav::run(o);
  } catch (const std::exception& e) {
    std::cerr << "coopnav_soak: " << e.what() << "\n";
    return 2;
  }
}
