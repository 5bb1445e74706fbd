/// @file Benchmark of the world simulator daemon: simulated seconds per wall second of a lockstep
/// run (1) alone, with no participant, and (2) with the band source in the loop (the real
/// coopnav_band_source process when it is built, else this process as its stand-in running the
/// lib DualBandPlanner once per step, said so in the output). Scenario: a 6 m corridor, 30 m long,
/// a robot driving its length and three humans (facilitating head-on, minimal and social force in
/// the side lanes) walking the other way. Runs on its own udpm port. Ends with RESULT lines.

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "maps/map_loader.hpp"
#include "wire/conversions.hpp"

extern char** environ;

namespace {

using namespace coopnav;  // NOLINT
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

const char* kUrl = "udpm://239.255.76.67:7989?ttl=0&recv_buf_size=4194304";

const char* kMap = R"(resolution_m: 0.05
walls:
  - {x0_m: -1, y0_m: 0, x1_m: 31, y1_m: 0, thickness_m: 0.2}
  - {x0_m: -1, y0_m: 6, x1_m: 31, y1_m: 6, thickness_m: 0.2}
  - {x0_m: -1, y0_m: 0, x1_m: -1, y1_m: 6, thickness_m: 0.2}
  - {x0_m: 31, y0_m: 0, x1_m: 31, y1_m: 6, thickness_m: 0.2}
)";

const Pose2 kRobotGoal{28.0, 3.0, 0.0};
/// Goals of humans 1..3 (known, as band_source gets them on COOPNAV_GOALS).
const Pose2 kHumanGoals[3] = {{4.0, 3.0, M_PI}, {4.0, 4.8, M_PI}, {4.0, 1.2, M_PI}};

std::string scenarioText(const std::string& participants) {
  std::string map;
  for (std::size_t a = 0, b; a < std::string(kMap).size(); a = b + 1) {
    b = std::string(kMap).find('\n', a);
    map += "  " + std::string(kMap).substr(a, b - a) + "\n";
  }
  return "name: bench_sim\nseed: 5\ntime_limit_s: 60.0\nmap:\n" + map +
         "rates: {physics_hz: 20, publish_hz: 10}\n"
         "lockstep: {enabled: true, participants: [" +
         participants +
         "], step_timeout_s: 30}\n"
         "robot:\n  start: {x_m: 1.5, y_m: 3.0, theta_rad: 0}\n  goal: {x_m: 28, y_m: 3.0}\n"
         "  limits: {max_forward_m_s: 0.7}\n"
         "humans:\n"
         "  - {id: 1, start: {x_m: 28, y_m: 3.0, theta_rad: 3.14159}, goal: {x_m: 4, y_m: 3.0},"
         " behaviour: facilitating, speed_m_s: 1.0}\n"
         "  - {id: 2, start: {x_m: 29, y_m: 4.8, theta_rad: 3.14159}, goal: {x_m: 4, y_m: 4.8},"
         " behaviour: minimal, speed_m_s: 0.9}\n"
         "  - {id: 3, start: {x_m: 24, y_m: 1.2, theta_rad: 3.14159}, goal: {x_m: 4, y_m: 1.2},"
         " behaviour: social_force, speed_m_s: 1.1, velocity_noise_m_s: 0.05}\n";
}

/// A child process; SIGTERM then SIGKILL on destruction.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (::posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ) != 0) pid_ = -1;
  }
  ~Child() {
    if (pid_ <= 0 || done_) return;
    ::kill(pid_, SIGTERM);
    for (int i = 0; i < 200 && !exited(); ++i) ::usleep(10000);
    if (!done_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool ok() const { return pid_ > 0; }
  bool exited() {
    if (done_) return true;
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) done_ = true;
    return done_;
  }

 private:
  pid_t pid_{-1};
  bool done_{false};
};

/// Watches a run; optionally plays participant "band_source" with an in-process planner.
class Run {
 public:
  explicit Run(std::unique_ptr<DualBandPlanner> planner = nullptr)
      : lcm_(kUrl), planner_(std::move(planner)) {
    auto* s = lcm_.subscribe(channels::kAgentStates, &Run::onStates, this);
    s->setQueueCapacity(0);  // the stand-in must see every step
    lcm_.subscribe(channels::kSimStatus, &Run::onSimStatus, this);
  }
  bool good() { return lcm_.good(); }

  /// Spins until the final SIM_STATUS or `timeout`; true if it came.
  bool spin(std::chrono::seconds timeout, Child& sim) {
    const auto end = Clock::now() + timeout;
    auto next_status = Clock::now();
    while (!final_ && Clock::now() < end) {
      if (planner_ && steps_ == 0 && Clock::now() >= next_status) {
        daemon_status_t st{};
        st.name = "band_source";
        st.pid = static_cast<int32_t>(::getpid());
        st.state = daemon_status_t::STATE_RUNNING;
        st.last_logic_utime = -1;
        lcm_.publish(channels::kStatus, &st);
        next_status = Clock::now() + std::chrono::milliseconds(100);
      }
      lcm_.handleTimeout(10);
      if (sim.exited()) {
        // It published its last messages before exiting: drain them.
        while (!final_ && lcm_.handleTimeout(200) > 0) {
        }
        return final_.has_value();
      }
    }
    return final_.has_value();
  }
  double speedup() const {
    const double wall_s = std::chrono::duration<double>(t_end_ - t_first_).count();
    return utimeToSeconds(final_->utime) / wall_s;
  }
  const sim_status_t& final() const { return *final_; }
  std::int64_t steps() const { return steps_; }
  int planFailures() const { return plan_failures_; }
  double planSeconds() const { return plan_s_; }

 private:
  void onStates(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (steps_++ == 0) t_first_ = Clock::now();
    if (!planner_) return;
    agent_states_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    const AgentStatesSnapshot s = fromLcm(m);
    PlanRequest req;
    req.stamp_s = utimeToSeconds(s.utime);
    req.agent = s.robot;
    req.goal = kRobotGoal;
    for (const AgentState& h : s.humans) {
      OtherAgentInput o;
      o.state = h;
      o.goal = h.id >= 1 && h.id <= 3 ? kHumanGoals[h.id - 1] : Pose2{std::nan(""), 0.0, 0.0};
      req.others.push_back(o);
    }
    const auto t0 = Clock::now();
    const PlanResult r = planner_->plan(req);
    plan_s_ += std::chrono::duration<double>(Clock::now() - t0).count();
    if (r.status != PlanStatus::kOk && r.status != PlanStatus::kGoalReached) ++plan_failures_;
    velocity_command_t c{};
    c.utime = s.utime;
    c.step = s.step;
    c.vx_m_s = r.command_body.vx_m_s;
    c.vy_m_s = r.command_body.vy_m_s;
    c.omega_rad_s = r.command_body.omega_rad_s;
    c.mode = velocity_command_t::MODE_NAVIGATING;
    lcm_.publish(channels::kRobotCmd, &c);
    step_ack_t a{};
    a.utime = s.utime;
    a.step = s.step;
    a.participant = "band_source";
    lcm_.publish(channels::kStepAck, &a);
  }
  void onSimStatus(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    sim_status_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    if (m.state == sim_status_t::STATE_RUNNING) return;
    t_end_ = Clock::now();
    final_ = m;
  }

  lcm::LCM lcm_;
  std::unique_ptr<DualBandPlanner> planner_;
  std::int64_t steps_{0};
  int plan_failures_{0};
  double plan_s_{0.0};
  Clock::time_point t_first_, t_end_;
  std::optional<sim_status_t> final_;
};

const char* stateName(std::int8_t s) {
  static const char* names[] = {"RUNNING",    "GOAL_REACHED",        "COLLISION",
                                "TIME_LIMIT", "PARTICIPANT_TIMEOUT", "ERROR",
                                "STANDSTILL"};
  return s >= 0 && s <= 6 ? names[s] : "?";
}

void report(const char* what, const Run& r) {
  std::printf("%-44s %5lld steps, %6.1f s simulated, end %s (%s), speed-up %.1f x\n", what,
              static_cast<long long>(r.steps()), utimeToSeconds(r.final().utime),
              stateName(r.final().state), r.final().detail.c_str(), r.speedup());
}

std::vector<std::string> simArgs(const std::string& scenario) {
  return {std::string(COOPNAV_BINARY_DIR) + "/daemons/world_sim/coopnav_world_sim",
          "--lcm-url",
          kUrl,
          "--log-level",
          "warn",
          "--set",
          "scenario=" + scenario};
}

}  // namespace

int main() {
  const fs::path dir =
      fs::temp_directory_path() / ("coopnav_bench_sim_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "map.yaml") << kMap;
  std::ofstream(dir / "alone.yaml") << scenarioText("");
  std::ofstream(dir / "with_band_source.yaml") << scenarioText("band_source");
  int rc = 0;

  double alone = std::nan("");
  {
    Run run;
    Child sim(simArgs((dir / "alone.yaml").string()));
    if (!run.good() || !sim.ok() || !run.spin(std::chrono::seconds(300), sim)) {
      std::printf(
          "sim alone: no final SIM_STATUS (is coopnav_world_sim built? multicast route?)\n");
      rc = 1;
    } else {
      report("world_sim alone (lockstep, no participant):", run);
      alone = run.speedup();
    }
  }

  double with_bs = std::nan("");
  const std::string band_source_exe =
      std::string(COOPNAV_BINARY_DIR) + "/daemons/band_source/coopnav_band_source";
  bool measured = false;
  if (fs::exists(band_source_exe)) {
    Run run;
    Child bs({band_source_exe, "--lcm-url", kUrl, "--log-level", "warn", "--set",
              "map_file=" + (dir / "map.yaml").string()});
    Child sim(simArgs((dir / "with_band_source.yaml").string()));
    if (bs.ok() && sim.ok() && run.spin(std::chrono::seconds(600), sim) &&
        run.final().state != sim_status_t::STATE_PARTICIPANT_TIMEOUT) {
      report("world_sim + coopnav_band_source process:", run);
      with_bs = run.speedup();
      measured = true;
    } else {
      std::printf("coopnav_band_source did not complete a run; using the in-process stand-in\n");
    }
  } else {
    std::printf(
        "coopnav_band_source is not built (%s): stand-in = this process as participant "
        "band_source, running the lib DualBandPlanner once per step\n",
        band_source_exe.c_str());
  }
  if (!measured) {
    auto field = std::make_shared<GridDistanceField>(loadMap((dir / "map.yaml").string()).grid);
    Run run(std::make_unique<DualBandPlanner>(BandPlannerConfig{}, field));
    Child sim(simArgs((dir / "with_band_source.yaml").string()));
    if (!sim.ok() || !run.spin(std::chrono::seconds(600), sim)) {
      std::printf("sim with stand-in: no final SIM_STATUS\n");
      rc = 1;
    } else {
      report("world_sim + in-process DualBandPlanner stand-in:", run);
      std::printf("  planner: %.1f ms per step (%.0f %% of the wall time), %d failed cycles\n",
                  1e3 * run.planSeconds() / static_cast<double>(run.steps()),
                  100.0 * run.planSeconds() * run.speedup() / utimeToSeconds(run.final().utime),
                  run.planFailures());
      with_bs = run.speedup();
    }
  }
  fs::remove_all(dir);
  std::printf("RESULT sim_speedup_alone %.2f\n", alone);
  std::printf("RESULT sim_speedup_with_band_source %.2f\n", with_bs);
  return rc;
}
