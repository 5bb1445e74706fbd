// The ROS 2 bridge node in-process: LCM on memq://, DDS on the loopback interface
// (CYCLONEDDS_URI, test/dds/cyclonedds_loopback.xml) in a domain of its own. A test-side DDS
// participant plays the robot's ROS 2 nodes with the same IDL, names and QoS: each direction
// (DDS in -> LCM out, LCM in -> DDS out) and the /cmd_vel watchdog.
#include "ros2_bridge_node.hpp"

#include <dds/dds.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kDomain = 71;  // this test's own (ros2_bridge e2e and bench use others)

/// The robot side: one participant with the bridge's topics, reversed.
struct RobotSide {
  dds_entity_t pp{dds_create_participant(kDomain, nullptr, nullptr)};
  ~RobotSide() { dds_delete(pp); }

  dds_entity_t make(const char* name, const dds_topic_descriptor_t* desc, bool reader,
                    bool sensor = false) {
    const dds_entity_t topic = dds_create_topic(pp, desc, name, nullptr, nullptr);
    dds_qos_t* q = dds_create_qos();
    if (sensor) {
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 5);
    } else {
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
    }
    dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
    const dds_entity_t e = reader ? dds_create_reader(pp, topic, q, nullptr)
                                  : dds_create_writer(pp, topic, q, nullptr);
    dds_delete_qos(q);
    return e;
  }

  /// Takes every sample of `reader` and calls fn on each.
  template <class Msg>
  static void take(dds_entity_t reader, const std::function<void(const Msg&)>& fn) {
    for (;;) {
      void* samples[8] = {};
      dds_sample_info_t infos[8];
      const dds_return_t n = dds_take(reader, samples, infos, 8, 8);
      if (n <= 0) return;
      for (dds_return_t i = 0; i < n; ++i)
        if (infos[i].valid_data) fn(*static_cast<const Msg*>(samples[i]));
      dds_return_loan(reader, samples, n);
    }
  }
};

Ros2BridgeConfig testConfig() {
  Ros2BridgeConfig c;
  c.domain_id = kDomain;
  c.cmd_timeout_s = 0.2;
  c.watchdog_hz = 50.0;
  c.odom_to_map_x_m = 10.0;  // odom's origin 10 m along the map's x
  c.laser_x_m = 0.2;
  return c;
}

/// Spins both runtimes (memq: one spin handles all) and calls `step` until `done` or timeout.
bool spinUntil(Runtime& rt, const std::function<void()>& step, const std::function<bool()>& done,
               double timeout_s = 5.0) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < end) {
    step();
    rt.spinFor(5);
    if (done()) return true;
  }
  return false;
}

TEST(Ros2BridgeNode, DdsInLcmOut) {
  Runtime rt("ros2_bridge", "memq://");
  Ros2BridgeNode node(testConfig(), rt);
  Runtime probe("ros2_bridge_probe", "memq://");
  std::optional<agent_states_t> states;
  std::optional<goals_t> goals;
  std::optional<laser_scan_t> scan;
  probe.subscribe<agent_states_t>(channels::kAgentStates,
                                  [&](const agent_states_t& m, std::int64_t) {
                                    if (m.num_humans == 1) states = m;
                                  });
  probe.subscribe<goals_t>(channels::kGoals, [&](const goals_t& m, std::int64_t) { goals = m; });
  probe.subscribe<laser_scan_t>(channels::kScan,
                                [&](const laser_scan_t& m, std::int64_t) { scan = m; });

  RobotSide robot;
  const auto odom_w = robot.make("rt/odom", &nav_msgs_msg_dds__Odometry__desc, false);
  const auto agents_w =
      robot.make("rt/tracked_agents", &cohan_msgs_msg_dds__TrackedAgents__desc, false);
  const auto goal_w = robot.make("rt/goal_pose", &geometry_msgs_msg_dds__PoseStamped__desc, false);
  const auto scan_w = robot.make("rt/scan", &sensor_msgs_msg_dds__LaserScan__desc, false, true);

  char odom_frame[] = "odom";
  char map_frame[] = "map";
  char base[] = "base_link";
  char empty[] = "";
  ros2::Odometry odom{};
  odom.header.frame_id = odom_frame;
  odom.header.stamp = {100, 0};
  odom.child_frame_id = base;
  odom.pose.pose.position = {1.0, 2.0, 0.0};
  odom.pose.pose.orientation = ros2::quaternionOfYaw(0.0);
  odom.twist.twist.linear.x = 0.7;

  cohan_msgs_msg_dds__TrackedSegment_ seg{};
  seg.type = 1;
  seg.pose.pose.position = {15.0, 2.0, 0.0};
  seg.pose.pose.orientation = ros2::quaternionOfYaw(M_PI);
  seg.twist.twist.linear.x = -1.0;
  cohan_msgs_msg_dds__TrackedAgent_ agent{};
  agent.track_id = 5;
  agent.type = 1;
  agent.name = empty;
  agent.radius = 0.3;
  agent.segments = {1, 1, &seg, false};
  ros2::TrackedAgents agents{};
  agents.header.frame_id = map_frame;
  agents.header.stamp = {100, 0};
  agents.agents = {1, 1, &agent, false};

  ros2::PoseStamped goal{};
  goal.header.frame_id = map_frame;
  goal.header.stamp = {100, 0};
  goal.pose.position = {20.0, 2.0, 0.0};
  goal.pose.orientation = ros2::quaternionOfYaw(0.0);

  std::vector<float> ranges(181, 4.0F);
  ros2::LaserScan ls{};
  ls.header.frame_id = base;
  ls.header.stamp = {100, 0};
  ls.angle_min = static_cast<float>(-M_PI / 2);
  ls.angle_max = static_cast<float>(M_PI / 2);
  ls.angle_increment = static_cast<float>(M_PI / 180);
  ls.range_min = 0.05F;
  ls.range_max = 8.0F;
  ls.ranges = {181, 181, ranges.data(), false};

  // Volatile topics: samples written before discovery matched are lost, so write until heard.
  const bool all = spinUntil(
      rt,
      [&] {
        dds_write(agents_w, &agents);
        dds_write(odom_w, &odom);
        dds_write(goal_w, &goal);
        dds_write(scan_w, &ls);
      },
      [&] { return states && goals && scan; });
  ASSERT_TRUE(all) << "states " << states.has_value() << " goals " << goals.has_value() << " scan "
                   << scan.has_value();
  EXPECT_EQ(states->utime, 100'000'000);
  EXPECT_EQ(states->step, -1);
  EXPECT_NEAR(states->robot.x_m, 11.0, 1e-9);  // odom (1, 2) + odom->map (10, 0)
  EXPECT_NEAR(states->robot.y_m, 2.0, 1e-9);
  EXPECT_NEAR(states->robot.vx_m_s, 0.7, 1e-9);
  EXPECT_EQ(states->humans[0].id, 5);
  EXPECT_NEAR(states->humans[0].x_m, 15.0, 1e-9);
  EXPECT_NEAR(states->humans[0].vx_m_s, -1.0, 1e-9);
  EXPECT_NEAR(goals->goals[0].x_m, 20.0, 1e-9);
  EXPECT_NEAR(scan->sensor_x_m, 11.2, 1e-9);  // the laser 0.2 m ahead of the base
  EXPECT_EQ(scan->num_ranges, 181);
  EXPECT_EQ(scan->utime, 100'000'000);
}

TEST(Ros2BridgeNode, AmclPoseSetsOdomToMap) {
  Ros2BridgeConfig config = testConfig();
  config.topics.pose = "amcl_pose";
  Runtime rt("ros2_bridge", "memq://");
  Ros2BridgeNode node(config, rt);
  Runtime probe("ros2_bridge_probe", "memq://");
  std::optional<agent_states_t> states;
  probe.subscribe<agent_states_t>(channels::kAgentStates,
                                  [&](const agent_states_t& m, std::int64_t) { states = m; });
  RobotSide robot;
  const auto odom_w = robot.make("rt/odom", &nav_msgs_msg_dds__Odometry__desc, false);
  const auto pose_w =
      robot.make("rt/amcl_pose", &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, false);
  char odom_frame[] = "odom";
  char map_frame[] = "map";
  char base[] = "base_link";
  ros2::Odometry odom{};
  odom.header.frame_id = odom_frame;
  odom.header.stamp = {50, 0};
  odom.child_frame_id = base;
  odom.pose.pose.position = {1.0, 0.0, 0.0};
  odom.pose.pose.orientation = ros2::quaternionOfYaw(0.0);
  // AMCL: the same base at (5, 5) heading +y in the map.
  ros2::PoseWithCovarianceStamped amcl{};
  amcl.header.frame_id = map_frame;
  amcl.header.stamp = {50, 0};
  amcl.pose.pose.position = {5.0, 5.0, 0.0};
  amcl.pose.pose.orientation = ros2::quaternionOfYaw(M_PI / 2);
  const bool moved = spinUntil(
      rt,
      [&] {
        dds_write(odom_w, &odom);
        dds_write(pose_w, &amcl);
      },
      [&] { return states && std::abs(states->robot.x_m - 5.0) < 1e-6; });
  ASSERT_TRUE(moved) << (states ? states->robot.x_m : -1.0);
  EXPECT_NEAR(states->robot.y_m, 5.0, 1e-6);
  EXPECT_NEAR(states->robot.theta_rad, M_PI / 2, 1e-6);
}

TEST(Ros2BridgeNode, LcmInDdsOutAndTheWatchdogStopsTheBase) {
  Runtime rt("ros2_bridge", "memq://");
  Ros2BridgeNode node(testConfig(), rt);
  Runtime probe("ros2_bridge_probe", "memq://");
  RobotSide robot;
  const auto cmd_r = robot.make("rt/cmd_vel", &geometry_msgs_msg_dds__Twist__desc, true);
  const auto markers_r =
      robot.make("rt/coopnav/markers", &visualization_msgs_msg_dds__MarkerArray__desc, true);
  const auto say_r = robot.make("rt/coopnav/utterance", &std_msgs_msg_dds__String__desc, true);

  std::vector<double> vx;  // every /cmd_vel linear.x, in order
  std::vector<Clock::time_point> at;
  std::vector<std::string> namespaces;
  std::string said;
  const auto read = [&] {
    RobotSide::take<ros2::Twist>(cmd_r, [&](const ros2::Twist& t) {
      vx.push_back(t.linear.x);
      at.push_back(Clock::now());
    });
    RobotSide::take<visualization_msgs_msg_dds__MarkerArray_>(
        markers_r, [&](const visualization_msgs_msg_dds__MarkerArray_& m) {
          namespaces.clear();
          for (std::uint32_t i = 0; i < m.markers._length; ++i)
            namespaces.emplace_back(m.markers._buffer[i].ns);
        });
    RobotSide::take<std_msgs_msg_dds__String_>(
        say_r, [&](const std_msgs_msg_dds__String_& s) { said = s.data; });
  };

  velocity_command_t cmd{};
  cmd.utime = 1'000'000;
  cmd.step = -1;
  cmd.vx_m_s = 0.5;
  bands_t bands{};
  bands.utime = 1'000'000;
  bands.step = -1;
  bands.status = bands_t::STATUS_OK;
  bands.robot.agent_id = 0;
  bands.robot.poses = {{0.0, 0.0, 0.0, 0.0}, {0.1, 0.05, 0.0, 0.0}};
  bands.robot.num_poses = 2;
  band_t hb{};
  hb.agent_id = 3;
  hb.kind = agent_state_t::KIND_HUMAN;
  hb.poses = {{0.0, 5.0, 0.5, M_PI}, {0.1, 4.9, 0.5, M_PI}};
  hb.num_poses = 2;
  bands.humans = {hb};
  bands.room_plans = {bands_t::ROOM_UNKNOWN};
  bands.num_humans = 1;
  situation_t sit{};
  sit.utime = 1'000'000;
  sit.human_id = 3;
  sit.cp_h_x_m = 2.5;
  sit.cp_h_y_m = 0.5;
  sit.cp_r_x_m = 2.5;
  sit.cp_r_y_m = -0.3;
  sit.dir = situation_t::DIR_RIGHT;
  sit.t_cross_s = 2.0;
  utterance_t utt{};
  utt.utime = 1'000'000;
  utt.human_id = 3;
  utt.text = "I will pass on your right.";
  utt.delivery = utterance_t::DELIVERY_SAID;

  const bool heard = spinUntil(
      rt,
      [&] {
        probe.publish(channels::kRobotCmd, cmd);
        probe.publish(channels::kSituation, sit);
        probe.publish(channels::kUtterance, utt);
        probe.publish(channels::kBands, bands);
        read();
      },
      [&] {
        bool has_half = false;
        for (double v : vx) has_half = has_half || v == 0.5;
        return has_half && !said.empty() && namespaces.size() > 4;
      });
  ASSERT_TRUE(heard) << vx.size() << " twists, said '" << said << "', " << namespaces.size()
                     << " markers";
  EXPECT_EQ(said, utt.text);
  for (const char* ns :
       {"robot_band", "human_bands", "cp_h", "cp_r", "dir", "assessment", "utterance"})
    EXPECT_NE(std::find(namespaces.begin(), namespaces.end(), ns), namespaces.end()) << ns;

  // The pipeline goes quiet: the watchdog sends zero within cmd_timeout_s (0.2 s) plus its
  // period and the DDS delivery; the bound checked here is loose (a loaded CI machine).
  const auto last_cmd = Clock::now();
  vx.clear();
  at.clear();
  const bool stopped = spinUntil(
      rt, read, [&] { return !vx.empty() && vx.back() == 0.0; }, 3.0);
  ASSERT_TRUE(stopped);
  const double after_s = std::chrono::duration<double>(at.back() - last_cmd).count();
  EXPECT_GE(after_s, 0.1);  // not before the timeout (minus the command in flight)
  EXPECT_LT(after_s, 1.5);
  EXPECT_GE(node.watchdogZeros(), 1);
  // A NaN command is never forwarded.
  cmd.vx_m_s = std::nan("");
  vx.clear();
  const auto before = rt.counters().rejected;
  spinUntil(
      rt, [&] { probe.publish(channels::kRobotCmd, cmd); },
      [&] { return rt.counters().rejected > before; });
  rt.spinFor(50);
  read();
  for (double v : vx) EXPECT_FALSE(std::isnan(v));
}

}  // namespace
}  // namespace coopnav
