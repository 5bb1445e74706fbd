// The band_source daemon as a process over an isolated udpm port: a head-on case in the 6 m
// corridor of open.pgm (robot (6.5, 6.5) -> (20.5, 6.5), human the reverse), lockstep steps in,
// bands / command / ack out stamped with the input, bad inputs counted, clean SIGTERM.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/goal_estimates_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr double kRobotRadius_m = 0.34;
constexpr double kHumanRadius_m = 0.30;
constexpr std::int64_t kStart_us = 1'000'000'000;  // any epoch: only differences matter
constexpr std::int64_t kStep_us = 100'000;         // 10 Hz lockstep
constexpr int kHumanId = 1;

/// Everything the daemon publishes, in arrival order.
struct Probe {
  Runtime rt{"band_source_probe", test::testLcmUrl()};
  std::vector<std::string> order;  // "bands:k", "cmd:k", "ack:k", "refs"
  std::map<std::int64_t, bands_t> bands;
  std::map<std::int64_t, velocity_command_t> cmds;
  std::map<std::int64_t, step_ack_t> acks;
  std::vector<reference_paths_t> refs;
  std::optional<daemon_status_t> status;

  Probe() {
    rt.subscribe<bands_t>(channels::kBands, [this](const bands_t& m, std::int64_t) {
      bands[m.step] = m;
      order.push_back("bands:" + std::to_string(m.step));
    });
    rt.subscribe<velocity_command_t>(channels::kRobotCmd,
                                     [this](const velocity_command_t& m, std::int64_t) {
                                       cmds[m.step] = m;
                                       order.push_back("cmd:" + std::to_string(m.step));
                                     });
    rt.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& m, std::int64_t) {
      if (m.participant != "band_source") return;
      acks[m.step] = m;
      order.push_back("ack:" + std::to_string(m.step));
    });
    rt.subscribe<reference_paths_t>(channels::kReferencePaths,
                                    [this](const reference_paths_t& m, std::int64_t) {
                                      refs.push_back(m);
                                      order.push_back("refs");
                                    });
    rt.subscribe<daemon_status_t>(channels::kStatus,
                                  [this](const daemon_status_t& m, std::int64_t) {
                                    if (m.name == "band_source") status = m;
                                  });
  }
  bool waitFor(const std::function<bool()>& pred, milliseconds timeout = seconds(10)) {
    return test::waitFor(pred, timeout, [this] { rt.spinFor(5); });
  }
  std::ptrdiff_t indexOf(const std::string& what) const {
    const auto it = std::find(order.begin(), order.end(), what);
    return it == order.end() ? -1 : it - order.begin();
  }
};

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double th, double vx,
                    double r) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = th;
  a.vx_m_s = vx;
  a.radius_m = r;
  return a;
}

/// Step k of the scripted head-on: both walk straight along y = 6.5 (robot 0.7 m/s, human 1 m/s).
agent_states_t headOnStates(std::int64_t step, double robot_x0 = 6.5, double human_x0 = 20.5) {
  const double t = static_cast<double>(step) * kStep_us * 1e-6;
  agent_states_t m{};
  m.utime = kStart_us + step * kStep_us;
  m.step = step;
  m.robot = agent(0, agent_state_t::KIND_ROBOT, robot_x0 + 0.7 * t, 6.5, 0.0, 0.7, kRobotRadius_m);
  m.humans.push_back(agent(kHumanId, agent_state_t::KIND_HUMAN, human_x0 - 1.0 * t, 6.5, M_PI, -1.0,
                           kHumanRadius_m));
  m.num_humans = 1;
  return m;
}

goals_t headOnGoals() {
  goals_t g{};
  g.utime = kStart_us;
  goal_t r{};
  r.agent_id = 0;
  r.kind = agent_state_t::KIND_ROBOT;
  r.x_m = 20.5;
  r.y_m = 6.5;
  r.theta_rad = 0.0;
  goal_t h{};
  h.agent_id = kHumanId;
  h.kind = agent_state_t::KIND_HUMAN;
  h.x_m = 6.5;
  h.y_m = 6.5;
  h.theta_rad = std::numeric_limits<double>::quiet_NaN();
  g.goals = {r, h};
  g.num_goals = 2;
  return g;
}

Band band(const band_t& b) {
  Band out;
  for (const auto& p : b.poses) out.poses.push_back({p.t_s, {p.x_m, p.y_m, p.theta_rad}});
  return out;
}

Eigen::Vector2d positionAt(const Band& b, double t) {
  if (t <= b.poses.front().t_s) return b.poses.front().pose.position();
  for (std::size_t i = 0; i + 1 < b.poses.size(); ++i) {
    const auto& p0 = b.poses[i];
    const auto& p1 = b.poses[i + 1];
    if (t <= p1.t_s) {
      const double s = (t - p0.t_s) / std::max(p1.t_s - p0.t_s, 1e-9);
      return (1.0 - s) * p0.pose.position() + s * p1.pose.position();
    }
  }
  return b.poses.back().pose.position();
}

class BandSourceNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = test::writeBandSourceTestConfig("band_source_test");
    dut_ = std::make_unique<test::ChildProcess>(
        test::daemonPath("band_source"),
        std::vector<std::string>{"--config", config_, "--lcm-url", test::testLcmUrl()});
    // Ready = its first status message (sent once subscribed).
    ASSERT_TRUE(probe_.waitFor([&] { return probe_.status.has_value(); }));
    probe_.rt.publish(channels::kGoals, headOnGoals());
    probe_.rt.spinFor(20);
  }
  void TearDown() override { std::filesystem::remove(config_); }

  /// Publishes step k and waits for its ack.
  bool step(const agent_states_t& m) {
    probe_.rt.publish(channels::kAgentStates, m);
    return probe_.waitFor([&] { return probe_.acks.count(m.step) > 0; });
  }

  std::string config_;
  Probe probe_;
  std::unique_ptr<test::ChildProcess> dut_;
};

TEST_F(BandSourceNodeTest, HeadOnLockstepBandsAndCommandsStampedFromTheInputAckedLast) {
  constexpr int kSteps = 5;
  for (int k = 0; k < kSteps; ++k) ASSERT_TRUE(step(headOnStates(k))) << "no ack of step " << k;
  for (int k = 0; k < kSteps; ++k) {
    const auto in = headOnStates(k);
    ASSERT_EQ(probe_.bands.count(k), 1u) << k;
    ASSERT_EQ(probe_.cmds.count(k), 1u) << k;
    const bands_t& b = probe_.bands[k];
    EXPECT_EQ(b.utime, in.utime);
    EXPECT_EQ(probe_.cmds[k].utime, in.utime);
    EXPECT_EQ(probe_.acks[k].utime, in.utime);
    EXPECT_EQ(b.status, bands_t::STATUS_OK);
    EXPECT_EQ(b.robot_mode, velocity_command_t::MODE_NAVIGATING);
    EXPECT_EQ(probe_.cmds[k].mode, velocity_command_t::MODE_NAVIGATING);
    EXPECT_GT(probe_.cmds[k].vx_m_s, 0.0);  // driving towards the goal
    ASSERT_GE(b.robot.num_poses, 2);
    ASSERT_EQ(b.num_humans, 1);
    EXPECT_EQ(b.humans[0].agent_id, kHumanId);
    // Bands start at the agents' poses of that step, time 0.
    EXPECT_EQ(b.robot.poses[0].t_s, 0.0);
    EXPECT_NEAR(b.robot.poses[0].x_m, in.robot.x_m, 1e-9);
    EXPECT_NEAR(b.humans[0].poses[0].x_m, in.humans[0].x_m, 1e-9);
    // Outputs of step k come before its ack.
    const auto ack_at = probe_.indexOf("ack:" + std::to_string(k));
    EXPECT_LT(probe_.indexOf("bands:" + std::to_string(k)), ack_at);
    EXPECT_LT(probe_.indexOf("cmd:" + std::to_string(k)), ack_at);
  }
  // The human's reference path was published once, before the first bands, revision 1.
  ASSERT_FALSE(probe_.refs.empty());
  EXPECT_LT(probe_.indexOf("refs"), probe_.indexOf("bands:0"));
  ASSERT_EQ(probe_.refs[0].num_paths, 1);
  EXPECT_EQ(probe_.refs[0].paths[0].agent_id, kHumanId);
  EXPECT_EQ(probe_.refs[0].revision[0], 1);
  EXPECT_EQ(probe_.refs[0].utime, kStart_us);

  // The bands pass each other: the robot's x overtakes the human's within the horizon, and at
  // every common time they keep the safety distance (disc edges 0.6 m apart, soft: -0.05 m).
  const Band r = band(probe_.bands[kSteps - 1].robot);
  const Band h = band(probe_.bands[kSteps - 1].humans[0]);
  const double t_end = std::min(r.poses.back().t_s, h.poses.back().t_s);
  bool crossed = false;
  double min_d = std::numeric_limits<double>::infinity();
  for (double t = 0.0; t <= t_end; t += 0.02) {
    const Eigen::Vector2d pr = positionAt(r, t), ph = positionAt(h, t);
    crossed = crossed || pr.x() > ph.x();
    min_d = std::min(min_d, (pr - ph).norm());
  }
  EXPECT_TRUE(crossed) << "bands end at robot x " << r.poses.back().pose.x_m << ", human x "
                       << h.poses.back().pose.x_m;
  EXPECT_GE(min_d, kRobotRadius_m + kHumanRadius_m + 0.6 - 0.05);
}

TEST_F(BandSourceNodeTest, BadAgentStatesAreCountedAckedAndTheDaemonGoesOn) {
  ASSERT_TRUE(step(headOnStates(0)));
  auto nan = headOnStates(1);
  nan.robot.x_m = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(step(nan)) << "a rejected step must still be acknowledged";
  EXPECT_EQ(probe_.bands.count(1), 0u);
  auto over = headOnStates(2);  // more humans than agent_states_t::MAX_HUMANS
  while (over.humans.size() <= static_cast<std::size_t>(agent_states_t::MAX_HUMANS)) {
    over.humans.push_back(over.humans[0]);
    over.humans.back().id = static_cast<std::int32_t>(over.humans.size());
    over.humans.back().y_m = 1.0 + 0.1 * static_cast<double>(over.humans.size());
  }
  over.num_humans = static_cast<std::int16_t>(over.humans.size());
  ASSERT_TRUE(step(over));
  EXPECT_EQ(probe_.bands.count(2), 0u);
  auto dup = headOnStates(3);  // the robot's id given to a human
  dup.humans[0].id = dup.robot.id;
  ASSERT_TRUE(step(dup));
  EXPECT_EQ(probe_.bands.count(3), 0u);
  ASSERT_TRUE(step(headOnStates(4)));
  probe_.rt.publish(channels::kAgentStates, headOnStates(2));  // step going backwards
  ASSERT_TRUE(step(headOnStates(5)));
  EXPECT_EQ(probe_.bands.count(4), 1u);
  EXPECT_EQ(probe_.bands.count(5), 1u);
  EXPECT_EQ(probe_.bands.count(2), 0u);
  // Status (once a second) reports the three rejections and the drop.
  probe_.status.reset();
  ASSERT_TRUE(probe_.waitFor(
      [&] { return probe_.status && probe_.status->rejected >= 3 && probe_.status->dropped >= 1; },
      seconds(3)))
      << "rejected " << (probe_.status ? probe_.status->rejected : -1);
  EXPECT_TRUE(dut_->running());
}

TEST_F(BandSourceNodeTest, FreeRunningPlansAtMostAtControlRateByMessageTime) {
  for (int i = 0; i < 5; ++i) {  // 20 Hz input, 10 Hz control: every other message
    auto m = headOnStates(i);
    m.step = -1;
    m.utime = kStart_us + i * kStep_us / 2;
    probe_.rt.publish(channels::kAgentStates, m);
  }
  ASSERT_TRUE(probe_.waitFor([&] {
    return probe_.bands.count(-1) && probe_.bands[-1].utime == kStart_us + 2 * kStep_us;
  }));
  probe_.rt.spinFor(100);
  // Three are due by message time; fewer when some arrived while a cycle ran (then only the
  // newest is planned), never more.
  const auto planned = std::count(probe_.order.begin(), probe_.order.end(), "bands:-1");
  EXPECT_GE(planned, 1);
  EXPECT_LE(planned, 3);
  EXPECT_TRUE(probe_.acks.empty());  // nobody waits in free-running
}

TEST_F(BandSourceNodeTest, DockActionSendsTheRobotToTheWallAndResumeBringsItBack) {
  // Over the divider (its top edge y 3.5 from x 9.65: the wall on the robot's right), the human
  // 4.5 m ahead (closer than dock.human_far_m, so it has not "gone").
  const auto at = [](std::int64_t k) { return headOnStates(k, 12.0, 16.5); };
  ASSERT_TRUE(step(at(0)));
  robot_action_t dock{};
  dock.utime = at(0).utime;
  dock.step = 0;
  dock.action = robot_action_t::ACTION_DOCK;
  dock.human_id = kHumanId;
  dock.reason = "test";
  probe_.rt.publish(channels::kRobotAction, dock);
  probe_.rt.spinFor(20);
  ASSERT_TRUE(step(at(1)));
  EXPECT_EQ(probe_.cmds[1].mode, velocity_command_t::MODE_DOCKING);
  // Keep right: the dock band ends to the robot's right (lower y), near the divider.
  const bands_t& b = probe_.bands[1];
  ASSERT_GE(b.robot.num_poses, 1);
  EXPECT_LT(b.robot.poses.back().y_m, 6.5 - 1.0);
  EXPECT_GT(b.robot.poses.back().y_m, 3.5 + kRobotRadius_m);
  robot_action_t resume = dock;
  resume.step = 1;
  resume.action = robot_action_t::ACTION_RESUME;
  probe_.rt.publish(channels::kRobotAction, resume);
  probe_.rt.spinFor(20);
  ASSERT_TRUE(step(at(2)));
  EXPECT_EQ(probe_.cmds[2].mode, velocity_command_t::MODE_RESUMING);
  ASSERT_TRUE(step(at(3)));
  EXPECT_EQ(probe_.cmds[3].mode, velocity_command_t::MODE_NAVIGATING);
}

// Going first (GO_FIRST, a stand-off's end): the robot stands, and a person who made room stands
// 1.6 m ahead, 0.4 m to the left of its line, in open.pgm's 6 m corridor. Told to go first, the
// robot drives
// on while the planner's own command is slower: forward, moving to its right (away from them),
// at most go_first.speed_m_s; once they are behind it, the planner's command is back.
TEST_F(BandSourceNodeTest, GoFirstDrivesOnPastAPersonStandingAside) {
  const auto at = [](std::int64_t k, double human_x) {
    agent_states_t m = headOnStates(k);
    m.robot = agent(0, agent_state_t::KIND_ROBOT, 12.0, 6.5, 0.0, 0.0, kRobotRadius_m);
    m.humans[0] =
        agent(kHumanId, agent_state_t::KIND_HUMAN, human_x, 6.9, M_PI, 0.0, kHumanRadius_m);
    return m;
  };
  ASSERT_TRUE(step(at(0, 13.6)));
  ASSERT_TRUE(step(at(1, 13.6)));
  const double planned_m_s = std::hypot(probe_.cmds[1].vx_m_s, probe_.cmds[1].vy_m_s);
  robot_action_t go{};
  go.utime = at(1, 13.6).utime;
  go.step = 1;
  go.action = robot_action_t::ACTION_GO_FIRST;
  go.human_id = kHumanId;
  go.reason = "test";
  probe_.rt.publish(channels::kRobotAction, go);
  probe_.rt.spinFor(20);
  ASSERT_TRUE(step(at(2, 13.6)));
  const velocity_command_t& c = probe_.cmds[2];
  EXPECT_EQ(c.mode, velocity_command_t::MODE_NAVIGATING);
  const double speed = std::hypot(c.vx_m_s, c.vy_m_s);
  // From rest the planner's band starts slower than going first (acceleration-limited).
  ASSERT_LT(planned_m_s, 0.3);
  EXPECT_GT(speed, planned_m_s);
  // To the right, away from the person on the left: sideways or turning.
  EXPECT_TRUE(c.vy_m_s < 0.0 || c.omega_rad_s < 0.0) << c.vy_m_s << " " << c.omega_rad_s;
  EXPECT_GT(c.vx_m_s, 0.0);
  EXPECT_LE(speed, 0.3 + 1e-6);
  // The person is passed (behind the robot): going first ends.
  ASSERT_TRUE(step(at(3, 10.0)));
  ASSERT_TRUE(step(at(4, 10.0)));
  EXPECT_EQ(probe_.cmds[4].mode, velocity_command_t::MODE_NAVIGATING);
}

TEST_F(BandSourceNodeTest, SigtermStopsWithinOneSecondExitZero) {
  ASSERT_TRUE(step(headOnStates(0)));
  dut_->signal(SIGTERM);
  EXPECT_EQ(dut_->waitExit(milliseconds(1000)), 0);
}

// Goals withheld (a tracker gives positions only): the human walks down open.pgm's narrow
// corridor off its centre line; the map file's section annotates the corridor mouths. The band
// source names the mouth ahead and plans the human to it in its own lane, not to its centre.
TEST(BandSourceGoalInferenceTest, AWithheldGoalIsInferredAndTheReferencePathKeepsTheLane) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string map = (dir / ("band_source_gi_map_" + std::to_string(::getpid()) + ".yaml"));
  std::ofstream(map) << "map:\n  file: " << ::coopnav::test::testDataDir() << "/maps/open.yaml\n"
                     << "  goal_regions:\n"
                     << "    - {x0_m: 9.65, y0_m: 0.45, x1_m: 9.65, y1_m: 2.70}\n"
                     << "    - {x0_m: 35.30, y0_m: 0.45, x1_m: 35.30, y1_m: 2.70}\n";
  const std::string config = (dir / ("band_source_gi_" + std::to_string(::getpid()) + ".yaml"));
  std::ofstream(config) << "map_file: " << map << "\nstep_gate_timeout_s: 0.5\n";
  Probe probe;
  std::vector<goal_estimates_t> estimates;
  probe.rt.subscribe<goal_estimates_t>(
      channels::kGoalEstimates,
      [&](const goal_estimates_t& m, std::int64_t) { estimates.push_back(m); });
  test::ChildProcess dut(test::daemonPath("band_source"),
                         {"--config", config, "--lcm-url", test::testLcmUrl()});
  ASSERT_TRUE(probe.waitFor([&] { return probe.status.has_value(); }));
  goals_t g = headOnGoals();  // the robot's goal only
  g.goals.resize(1);
  g.num_goals = 1;
  probe.rt.publish(channels::kGoals, g);
  probe.rt.spinFor(20);
  constexpr double kLane_m = 1.2;  // the corridor's centre line is y 1.575
  constexpr int kSteps = 20;       // 2 m walked
  for (std::int64_t k = 0; k < kSteps; ++k) {
    agent_states_t m = headOnStates(k, 12.0, 30.0);
    m.humans[0].y_m = kLane_m;
    probe.rt.publish(channels::kAgentStates, m);
    ASSERT_TRUE(probe.waitFor([&] { return probe.acks.count(k) > 0; })) << k;
  }
  std::filesystem::remove(config);
  std::filesystem::remove(map);
  ASSERT_FALSE(estimates.empty());
  const goal_estimates_t& e = estimates.back();
  ASSERT_EQ(e.num_goals, 2);
  ASSERT_EQ(e.num_humans, 1);
  EXPECT_EQ(e.humans[0].agent_id, kHumanId);
  EXPECT_EQ(e.humans[0].most_likely, 0);  // the mouth ahead (x 9.65), published by its centre
  EXPECT_NEAR(e.goal_x_m[0], 9.65, 1e-9);
  EXPECT_NEAR(e.goal_y_m[0], 1.575, 1e-9);
  EXPECT_GT(e.humans[0].probability[0], 0.9f);
  // The reference path in force ends where the human crosses the mouth in its lane.
  ASSERT_FALSE(probe.refs.empty());
  const reference_paths_t& r = probe.refs.back();
  ASSERT_EQ(r.num_paths, 1);
  const auto& path = r.paths[0];
  ASSERT_GE(path.num_points, 2);
  EXPECT_NEAR(path.x_m[path.num_points - 1], 9.65, 0.15);
  EXPECT_NEAR(path.y_m[path.num_points - 1], kLane_m, 0.15);
}

std::string run(const std::string& command) {
  std::string out;
  FILE* f = ::popen(command.c_str(), "r");
  if (!f) return out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, f)) {
    if (std::string(buf).rfind("map_file:", 0) != 0) out += buf;  // resolved per config dir
  }
  ::pclose(f);
  return out;
}

// The shipped file lists every default, except the settings it deliberately overrides (each
// explained in the file): warm_start off, as CoHAN runs it.
TEST(BandSourceConfigTest, ShippedConfigListsTheDefaultsAndLoads) {
  const std::string exe = test::daemonPath("band_source");
  const std::string defaults = run(exe + " --set planner.warm_start=false --print-config");
  const std::string shipped = run(exe + " --config " + ::coopnav::test::sourceDir() +
                                  "/config/band_source.yaml --print-config");
  ASSERT_NE(defaults.find("planner:"), std::string::npos);
  EXPECT_EQ(shipped, defaults);
}

}  // namespace
}  // namespace coopnav
