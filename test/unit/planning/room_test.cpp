// Room that is really made: the dock pose flush to the wall, the passage check, the
// wider place back along the robot's path, the retreat, and the mode machine's escalation.
#include "coopnav/planning/room.hpp"

#include <gtest/gtest.h>

#include "../band/analytic_map.hpp"
#include "coopnav/planning/dock.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

constexpr double kRobotRadius_m = 0.47;  // CoHAN's PR2 footprint, world_sim's default
constexpr double kHumanRadius_m = 0.3;

/// A straight corridor along x, free for y in [0, width].
std::shared_ptr<BoxMap> corridor(double width_m, double length_m = 60.0) {
  return BoxMap::corridor(0.0, length_m, 0.0, width_m);
}

/// The robot mid-corridor heading +x, a human ahead walking at it at 1 m/s.
Encounter headOn(double width_m, double human_x_m, const Path2* trail = nullptr) {
  Encounter e;
  e.robot = {12.0, width_m / 2, 0.0};
  e.robot_radius_m = kRobotRadius_m;
  e.human_position = {human_x_m, width_m / 2};
  e.human_velocity = {-1.0, 0.0};
  e.human_radius_m = kHumanRadius_m;
  e.trail = trail;
  return e;
}

/// The way the robot came: along the corridor's centre from x = 1 to the robot.
Path2 trailTo(double x_m, double y_m) {
  Path2 t;
  for (double x = 1.0; x <= x_m + 1e-9; x += 0.1) t.emplace_back(x, y_m);
  return t;
}

TEST(PassageCheckTest, FlushInA18mCorridorLeavesTheHumanRoomButNotIn15m) {
  // A robot of radius 0.47 flush at the wall (body 0.05 m off it) leaves 1.8 - 0.99 = 0.81 m:
  // enough for a human of radius 0.3 and the 0.1 m margin (0.7 m); 1.5 m leaves 0.51 m.
  const Eigen::Vector2d axis(1.0, 0.0), towards_wall(0.0, -1.0);
  const auto wide = corridor(1.8);
  const PassageCheck ok =
      checkPassage(*wide, {10.0, 0.52}, kRobotRadius_m, axis, towards_wall, kHumanRadius_m, 0.1);
  EXPECT_TRUE(ok.ok);
  EXPECT_NEAR(ok.free_width_m, 0.81, 1e-6);
  EXPECT_NEAR(ok.needed_m, 0.7, 1e-12);
  const auto narrow = corridor(1.5);
  const PassageCheck no =
      checkPassage(*narrow, {10.0, 0.52}, kRobotRadius_m, axis, towards_wall, kHumanRadius_m, 0.1);
  EXPECT_FALSE(no.ok);
  EXPECT_NEAR(no.free_width_m, 0.51, 1e-6);
  // The robot left mid-corridor (where the robot ended, centre 0.6 m off the wall at
  // best) leaves 1.8 - 1.07 = 0.73 m at 0.6, 0.43 m mid-corridor.
  EXPECT_FALSE(
      checkPassage(*wide, {10.0, 0.9}, kRobotRadius_m, axis, towards_wall, kHumanRadius_m, 0.1).ok);
}

TEST(PassageCheckTest, AHumanSideSteppingAskewDoesNotNarrowThePassageAlongTheRobotsPath) {
  // The robot flush in 1.8 m, the human 2 m ahead stepping aside at 14 degrees to the corridor:
  // measured across its askew course the passage reads 0.65 m (< 0.7), along the corridor 0.81 m.
  const auto map = corridor(1.8);
  Encounter e;
  e.robot = {10.0, 0.52, 0.0};
  e.robot_radius_m = kRobotRadius_m;
  e.human_position = {12.0, 1.15};
  e.human_velocity = {-0.97, 0.245};
  e.human_radius_m = kHumanRadius_m;
  EXPECT_FALSE(passageHere(*map, e, 0.1).ok);
  const Path2 trail = trailTo(9.0, 0.9);  // it came along the corridor, then docked
  e.trail = &trail;
  const PassageCheck pc = passageHere(*map, e, 0.1);
  EXPECT_TRUE(pc.ok);
  EXPECT_NEAR(pc.free_width_m, 0.81, 1e-6);
  EXPECT_NEAR(encounterAxis(e).x(), 1.0, 1e-9);
}

TEST(RoomDecisionTest, DocksFlushToTheWallWithinTheMarginInA18mCorridor) {
  const auto map = corridor(1.8);
  DockOptions dock;  // margin 0.05
  const RoomDecision d = decideRoom(*map, headOn(1.8, 16.0), dock, RoomOptions{});
  ASSERT_EQ(d.move, RoomMove::kDockHere);
  // Keep right (the human dead ahead): the low wall, the body dock.margin_m from it.
  EXPECT_NEAR(d.target.y_m, kRobotRadius_m + dock.margin_m, 1e-6);
  EXPECT_GE(map->nearest(d.target.position()).distance_m, kRobotRadius_m + dock.margin_m - 1e-6);
  EXPECT_TRUE(d.passage.ok);
  EXPECT_NEAR(d.passage.free_width_m, 1.8 - 2 * kRobotRadius_m - dock.margin_m, 1e-6);
  ASSERT_FALSE(d.route.empty());
  EXPECT_EQ(d.route.back(), d.target.position());
  // A wider margin leaves less: at 0.2 m the passage (0.66 m) no longer holds here.
  dock.margin_m = 0.2;
  EXPECT_NE(decideRoom(*map, headOn(1.8, 16.0), dock, RoomOptions{}).move, RoomMove::kDockHere);
}

TEST(RoomDecisionTest, NoWallAndRoomToPassIsNothingToMakeRoomIn) {
  const auto open = BoxMap::corridor(0.0, 30.0, 0.0, 30.0);
  DockOptions dock;
  dock.search_range_m = 2.0;
  Encounter e = headOn(30.0, 18.0);
  EXPECT_EQ(decideRoom(*open, e, dock, RoomOptions{}).move, RoomMove::kUnknown);
}

/// A 1.5 m corridor (too narrow to dock in) with a 1 m deep recess below it for x in [7, 9].
std::shared_ptr<BoxMap> corridorWithRecess() {
  auto map = BoxMap::corridor(0.0, 60.0, -1.0, 1.5);
  map->addBox({Eigen::Vector2d(0.0, -1.0), Eigen::Vector2d(7.0, 0.0)});
  map->addBox({Eigen::Vector2d(9.0, -1.0), Eigen::Vector2d(60.0, 0.0)});
  return map;
}

TEST(RoomDecisionTest, AWiderPlaceBehindIsTakenWhenReachedBeforeTheHuman) {
  const auto map = corridorWithRecess();
  const Path2 trail = trailTo(12.0, 0.75);
  Encounter e = headOn(1.5, 40.0, &trail);  // the human 28 m away: ~27 s
  e.robot.y_m = 0.75;
  e.human_position.y() = 0.75;
  const RoomDecision d = decideRoom(*map, e, DockOptions{}, RoomOptions{});
  ASSERT_EQ(d.move, RoomMove::kWiderPlace);
  // In the recess, aside from the trail towards it, with the passage holding there.
  EXPECT_GT(d.target.x_m, 7.0 + kRobotRadius_m - 1e-6);
  EXPECT_LT(d.target.x_m, 9.0 - kRobotRadius_m + 1e-6);
  EXPECT_LT(d.target.y_m, 0.75 - 0.4);
  EXPECT_TRUE(d.passage.ok);
  EXPECT_GE(map->nearest(d.target.position()).distance_m, kRobotRadius_m);
  EXPECT_LT(d.robot_time_s + RoomOptions{}.reach_margin_s, d.human_time_s);
  ASSERT_GE(d.route.size(), 3u);
  EXPECT_EQ(d.route.front(), e.robot.position());
  EXPECT_EQ(d.route.back(), d.target.position());
  for (const auto& p : d.route) EXPECT_GE(map->nearest(p).distance_m, kRobotRadius_m - 1e-6);
}

TEST(RoomDecisionTest, AWiderPlaceTheHumanReachesFirstIsNotTakenTheRobotRetreats) {
  const auto map = corridorWithRecess();
  const Path2 trail = trailTo(12.0, 0.75);
  Encounter e = headOn(1.5, 17.0, &trail);  // the human ~8 s from the recess
  e.robot.y_m = 0.75;
  e.human_position.y() = 0.75;
  const RoomDecision d = decideRoom(*map, e, DockOptions{}, RoomOptions{});
  EXPECT_EQ(d.move, RoomMove::kRetreat);
  // Without the recess, nothing behind is wider at any distance: retreat too.
  const auto plain = corridor(1.5);
  Encounter far = headOn(1.5, 40.0, &trail);
  far.robot.y_m = far.human_position.y() = 0.75;
  EXPECT_EQ(decideRoom(*plain, far, DockOptions{}, RoomOptions{}).move, RoomMove::kRetreat);
}

TEST(RoomDecisionTest, NoRoomBehindIsNone) {
  // The robot with its back against the corridor's closed end.
  const auto map = corridor(1.5);
  Encounter e = headOn(1.5, 8.0);
  e.robot.x_m = 0.5;
  EXPECT_EQ(decideRoom(*map, e, DockOptions{}, RoomOptions{}).move, RoomMove::kNone);
}

TEST(RetreatTest, BacksAlongTheWayItCameAndNeverTowardsTheHuman) {
  const auto map = corridor(1.5);
  // It came in along the corridor from the left, then stepped to the wall: the retreat keeps
  // along the corridor, not back to the centre line.
  const Path2 trail = trailTo(12.0, 0.75);
  Encounter e = headOn(1.5, 16.0, &trail);
  e.robot = {12.0, 0.55, 0.0};
  const auto dir = retreatDirection(*map, e, RoomOptions{});
  ASSERT_TRUE(dir.has_value());
  EXPECT_NEAR(dir->x(), -1.0, 1e-9);
  EXPECT_NEAR(dir->y(), 0.0, 1e-9);
  // A trail that came down from above (a bend): back up it, still away from the human.
  Path2 bend;
  for (double y = 5.0; y >= 0.75; y -= 0.1) bend.emplace_back(2.0, y);
  for (double x = 2.0; x <= 12.0; x += 0.1) bend.emplace_back(x, 0.75);
  auto open = BoxMap::corridor(0.0, 30.0, 0.0, 10.0);
  Encounter b = headOn(1.5, 16.0, &bend);
  b.robot = {2.3, 0.75, 0.0};
  const auto up = retreatDirection(*open, b, RoomOptions{});
  ASSERT_TRUE(up.has_value());
  EXPECT_LT(up->x(), 0.0);
  EXPECT_GT(up->y(), 0.0);
}

TEST(RetreatTest, TheModeMachineRetreatsWhileTheHumanClosesAndHoldsWhenItStops) {
  const auto map = corridor(1.5);
  const Path2 trail = trailTo(12.0, 0.75);
  DockModeMachine dut;
  ModeInput in;
  in.robot = {12.0, 0.75, 0.0};
  in.robot_radius_m = kRobotRadius_m;
  in.goal = {50.0, 0.75, 0.0};
  in.has_human = true;
  in.human = {16.0, 0.75, M_PI};
  in.human_velocity = {-1.0, 0.0};
  in.human_radius_m = kHumanRadius_m;
  in.trail = &trail;
  in.dock_requested = true;
  ModeOutput out = dut.update(*map, in);
  ASSERT_EQ(out.mode, RobotMode::kRetreating);
  EXPECT_EQ(out.room, RoomMove::kRetreat);
  ASSERT_TRUE(out.retreat_direction.has_value());
  EXPECT_LT(out.retreat_direction->x(), -0.99);
  // The command backs it away (holonomic: straight back, at the backward limit).
  const Velocity2 cmd = driveAlong(in.robot, *out.retreat_direction, 5.0, in.limits);
  EXPECT_LT(cmd.vx_m_s, 0.0);
  EXPECT_NEAR(cmd.vy_m_s, 0.0, 1e-9);
  in.dock_requested = false;
  // Still closing: keeps retreating.
  in.stamp_s = 0.5;
  in.robot.x_m = 11.8;
  in.human.x_m = 15.5;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kRetreating);
  // The human stops: the robot stops retreating and holds.
  in.stamp_s = 1.0;
  in.human_velocity = {0.0, 0.0};
  out = dut.update(*map, in);
  EXPECT_EQ(out.mode, RobotMode::kHolding);
  EXPECT_TRUE(out.hold_still);
  // It comes on again and cannot pass beside the robot: retreat again.
  in.stamp_s = 1.5;
  in.human_velocity = {-1.0, 0.0};
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kRetreating);
  // It turns away: hold.
  in.stamp_s = 2.0;
  in.human_velocity = {1.0, 0.0};
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  // It has passed: resume.
  in.human = {10.0, 0.75, M_PI};
  in.human_velocity = {-1.0, 0.0};
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kResuming);
}

TEST(RetreatTest, AHumanClosingOnADockTooNarrowForItEscalatesToRetreat) {
  // A dock asked for where the passage holds (1.8 m), then the robot held short of the wall
  // (centre 0.75 m off it, 0.58 m left): the human cannot pass there and comes on.
  const auto map = corridor(1.8);
  const Path2 trail = trailTo(12.0, 0.9);
  DockModeMachine dut;
  ModeInput in;
  in.robot = {12.0, 0.9, 0.0};
  in.robot_radius_m = kRobotRadius_m;
  in.goal = {50.0, 0.9, 0.0};
  in.has_human = true;
  in.human = {20.0, 0.9, M_PI};
  in.human_velocity = {-1.0, 0.0};
  in.human_radius_m = kHumanRadius_m;
  in.trail = &trail;
  in.dock_requested = true;
  ModeOutput out = dut.update(*map, in);
  ASSERT_EQ(out.mode, RobotMode::kDocking);
  EXPECT_EQ(out.room, RoomMove::kDockHere);
  in.dock_requested = false;
  // Reached: holding; the passage beside it holds, so the closing human is let through.
  in.robot = out.active_goal;
  in.stamp_s = 1.0;
  in.human.x_m = 15.0;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  in.stamp_s = 1.1;
  EXPECT_EQ(dut.update(*map, in).mode, RobotMode::kHolding);
  // Pushed off the wall (by hand, say) with the human closing: retreat.
  in.robot.y_m = 0.75;
  in.stamp_s = 1.2;
  out = dut.update(*map, in);
  EXPECT_EQ(out.mode, RobotMode::kRetreating);
  EXPECT_EQ(out.room, RoomMove::kRetreat);
}

TEST(DriveTest, FollowingTheDockRouteEndsFlushAtTheWall) {
  // A holonomic robot integrating the command at 10 Hz reaches the dock pose within the
  // dock-reached tolerance and never leaves its radius from the wall.
  const auto map = corridor(1.8);
  const RoomDecision d = decideRoom(*map, headOn(1.8, 20.0), DockOptions{}, RoomOptions{});
  ASSERT_EQ(d.move, RoomMove::kDockHere);
  Pose2 robot{12.0, 0.9, 0.0};
  const RobotLimits limits;
  for (int k = 0; k < 100; ++k) {
    const Velocity2 v = followRoute(robot, d.route, limits.max_forward_m_s, limits);
    const double c = std::cos(robot.theta_rad), s = std::sin(robot.theta_rad);
    robot.x_m += 0.1 * (c * v.vx_m_s - s * v.vy_m_s);
    robot.y_m += 0.1 * (s * v.vx_m_s + c * v.vy_m_s);
    robot.theta_rad += 0.1 * v.omega_rad_s;
    ASSERT_GE(map->nearest(robot.position()).distance_m, kRobotRadius_m);
  }
  EXPECT_LT((robot.position() - d.target.position()).norm(),
            ModeMachineOptions{}.dock_reached_tolerance_m);
  // A differential drive gets there too (turning, then driving).
  RobotLimits diff;
  diff.holonomic = false;
  robot = {12.0, 0.9, 0.0};
  for (int k = 0; k < 300; ++k) {
    const Velocity2 v = followRoute(robot, d.route, diff.max_forward_m_s, diff);
    EXPECT_EQ(v.vy_m_s, 0.0);
    robot.x_m += 0.1 * std::cos(robot.theta_rad) * v.vx_m_s;
    robot.y_m += 0.1 * std::sin(robot.theta_rad) * v.vx_m_s;
    robot.theta_rad += 0.1 * v.omega_rad_s;
  }
  EXPECT_LT((robot.position() - d.target.position()).norm(), 0.1);
}

TEST(DriveTest, TravelTimeBacksOrTurnsWhicheverIsFaster) {
  RobotLimits l;  // back 0.4, forward 0.7, lateral 0.7, yaw 1.2
  const Eigen::Vector2d behind(-1.0, 0.0);
  // Holonomic: it just moves, keeping its heading (backwards at 0.4, sideways at 0.7).
  EXPECT_NEAR(travelTime(10.0, behind, 0.0, l), 10.0 / 0.4, 1e-9);
  EXPECT_NEAR(travelTime(1.0, {0.0, 1.0}, 0.0, l), 1.0 / 0.7, 1e-9);
  // Differential drive: 1 m behind, backing (2.5 s) beats turning round (2.6 s + 1.4 s); 10 m
  // behind, turning round (2.6 s + 14.3 s) beats backing (25 s).
  l.holonomic = false;
  EXPECT_NEAR(travelTime(1.0, behind, 0.0, l), 1.0 / 0.4, 1e-9);
  EXPECT_NEAR(travelTime(10.0, behind, 0.0, l), M_PI / 1.2 + 10.0 / 0.7, 1e-9);
  EXPECT_NEAR(travelTime(1.0, {0.0, 1.0}, 0.0, l), M_PI / 2 / 1.2 + 1.0 / 0.7, 1e-9);
  // And the command does what the time assumed: far behind it turns (no backing), near it backs.
  const Velocity2 far = driveAlong({0.0, 0.0, 0.0}, behind, 10.0, l);
  EXPECT_EQ(far.vx_m_s, 0.0);
  EXPECT_GT(std::abs(far.omega_rad_s), 0.0);
  const Velocity2 near = driveAlong({0.0, 0.0, 0.0}, behind, 1.0, l);
  EXPECT_NEAR(near.vx_m_s, -l.max_backward_m_s, 1e-12);
}

TEST(TrailTest, BoundedSpacedAndCutWhenTheRobotComesBack) {
  Trail t(5.0, 0.1);
  for (double x = 0.0; x <= 10.0 + 1e-9; x += 0.05) t.add({x, 0.0});
  ASSERT_GE(t.points().size(), 2u);
  EXPECT_NEAR(t.points().back().x(), 10.0, 0.06);
  EXPECT_GE(t.points().front().x(), 10.0 - 5.0 - 0.11);
  for (std::size_t i = 1; i < t.points().size(); ++i)
    EXPECT_GE((t.points()[i] - t.points()[i - 1]).norm(), 0.1 - 1e-9);
  // Back to x = 8 the way it came: the trail now ends there.
  for (double x = 10.0; x >= 8.0 - 1e-9; x -= 0.05) t.add({x, 0.0});
  EXPECT_NEAR(t.points().back().x(), 8.0, 0.21);
  for (const auto& p : t.points()) EXPECT_LE(p.x(), 8.21);
  // A jump starts it afresh.
  t.add({30.0, 5.0});
  ASSERT_EQ(t.points().size(), 1u);
}

}  // namespace
}  // namespace coopnav
