/// Closed-loop acceptance of the dual-band planner: every 0.1 s the robot integrates
/// its command and the human moves (straight at 1 m/s, or along its anticipated band), and the
/// planner runs again warm-started, as band_source does at 10 Hz in lockstep (iteration budget
/// only). Head-on in the 6 m corridor of open.pgm and in the 2.25 m corridor.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include "analytic_map.hpp"
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

enum class HumanMotion { kStraight, kAlongBand };

struct Scenario {
  Eigen::Vector2d robot_start;
  Eigen::Vector2d robot_goal;
  Eigen::Vector2d human_start;
  Eigen::Vector2d human_goal;
  HumanMotion motion{HumanMotion::kStraight};
  double max_time_s{60.0};
};

struct RunLog {
  bool reached_goal{false};
  double goal_time_s{std::numeric_limits<double>::quiet_NaN()};
  /// First time the robot is level with the human along the corridor (x), NaN if never.
  double crossing_time_s{std::numeric_limits<double>::quiet_NaN()};
  double path_until_crossing_m{0.0};
  double min_centre_distance_m{std::numeric_limits<double>::infinity()};
  double min_wall_distance_m{std::numeric_limits<double>::infinity()};  ///< centre to wall
  double max_band_offset_m{0.0};  ///< robot band's largest |y − start y| over all cycles
  std::size_t first_band_poses{0};
  double first_band_duration_s{0.0};
  int failed_cycles{0};
};

Eigen::Vector2d bodyToWorld(const Velocity2& body, double th) {
  return {std::cos(th) * body.vx_m_s - std::sin(th) * body.vy_m_s,
          std::sin(th) * body.vx_m_s + std::cos(th) * body.vy_m_s};
}

/// Smallest distance between two points moving linearly over one cycle.
double minDistanceOverStep(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1,
                           const Eigen::Vector2d& b0, const Eigen::Vector2d& b1) {
  const Eigen::Vector2d d0 = a0 - b0;
  const Eigen::Vector2d dd = (a1 - b1) - d0;
  const double den = dd.squaredNorm();
  const double s = den > 1e-12 ? std::clamp(-d0.dot(dd) / den, 0.0, 1.0) : 0.0;
  return (d0 + s * dd).norm();
}

RunLog runClosedLoop(const std::shared_ptr<const DistanceMap>& map, const Scenario& sc,
                     const BandPlannerConfig& cfg = {}, bool verbose = false) {
  DualBandPlanner planner(cfg, map);
  RunLog log;
  AgentState robot = test::makeAgent(0, AgentKind::kRobot, sc.robot_start.x(), sc.robot_start.y(),
                                     0.0, 0.0, kRobotRadius_m);
  const Eigen::Vector2d hdir = (sc.human_goal - sc.human_start).normalized();
  AgentState human =
      test::makeAgent(1, AgentKind::kHuman, sc.human_start.x(), sc.human_start.y(),
                      std::atan2(hdir.y(), hdir.x()), kHumanSpeed_m_s, kHumanRadius_m);
  const double dir_x = sc.robot_goal.x() > sc.robot_start.x() ? 1.0 : -1.0;
  double t = 0.0;
  for (int cycle = 0; t < sc.max_time_s; ++cycle, t += kCycle_s) {
    PlanRequest req;
    req.stamp_s = t;
    req.agent = robot;
    req.goal = {sc.robot_goal.x(), sc.robot_goal.y(), 0.0};
    const bool human_active = (sc.human_goal - human.pose.position()).norm() > 0.05;
    if (human_active) {
      OtherAgentInput o;
      o.state = human;
      o.goal = {sc.human_goal.x(), sc.human_goal.y(), human.pose.theta_rad};
      req.others.push_back(o);
    }
    const PlanResult r = planner.plan(req);
    if (r.status == PlanStatus::kGoalReached) {
      log.reached_goal = true;
      log.goal_time_s = t;
      break;
    }
    if (r.status != PlanStatus::kOk) {
      ++log.failed_cycles;
    }
    if (cycle == 0) {
      log.first_band_poses = r.agent_band.poses.size();
      log.first_band_duration_s = r.agent_band.poses.back().t_s;
    }
    for (const auto& p : r.agent_band.poses) {
      log.max_band_offset_m =
          std::max(log.max_band_offset_m, std::abs(p.pose.y_m - sc.robot_start.y()));
    }
    if (verbose && cycle % 10 == 0) {
      std::printf(
          "t %5.1f robot (%6.2f %5.2f) v %.2f human (%6.2f %5.2f) band %zu poses %.1f s it %d", t,
          robot.pose.x_m, robot.pose.y_m, std::hypot(robot.velocity.vx_m_s, robot.velocity.vy_m_s),
          human.pose.x_m, human.pose.y_m, r.agent_band.poses.size(),
          r.agent_band.poses.empty() ? 0.0 : r.agent_band.poses.back().t_s, r.iterations);
      if (!r.others.empty()) std::printf(" hband %zu", r.others[0].band.poses.size());
      for (const auto& tc : r.term_costs) std::printf(" %s=%.3g", tc.name.c_str(), tc.cost);
      std::printf("\n");
    }
    // --- move the agents one cycle ---
    const Eigen::Vector2d r0 = robot.pose.position();
    const Eigen::Vector2d v_r = bodyToWorld(r.command_body, robot.pose.theta_rad);
    robot.pose.x_m += v_r.x() * kCycle_s;
    robot.pose.y_m += v_r.y() * kCycle_s;
    robot.pose.theta_rad = wrapAngle(robot.pose.theta_rad + r.command_body.omega_rad_s * kCycle_s);
    robot.velocity = {v_r.x(), v_r.y(), r.command_body.omega_rad_s};
    const Eigen::Vector2d h0 = human.pose.position();
    Eigen::Vector2d h1 = h0;
    if (human_active) {
      if (sc.motion == HumanMotion::kStraight || r.others.empty()) {
        const Eigen::Vector2d to_goal = sc.human_goal - h0;
        const double step = std::min(kHumanSpeed_m_s * kCycle_s, to_goal.norm());
        h1 = h0 + to_goal.normalized() * step;
      } else {
        h1 = test::positionAt(r.others[0].band, kCycle_s);
      }
    }
    const Eigen::Vector2d v_h = (h1 - h0) / kCycle_s;
    human.pose.x_m = h1.x();
    human.pose.y_m = h1.y();
    if (v_h.norm() > 0.1) human.pose.theta_rad = std::atan2(v_h.y(), v_h.x());
    human.velocity = {v_h.x(), v_h.y(), 0.0};
    // --- measure ---
    const Eigen::Vector2d r1 = robot.pose.position();
    log.min_centre_distance_m =
        std::min(log.min_centre_distance_m, minDistanceOverStep(r0, r1, h0, h1));
    log.min_wall_distance_m = std::min(log.min_wall_distance_m, map->nearest(r1).distance_m);
    if (std::isnan(log.crossing_time_s)) {
      log.path_until_crossing_m += (r1 - r0).norm();
      if (dir_x * (r1.x() - h1.x()) >= 0.0) log.crossing_time_s = t + kCycle_s;
    }
  }
  {  // one summary line per run: the figures behind the assertions
    std::printf(
        "reached %d at %.1f s, crossing %.1f s after %.2f m (mean %.2f m/s), min centre %.2f m, "
        "min wall %.2f m, band offset %.2f m, first band %zu poses %.1f s, failed %d\n",
        log.reached_goal, log.goal_time_s, log.crossing_time_s, log.path_until_crossing_m,
        log.path_until_crossing_m / log.crossing_time_s, log.min_centre_distance_m,
        log.min_wall_distance_m, log.max_band_offset_m, log.first_band_poses,
        log.first_band_duration_s, log.failed_cycles);
  }
  return log;
}

std::shared_ptr<const DistanceMap> openPgm() {
  static const std::shared_ptr<const DistanceMap> map = [] {
    LoadedMap loaded = loadMap(::coopnav::test::testDataDir() + "/maps/open.yaml");
    // As band_source ships it: unknown cells (the hollow pillar) are obstacles.
    return std::make_shared<GridDistanceField>(std::move(loaded.grid), UnknownPolicy::kObstacle);
  }();
  return map;
}

/// Acceptance: speed until the crossing, passing distance, wall clearance, goal.
void expectCohanLikePass(const RunLog& log) {
  ASSERT_EQ(log.failed_cycles, 0);
  ASSERT_FALSE(std::isnan(log.crossing_time_s)) << "the robot never passed the human";
  // CoHAN's robot keeps moving (~0.5-0.7 m/s) and bends aside instead of waiting.
  EXPECT_GE(log.path_until_crossing_m / log.crossing_time_s, 0.45);
  EXPECT_GE(log.min_centre_distance_m, kRobotRadius_m + kHumanRadius_m + 0.2);
  EXPECT_GE(log.min_wall_distance_m, kRobotRadius_m);
  EXPECT_TRUE(log.reached_goal);
}

Scenario openHeadOn(HumanMotion motion) {
  // The daemon author's case: robot (6.5, 6.5) -> (20.5, 6.5) in the 6 m upper corridor of
  // open.pgm, the human walking the reverse at 1 m/s.
  Scenario sc;
  sc.robot_start = {6.5, 6.5};
  sc.robot_goal = {20.5, 6.5};
  sc.human_start = {20.5, 6.5};
  sc.human_goal = {6.5, 6.5};
  sc.motion = motion;
  return sc;
}

TEST(ClosedLoopTest, OpenCorridorHeadOnStraightHumanRobotKeepsMovingAndPassesAside) {
  // Given a human who walks straight on at 1 m/s whatever the robot does,
  // when the robot runs its planner in closed loop at 10 Hz,
  const RunLog log = runClosedLoop(openPgm(), openHeadOn(HumanMotion::kStraight));
  // then it keeps moving, passes with a margin, and reaches its goal.
  expectCohanLikePass(log);
  EXPECT_GT(log.max_band_offset_m, 0.5);
}

TEST(ClosedLoopTest, OpenCorridorHeadOnHumanAlongAnticipatedBand) {
  const RunLog log = runClosedLoop(openPgm(), openHeadOn(HumanMotion::kAlongBand));
  expectCohanLikePass(log);
}

// What this guards against (band_source README, "The problem": why bands start cold): cold-started
// every cycle, as band_source runs, the band was laid on the path from a robot already beside it,
// so its first segment (the command) pointed back at the path, the optimiser slowed the band to
// keep that segment within the limits, and the robot crept towards the human (0.31 m/s on average
// until the crossing, against 0.58 m/s warm-started).
TEST(ClosedLoopTest, ColdStartedAsBandSourceTheRobotKeepsMovingPastAStraightHuman) {
  BandPlannerConfig cfg;
  cfg.warm_start = false;
  const RunLog log = runClosedLoop(openPgm(), openHeadOn(HumanMotion::kStraight), cfg);
  expectCohanLikePass(log);
}

TEST(ClosedLoopTest, ColdStartedDifferentialDriveRobotKeepsMovingPastAStraightHuman) {
  // The same for a differential-drive robot (it turns to move aside): before the cold-start fix
  // it averaged 0.18 m/s until the crossing and reached its goal at 37.6 s, after it 0.44 m/s
  // and 24.1 s.
  BandPlannerConfig cfg;
  cfg.warm_start = false;
  cfg.robot.holonomic = false;
  cfg.robot.max_vel_y_m_s = 0.0;
  const RunLog log = runClosedLoop(openPgm(), openHeadOn(HumanMotion::kStraight), cfg);
  ASSERT_EQ(log.failed_cycles, 0);
  ASSERT_FALSE(std::isnan(log.crossing_time_s));
  EXPECT_GE(log.path_until_crossing_m / log.crossing_time_s, 0.4);
  EXPECT_GE(log.min_centre_distance_m, kRobotRadius_m + kHumanRadius_m + 0.2);
  EXPECT_GE(log.min_wall_distance_m, kRobotRadius_m);
  EXPECT_TRUE(log.reached_goal);
}

TEST(ClosedLoopTest, OpenCorridorFirstBandHasCohanSize) {
  // The reported bug: a first band of 6.75 m over 17.9 s with 141-180 poses. Expected ~77
  // poses at 0.7 m/s and dt_ref 0.125 s, plus the acceleration ramp from standstill and some
  // slowing where the bands meet.
  const RunLog log = runClosedLoop(openPgm(), [] {
    Scenario sc = openHeadOn(HumanMotion::kStraight);
    sc.max_time_s = 0.05;  // one cycle
    return sc;
  }());
  EXPECT_LE(log.first_band_duration_s, 14.0);
  EXPECT_LE(log.first_band_poses, 115u);
}

TEST(ClosedLoopTest, NarrowCorridorHeadOnRobotMovesAsideWithoutCollision) {
  // Given the 2.25 m lower corridor of open.pgm (y 0.45-2.70) and a head-on human who follows
  // the band the robot anticipates for it,
  Scenario sc;
  sc.robot_start = {11.0, 1.575};
  sc.robot_goal = {30.0, 1.575};
  sc.human_start = {25.0, 1.575};
  sc.human_goal = {11.0, 1.575};
  sc.motion = HumanMotion::kAlongBand;
  const RunLog log = runClosedLoop(openPgm(), sc);
  // then the robot band moves to one side and nobody collides.
  ASSERT_EQ(log.failed_cycles, 0);
  EXPECT_GT(log.max_band_offset_m, 0.25);
  EXPECT_GE(log.min_centre_distance_m, kRobotRadius_m + kHumanRadius_m);
  EXPECT_GE(log.min_wall_distance_m, kRobotRadius_m);
  EXPECT_TRUE(log.reached_goal);
}

}  // namespace
}  // namespace coopnav
