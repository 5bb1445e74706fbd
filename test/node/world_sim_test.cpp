// The world_sim daemon as a process on this executable's own udpm port. The test plays the one
// lockstep participant of the scenario ("fake_planner"): it reports a status, then answers each
// step's agent states with a velocity command and an acknowledgement, as band_source would.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;
using test::ChildProcess;
using test::daemonPath;
using test::testLcmUrl;

constexpr const char* kParticipant = "fake_planner";

/// A file of test/data/scenarios, or an absolute path as it is.
std::string scenarioPath(const std::string& name) {
  if (!name.empty() && name.front() == '/') return name;
  return ::coopnav::test::testDataDir() + "/scenarios/" + name;
}

/// A scenario of a straight corridor, free for y in (0, width_m), x in (-1, 25), written to a
/// file of its own; the robot and its one human as YAML flow mappings, the rest as given.
class CorridorScenario {
 public:
  CorridorScenario(const std::string& name, double width_m, const std::string& robot,
                   const std::string& human, const std::string& extra = "") {
    path_ = (std::filesystem::temp_directory_path() /
             ("coopnav_world_sim_" + std::to_string(::getpid()) + "_" + name + ".yaml"))
                .string();
    std::ofstream out(path_);
    out << "name: " << name << "\nseed: 1\ntime_limit_s: 40.0\n"
        << extra << "map:\n  resolution_m: 0.05\n  walls:\n"
        << "    - {x0_m: -1, y0_m: -0.1, x1_m: 25, y1_m: -0.1}\n"
        << "    - {x0_m: -1, y0_m: " << width_m + 0.1 << ", x1_m: 25, y1_m: " << width_m + 0.1
        << "}\n"
        << "lockstep: {enabled: true, participants: [fake_planner], step_timeout_s: 5.0}\n"
        << "robot: " << robot << "\nhumans:\n  - " << human << "\n";
  }
  ~CorridorScenario() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Listens to what world_sim publishes and plays its participant.
class Harness {
 public:
  Harness() : lcm_(testLcmUrl()) {
    EXPECT_TRUE(lcm_.good());
    listen<&Harness::onStates>(channels::kAgentStates);
    listen<&Harness::onSimStatus>(channels::kSimStatus);
    listen<&Harness::onStatus>(channels::kStatus);
    listen<&Harness::onGoals>(channels::kGoals);
  }

  /// Through LCM's subscribeFunction, not its member-function overload, which GCC 12's UBSan
  /// reports at every message (a compiler bug; Runtime::Subscription in runtime/runtime.hpp).
  template <void (Harness::*Method)(const lcm::ReceiveBuffer*, const std::string&)>
  void listen(const std::string& channel) {
    lcm_.subscribeFunction(
        channel,
        +[](const lcm::ReceiveBuffer* rbuf, const std::string& chan, Harness* self) {
          (self->*Method)(rbuf, chan);
        },
        this);
  }

  void spin(std::chrono::milliseconds d) {
    const auto end = std::chrono::steady_clock::now() + d;
    while (std::chrono::steady_clock::now() < end) lcm_.handleTimeout(2);
  }
  bool spinUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    return test::waitFor(pred, timeout, [this] { lcm_.handleTimeout(2); });
  }

  void sendStatus(const std::string& name, const std::string& detail = "") {
    daemon_status_t s{};
    s.detail = detail;
    s.utime = 0;
    s.name = name;
    s.pid = 1;
    s.state = daemon_status_t::STATE_RUNNING;
    s.last_logic_utime = -1;
    s.cycle_p50_ms = s.cycle_max_ms = 0.0;
    lcm_.publish(channels::kStatus, &s);
  }
  void sendCommand(std::int64_t step, std::int64_t utime, double vx, double omega) {
    velocity_command_t c{};
    c.utime = utime;
    c.step = step;
    c.vx_m_s = vx;
    c.vy_m_s = 0.0;
    c.omega_rad_s = omega;
    c.mode = velocity_command_t::MODE_NAVIGATING;
    lcm_.publish(channels::kRobotCmd, &c);
  }
  void sendAck(std::int64_t step, std::int64_t utime) {
    step_ack_t a{};
    a.utime = utime;
    a.step = step;
    a.participant = kParticipant;
    lcm_.publish(channels::kStepAck, &a);
  }
  /// "Could you move aside?", said at once, lasting `duration_s` (or decided and not said).
  void sendAskToMove(std::int64_t step, std::int64_t utime, std::int32_t human_id, std::int8_t dir,
                     double duration_s = 0.0, std::int8_t delivery = utterance_t::DELIVERY_SAID) {
    utterance_t u{};
    u.utime = utime;
    u.step = step;
    u.human_id = human_id;
    u.speech_act = utterance_t::ACT_ASK_TO_MOVE;
    u.direction = dir;
    u.round = 1;
    u.t_cross_s = 5.0;
    u.text = "Could you move aside?";
    u.delivery = delivery;
    u.speech_start_s = 0.0;
    u.speech_duration_s = duration_s;
    lcm_.publish(channels::kUtterance, &u);
  }

  bool worldSimReady() const { return world_sim_status_ > 0; }
  const std::vector<agent_states_t>& states() const { return states_; }
  const std::vector<std::string>& stateBytes() const { return state_bytes_; }
  const std::vector<sim_status_t>& simStatus() const { return sim_status_; }
  std::size_t goals() const { return goals_; }
  const std::vector<goals_t>& goalMessages() const { return goal_msgs_; }
  std::size_t repeats() const { return repeats_; }
  /// The final SIM_STATUS, or nullptr while the run goes on.
  const sim_status_t* final() const {
    for (const auto& s : sim_status_)
      if (s.state != sim_status_t::STATE_RUNNING) return &s;
    return nullptr;
  }

 private:
  void onStates(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    agent_states_t m;
    ASSERT_EQ(m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)),
              static_cast<int>(rbuf->data_size));
    std::string bytes(static_cast<const char*>(rbuf->data), rbuf->data_size);
    // A step published again (its acks overdue) is the same bytes: kept once, counted.
    if (std::find(state_bytes_.begin(), state_bytes_.end(), bytes) != state_bytes_.end()) {
      ++repeats_;
      return;
    }
    states_.push_back(m);
    state_bytes_.push_back(std::move(bytes));
  }
  void onSimStatus(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    sim_status_t m;
    ASSERT_GT(m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)), 0);
    sim_status_.push_back(m);
  }
  void onStatus(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    daemon_status_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0 && m.name == "world_sim") {
      ++world_sim_status_;
      world_sim_rejected_ = std::max(world_sim_rejected_, m.rejected);
      world_sim_dropped_ = std::max(world_sim_dropped_, m.dropped);
    }
  }
  void onGoals(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    ++goals_;
    goals_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) goal_msgs_.push_back(m);
  }

  lcm::LCM lcm_;
  std::vector<agent_states_t> states_;
  std::vector<std::string> state_bytes_;
  std::vector<sim_status_t> sim_status_;
  int world_sim_status_{0};

 public:
  std::int64_t world_sim_rejected_{0};  ///< world_sim's counters, the highest reported
  std::int64_t world_sim_dropped_{0};

 private:
  std::size_t goals_{0};
  std::vector<goals_t> goal_msgs_;
  std::size_t repeats_{0};
};

std::vector<std::string> daemonArgs(const std::string& scenario,
                                    const std::vector<std::string>& extra = {}) {
  std::vector<std::string> a = {"--lcm-url", testLcmUrl(), "--log-level",
                                "warn",      "--set",      "scenario=" + scenarioPath(scenario)};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

struct Participant {
  /// Command for step k (body frame vx, omega).
  std::function<std::pair<double, double>(std::int64_t)> command = [](std::int64_t) {
    return std::make_pair(0.5, 0.0);
  };
  /// Called before the command of step k is sent (e.g. to send utterances).
  std::function<void(Harness&, const agent_states_t&)> before_command;
  /// Steps at which the participant waits before acknowledging, checking nothing advances.
  std::vector<std::int64_t> hold_at_steps;
  bool ack{true};
};

struct RunOutcome {
  int exit_code{-1};
  bool advanced_without_ack{false};
};

/// Runs world_sim on `scenario` with the test as its participant until the final SIM_STATUS.
RunOutcome runWithParticipant(Harness& h, const std::string& scenario, const Participant& p,
                              const std::vector<std::string>& extra = {}) {
  RunOutcome out;
  ChildProcess sim(daemonPath("world_sim"), daemonArgs(scenario, extra));
  EXPECT_TRUE(h.spinUntil([&] { return h.worldSimReady(); }, 10s)) << "world_sim never started";
  // Report until step 0 arrives: a status sent before world_sim subscribed is lost.
  EXPECT_TRUE(h.spinUntil(
      [&] {
        if (!h.states().empty()) return true;
        h.sendStatus(kParticipant);
        h.spin(50ms);
        return !h.states().empty();
      },
      10s))
      << "no step 0";
  std::size_t handled = 0;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (h.final() == nullptr && std::chrono::steady_clock::now() < deadline) {
    h.spin(1ms);
    while (p.ack && handled < h.states().size() && h.final() == nullptr) {
      const agent_states_t s = h.states()[handled++];
      for (std::int64_t k : p.hold_at_steps) {
        if (k != s.step) continue;
        const std::size_t before = h.states().size();
        h.spin(300ms);
        if (h.states().size() != before) out.advanced_without_ack = true;
      }
      if (p.before_command) p.before_command(h, s);
      const auto [vx, omega] = p.command(s.step);
      h.sendCommand(s.step, s.utime, vx, omega);
      h.sendAck(s.step, s.utime);
    }
  }
  EXPECT_NE(h.final(), nullptr) << "no final SIM_STATUS";
  out.exit_code = sim.waitExit(10s);
  return out;
}

TEST(WorldSimNode, LockstepAdvancesOnlyOnAcksAndDrivesTheRobotByItsCommands) {
  Harness h;
  Participant p;
  p.hold_at_steps = {0, 10};
  const RunOutcome r = runWithParticipant(h, "tiny_lockstep.yaml", p);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_FALSE(r.advanced_without_ack) << "a step was published before its predecessor's ack";

  const auto& st = h.states();
  ASSERT_GT(st.size(), 20u);
  EXPECT_GE(h.goals(), st.size());  // GOALS with every step
  for (std::size_t k = 0; k < st.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(st[k].step, static_cast<std::int64_t>(k));
    EXPECT_EQ(st[k].utime, static_cast<std::int64_t>(k) * 100000);  // 10 Hz, from t = 0
    ASSERT_EQ(st[k].num_humans, 1);
    EXPECT_EQ(st[k].robot.id, 0);
    EXPECT_NEAR(st[k].robot.y_m, 1.5, 1e-9);  // straight: omega 0
    if (k > 0) {
      EXPECT_GE(st[k].robot.x_m, st[k - 1].robot.x_m);
    }
  }
  EXPECT_DOUBLE_EQ(st[0].robot.x_m, 1.0);
  // The command of step 0 is applied over step 0 -> 1: 2 physics steps at 0.8 m/s^2.
  EXPECT_NEAR(st[1].robot.x_m, 1.0 + 0.05 * 0.04 + 0.05 * 0.08, 1e-9);
  EXPECT_NEAR(st[20].robot.vx_m_s, 0.5, 1e-9);  // reached the commanded speed

  const sim_status_t* fin = h.final();
  ASSERT_NE(fin, nullptr);
  EXPECT_EQ(fin->state, sim_status_t::STATE_GOAL_REACHED) << fin->detail;
  EXPECT_EQ(fin->scenario, "tiny_lockstep");
  EXPECT_EQ(fin->step, st.back().step);
  EXPECT_EQ(fin->utime, st.back().utime);
  // 0.625 s to reach 0.5 m/s (0.156 m), then 2.544 m at 0.5 m/s: 5.71 s.
  EXPECT_NEAR(fin->robot_time_to_goal_s, 5.71, 0.1);
  EXPECT_GT(fin->min_clearance_m, 0.5);
  // One RUNNING status per simulated second before the final one.
  std::size_t running = 0;
  for (const auto& s : h.simStatus()) {
    if (s.state != sim_status_t::STATE_RUNNING) continue;
    EXPECT_EQ(s.utime % 1000000, 0) << s.utime;
    ++running;
  }
  EXPECT_EQ(running, static_cast<std::size_t>(st.back().utime / 1000000));
}

TEST(WorldSimNode, AStepWhoseAckIsOverdueIsPublishedAgainIdenticalAndTheRunGoesOn) {
  Harness h;
  Participant p;
  p.hold_at_steps = {5};  // 300 ms without an ack: longer than retransmit_period_s (0.25 s)
  const RunOutcome r = runWithParticipant(h, "tiny_lockstep.yaml", p);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_FALSE(r.advanced_without_ack);
  EXPECT_GE(h.repeats(), 1u);  // the repeats were byte-identical to step 5 (Harness::onStates)
  ASSERT_NE(h.final(), nullptr);
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_GOAL_REACHED) << h.final()->detail;
  for (std::size_t k = 0; k < h.states().size(); ++k)
    EXPECT_EQ(h.states()[k].step, static_cast<std::int64_t>(k));
}

TEST(WorldSimNode, TheLastStepIsAcknowledgedAndPublishedAgainBeforeTheRunEnds) {
  // The participants' answers of the last step belong to the run (the path assessor's last CM is
  // the transcript's FINAL CM): under message loss they were missing when the world ended at
  // once. The last step is waited for, and published again while overdue, like any other.
  std::int64_t last = -1;
  {
    Harness h;
    runWithParticipant(h, "tiny_lockstep.yaml", Participant{});
    ASSERT_NE(h.final(), nullptr);
    last = h.final()->step;
  }
  ASSERT_GT(last, 0);
  Harness h;
  Participant p;
  bool ended_before_ack = false;
  std::size_t repeats_before = 0;
  p.before_command = [&](Harness& hh, const agent_states_t& s) {
    if (s.step != last) return;
    repeats_before = hh.repeats();
    hh.spin(600ms);  // > retransmit_period_s (0.25 s)
    ended_before_ack = hh.final() != nullptr;
  };
  const RunOutcome r = runWithParticipant(h, "tiny_lockstep.yaml", p);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_FALSE(ended_before_ack) << "the run ended before its last step was acknowledged";
  EXPECT_GT(h.repeats(), repeats_before) << "the overdue last step was not published again";
  ASSERT_NE(h.final(), nullptr);
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_GOAL_REACHED) << h.final()->detail;
  EXPECT_EQ(h.final()->step, last);
}

TEST(WorldSimNode, SameScenarioTwiceGivesByteIdenticalAgentStates) {
  Participant p;
  p.command = [](std::int64_t k) {
    return std::make_pair(0.3 + 0.2 * std::sin(0.3 * static_cast<double>(k)),
                          0.1 * std::cos(0.2 * static_cast<double>(k)));
  };
  std::vector<std::string> runs[2];
  for (auto& bytes : runs) {
    Harness h;
    EXPECT_EQ(runWithParticipant(h, "tiny_lockstep.yaml", p).exit_code, 0);
    bytes = h.stateBytes();
  }
  ASSERT_GT(runs[0].size(), 20u);
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (std::size_t k = 0; k < runs[0].size(); ++k) EXPECT_EQ(runs[0][k], runs[1][k]) << k;
}

TEST(WorldSimNode, ParticipantThatNeverAcksEndsTheRunNamingIt) {
  Harness h;
  Participant p;
  p.ack = false;
  const RunOutcome r = runWithParticipant(h, "tiny_lockstep.yaml", p);
  EXPECT_EQ(r.exit_code, 0);
  ASSERT_NE(h.final(), nullptr);
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_PARTICIPANT_TIMEOUT);
  EXPECT_NE(h.final()->detail.find(kParticipant), std::string::npos) << h.final()->detail;
  EXPECT_EQ(h.states().size(), 1u);  // step 0 only
}

TEST(WorldSimNode, ParticipantThatNeverReportsFailsTheStartNamingIt) {
  Harness h;
  ChildProcess sim(daemonPath("world_sim"),
                   daemonArgs("tiny_lockstep.yaml", {"--set", "wait_ready_timeout_s=0.5"}));
  ASSERT_TRUE(h.spinUntil([&] { return h.final() != nullptr; }, 10s));
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_PARTICIPANT_TIMEOUT);
  EXPECT_NE(h.final()->detail.find(kParticipant), std::string::npos) << h.final()->detail;
  EXPECT_NE(h.final()->detail.find("never"), std::string::npos) << h.final()->detail;
  EXPECT_TRUE(h.states().empty());
  EXPECT_EQ(sim.waitExit(5s), 0);
}

TEST(WorldSimNode, ABandSourcePlanningOtherKinematicsIsRefusedBeforeTheFirstStep) {
  // tiny_lockstep's robot is differential (the scenario default); the band source announces
  // holonomic plans (its default config): world_sim ends with an error naming both settings.
  Harness h;
  ChildProcess sim(daemonPath("world_sim"), daemonArgs("tiny_lockstep.yaml"));
  ASSERT_TRUE(h.spinUntil([&] { return h.worldSimReady(); }, 10s));
  ASSERT_TRUE(h.spinUntil(
      [&] {
        h.sendStatus("band_source", "map m.yaml 10x10 @ 0.05 m; robot kinematics holonomic");
        h.spin(50ms);
        return h.final() != nullptr;
      },
      10s));
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_ERROR);
  const std::string& d = h.final()->detail;
  EXPECT_NE(d.find("robot.kinematics is differential"), std::string::npos) << d;
  EXPECT_NE(d.find("planner.robot.holonomic: true"), std::string::npos) << d;
  EXPECT_TRUE(h.states().empty()) << "a step was simulated with the wrong robot";
  EXPECT_EQ(sim.waitExit(5s), 0);
}

TEST(WorldSimNode, ABandSourcePlanningTheScenariosKinematicsRunsAsUsual) {
  Harness h;
  Participant p;
  p.before_command = [](Harness& hh, const agent_states_t&) {
    hh.sendStatus("band_source", "map m.yaml 10x10 @ 0.05 m; robot kinematics differential");
  };
  const RunOutcome r = runWithParticipant(h, "tiny_lockstep.yaml", p);
  EXPECT_EQ(r.exit_code, 0);
  ASSERT_NE(h.final(), nullptr);
  EXPECT_NE(h.final()->state, sim_status_t::STATE_ERROR) << h.final()->detail;
}

/// Runs the daemon on a file, with more arguments if given (already quoted for the shell), and
/// returns (exit code, stdout + stderr).
std::pair<int, std::string> runCapture(const std::string& scenario,
                                       const std::string& more_args = "") {
  std::string cmd = daemonPath("world_sim") + " --lcm-url '" + testLcmUrl() + "' --set scenario='" +
                    scenarioPath(scenario) + "' " + more_args + " 2>&1";
  FILE* f = ::popen(cmd.c_str(), "r");
  std::string out;
  if (f == nullptr) return {-1, out};
  char buf[512];
  while (std::fgets(buf, sizeof buf, f)) out += buf;
  const int st = ::pclose(f);
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

TEST(WorldSimNode, BadScenarioFilesExitWithCode3AndNameTheProblem) {
  const std::map<std::string, std::vector<std::string>> cases = {
      {"bad_missing_key.yaml", {"'robot.goal'", "missing"}},
      {"bad_start_in_wall.yaml", {"'humans[0].start'", "not in free space"}},
      {"bad_unknown_behaviour.yaml", {"'humans[0].behaviour'", "teleport", "social_force"}},
      {"bad_negative_speed.yaml", {"'humans[0].speed_m_s'", "-0.5", "[0, 3]"}},
  };
  for (const auto& [file, expect] : cases) {
    SCOPED_TRACE(file);
    const auto [rc, out] = runCapture(file);
    EXPECT_EQ(rc, 3) << out;
    EXPECT_NE(out.find(file), std::string::npos) << out;
    for (const auto& s : expect) EXPECT_NE(out.find(s), std::string::npos) << out;
  }
  // A missing scenario key is a config error (2), a missing file a scenario error (3).
  const auto [rc, out] = runCapture("absent.yaml");
  EXPECT_EQ(rc, 3) << out;
  EXPECT_NE(out.find("absent.yaml"), std::string::npos) << out;
}

TEST(WorldSimNode, SigtermExitsCleanlyWithinOneSecond) {
  {  // waiting for its participants
    Harness h;
    ChildProcess sim(daemonPath("world_sim"), daemonArgs("tiny_lockstep.yaml"));
    ASSERT_TRUE(h.spinUntil([&] { return h.worldSimReady(); }, 10s));
    sim.signal(SIGTERM);
    EXPECT_EQ(sim.waitExit(1s), 0);
  }
  {  // running in real time: free-running steps (-1), 0.1 s apart in simulated time
    Harness h;
    ChildProcess sim(daemonPath("world_sim"),
                     daemonArgs("tiny_lockstep.yaml",
                                {"--set", "mode=real_time", "--set", "real_time_factor=2"}));
    ASSERT_TRUE(h.spinUntil([&] { return h.states().size() >= 3; }, 10s));
    sim.signal(SIGTERM);
    EXPECT_EQ(sim.waitExit(1s), 0);
    const auto& st = h.states();
    for (std::size_t k = 0; k < st.size(); ++k) {
      EXPECT_EQ(st[k].step, -1);
      if (k > 0) {
        EXPECT_EQ(st[k].utime - st[k - 1].utime, 100000);
      }
    }
  }
}

TEST(WorldSimNode, AskToMoveMakesAResponsiveHumanYieldToTheAskedSide) {
  // Human 1 walks -x on y = 3; its left is -y. Asked at step 5 with words lasting 0.5 s, it
  // yields once it has heard them and reacted; unasked, or asked by a muted robot, it keeps its
  // line (the robot is still far: a minimal human has not reacted yet at the end). Its scenario
  // makes it hear at any distance and always comply.
  double final_y[3] = {0.0, 0.0, 0.0};
  for (int run = 0; run < 3; ++run) {
    SCOPED_TRACE(run);
    Harness h;
    Participant p;
    if (run > 0) {
      const std::int8_t delivery =
          run == 1 ? utterance_t::DELIVERY_SAID : utterance_t::DELIVERY_MUTED;
      p.before_command = [delivery](Harness& hh, const agent_states_t& s) {
        if (s.step == 5) hh.sendAskToMove(s.step, s.utime, 1, situation_t::DIR_LEFT, 0.5, delivery);
      };
    }
    // What became of each cue, as JSON lines (cue_outcomes_file: the population reads them).
    const std::string cues = (std::filesystem::temp_directory_path() /
                              ("coopnav_world_sim_cues_" + std::to_string(::getpid()) + ".jsonl"))
                                 .string();
    EXPECT_EQ(
        runWithParticipant(h, "tiny_responsive.yaml", p, {"--set", "cue_outcomes_file=" + cues})
            .exit_code,
        0);
    ASSERT_FALSE(h.states().empty());
    ASSERT_NE(h.final(), nullptr);
    EXPECT_EQ(h.final()->state, sim_status_t::STATE_TIME_LIMIT) << h.final()->detail;
    final_y[run] = h.states().back().humans[0].y_m;
    std::ifstream in(cues);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::filesystem::remove(cues);
    if (run == 1) {
      ASSERT_EQ(lines.size(), 1U);
      const auto o = nlohmann::json::parse(lines[0]);
      EXPECT_EQ(o.at("human_id"), 1);
      EXPECT_EQ(o.at("cue"), "move_to_side");
      EXPECT_EQ(o.at("side"), "left");
      EXPECT_EQ(o.at("repeat"), false);
      EXPECT_EQ(o.at("responds"), true);
      EXPECT_EQ(o.at("heard"), true);
      EXPECT_EQ(o.at("complies"), true);
      EXPECT_GE(o.at("act_s").get<double>(), o.at("t_s").get<double>()) << lines[0];
      EXPECT_NEAR(o.at("t_s").get<double>(), 1.0, 0.11) << lines[0];  // words end 0.5 + 0.5 s
    } else {
      EXPECT_TRUE(lines.empty()) << lines.front();  // nothing said, or said muted: nothing heard
    }
    if (run == 1) {
      // Nothing moves before the words have ended (0.5 s + 0.5 s) and a reaction time has
      // passed (log-normal, 5 % quantile 0.6 s).
      for (const auto& s : h.states())
        if (s.utime < 1400000) {
          EXPECT_NEAR(s.humans[0].y_m, 3.0, 1e-9) << s.step;
        }
    }
  }
  EXPECT_NEAR(final_y[2], final_y[0], 1e-9);  // muted: as if nothing was said
  EXPECT_NEAR(final_y[0], 3.0, 0.05);
  EXPECT_LT(final_y[1], 3.0 - 0.5);
}

TEST(WorldSimNode, UtterancesEndingFarAheadOrBeyondWhatAPersonHearsAtOnceAreNotKept) {
  // Issue 47: world_sim kept every cue it heard, whatever its time. At step 5: an ask whose words
  // end 1000 s ahead (more than limits.max_time_jump_s: rejected), then 40 asks for steps 5..44
  // ending 30 s ahead (at most 16 not yet ended are kept per person: 24 dropped).
  Harness h;
  Participant p;
  p.before_command = [](Harness& hh, const agent_states_t& s) {
    if (s.step != 5) return;
    hh.sendAskToMove(s.step, s.utime + 1'000'000'000, 1, situation_t::DIR_LEFT, 0.5);
    for (int i = 0; i < 40; ++i)  // steps ahead: a step's words are heard once (one key)
      hh.sendAskToMove(s.step + i, s.utime + 30'000'000, 1, situation_t::DIR_LEFT, 0.5);
  };
  EXPECT_EQ(runWithParticipant(h, "tiny_responsive.yaml", p).exit_code, 0);
  h.spin(300ms);  // the final status
  EXPECT_EQ(h.world_sim_rejected_, 1);
  EXPECT_EQ(h.world_sim_dropped_, 24);
  // None of them ended within the run: the person kept its line.
  ASSERT_FALSE(h.states().empty());
  EXPECT_NEAR(h.states().back().humans[0].y_m, 3.0, 0.05);
}

TEST(WorldSimNode, PlannerBackedFacilitatingHumanWalksWithoutParticipants) {
  Harness h;
  ChildProcess sim(daemonPath("world_sim"), daemonArgs("tiny_band_human.yaml"));
  ASSERT_TRUE(h.spinUntil([&] { return h.final() != nullptr; }, 60s));
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_TIME_LIMIT) << h.final()->detail;
  EXPECT_EQ(h.final()->utime, 3000000);
  EXPECT_EQ(sim.waitExit(5s), 0);
  ASSERT_FALSE(h.states().empty());
  // Its planner walks it towards its goal (-x) while the robot, given no command, stands.
  const agent_states_t& last = h.states().back();
  EXPECT_LT(last.humans[0].x_m, 10.0 - 1.0);
  EXPECT_DOUBLE_EQ(last.robot.x_m, 2.0);
  EXPECT_DOUBLE_EQ(last.robot.y_m, 1.0);
}

TEST(WorldSimNode, HumanPlannerKeysReachThePlannerBackedHumans) {
  // Given the planner-backed human of the test above, its planner's walking speed capped at
  // 0.2 m/s from the config (human_planner.* are band_source's planner.* keys).
  Harness h;
  ChildProcess sim(
      daemonPath("world_sim"),
      daemonArgs("tiny_band_human.yaml", {"--set", "human_planner.human.max_vel_x_m_s=0.2"}));
  ASSERT_TRUE(h.spinUntil([&] { return h.final() != nullptr; }, 60s));
  EXPECT_EQ(sim.waitExit(5s), 0);
  ASSERT_FALSE(h.states().empty());
  // Then in its 3 s it walks at most 0.2 m/s (it walked over 1 m with the defaults).
  const agent_states_t& last = h.states().back();
  EXPECT_LT(last.humans[0].x_m, 10.0 - 0.1);
  EXPECT_GT(last.humans[0].x_m, 10.0 - 0.2 * 3.0 - 0.05);
  // And a value out of range stops the daemon at start naming the dotted key.
  const auto [code, out] = runCapture("tiny_band_human.yaml", "--set human_planner.dt_ref_s=0");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("human_planner.dt_ref_s"), std::string::npos) << out;
}

// ---- who touched whom, standstill

constexpr const char* kRobotAtWall =
    "{start: {x_m: 10, y_m: 0.55, theta_rad: 0}, goal: {x_m: 10, y_m: 0.55}, radius_m: 0.47}";

TEST(WorldSimNode, FinalStatusSaysTheHumanWalkedIntoTheRobotAtRest) {
  // An oblivious human walks into the robot standing at the wall of a 1.8 m corridor.
  CorridorScenario sc("oblivious_into_robot", 1.8, kRobotAtWall,
                      "{id: 1, start: {x_m: 2, y_m: 0.9}, goal: {x_m: 20, y_m: 0.9}, "
                      "behaviour: oblivious, speed_m_s: 1.2}");
  Harness h;
  Participant p;
  p.command = [](std::int64_t) { return std::make_pair(0.0, 0.0); };
  EXPECT_EQ(runWithParticipant(h, sc.path(), p).exit_code, 0);
  const sim_status_t* fin = h.final();
  ASSERT_NE(fin, nullptr);
  EXPECT_EQ(fin->state, sim_status_t::STATE_COLLISION) << fin->detail;
  EXPECT_EQ(fin->contact, sim_status_t::CONTACT_HUMAN_AT_FAULT);
  EXPECT_EQ(fin->contact_human_id, 1);
  EXPECT_DOUBLE_EQ(fin->contact_robot_speed_m_s, 0.0);
  EXPECT_GT(fin->contact_t_s, 5.0);
  EXPECT_LE(fin->contact_t_s, 1e-6 * static_cast<double>(fin->utime));
  EXPECT_LT(fin->min_clearance_m, 0.0);
  EXPECT_DOUBLE_EQ(fin->min_clearance_t_s, fin->contact_t_s);
  EXPECT_EQ(fin->detail.rfind("human 1 walked into the robot at rest at t ", 0), 0u) << fin->detail;
  // The running reports before it: no contact yet, every field set.
  ASSERT_GT(h.simStatus().size(), 1u);
  const sim_status_t& running = h.simStatus().front();
  EXPECT_EQ(running.state, sim_status_t::STATE_RUNNING);
  EXPECT_EQ(running.contact, sim_status_t::CONTACT_NONE);
  EXPECT_EQ(running.contact_human_id, -1);
  EXPECT_TRUE(std::isnan(running.contact_t_s));
  EXPECT_TRUE(std::isnan(running.contact_robot_speed_m_s));
  EXPECT_TRUE(std::isfinite(running.min_clearance_t_s));
}

TEST(WorldSimNode, FinalStatusSaysTheRobotDroveIntoTheHuman) {
  // A human standing at its goal; the robot drives into it at 0.5 m/s.
  CorridorScenario sc("robot_into_human", 3.0,
                      "{start: {x_m: 1, y_m: 1.5, theta_rad: 0}, goal: {x_m: 20, y_m: 1.5}, "
                      "radius_m: 0.47}",
                      "{id: 1, start: {x_m: 5, y_m: 1.5}, goal: {x_m: 5, y_m: 1.5}, "
                      "behaviour: minimal}");
  Harness h;
  EXPECT_EQ(runWithParticipant(h, sc.path(), Participant{}).exit_code, 0);
  const sim_status_t* fin = h.final();
  ASSERT_NE(fin, nullptr);
  EXPECT_EQ(fin->state, sim_status_t::STATE_COLLISION) << fin->detail;
  EXPECT_EQ(fin->contact, sim_status_t::CONTACT_ROBOT_AT_FAULT);
  EXPECT_NEAR(fin->contact_robot_speed_m_s, 0.5, 1e-9);
  EXPECT_EQ(fin->detail.rfind("the robot drove into human 1 at 0.50 m/s at t ", 0), 0u)
      << fin->detail;
}

TEST(WorldSimNode, AnEncounterNobodyResolvesEndsInStandstillWithoutContact) {
  // 1.5 m corridor: beside the robot at the wall there is no room for the human's body; it stops
  // short of the robot and waits, the robot holds: STANDSTILL after standstill_time_s.
  CorridorScenario sc("standstill", 1.5, kRobotAtWall,
                      "{id: 1, start: {x_m: 2, y_m: 0.75}, goal: {x_m: 20, y_m: 0.75}, "
                      "behaviour: minimal, speed_m_s: 1.2}",
                      "standstill_time_s: 5.0\n");
  Harness h;
  Participant p;
  p.command = [](std::int64_t) { return std::make_pair(0.0, 0.0); };
  EXPECT_EQ(runWithParticipant(h, sc.path(), p).exit_code, 0);
  const sim_status_t* fin = h.final();
  ASSERT_NE(fin, nullptr);
  EXPECT_EQ(fin->state, sim_status_t::STATE_STANDSTILL) << fin->detail;
  EXPECT_EQ(fin->contact, sim_status_t::CONTACT_NONE);
  EXPECT_EQ(fin->contact_human_id, -1);
  EXPECT_TRUE(std::isnan(fin->contact_t_s));
  EXPECT_GT(fin->min_clearance_m, 0.15);
  EXPECT_LT(1e-6 * static_cast<double>(fin->utime), 20.0);  // not the time limit (40 s)
  EXPECT_EQ(fin->detail,
            "standstill: no agent moved more than 0.1 m for 5 s; the robot was navigating (at its "
            "goal), had said nothing");
}

// ---- tracker model, withheld goals, recorded humans

namespace tracker_model {

std::vector<std::string> trackerArgs() {
  return {"--set", "tracker.position_sigma_m=0.05", "--set", "tracker.id_switches=1",
          "--set", "tracker.id_switch_window_s=2"};
}

}  // namespace tracker_model

TEST(WorldSimNode, TrackerNoiseFromTheConfigPublishesNoisyPositionsAndNewIds) {
  // Given the same scenario run with the truth and with the tracker model set on the command
  // line (sigma 5 cm, one id switch within the first 2 s).
  Harness truth;
  ASSERT_EQ(runWithParticipant(truth, "tiny_lockstep.yaml", Participant{}).exit_code, 0);
  std::vector<std::string> bytes[2];
  std::vector<agent_states_t> noisy;
  std::vector<goals_t> goals;
  for (auto& run : bytes) {
    Harness h;
    ASSERT_EQ(
        runWithParticipant(h, "tiny_lockstep.yaml", Participant{}, tracker_model::trackerArgs())
            .exit_code,
        0);
    run = h.stateBytes();
    noisy = h.states();
    goals = h.goalMessages();
  }
  // Then the run repeats to the byte with the tracker on too.
  EXPECT_EQ(bytes[0], bytes[1]);
  // And the world is the same (the tracker draws from streams of its own): the robot exactly,
  // each human within 5 sigma of its true position, with a spread of about sigma.
  ASSERT_EQ(noisy.size(), truth.states().size());
  double sum2 = 0.0;
  std::size_t n = 0;
  std::set<std::int32_t> ids;
  for (std::size_t k = 0; k < noisy.size(); ++k) {
    SCOPED_TRACE(k);
    const agent_states_t& a = truth.states()[k];
    const agent_states_t& b = noisy[k];
    EXPECT_EQ(b.robot.x_m, a.robot.x_m);
    EXPECT_EQ(b.robot.y_m, a.robot.y_m);
    ASSERT_EQ(b.num_humans, 1);
    const double e =
        std::hypot(b.humans[0].x_m - a.humans[0].x_m, b.humans[0].y_m - a.humans[0].y_m);
    EXPECT_LT(e, 5 * 0.05 * std::sqrt(2.0));
    sum2 += e * e;
    ++n;
    ids.insert(b.humans[0].id);
  }
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(n)), 0.05 * std::sqrt(2.0), 0.02);
  // And the person was published under its own id, then under a new one from 1000 on.
  EXPECT_EQ(ids, (std::set<std::int32_t>{1, 1000}));
  EXPECT_EQ(noisy.front().humans[0].id, 1);
  EXPECT_EQ(noisy.back().humans[0].id, 1000);
  // And the goal of the new id is the person's goal.
  ASSERT_FALSE(goals.empty());
  const goals_t& last = goals.back();
  ASSERT_EQ(last.num_goals, 2);
  EXPECT_EQ(last.goals[1].agent_id, 1000);
  EXPECT_DOUBLE_EQ(last.goals[1].x_m, 7.0);
  EXPECT_DOUBLE_EQ(last.goals[1].y_m, 3.0);
}

TEST(WorldSimNode, WithheldHumanGoalsLeaveOnlyTheRobotsGoal) {
  Harness h;
  ASSERT_EQ(runWithParticipant(h, "tiny_lockstep.yaml", Participant{},
                               {"--set", "publish_human_goals=false"})
                .exit_code,
            0);
  ASSERT_FALSE(h.goalMessages().empty());
  for (const goals_t& g : h.goalMessages()) {
    ASSERT_EQ(g.num_goals, 1);
    EXPECT_EQ(g.goals[0].agent_id, 0);
    EXPECT_DOUBLE_EQ(g.goals[0].x_m, 4.0);
  }
  ASSERT_FALSE(h.states().empty());
  EXPECT_EQ(h.states().back().num_humans, 1);  // the human is still published
  // A bad value stops the daemon at start naming the key.
  const auto [code, out] = runCapture("tiny_lockstep.yaml", "--set publish_human_goals=perhaps");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("publish_human_goals"), std::string::npos) << out;
  const auto [code2, out2] =
      runCapture("tiny_lockstep.yaml", "--set tracker.miss_probability=-0.5");
  EXPECT_EQ(code2, 2) << out2;
  EXPECT_NE(out2.find("tracker.miss_probability"), std::string::npos) << out2;
}

TEST(WorldSimNode, AnUtteranceToASwitchedIdReachesThePerson) {
  // Given the responsive human published under a new id from within the first 0.5 s, asked to
  // move left under that id at step 5.
  Harness h;
  Participant p;
  std::int32_t asked = -1;
  p.before_command = [&](Harness& hh, const agent_states_t& s) {
    if (s.step != 5) return;
    asked = s.humans[0].id;
    hh.sendAskToMove(s.step, s.utime, asked, situation_t::DIR_LEFT);
  };
  EXPECT_EQ(runWithParticipant(
                h, "tiny_responsive.yaml", p,
                {"--set", "tracker.id_switches=1", "--set", "tracker.id_switch_window_s=0.5"})
                .exit_code,
            0);
  EXPECT_EQ(asked, 1000);
  ASSERT_FALSE(h.states().empty());
  // Then it yields to its left (-y), as when asked under its scenario id.
  EXPECT_LT(h.states().back().humans[0].y_m, 3.0 - 0.5);
}

TEST(WorldSimNode, RecordedHumansReplayTheirTracks) {
  // Given both walkers of a real encounter replayed (test/data/tracks), and a robot at its goal.
  Harness h;
  // Paced (10x real time): free-running as fast as the CPU allows, its bursts overflow the
  // test's receive buffer.
  ChildProcess sim(daemonPath("world_sim"),
                   daemonArgs("recorded_zara01.yaml",
                              {"--set", "mode=real_time", "--set", "real_time_factor=10"}));
  ASSERT_TRUE(h.spinUntil([&] { return h.final() != nullptr; }, 60s));
  EXPECT_EQ(sim.waitExit(5s), 0);
  // Then they walk their tracks to their ends (walker a's lasts 12.8 s, b's 12.4 s) and the run
  // ends with every goal reached, without contact.
  EXPECT_EQ(h.final()->state, sim_status_t::STATE_GOAL_REACHED) << h.final()->detail;
  EXPECT_EQ(h.final()->contact, sim_status_t::CONTACT_NONE);
  EXPECT_GT(h.final()->utime, 12000000);
  // At 6 s walker a is where its track puts it: its sample at 6.0 s, (-0.9171303, 10.9087), in
  // the map frame (x, y) -> (22 - y, 3 + x), within 2 cm.
  const auto it = std::find_if(h.states().begin(), h.states().end(),
                               [](const agent_states_t& s) { return s.utime == 6000000; });
  ASSERT_NE(it, h.states().end());
  const agent_states_t& at6 = *it;
  ASSERT_EQ(at6.num_humans, 2);
  EXPECT_EQ(at6.humans[0].id, 1);
  EXPECT_NEAR(at6.humans[0].x_m, 22.0 - 10.9087, 0.02);
  EXPECT_NEAR(at6.humans[0].y_m, 3.0 - 0.9171303, 0.02);
}

}  // namespace
}  // namespace coopnav
