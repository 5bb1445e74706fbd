#include "coopnav/planning/dock.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "../band/analytic_map.hpp"
#include "coopnav/distance/point_obstacle_map.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

// 2.25 m corridor along x, y 0.45 .. 2.70 (open.pgm's narrow corridor).
std::shared_ptr<BoxMap> narrow() { return BoxMap::corridor(0.0, 30.0, 0.45, 2.70); }

TEST(DockTest, DocksOnTheSideAwayFromTheHumanWithClearance) {
  auto map = narrow();
  const Pose2 robot{10.0, 1.575, 0.0};
  // Human ahead and slightly to the robot's left → dock right (low y).
  const Pose2 human{14.0, 1.9, M_PI};
  const DockOptions o;
  const DockResult d = findDockPose(*map, robot, human, o);
  ASSERT_EQ(d.status, DockStatus::kOk);
  EXPECT_EQ(d.side, Side::kRight);
  EXPECT_LT(d.pose.y_m, robot.y_m);
  EXPECT_GE(map->nearest(d.pose.position()).distance_m, o.robot_radius_m + o.margin_m - 1e-6);
  EXPECT_NEAR(d.pose.y_m, 0.45 + o.robot_radius_m + o.margin_m, 0.02);
  EXPECT_LE(std::abs(d.pose.x_m - robot.x_m), o.max_ahead_m + 1e-9);
}

TEST(DockTest, HumanOnTheRightGivesLeftDock) {
  auto map = narrow();
  const DockResult d = findDockPose(*map, {10.0, 1.575, 0.0}, {14.0, 1.2, M_PI});
  ASSERT_EQ(d.status, DockStatus::kOk);
  EXPECT_EQ(d.side, Side::kLeft);
  EXPECT_GT(d.pose.y_m, 1.575);
}

TEST(DockTest, DeadAheadKeepsRight) {
  auto map = narrow();
  const DockResult d = findDockPose(*map, {10.0, 1.575, 0.0}, {14.0, 1.575, M_PI});
  ASSERT_EQ(d.status, DockStatus::kOk);
  EXPECT_EQ(d.side, Side::kRight);
}

TEST(DockTest, NoWallInRange) {
  auto map = BoxMap::corridor(0.0, 30.0, 0.0, 30.0);
  DockOptions o;
  o.search_range_m = 2.0;
  EXPECT_EQ(findDockPose(*map, {15.0, 15.0, 0.0}, {18.0, 15.5, M_PI}, o).status,
            DockStatus::kNoWall);
}

TEST(DockTest, ASpotBehindAnUnmappedObstacleIsNotChosen) {
  // Given the corridor and a bench the map does not hold, seen by the laser as a row of returns
  // along y 1.2 from x 8.5 to 11.5, between the robot and the wall on the side away from the human.
  auto map = narrow();
  std::vector<Eigen::Vector2d> bench;
  for (double x = 8.5; x <= 11.5 + 1e-9; x += 0.05) bench.emplace_back(x, 1.2);
  const PointObstacleMap seen(*map, bench);
  const Pose2 robot{10.0, 1.575, 0.0};
  const Pose2 human{14.0, 1.9, M_PI};
  DockOptions o;
  o.robot_radius_m = 0.47;
  const double need_m = o.robot_radius_m + o.margin_m;
  // Then on the static map alone the dock is right behind the bench, flush to the wall,
  const DockResult blind = findDockPose(*map, robot, human, o);
  ASSERT_EQ(blind.status, DockStatus::kOk);
  EXPECT_LT(blind.pose.y_m, 1.2);
  EXPECT_GT(blind.pose.x_m, 8.5);
  EXPECT_LT(blind.pose.x_m, 11.5);
  // And with the returns no spot behind it is chosen: any dock keeps its clearance from them
  // and lies beyond the bench's ends.
  const DockResult d = findDockPose(seen, robot, human, o);
  if (d.status == DockStatus::kOk) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& q : bench) nearest = std::min(nearest, (q - d.pose.position()).norm());
    EXPECT_GE(nearest, need_m - 1e-3);
    EXPECT_TRUE(d.pose.x_m < 8.5 || d.pose.x_m > 11.5 || d.pose.y_m > 1.2)
        << d.pose.x_m << " " << d.pose.y_m;
  } else {
    EXPECT_EQ(d.status, DockStatus::kUnreachable);
  }
}

TEST(DockModeMachineTest, NavigateDockHoldResumeGoal) {
  auto map = narrow();
  DockModeMachine dut;
  ModeInput in;
  in.stamp_s = 0.0;
  in.robot = {10.0, 1.575, 0.0};
  in.goal = {25.0, 1.575, 0.0};
  in.has_human = true;
  in.human = {13.0, 1.9, M_PI};
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kNavigate);
  in.dock_requested = true;
  in.stamp_s = 0.1;
  ModeOutput out = dut.update(*map, in);
  ASSERT_EQ(out.mode, RobotMode::kDocking);
  EXPECT_TRUE(out.changed);
  EXPECT_LT(out.active_goal.y_m, 1.0);
  in.dock_requested = false;
  // Reaches the dock pose → holding, zero velocity.
  in.robot = out.active_goal;
  in.stamp_s = 2.0;
  out = dut.update(*map, in);
  EXPECT_EQ(out.mode, RobotMode::kHolding);
  EXPECT_TRUE(out.hold_still);
  // Human still ahead → keep holding.
  in.human = {11.0, 1.9, M_PI};
  in.stamp_s = 4.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  // Human has passed (robot behind it along its heading) → resuming, then navigate to goal.
  in.human = {9.0, 1.9, M_PI};
  in.stamp_s = 5.0;
  out = dut.update(*map, in);
  EXPECT_EQ(out.mode, RobotMode::kResuming);
  EXPECT_EQ(out.active_goal, in.goal);
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kNavigate);
  in.robot = {25.05, 1.6, 0.0};
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kGoalReached);
}

/// The robot in the narrow corridor heading +x to its goal, a human ahead at x walking towards
/// it, and a dock asked for.
ModeInput dockRequestInNarrow(double human_x_m) {
  ModeInput in;
  in.robot = {10.0, 1.575, 0.0};
  in.goal = {25.0, 1.575, 0.0};
  in.has_human = true;
  in.human = {human_x_m, 1.9, M_PI};
  in.dock_requested = true;
  return in;
}

TEST(DockModeMachineTest, HoldTimesOutAndFailedDockIsReported) {
  auto map = narrow();
  DockModeMachine dut;
  ModeInput in = dockRequestInNarrow(12.0);
  ModeOutput out = dut.update(*map, in);
  ASSERT_EQ(out.mode, RobotMode::kDocking);
  in.dock_requested = false;
  in.robot = out.active_goal;
  in.stamp_s = 1.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  in.stamp_s = 40.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kResuming);

  auto open = BoxMap::corridor(0.0, 30.0, 0.0, 30.0);
  ModeMachineOptions o;
  o.dock.search_range_m = 1.0;
  DockModeMachine dut2(o);
  ModeInput in2 = in;
  in2.robot = {15.0, 15.0, 0.0};
  in2.human = {17.0, 15.5, M_PI};
  in2.dock_requested = true;
  out = dut2.update(*open, in2);
  EXPECT_EQ(out.mode, RobotMode::kNavigate);
  ASSERT_TRUE(out.dock_failure.has_value());
  EXPECT_EQ(*out.dock_failure, DockStatus::kNoWall);
}

TEST(DockModeMachineTest, ADockAskedForWhileTheHumanIsFarWaitsForItToComeAndPass) {
  // Given a dock request with the human 7 m ahead and walking towards the robot (t_CROSS ~4 s).
  auto map = narrow();
  DockModeMachine dut;
  ModeInput in = dockRequestInNarrow(17.0);
  ASSERT_EQ(dut.update(*map, in).mode, RobotMode::kDocking);
  in.dock_requested = false;
  // Then it keeps docking while the human approaches from beyond human_far_m ...
  for (double x = 16.5; x > 11.0; x -= 0.5) {
    in.human.x_m = x;
    in.stamp_s += 0.5;
    EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kDocking) << "human at x = " << x;
  }
  // ... and resumes once it has passed; or, in another run, once it turns and walks away.
  in.human.x_m = 9.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kResuming);
  DockModeMachine dut2;
  in = dockRequestInNarrow(17.0);
  ASSERT_EQ(dut2.update(*map, in).mode, RobotMode::kDocking);
  in.dock_requested = false;
  in.human = {18.0, 1.9, 0.0};
  EXPECT_EQ(dut2.update(*map, in).mode, RobotMode::kResuming);
}

TEST(DockModeMachineTest, HoldingAtTheDockPoseKeepsTheRobotOnItToTheSettleTolerance) {
  // Given a robot that reached its dock within the reached tolerance but 4 cm short of the wall
  // side: every centimetre is taken from the passage it leaves the human.
  auto map = narrow();
  DockModeMachine dut;
  ModeInput in = dockRequestInNarrow(13.0);
  ModeOutput out = dut.update(*map, in);
  ASSERT_EQ(out.mode, RobotMode::kDocking);
  const Pose2 dock = out.active_goal;
  in.dock_requested = false;
  in.robot = {dock.x_m, dock.y_m + 0.04, 0.0};
  in.stamp_s = 1.0;
  out = dut.update(*map, in);
  // Then it holds, settling on the dock pose ...
  ASSERT_EQ(out.mode, RobotMode::kHolding);
  EXPECT_TRUE(out.hold_still);
  EXPECT_TRUE(out.settle);
  EXPECT_EQ(out.active_goal, dock);
  const Velocity2 v =
      settleOn(in.robot, dock.position(), dut.options().dock_settle_tolerance_m, in.limits);
  EXPECT_LT(v.vy_m_s, 0.0);  // towards the wall (dock below the robot, body frame = world)
  EXPECT_NEAR(v.vy_m_s, -0.04, 1e-9);  // the route follower's gain, 1/s
  // ... and stops within the tolerance.
  const Pose2 near{dock.x_m, dock.y_m + 0.005, 0.0};
  EXPECT_EQ(settleOn(near, dock.position(), dut.options().dock_settle_tolerance_m, in.limits),
            Velocity2{});
  // A hold where the robot stopped because no move left room is no dock pose: no settling.
  DockModeMachine still;
  ModeInput blocked = in;
  blocked.dock_requested = true;
  blocked.robot = {10.0, 1.575, 0.0};
  // 1.1 m wide, closed 0.06 m behind the robot: no dock, no wider place, no room to retreat.
  auto tight = BoxMap::corridor(9.6, 30.0, 1.0, 2.1);
  blocked.trail = nullptr;
  blocked.human = {11.5, 1.575, M_PI};
  blocked.human_velocity = {0.0, 0.0};
  const ModeOutput o2 = still.update(*tight, blocked);
  ASSERT_EQ(o2.mode, RobotMode::kHolding);
  EXPECT_FALSE(o2.settle);
}

TEST(DockModeMachineTest, ARobotAtItsGoalDocksWhenAskedAndGoesBackToIt) {
  // Given a robot parked at its goal in the narrow corridor and a person coming who cannot pass.
  auto map = narrow();
  DockModeMachine dut;
  ModeInput in;
  in.robot = {20.0, 1.575, 0.0};
  in.goal = {20.0, 1.575, 0.0};
  in.has_human = true;
  in.human = {23.0, 1.9, M_PI};
  ASSERT_EQ(dut.update(*map, in).mode, RobotMode::kGoalReached);
  // When a dock is asked for, it makes room as on its way ...
  in.dock_requested = true;
  in.stamp_s = 0.1;
  const ModeOutput out = dut.update(*map, in);
  EXPECT_EQ(out.mode, RobotMode::kDocking);
  EXPECT_LT(out.active_goal.y_m, 1.2);
  // ... and once the person has passed it resumes, and is at its goal again there.
  in.dock_requested = false;
  in.robot = out.active_goal;
  in.stamp_s = 2.0;
  ASSERT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  in.human = {18.0, 1.9, M_PI};
  in.stamp_s = 4.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kResuming);
  in.robot = in.goal;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kGoalReached);
}

}  // namespace
}  // namespace coopnav
