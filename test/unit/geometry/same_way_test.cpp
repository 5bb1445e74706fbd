// Who the robot follows: a person ahead, in its way, walking its way or standing in it.

#include "coopnav/geometry/same_way.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace coopnav {
namespace {

constexpr double kRobotRadius_m = 0.47;

AgentState person(std::int32_t id, double x_m, double y_m, double vx_m_s, double vy_m_s = 0.0) {
  AgentState h;
  h.id = id;
  h.pose = {x_m, y_m, 0.0};
  h.velocity = {vx_m_s, vy_m_s, 0.0};
  h.radius_m = 0.3;
  return h;
}

const Pose2 kRobot{2.0, 1.0, 0.0};  // heading +x

TEST(SameWayTest, APersonAheadWalkingTheRobotsWayIsFollowed) {
  const auto p = sameWayAhead(kRobot, kRobotRadius_m, {person(4, 5.0, 1.2, 0.5)}, {});
  ASSERT_TRUE(p);
  EXPECT_EQ(p->id, 4);
  EXPECT_NEAR(p->along_m, 3.0, 1e-12);
  EXPECT_NEAR(p->lateral_m, 0.2, 1e-12);
  EXPECT_NEAR(p->gap_m, std::hypot(3.0, 0.2) - 0.77, 1e-12);
  EXPECT_NEAR(p->speed_along_m_s, 0.5, 1e-12);
  // The person is to the robot's left: the robot is on their right (they face its way).
  EXPECT_EQ(p->robot_side, Side::kRight);
  EXPECT_NEAR(lateralClearance(*p, kRobotRadius_m), 0.2 - 0.77, 1e-12);
}

TEST(SameWayTest, StandingAheadCountsOncomingBehindOrAsideDoNot) {
  EXPECT_TRUE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 1.0, 0.0)}, {}));
  EXPECT_TRUE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 1.0, -0.05)}, {}));
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 1.0, -1.0)}, {}));  // oncoming
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 1.0, 1.0, 0.5)}, {}));   // behind
  // Beside the robot's line by more than both radii and lane_margin_m (1.37 m): out of its way.
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 2.5, 0.5)}, {}));
  EXPECT_TRUE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 2.3, 0.5)}, {}));
  // Beyond ahead_range_m (6 m of surface gap).
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {person(1, 9.0, 1.0, 0.5)}, {}));
}

TEST(SameWayTest, SomeoneStandingCountsOnlyFacingTheRobotsWay) {
  AgentState h = person(1, 5.0, 1.0, 0.0);
  h.pose.theta_rad = M_PI;  // stopped facing the robot (made room, waiting for it to go by)
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {h}, {}));
  h.pose.theta_rad = 0.3;  // stopped on the way (a phone)
  EXPECT_TRUE(sameWayAhead(kRobot, kRobotRadius_m, {h}, {}));
  // Walking, the velocity says where to, whatever the heading.
  h.velocity.vx_m_s = 0.5;
  h.pose.theta_rad = M_PI;
  EXPECT_TRUE(sameWayAhead(kRobot, kRobotRadius_m, {h}, {}));
}

TEST(SameWayTest, TheNearestIsFollowed) {
  const std::vector<AgentState> people{person(1, 7.0, 1.0, 0.5), person(2, 4.5, 0.8, 0.4),
                                       person(3, 3.5, 1.0, -1.0)};
  const auto p = sameWayAhead(kRobot, kRobotRadius_m, people, {});
  ASSERT_TRUE(p);
  EXPECT_EQ(p->id, 2);
  EXPECT_EQ(p->robot_side, Side::kLeft);  // they are to the robot's right
}

TEST(SameWayTest, StraightBehindHasNoSideAndTheFrameIsTheRobotsHeading) {
  const auto p = sameWayAhead(kRobot, kRobotRadius_m, {person(1, 5.0, 1.0, 0.5)}, {});
  ASSERT_TRUE(p);
  EXPECT_EQ(p->robot_side, Side::kUndefined);
  // Heading +y: a person at +y walking +y is ahead; their +x is the robot's right.
  const Pose2 north{2.0, 1.0, M_PI / 2};
  const auto q = sameWayAhead(north, kRobotRadius_m, {person(1, 2.3, 4.0, 0.0, 0.6)}, {});
  ASSERT_TRUE(q);
  EXPECT_NEAR(q->along_m, 3.0, 1e-9);
  EXPECT_NEAR(q->lateral_m, -0.3, 1e-9);
  EXPECT_NEAR(q->speed_along_m_s, 0.6, 1e-9);
  EXPECT_EQ(q->robot_side, Side::kLeft);
}

TEST(SameWayTest, NonFiniteStatesAreNobody) {
  AgentState h = person(1, 5.0, 1.0, 0.5);
  h.velocity.vx_m_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(sameWayAhead(kRobot, kRobotRadius_m, {h}, {}));
}

}  // namespace
}  // namespace coopnav
