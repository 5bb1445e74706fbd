// Following a person ahead walking the robot's way, and passing them in the lane beside them.

#include "coopnav/planning/overtake.hpp"

#include <gtest/gtest.h>

#include "../band/analytic_map.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

constexpr double kRobotRadius_m = 0.47;

SameWayPerson ahead(const Pose2& robot, double x_m, double y_m, double speed_m_s) {
  AgentState h;
  h.id = 1;
  h.pose = {x_m, y_m, 0.0};
  h.velocity = {speed_m_s, 0.0, 0.0};
  h.radius_m = 0.3;
  const auto p = sameWayPerson(robot, kRobotRadius_m, h, {});
  EXPECT_TRUE(p);
  return *p;
}

TEST(OvertakeTest, NoLaneBesideACentredPersonInA23mCorridor) {
  // Each side of the person's centre 1.15 m; the lane needs 0.3 + 0.25 + 0.94 + 0.05 = 1.54 m.
  const auto map = BoxMap::corridor(0.0, 40.0, 0.0, 2.3);
  const Pose2 robot{10.0, 1.15, 0.0};
  const PassLane lane = passLane(*map, robot, kRobotRadius_m, ahead(robot, 12.5, 1.15, 0.5), {});
  EXPECT_FALSE(lane.fits);
  EXPECT_EQ(lane.side, Side::kUndefined);
  EXPECT_NEAR(lane.room_left_m, 1.15, 1e-6);
  EXPECT_NEAR(lane.room_right_m, 1.15, 1e-6);
}

TEST(OvertakeTest, TheLaneIsOnTheSideWithRoom) {
  // 3 m corridor, the person 0.4 m left of the centre: 1.9 m on their right, 1.1 m on their left.
  const auto map = BoxMap::corridor(0.0, 40.0, 0.0, 3.0);
  const Pose2 robot{10.0, 1.5, 0.0};
  const SameWayPerson p = ahead(robot, 12.5, 1.9, 0.5);
  const OvertakeOptions o;
  const PassLane lane = passLane(*map, robot, kRobotRadius_m, p, o);
  ASSERT_TRUE(lane.fits);
  EXPECT_EQ(lane.side, Side::kRight);
  // The lane's centre: the person's lateral (0.4) less both radii and the clearance (1.02).
  EXPECT_NEAR(lane.lateral_m, 0.4 - 1.02, 1e-9);
  // In the lane, the robot's body stays wall_clearance_m or more off the wall (y 0).
  EXPECT_GE(robot.y_m + lane.lateral_m - kRobotRadius_m, o.wall_clearance_m - 1e-9);
}

TEST(OvertakeTest, BothSidesFitTheRobotKeepsItsOwn) {
  const auto map = BoxMap::corridor(0.0, 40.0, 0.0, 5.0);
  const Pose2 robot{10.0, 2.2, 0.0};
  // The person is 0.3 m to the robot's left: the robot is on their right and stays there.
  const PassLane lane = passLane(*map, robot, kRobotRadius_m, ahead(robot, 12.5, 2.5, 0.5), {});
  ASSERT_TRUE(lane.fits);
  EXPECT_EQ(lane.side, Side::kRight);
  const Pose2 other{10.0, 2.8, 0.0};
  const PassLane l2 = passLane(*map, other, kRobotRadius_m, ahead(other, 12.5, 2.5, 0.5), {});
  EXPECT_EQ(l2.side, Side::kLeft);
}

TEST(OvertakeTest, WhilePassingTheLaneKeepsItsSideAndStaysOffTheWall) {
  // 2.6 m corridor, the person 0.2 m left of the centre (y 1.5): 1.5 m to the right wall from
  // their centre, 0.04 m short of a full lane. Passing on their right anyway (told so), the lane
  // is cut to keep the robot's body wall_clearance_m off the wall.
  const auto map = BoxMap::corridor(0.0, 40.0, 0.0, 2.6);
  const Pose2 robot{10.0, 1.3, 0.0};
  const OvertakeOptions o;
  const SameWayPerson p = ahead(robot, 11.0, 1.5, 0.5);
  const PassLane lane = laneOnSide(*map, robot, kRobotRadius_m, p, Side::kRight, o);
  EXPECT_FALSE(lane.fits);
  EXPECT_EQ(lane.side, Side::kRight);
  EXPECT_NEAR(robot.y_m + lane.lateral_m, kRobotRadius_m + o.wall_clearance_m, 1e-6);
  // Room enough: the full offset from the person.
  const auto wide = BoxMap::corridor(0.0, 40.0, 0.0, 4.0);
  const Pose2 robot2{10.0, 2.3, 0.0};
  const SameWayPerson p2 = ahead(robot2, 11.0, 2.5, 0.5);
  const PassLane full = laneOnSide(*wide, robot2, kRobotRadius_m, p2, Side::kRight, o);
  EXPECT_TRUE(full.fits);
  EXPECT_NEAR(full.lateral_m, p2.lateral_m - (0.3 + o.pass_clearance_m + kRobotRadius_m), 1e-9);
  EXPECT_FALSE(laneOnSide(*wide, robot, kRobotRadius_m, p, Side::kUndefined, o).fits);
}

TEST(OvertakeTest, FollowSpeedMatchesThePaceAtTheGap) {
  const Pose2 robot{10.0, 1.15, 0.0};
  OvertakeOptions o;
  // Surface gap = centre distance - 0.77: at the follow gap the pace is the person's.
  const SameWayPerson at_gap = ahead(robot, 10.0 + 0.77 + o.follow_gap_m, 1.15, 0.45);
  EXPECT_NEAR(followSpeed(at_gap, o, 0.7), 0.45, 1e-9);
  // Farther: faster, up to the limit; nearer: slower; never backwards.
  EXPECT_NEAR(followSpeed(ahead(robot, 13.47, 1.15, 0.45), o, 0.7), 0.45 + 0.5 / 2.0, 1e-9);
  EXPECT_DOUBLE_EQ(followSpeed(ahead(robot, 16.0, 1.15, 0.45), o, 0.7), 0.7);
  EXPECT_LT(followSpeed(ahead(robot, 11.8, 1.15, 0.45), o, 0.7), 0.45);
  EXPECT_DOUBLE_EQ(followSpeed(ahead(robot, 11.5, 1.15, 0.0), o, 0.7), 0.0);
}

TEST(OvertakeTest, FollowingNeverFasterThanThePaceAndTowardsTheLane) {
  const auto map = BoxMap::corridor(0.0, 40.0, 0.0, 3.0);
  const Pose2 robot{10.0, 1.5, 0.0};
  const OvertakeOptions o;
  RobotLimits limits;
  const SameWayPerson p = ahead(robot, 12.2, 1.9, 0.5);
  const PassLane lane = passLane(*map, robot, kRobotRadius_m, p, o);
  ASSERT_TRUE(lane.fits);
  const Velocity2 v = followCommand(robot, robot, p, lane, o, limits);
  EXPECT_LE(v.vx_m_s, followSpeed(p, o, limits.max_forward_m_s) + 1e-9);
  EXPECT_GT(v.vx_m_s, 0.0);
  EXPECT_LT(v.vy_m_s, 0.0);  // towards the lane on the right
  // No lane: straight on, at the pace.
  const Velocity2 w = followCommand(robot, robot, p, PassLane{}, o, limits);
  EXPECT_NEAR(w.vy_m_s, 0.0, 1e-9);
  EXPECT_LE(w.vx_m_s, followSpeed(p, o, limits.max_forward_m_s) + 1e-9);
  // Behind a person who stopped, too near: the robot does not move on, only into the lane.
  const SameWayPerson stopped = ahead(robot, 11.9, 1.9, 0.0);
  const Velocity2 s = followCommand(robot, robot, stopped, lane, o, limits);
  EXPECT_LE(s.vx_m_s, 1e-9);
  EXPECT_LT(s.vy_m_s, 0.0);
  EXPECT_EQ(followCommand(robot, robot, stopped, PassLane{}, o, limits), Velocity2{});
}

TEST(OvertakeTest, PassingDrivesAlongTheLaneAtFullSpeed) {
  const Pose2 robot{10.0, 0.9, 0.0};
  PassLane lane;
  lane.fits = true;
  lane.side = Side::kRight;
  lane.lateral_m = 0.0;  // in it already
  RobotLimits limits;
  const Velocity2 v = passCommand(robot, robot, lane, {}, limits);
  EXPECT_NEAR(std::hypot(v.vx_m_s, v.vy_m_s), limits.max_forward_m_s, 1e-6);
  EXPECT_NEAR(v.vy_m_s, 0.0, 1e-9);
  // Differential drive: forwards, turning towards a lane to its right.
  limits.holonomic = false;
  lane.lateral_m = -0.3;
  const Velocity2 d = passCommand(robot, robot, lane, {}, limits);
  EXPECT_GT(d.vx_m_s, 0.0);
  EXPECT_DOUBLE_EQ(d.vy_m_s, 0.0);
  EXPECT_LT(d.omega_rad_s, 0.0);
}

}  // namespace
}  // namespace coopnav
