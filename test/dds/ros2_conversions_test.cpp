// The ROS 2 <-> lcmtypes conversions of the bridge (daemons/ros2_bridge/ros2_conversions.hpp):
// frames, stamps, quaternions, each inbound message (and its rejections), /cmd_vel, the
// watchdog decision, the markers and the DDS topic names.
#include "ros2_conversions.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "ros2_bridge_node.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"

namespace coopnav::ros2 {
namespace {

constexpr double kEps = 1e-9;
char kMap[] = "map";
char kOdom[] = "odom";
char kBaseLink[] = "base_link";
char kEmpty[] = "";

FrameSet frames(double x = 0.0, double y = 0.0, double yaw = 0.0) {
  FrameSet f;
  f.odom_to_map = {x, y, yaw};
  return f;
}

Odometry odometry(char* frame, double x, double y, double yaw, double vx, double omega) {
  Odometry o{};
  o.header.frame_id = frame;
  o.header.stamp = {12, 500000000U};
  o.child_frame_id = kBaseLink;
  o.pose.pose.position = {x, y, 0.0};
  o.pose.pose.orientation = quaternionOfYaw(yaw);
  o.twist.twist.linear.x = vx;
  o.twist.twist.angular.z = omega;
  return o;
}

TEST(Ros2Conversions, StampsRoundTripAndRejectBadOnes) {
  EXPECT_EQ(stampToUtime({12, 500000000U}), 12'500'000);
  const Time t = utimeToStamp(1'700'000'123'456'789);
  EXPECT_EQ(t.sec, 1'700'000'123);
  EXPECT_EQ(t.nanosec, 456'789'000U);
  EXPECT_EQ(stampToUtime(t), 1'700'000'123'456'789);
  EXPECT_THROW(stampToUtime({-1, 0}), RejectedMessage);
  EXPECT_THROW(stampToUtime({1, 1000000000U}), RejectedMessage);
}

TEST(Ros2Conversions, YawOfQuaternion) {
  for (double yaw : {0.0, 0.3, -2.0, 3.0}) EXPECT_NEAR(yawOf(quaternionOfYaw(yaw)), yaw, kEps);
  Quaternion q = quaternionOfYaw(1.0);
  q.z *= 3.0;  // not unit: normalised
  q.w *= 3.0;
  EXPECT_NEAR(yawOf(q), 1.0, kEps);
  EXPECT_THROW(yawOf(Quaternion{0, 0, 0, 0}), RejectedMessage);
  EXPECT_THROW(yawOf(Quaternion{0, 0, std::nan(""), 1}), RejectedMessage);
}

TEST(Ros2Conversions, TransformsComposeAndInvert) {
  const Transform2 a{1.0, 2.0, M_PI / 2};
  const Pose2 p = a.apply({1.0, 0.0, 0.0});
  EXPECT_NEAR(p.x_m, 1.0, kEps);
  EXPECT_NEAR(p.y_m, 3.0, kEps);
  EXPECT_NEAR(p.yaw_rad, M_PI / 2, kEps);
  const Transform2 id = a.compose(a.inverse());
  EXPECT_NEAR(id.x_m, 0.0, kEps);
  EXPECT_NEAR(id.y_m, 0.0, kEps);
  EXPECT_NEAR(id.yaw_rad, 0.0, kEps);
  // AMCL: base at (5, 5, 90 deg) in the map, at (1, 0, 0) in odom -> odom's origin in the map
  // is one metre behind the base along its heading: (5, 4), rotated 90 deg.
  const Transform2 m = odomToMapFromPoses({5.0, 5.0, M_PI / 2}, {1.0, 0.0, 0.0});
  EXPECT_NEAR(m.x_m, 5.0, kEps);
  EXPECT_NEAR(m.y_m, 4.0, kEps);
  EXPECT_NEAR(m.yaw_rad, M_PI / 2, kEps);
  const Pose2 back = m.apply({1.0, 0.0, 0.0});
  EXPECT_NEAR(back.x_m, 5.0, kEps);
  EXPECT_NEAR(back.y_m, 5.0, kEps);
}

TEST(Ros2Conversions, FramesKnownOrRejected) {
  const FrameSet f = frames(3.0, 0.0, 0.0);
  EXPECT_NEAR(frameToMap(kMap, f).x_m, 0.0, kEps);
  EXPECT_NEAR(frameToMap(kEmpty, f).x_m, 0.0, kEps);
  EXPECT_NEAR(frameToMap(kOdom, f).x_m, 3.0, kEps);
  EXPECT_THROW(frameToMap(kBaseLink, f), RejectedMessage);
}

TEST(Ros2Conversions, RobotFromOdometryInTheMapFrameWithWorldVelocity) {
  // odom's origin at (10, 0) in the map, turned 90 deg: the base at (1, 0, 0) in odom is at
  // (10, 1) heading +y in the map; 0.5 m/s forward is +y in the map.
  const agent_state_t s = robotFromOdometry(odometry(kOdom, 1.0, 0.0, 0.0, 0.5, 0.2),
                                            frames(10.0, 0.0, M_PI / 2), 0.34);
  EXPECT_EQ(s.id, 0);
  EXPECT_EQ(s.kind, +agent_state_t::KIND_ROBOT);
  EXPECT_NEAR(s.x_m, 10.0, kEps);
  EXPECT_NEAR(s.y_m, 1.0, kEps);
  EXPECT_NEAR(s.theta_rad, M_PI / 2, kEps);
  EXPECT_NEAR(s.vx_m_s, 0.0, kEps);
  EXPECT_NEAR(s.vy_m_s, 0.5, kEps);
  EXPECT_NEAR(s.omega_rad_s, 0.2, kEps);
  EXPECT_DOUBLE_EQ(s.radius_m, 0.34);
  EXPECT_THROW(robotFromOdometry(odometry(kBaseLink, 0, 0, 0, 0, 0), frames(), 0.34),
               RejectedMessage);
  EXPECT_THROW(robotFromOdometry(odometry(kMap, std::nan(""), 0, 0, 0, 0), frames(), 0.34),
               RejectedMessage);
}

TEST(Ros2Conversions, HumansFromTrackedAgentsUseTheBodySegmentAndSkipTheRobot) {
  std::vector<cohan_msgs_msg_dds__TrackedSegment_> head_torso(2);
  head_torso[0] = {};
  head_torso[0].type = 0;  // HEAD: not the body
  head_torso[0].pose.pose.position = {99.0, 99.0, 0.0};
  head_torso[0].pose.pose.orientation = quaternionOfYaw(0.0);
  head_torso[1] = {};
  head_torso[1].type = 1;  // TORSO
  head_torso[1].pose.pose.position = {2.0, 1.0, 0.0};
  head_torso[1].pose.pose.orientation = quaternionOfYaw(M_PI);
  head_torso[1].twist.twist.linear.x = -1.2;
  std::vector<cohan_msgs_msg_dds__TrackedSegment_> robot_seg(1);
  robot_seg[0] = head_torso[1];
  std::vector<cohan_msgs_msg_dds__TrackedAgent_> agents(2);
  agents[0] = {};
  agents[0].track_id = 0;
  agents[0].type = 0;  // ROBOT: skipped
  agents[0].name = kEmpty;
  agents[0].segments = {1, 1, robot_seg.data(), false};
  agents[1] = {};
  agents[1].track_id = 7;
  agents[1].type = 1;  // HUMAN
  agents[1].name = kEmpty;
  agents[1].radius = 0.0;  // none: the default
  agents[1].segments = {2, 2, head_torso.data(), false};
  TrackedAgents msg{};
  msg.header.frame_id = kOdom;
  msg.agents = {2, 2, agents.data(), false};
  HumanOptions opt;
  opt.default_radius_m = 0.25;
  const auto humans = humansFromTrackedAgents(msg, frames(1.0, 0.0, 0.0), opt);
  ASSERT_EQ(humans.size(), 1U);
  EXPECT_EQ(humans[0].id, 7);
  EXPECT_EQ(humans[0].kind, +agent_state_t::KIND_HUMAN);
  EXPECT_NEAR(humans[0].x_m, 3.0, kEps);
  EXPECT_NEAR(humans[0].y_m, 1.0, kEps);
  EXPECT_NEAR(std::abs(humans[0].theta_rad), M_PI, kEps);
  EXPECT_NEAR(humans[0].vx_m_s, -1.2, kEps);
  EXPECT_DOUBLE_EQ(humans[0].radius_m, 0.25);
  // The same id twice, or an id that does not fit an int32, is rejected.
  agents[0] = agents[1];
  EXPECT_THROW(humansFromTrackedAgents(msg, frames(), opt), RejectedMessage);
  agents[0].track_id = 1ULL << 40;
  EXPECT_THROW(humansFromTrackedAgents(msg, frames(), opt), RejectedMessage);
}

TEST(Ros2Conversions, HumansFromPeopleTakeTheirIdFromTheName) {
  char name1[] = "person_12";
  char name2[] = "3";
  char bad[] = "alice";
  std::vector<people_msgs_msg_dds__Person_> people(2);
  people[0] = {};
  people[0].name = name1;
  people[0].position = {1.0, 2.0, 0.0};
  people[0].velocity = {0.0, 1.0, 0.0};
  people[1] = {};
  people[1].name = name2;
  people[1].position = {4.0, 2.0, 0.0};
  People msg{};
  msg.header.frame_id = kMap;
  msg.people = {2, 2, people.data(), false};
  const auto humans = humansFromPeople(msg, frames(), HumanOptions{});
  ASSERT_EQ(humans.size(), 2U);
  EXPECT_EQ(humans[0].id, 12);
  EXPECT_NEAR(humans[0].theta_rad, M_PI / 2, kEps);  // heading from the velocity
  EXPECT_NEAR(humans[0].vy_m_s, 1.0, kEps);
  EXPECT_EQ(humans[1].id, 3);
  EXPECT_NEAR(humans[1].theta_rad, 0.0, kEps);  // standing
  people[1].name = bad;
  EXPECT_THROW(humansFromPeople(msg, frames(), HumanOptions{}), RejectedMessage);
  people[1].name = name1;
  EXPECT_THROW(humansFromPeople(msg, frames(), HumanOptions{}), RejectedMessage);
}

TEST(Ros2Conversions, GoalPoseBecomesTheRobotsGoal) {
  PoseStamped p{};
  p.header.frame_id = kMap;
  p.header.stamp = {5, 0};
  p.pose.position = {20.5, 6.5, 0.0};
  p.pose.orientation = quaternionOfYaw(0.5);
  const goals_t g = goalsFromPoseStamped(p, frames(), 0);
  ASSERT_EQ(g.num_goals, 1);
  EXPECT_EQ(g.utime, 5'000'000);
  EXPECT_EQ(g.goals[0].agent_id, 0);
  EXPECT_EQ(g.goals[0].kind, +agent_state_t::KIND_ROBOT);
  EXPECT_NEAR(g.goals[0].x_m, 20.5, kEps);
  EXPECT_NEAR(g.goals[0].theta_rad, 0.5, kEps);
}

TEST(Ros2Conversions, ScanGetsTheSensorPoseInTheMapFrame) {
  std::vector<float> ranges{1.0F, std::numeric_limits<float>::infinity(), 2.5F};
  LaserScan s{};
  s.header.frame_id = kBaseLink;
  s.header.stamp = {3, 250000000U};
  s.angle_min = -0.5F;
  s.angle_max = 0.5F;
  s.angle_increment = 0.5F;
  s.range_min = 0.05F;
  s.range_max = 10.0F;
  s.ranges = {3, 3, ranges.data(), false};
  // Robot at (2, 1) facing +y; laser 0.2 m ahead of the base: at (2, 1.2) facing +y.
  const laser_scan_t out = scanFromLaserScan(s, {2.0, 1.0, M_PI / 2}, {0.2, 0.0, 0.0}, -1);
  EXPECT_EQ(out.utime, 3'250'000);
  EXPECT_EQ(out.step, -1);
  EXPECT_NEAR(out.sensor_x_m, 2.0, kEps);
  EXPECT_NEAR(out.sensor_y_m, 1.2, kEps);
  EXPECT_NEAR(out.sensor_yaw_rad, M_PI / 2, kEps);
  ASSERT_EQ(out.num_ranges, 3);
  EXPECT_TRUE(std::isinf(out.ranges_m[1]));
  EXPECT_FLOAT_EQ(out.ranges_m[2], 2.5F);
  s.angle_increment = -0.5F;
  EXPECT_THROW(scanFromLaserScan(s, {}, {}, -1), RejectedMessage);
  s.angle_increment = 0.5F;
  s.range_max = 0.0F;
  EXPECT_THROW(scanFromLaserScan(s, {}, {}, -1), RejectedMessage);
}

TEST(Ros2Conversions, CommandBecomesTwistAndNanIsNeverSent) {
  velocity_command_t c{};
  c.vx_m_s = 0.6;
  c.omega_rad_s = -0.3;
  const Twist t = twistOfCommand(c);
  EXPECT_DOUBLE_EQ(t.linear.x, 0.6);
  EXPECT_DOUBLE_EQ(t.linear.y, 0.0);
  EXPECT_DOUBLE_EQ(t.angular.z, -0.3);
  c.vx_m_s = std::nan("");
  EXPECT_THROW(twistOfCommand(c), RejectedMessage);
}

TEST(Ros2Conversions, WatchdogDecision) {
  EXPECT_TRUE(commandStale(std::nullopt, 0.0, 0.5));
  EXPECT_FALSE(commandStale(10.0, 10.4, 0.5));
  EXPECT_FALSE(commandStale(10.0, 10.5, 0.5));
  EXPECT_TRUE(commandStale(10.0, 10.51, 0.5));
}

TEST(Ros2Conversions, DdsTopicNamesFollowRmwCycloneDds) {
  EXPECT_EQ(ddsTopicName("", "cmd_vel"), "rt/cmd_vel");
  EXPECT_EQ(ddsTopicName("/", "cmd_vel"), "rt/cmd_vel");
  EXPECT_EQ(ddsTopicName("/robot1", "cmd_vel"), "rt/robot1/cmd_vel");
  EXPECT_EQ(ddsTopicName("robot1/", "coopnav/markers"), "rt/robot1/coopnav/markers");
  EXPECT_EQ(ddsTopicName("/robot1", "/scan"), "rt/scan");
  EXPECT_EQ(ddsTopicName("/robot1", ""), "");
}

band_t band(std::int32_t id, std::int8_t kind, std::vector<std::pair<double, double>> xy) {
  band_t b{};
  b.agent_id = id;
  b.kind = kind;
  for (std::size_t i = 0; i < xy.size(); ++i)
    b.poses.push_back({0.1 * static_cast<double>(i), xy[i].first, xy[i].second, 0.0});
  b.num_poses = static_cast<std::int16_t>(b.poses.size());
  return b;
}

TEST(Ros2Conversions, MarkersShowBandsAssessmentAndUtterance) {
  bands_t b{};
  b.utime = 1'000'000;
  b.status = bands_t::STATUS_OK;
  b.robot = band(0, agent_state_t::KIND_ROBOT, {{0, 0}, {1, 0}, {2, 0}});
  b.humans.push_back(band(4, agent_state_t::KIND_HUMAN, {{5, 0.5}, {4, 0.5}}));
  b.num_humans = 1;
  situation_t s{};
  s.human_id = 4;
  s.t_cross_s = 2.0;
  s.cp_h_x_m = 3.0;
  s.cp_h_y_m = 0.5;
  s.cp_r_x_m = 3.0;
  s.cp_r_y_m = -0.5;
  s.dir = situation_t::DIR_LEFT;
  s.d_h_m = 0.4;
  s.d_oh_m = 0.8;
  s.d_or_m = std::nan("");
  s.human_needs_to_contribute = situation_t::PRED_TRUE;
  s.human_is_constrained = situation_t::PRED_FALSE;
  s.robot_is_constrained = situation_t::PRED_UNKNOWN;
  utterance_t u{};
  u.text = "I will pass on your left.";
  const auto m = markersOf(b, {s}, &u);
  auto find = [&](const std::string& ns) -> const MarkerSpec* {
    for (const auto& x : m)
      if (x.ns == ns) return &x;
    return nullptr;
  };
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(m.front().action, +kMarkerDeleteAll);
  ASSERT_NE(find("robot_band"), nullptr);
  EXPECT_EQ(find("robot_band")->type, +kMarkerLineStrip);
  EXPECT_EQ(find("robot_band")->points.size(), 3U);
  ASSERT_NE(find("human_bands"), nullptr);
  EXPECT_EQ(find("human_bands")->id, 4);
  ASSERT_NE(find("cp_h"), nullptr);
  EXPECT_NEAR(find("cp_h")->pose.y_m, 0.5, kEps);
  ASSERT_NE(find("cp_r"), nullptr);
  EXPECT_NEAR(find("cp_r")->pose.y_m, -0.5, kEps);
  ASSERT_NE(find("dir"), nullptr);
  EXPECT_EQ(find("dir")->type, +kMarkerArrow);
  const MarkerSpec* text = find("assessment");
  ASSERT_NE(text, nullptr);
  for (const char* part :
       {"Dir left", "d_h 0.40", "d_OH 0.80", "d_OR ?", "human_needs_to_contribute true",
        "human_is_constrained false", "robot_is_constrained unknown"})
    EXPECT_NE(text->text.find(part), std::string::npos) << part << " in " << text->text;
  ASSERT_NE(find("utterance"), nullptr);
  EXPECT_EQ(find("utterance")->text, u.text);
  // No utterance, no bands (status not OK): only what is known is drawn.
  b.status = bands_t::STATUS_NO_PATH;
  const auto m2 = markersOf(b, {}, nullptr);
  ASSERT_EQ(m2.size(), 1U);
  EXPECT_EQ(m2.front().action, +kMarkerDeleteAll);
}

}  // namespace
}  // namespace coopnav::ros2

namespace coopnav {
namespace {

// One robot radius: the bridge's (agent states), the situation assessor's (clearances of the
// robot's body) and the scenarios' robot (docs/scenario-format.md, 0.47 m: CoHAN's PR2) are the
// same in the shipped files and in the bridge's in-class default.
TEST(Ros2BridgeConfig, RobotRadiusIsTheRestOfTheConfigs) {
  const std::string dir = ::coopnav::test::sourceDir() + "/config/";
  const Ros2BridgeConfig bridge = loadConfig<Ros2BridgeConfig>(dir + "ros2_bridge.yaml");
  const YAML::Node assessor = YAML::LoadFile(dir + "situation_assessor.yaml");
  const double assessor_m = assessor["robot_radius_m"].as<double>();
  EXPECT_DOUBLE_EQ(bridge.robot_radius_m, assessor_m);
  EXPECT_DOUBLE_EQ(Ros2BridgeConfig{}.robot_radius_m, assessor_m);
  EXPECT_DOUBLE_EQ(assessor_m, 0.47);
}

}  // namespace
}  // namespace coopnav
