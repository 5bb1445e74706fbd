// The band source's control cycle (lib/band/band_cycle.hpp) without a bus: goal choice, the
// dialogue's actions through the mode machine and the human a dock is for, the command's mode,
// reference paths and their revisions, the planner's memory bounded.
#include "coopnav/band/band_cycle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "analytic_map.hpp"
#include "band_test_util.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

constexpr double kY = 1.575;               // centre line of the 2.25 m corridor
constexpr std::int64_t kStepUs = 100'000;  // 10 Hz

BandCycleConfig cycleConfig() {
  BandCycleConfig c;
  c.max_iterations = 8;  // cheap: what is tested is the cycle around the planner
  c.reference_paths_republish_s = 1.0;
  c.goal_min_walked_m = 1.0;
  c.goal_switch_margin_m = 1.0;
  c.forget_after_s = 60.0;
  c.max_ids = 256;
  return c;
}

class BandCycleTest : public ::testing::Test {
 protected:
  explicit BandCycleTest(BandCycleConfig config = cycleConfig())
      : cycle_(config, BoxMap::corridor(0.0, 20.0, 0.45, 2.70), nullptr, {}) {}

  /// Step k: the robot at x_r heading +x, human 1 at x_h walking -x at 1 m/s.
  BandCycleInput input(std::int64_t k, double x_r, double x_h, bool goals = true) const {
    BandCycleInput in;
    in.utime = 1'000'000'000 + k * kStepUs;
    in.step = k;
    in.robot = test::makeAgent(0, AgentKind::kRobot, x_r, kY, 0.0, 0.5, 0.34);
    if (x_h > 0.0)
      in.humans.push_back(test::makeAgent(1, AgentKind::kHuman, x_h, kY, M_PI, 1.0, 0.3));
    if (goals) {
      in.goals.emplace();
      // Another robot's goal first: the robot's own id is preferred.
      in.goals->push_back({7, AgentKind::kRobot, {5.0, kY, 0.0}});
      in.goals->push_back({0, AgentKind::kRobot, {17.0, kY, 0.0}});
      in.goals->push_back({1, AgentKind::kHuman, {1.0, kY, M_PI}});
    }
    return in;
  }

  static bool noted(const BandCycleOutput& out, const std::string& text) {
    for (const auto& n : out.notes)
      if (n.text.find(text) != std::string::npos) return true;
    return false;
  }

  BandCycle cycle_;
};

TEST_F(BandCycleTest, WithoutAGoalTheRobotIsIdleAndAnActionIsIgnored) {
  BandCycleInput in = input(0, 3.0, 9.0, /*goals=*/false);
  in.action = CycleAction{true, 1};
  const BandCycleOutput out = cycle_.step(in);
  EXPECT_TRUE(out.idle);
  EXPECT_EQ(out.command_body.vx_m_s, 0.0);
  EXPECT_EQ(out.command_body.omega_rad_s, 0.0);
  EXPECT_TRUE(noted(out, "robot action ignored: the robot has no goal"));
  EXPECT_TRUE(noted(out, "humans without a goal (constant-velocity band, no reference path): 1"));
  EXPECT_FALSE(out.reference_paths);  // no goal for the human: no reference path
  EXPECT_EQ(cycle_.cycles(), 1);
}

TEST_F(BandCycleTest, TheRobotsOwnGoalIsPlannedToAndTheHumansGivenGoalGivesAReferencePath) {
  const BandCycleOutput out = cycle_.step(input(0, 3.0, 9.0));
  EXPECT_FALSE(out.idle);
  EXPECT_FALSE(out.stopped);
  EXPECT_EQ(out.mode, RobotMode::kNavigate);
  // Towards (17, y), not the other robot's (5, y): the band ends near the own goal's side.
  ASSERT_FALSE(out.plan.agent_band.poses.empty());
  EXPECT_GT(out.plan.agent_band.poses.back().pose.x_m, 5.5);
  EXPECT_GT(out.command_body.vx_m_s, 0.0);
  ASSERT_TRUE(out.reference_paths);
  ASSERT_EQ(out.reference_paths->size(), 1U);
  EXPECT_EQ((*out.reference_paths)[0].agent_id, 1);
  EXPECT_EQ((*out.reference_paths)[0].revision, 1);
  ASSERT_EQ(out.room_plans.size(), out.plan.others.size());
  // The same reference path is not published again until reference_paths_republish_s (1 s).
  int republished_at = -1;
  for (std::int64_t k = 1; k <= 10 && republished_at < 0; ++k) {
    const BandCycleOutput o = cycle_.step(input(k, 3.0, 9.0));
    if (o.reference_paths) {
      republished_at = static_cast<int>(k);
      ASSERT_EQ(o.reference_paths->size(), 1U);
      EXPECT_EQ((*o.reference_paths)[0].revision, 1);  // unchanged, as the human stood still
    }
  }
  EXPECT_EQ(republished_at, 10);
  // The human gone: its reference path is withdrawn at once.
  const BandCycleOutput gone = cycle_.step(input(11, 3.0, -1.0));
  ASSERT_TRUE(gone.reference_paths);
  EXPECT_TRUE(gone.reference_paths->empty());
}

TEST_F(BandCycleTest, ADockIsForTheHumanItWasAskedForUntilAResume) {
  cycle_.step(input(0, 3.0, 9.0));
  // A DOCK for someone not in the scene changes nothing.
  BandCycleInput stray = input(1, 3.0, 8.9);
  stray.action = CycleAction{true, 42};
  const BandCycleOutput ignored = cycle_.step(stray);
  EXPECT_TRUE(noted(ignored, "DOCK for human 42 who is not in the agent states: ignored"));
  EXPECT_EQ(ignored.mode, RobotMode::kNavigate);
  // A DOCK for human 1 ahead and closing: the robot makes room for it, and goes on doing so on
  // the next cycles without a new action (the dock is tracked to human 1).
  BandCycleInput dock = input(2, 3.0, 8.8);
  dock.action = CycleAction{true, 1};
  const BandCycleOutput docking = cycle_.step(dock);
  EXPECT_NE(docking.mode, RobotMode::kNavigate);
  EXPECT_TRUE(noted(docking, "for human 1, room: "))
      << (docking.notes.empty() ? "" : docking.notes[0].text);
  const BandCycleOutput still = cycle_.step(input(3, 3.0, 8.7));
  EXPECT_NE(still.mode, RobotMode::kNavigate);
  // A RESUME for someone else (the end of their slowing) leaves it in place ...
  BandCycleInput other = input(4, 3.0, 8.6);
  other.action = CycleAction{false, 2};
  EXPECT_NE(cycle_.step(other).mode, RobotMode::kNavigate);
  // ... a RESUME for human 1 ends it.
  BandCycleInput resume = input(5, 3.0, 8.5);
  resume.action = CycleAction{false, 1};
  const BandCycleOutput resumed = cycle_.step(resume);
  EXPECT_TRUE(resumed.mode == RobotMode::kResuming || resumed.mode == RobotMode::kNavigate)
      << toString(resumed.mode);
}

// SLOW (the dialogue's make_time): the command's speed is capped at slow.speed_m_s, its direction
// and curvature kept, until the next action; a SLOW for someone not tracked ends at once.
TEST_F(BandCycleTest, ASlowCapsTheCommandUntilTheNextAction) {
  const double cap = cycleConfig().slow.speed_m_s;
  const auto speed = [](const Velocity2& v) { return std::hypot(v.vx_m_s, v.vy_m_s); };
  BandCycle free_cycle(cycleConfig(), BoxMap::corridor(0.0, 20.0, 0.45, 2.70), nullptr, {});
  const Velocity2 full = free_cycle.step(input(0, 3.0, 9.0)).command_body;
  ASSERT_GT(speed(full), cap + 0.05);  // the test means something
  BandCycleInput slow = input(0, 3.0, 9.0);
  slow.action = CycleAction{false, 1, false, true};
  const BandCycleOutput slowed = cycle_.step(slow);
  EXPECT_EQ(slowed.mode, RobotMode::kNavigate);
  EXPECT_NEAR(speed(slowed.command_body), cap, 1e-9);
  EXPECT_NEAR(slowed.command_body.omega_rad_s * speed(full),
              full.omega_rad_s * speed(slowed.command_body), 1e-9);
  EXPECT_LE(speed(cycle_.step(input(1, 3.0, 8.9)).command_body), cap + 1e-9);
  BandCycleInput resume = input(2, 3.0, 8.8);
  resume.action = CycleAction{false, 1};
  EXPECT_GT(speed(cycle_.step(resume).command_body), cap + 0.05);
  BandCycleInput stray = input(3, 3.0, 8.7);
  stray.action = CycleAction{false, 42, false, true};
  const BandCycleOutput ended = cycle_.step(stray);
  EXPECT_TRUE(noted(ended, "slowing for human 42 ends at step 3: the person is not tracked"));
  EXPECT_GT(speed(ended.command_body), cap + 0.05);
}

class BandCycleMemoryTest : public BandCycleTest {
 protected:
  static BandCycleConfig small() {
    BandCycleConfig c = cycleConfig();
    c.max_ids = 3;
    return c;
  }
  BandCycleMemoryTest() : BandCycleTest(small()) {}
};

TEST_F(BandCycleMemoryTest, MoreAgentIdsThanMaxIdsClearThePlannersMemory) {
  // The robot and human 1, then humans 2 and 3 each once: the fourth id is one too many.
  cycle_.step(input(0, 3.0, 9.0, false));
  EXPECT_EQ(cycle_.plannerIdsKept(), 2U);
  BandCycleInput in = input(1, 3.0, 9.0, false);
  in.humans.push_back(test::makeAgent(2, AgentKind::kHuman, 12.0, 1.0, M_PI, 1.0, 0.3));
  cycle_.step(in);
  EXPECT_EQ(cycle_.plannerIdsKept(), 3U);
  in = input(2, 3.0, 9.0, false);
  in.humans.push_back(test::makeAgent(3, AgentKind::kHuman, 14.0, 2.0, M_PI, 1.0, 0.3));
  const BandCycleOutput out = cycle_.step(in);
  EXPECT_TRUE(noted(out, "planner memory of 4 agents cleared (more than limits.max_ids)"));
  EXPECT_EQ(cycle_.plannerIdsKept(), 0U);
}

}  // namespace
}  // namespace coopnav
