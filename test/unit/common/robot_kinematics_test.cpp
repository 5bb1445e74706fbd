// The band source's kinematics announcement in its status detail (wire/robot_kinematics.hpp),
// which world_sim compares with its scenario's robot.
#include "wire/robot_kinematics.hpp"

#include <gtest/gtest.h>

namespace coopnav {
namespace {

TEST(RobotKinematicsDetail, ReadsBackWhatTheBandSourceAnnounces) {
  EXPECT_EQ(holonomicFromStatusDetail("map a.yaml 10x10 @ 0.05 m; " + robotKinematicsDetail(true)),
            true);
  EXPECT_EQ(holonomicFromStatusDetail(robotKinematicsDetail(false)), false);
  EXPECT_EQ(holonomicFromStatusDetail(robotKinematicsDetail(false) + "; more"), false);
}

TEST(RobotKinematicsDetail, NoAnnouncementIsNoVerdict) {
  EXPECT_FALSE(holonomicFromStatusDetail("").has_value());
  EXPECT_FALSE(holonomicFromStatusDetail("step 12 planned without path_assessor").has_value());
  EXPECT_FALSE(holonomicFromStatusDetail("robot kinematics holonomicity").has_value());
  EXPECT_FALSE(holonomicFromStatusDetail("robot kinematics ").has_value());
}

TEST(RobotKinematicsDetail, TheMismatchNamesBothSettings) {
  const std::string m = robotKinematicsMismatch(false, true);
  EXPECT_NE(m.find("robot.kinematics is differential"), std::string::npos) << m;
  EXPECT_NE(m.find("planner.robot.holonomic: true"), std::string::npos) << m;
  EXPECT_NE(m.find("--set planner.robot.holonomic=false"), std::string::npos) << m;
}

}  // namespace
}  // namespace coopnav
