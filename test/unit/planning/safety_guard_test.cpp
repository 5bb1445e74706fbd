// The last safety layer: unchanged far from people, scaled or stopped when the command would
// close on a human, evading a human who closes on a robot at rest when there is room.
#include "coopnav/planning/safety_guard.hpp"

#include <gtest/gtest.h>

#include "../band/analytic_map.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

constexpr double kRobotRadius_m = 0.47;
constexpr double kHumanRadius_m = 0.3;

std::shared_ptr<BoxMap> open() { return BoxMap::corridor(-20.0, 20.0, -20.0, 20.0); }

GuardInput robotAtOrigin(const Velocity2& cmd) {
  GuardInput in;
  in.robot = {0.0, 0.0, 0.0};
  in.robot_radius_m = kRobotRadius_m;
  in.command_body = cmd;
  return in;
}

GuardHuman human(double x, double y, double vx, double vy) {
  return {{x, y}, {vx, vy}, kHumanRadius_m};
}

/// World velocity of a body-frame command of a robot at heading theta.
Eigen::Vector2d world(const Velocity2& v, double theta) {
  return {std::cos(theta) * v.vx_m_s - std::sin(theta) * v.vy_m_s,
          std::sin(theta) * v.vx_m_s + std::cos(theta) * v.vy_m_s};
}

TEST(SafetyGuardTest, FarFromHumansTheCommandIsReturnedBitForBit) {
  const auto map = open();
  const Velocity2 cmd{0.6180339887, -0.1234567, 0.3141592};
  GuardInput in = robotAtOrigin(cmd);
  EXPECT_EQ(guardCommand(*map, in, {}).command_body, cmd);                // nobody
  in.humans = {human(8.0, 1.0, -1.0, 0.0), human(-3.0, 0.0, -1.0, 0.0)};  // ahead far, behind
  const GuardOutput g = guardCommand(*map, in, {});
  EXPECT_EQ(g.command_body, cmd);
  EXPECT_EQ(g.action, GuardAction::kNone);
  // A human near but walking past in parallel (gap 0.6 m) changes nothing either.
  in.humans = {human(0.5, 1.37, 0.6, 0.0)};
  EXPECT_EQ(guardCommand(*map, in, {}).command_body, cmd);
}

TEST(SafetyGuardTest, ACommandClosingOnAHumanIsScaledToKeepTheClearance) {
  const auto map = open();
  GuardOptions o;  // 0.2 m over 1 s
  // A standing human 1.5 m ahead: gap 0.73 m; 0.7 m/s for 1 s would leave 0.03 m.
  GuardInput in = robotAtOrigin({0.7, 0.0, 0.0});
  in.humans = {human(1.5, 0.0, 0.0, 0.0)};
  const GuardOutput g = guardCommand(*map, in, o);
  EXPECT_EQ(g.action, GuardAction::kSlowed);
  EXPECT_NEAR(g.scale, (0.73 - o.min_clearance_m) / 0.7, 1e-3);
  EXPECT_LE(g.scale, (0.73 - o.min_clearance_m) / 0.7 + 1e-12);
  EXPECT_NEAR(g.command_body.vx_m_s, 0.7 * g.scale, 1e-12);
  // A human walking at the robot: the robot's share of the closing is what is cut.
  in.humans = {human(2.5, 0.0, -1.0, 0.0)};
  const GuardOutput w = guardCommand(*map, in, o);
  EXPECT_EQ(w.action, GuardAction::kSlowed);
  EXPECT_LT(w.command_body.vx_m_s, 0.7);
}

TEST(SafetyGuardTest, ACommandIntoAHumanAlreadyWithinTheClearanceIsStopped) {
  const auto map = open();
  GuardInput in = robotAtOrigin({0.5, 0.2, 0.0});
  in.humans = {human(0.95, 0.0, 0.0, 0.0)};  // gap 0.18 < 0.2
  const GuardOutput g = guardCommand(*map, in, {});
  EXPECT_EQ(g.action, GuardAction::kStopped);
  EXPECT_EQ(g.command_body, Velocity2{});
  // Moving away from it is fine as it is.
  in.command_body = {-0.3, 0.0, 0.0};
  EXPECT_EQ(guardCommand(*map, in, {}).action, GuardAction::kNone);
}

TEST(SafetyGuardTest, AHumanClosingOnARobotAtRestMakesItMoveAwayWhenThereIsRoom) {
  const auto map = open();
  GuardInput in = robotAtOrigin({});
  in.humans = {human(1.2, 0.0, -1.0, 0.0)};  // gap 0.43 m, closing at 1 m/s
  const GuardOutput g = guardCommand(*map, in, {});
  ASSERT_EQ(g.action, GuardAction::kEvading);
  const Eigen::Vector2d v = world(g.command_body, in.robot.theta_rad);
  EXPECT_LT(v.x(), 0.0);  // away from the human
  EXPECT_GT(v.norm(), 0.3);
  // Within the limits (holonomic: backwards at most 0.4, sideways at most 0.7).
  EXPECT_GE(g.command_body.vx_m_s, -in.limits.max_backward_m_s - 1e-12);
  EXPECT_LE(std::abs(g.command_body.vy_m_s), in.limits.max_lateral_m_s + 1e-12);
  // A differential drive backs straight away.
  in.limits.holonomic = false;
  const GuardOutput d = guardCommand(*map, in, {});
  ASSERT_EQ(d.action, GuardAction::kEvading);
  EXPECT_NEAR(d.command_body.vx_m_s, -in.limits.max_backward_m_s, 1e-12);
  EXPECT_EQ(d.command_body.vy_m_s, 0.0);
  EXPECT_EQ(d.command_body.omega_rad_s, 0.0);
}

TEST(SafetyGuardTest, WithAWallBehindAHolonomicRobotEvadesSidewaysToTheFreeSide) {
  // A wall 0.55 m behind the robot's centre and one 0.6 m to its right: only to its left.
  auto map = open();
  map->addBox({Eigen::Vector2d(-3.0, -3.0), Eigen::Vector2d(-0.55, 3.0)});
  map->addBox({Eigen::Vector2d(-3.0, -3.0), Eigen::Vector2d(3.0, -0.6)});
  GuardInput in = robotAtOrigin({});
  in.humans = {human(1.2, -0.1, -1.0, 0.0)};
  const GuardOutput g = guardCommand(*map, in, {});
  ASSERT_EQ(g.action, GuardAction::kEvading);
  const Eigen::Vector2d v = world(g.command_body, 0.0);
  EXPECT_GT(v.y(), 2.0 * std::abs(v.x()));  // sideways, to the free side
}

// An evasion is held to the scaling's rule: it never moves the robot towards a human within the
// clearance. A differential drive turned across the corridor (docking) whose heading points
// half at a person walking in must not drive forwards into them to get out of their lane; a
// holonomic robot by a wall must not slide towards a person squeezing past it.
TEST(SafetyGuardTest, AnEvasionNeverMovesTowardsAHumanWithinTheClearance) {
  const auto map = open();
  for (const double theta : {M_PI / 4.0, -M_PI / 4.0, M_PI / 3.0}) {
    GuardInput in;
    in.robot = {0.0, 0.0, theta};
    in.robot_radius_m = kRobotRadius_m;
    in.limits.holonomic = false;
    const GuardHuman h = human(1.0, -0.2 * std::sin(theta) / std::abs(std::sin(theta)), -1.05,
                               0.0);  // gap 0.25 m, walking in
    in.humans = {h};
    const GuardOutput g = guardCommand(*map, in, {});
    const Eigen::Vector2d v = world(g.command_body, theta);
    EXPECT_LE(v.dot(h.position - in.robot.position()), 1e-9)
        << "theta " << theta << ": " << toString(g.action) << " (" << v.transpose() << ")";
  }
  // Holonomic, 0.09 m off a wall below it, a person passing above it, nearly alongside.
  auto walled = open();
  walled->addBox({Eigen::Vector2d(-3.0, -3.0), Eigen::Vector2d(3.0, -0.56)});
  GuardInput in = robotAtOrigin({});
  const GuardHuman passing = human(-0.2, 0.78, -0.6, 0.1);
  in.humans = {passing};
  const GuardOutput g = guardCommand(*walled, in, {});
  const Eigen::Vector2d v = world(g.command_body, 0.0);
  for (int k = 0; k <= 10; ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector2d r = v * t;
    const Eigen::Vector2d p = passing.position + passing.velocity * t;
    if ((p - r).norm() - kRobotRadius_m - kHumanRadius_m < GuardOptions{}.min_clearance_m) {
      EXPECT_LE(r.dot(p - r), 1e-9) << "t " << t << ": " << toString(g.action);
    }
  }
}

TEST(SafetyGuardTest, WithNoRoomTheRobotStaysPut) {
  // The robot in the closed end of a 1.1 m corridor, a human walking in at it.
  const auto map = BoxMap::corridor(0.0, 30.0, 0.0, 1.1);
  GuardInput in;
  in.robot = {0.55, 0.55, 0.0};
  in.robot_radius_m = kRobotRadius_m;
  in.humans = {human(1.9, 0.55, -1.0, 0.0)};
  const GuardOutput g = guardCommand(*map, in, {});
  EXPECT_NE(g.action, GuardAction::kEvading);
  EXPECT_EQ(g.command_body, Velocity2{});
  // A planner command towards it is stopped, and nothing replaces it.
  in.command_body = {0.3, 0.0, 0.0};
  const GuardOutput s = guardCommand(*map, in, {});
  EXPECT_EQ(s.action, GuardAction::kStopped);
  EXPECT_EQ(s.command_body, Velocity2{});
}

}  // namespace
}  // namespace coopnav

namespace coopnav {
namespace {

// Obstacles of the moment: a laser return closes the command's way as a standing human does.
TEST(SafetyGuardScanTest, ACommandTowardsAScanPointIsScaledToKeepTheClearance) {
  const auto map = test::BoxMap::corridor(-20.0, 20.0, -20.0, 20.0);
  GuardOptions o;
  GuardInput in;
  in.robot = {0.0, 0.0, 0.0};
  in.robot_radius_m = 0.47;
  in.command_body = {0.7, 0.0, 0.0};
  // A box face 1.2 m ahead: gap 0.73 m; 0.7 m/s for 1 s would leave 0.03 m.
  in.obstacle_points = {{1.2, -0.05}, {1.2, 0.0}, {1.2, 0.05}};
  const GuardOutput g = guardCommand(*map, in, o);
  EXPECT_EQ(g.action, GuardAction::kSlowed);
  EXPECT_NEAR(g.scale, (0.73 - o.min_clearance_m) / 0.7, 1e-3);
  EXPECT_LE(g.scale, (0.73 - o.min_clearance_m) / 0.7 + 1e-12);
  // Already within the clearance: stopped; backing off is left alone; a point behind or far to
  // the side changes nothing, bit for bit.
  in.obstacle_points = {{0.6, 0.0}};
  EXPECT_EQ(guardCommand(*map, in, o).action, GuardAction::kStopped);
  in.command_body = {-0.3, 0.0, 0.0};
  EXPECT_EQ(guardCommand(*map, in, o).action, GuardAction::kNone);
  const Velocity2 cmd{0.6180339887, -0.1234567, 0.3141592};
  in.command_body = cmd;
  in.obstacle_points = {{-2.0, 0.0}, {0.3, 3.0}};
  const GuardOutput far = guardCommand(*map, in, o);
  EXPECT_EQ(far.action, GuardAction::kNone);
  EXPECT_EQ(far.command_body, cmd);
}

TEST(SafetyGuardScanTest, AnEvasionFromAHumanDoesNotDriveIntoScanPoints) {
  // A human closing on a robot at rest in open space; then a trolley the map does not hold
  // (its outline as laser returns) where that evasion went: the robot evades elsewhere, keeping
  // its wall margin from the trolley over the horizon.
  const auto map = test::BoxMap::corridor(-20.0, 20.0, -20.0, 20.0);
  GuardOptions o;
  GuardInput in;
  in.robot = {0.0, 0.0, 0.0};
  in.robot_radius_m = 0.47;
  in.humans = {{{1.2, 0.0}, {-1.0, 0.0}, 0.3}};
  const GuardOutput free = guardCommand(*map, in, o);
  ASSERT_EQ(free.action, GuardAction::kEvading);
  const Eigen::Vector2d way = world(free.command_body, 0.0).normalized();
  const Eigen::Vector2d c = way * 0.75;  // the trolley's centre, on that way
  const Eigen::Vector2d side(-way.y(), way.x());
  for (double s = -0.3; s <= 0.3 + 1e-9; s += 0.05) {
    in.obstacle_points.push_back(c + side * s - way * 0.1);
    in.obstacle_points.push_back(c + side * s + way * 0.1);
  }
  const GuardOutput g = guardCommand(*map, in, o);
  ASSERT_EQ(g.action, GuardAction::kEvading);
  const Eigen::Vector2d v = world(g.command_body, 0.0);
  for (int k = 0; k <= 20; ++k) {
    const Eigen::Vector2d r = v * (o.horizon_s * k / 20.0);
    for (const Eigen::Vector2d& q : in.obstacle_points)
      EXPECT_GE((r - q).norm(), in.robot_radius_m + o.evade_wall_margin_m - 2e-3);
  }
}

}  // namespace
}  // namespace coopnav
