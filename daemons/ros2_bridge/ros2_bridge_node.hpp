#pragma once
/// @file ROS 2 bridge: coopnav's LCM bus <-> a ROS 2 system over Cyclone DDS, with ROS 2's
/// names, types (idl/ros2_types.idl) and QoS, without ROS installed. In: odometry (or AMCL's
/// pose), tracked people, the goal and the laser scan -> agent states, goals and scans on LCM.
/// Out: the velocity command -> /cmd_vel, with a watchdog that sends zero when the pipeline goes
/// quiet; bands, situations and utterances -> rviz2 markers and the utterance text.
///
/// DDS is polled from the runtime's loop by a timer (dds_take, never blocking), so that every
/// handler runs on the loop's thread like any other daemon's. Conversions: ros2_conversions.hpp.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "ros2_conversions.hpp"
#include "runtime/limits.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// ROS 2 topic names, relative to `ros_namespace` unless they start with '/'. "" disables one.
struct Ros2TopicsConfig {
  std::string odom{"odom"};
  std::string pose{""};
  std::string tracked_agents{"tracked_agents"};
  std::string people{"people"};
  std::string goal{"goal_pose"};
  std::string scan{"scan"};
  std::string cmd_vel{"cmd_vel"};
  std::string markers{"coopnav/markers"};
  std::string utterance{"coopnav/utterance"};
  template <class V>
  void visit(V& v) {
    v("odom", odom);
    v("pose", pose);
    v("tracked_agents", tracked_agents);
    v("people", people);
    v("goal", goal);
    v("scan", scan);
    v("cmd_vel", cmd_vel);
    v("markers", markers);
    v("utterance", utterance);
  }
};

struct Ros2BridgeConfig {
  /// DDS domain = ROS_DOMAIN_ID; -1 = $ROS_DOMAIN_ID when set, else 0.
  int domain_id{-1};
  /// ROS 2 namespace of the relative topic names ("" = root, "/robot1").
  std::string ros_namespace{""};
  Ros2TopicsConfig topics;
  std::string map_frame{"map"};
  std::string odom_frame{"odom"};
  /// odom -> map [m, m, rad] (the odometry frame's origin in the map) when topics.pose is "".
  double odom_to_map_x_m{0.0};
  double odom_to_map_y_m{0.0};
  double odom_to_map_yaw_rad{0.0};
  /// [m] the robot's disc radius in the agent states.
  double robot_radius_m{0.47};
  /// [m] a human's disc radius when the tracker gives none.
  double human_radius_m{0.3};
  /// Where the humans come from: "tracked_agents" (cohan_msgs) or "people" (people_msgs).
  std::string humans_from{"tracked_agents"};
  /// cohan_msgs/TrackedSegmentType of the body segment (TORSO).
  int body_segment_type{1};
  /// [s of message time] humans older than this than the odometry are left out.
  double humans_max_age_s{1.0};
  /// The laser's mounting on the base [m, m, rad] (base_link -> laser).
  double laser_x_m{0.0};
  double laser_y_m{0.0};
  double laser_yaw_rad{0.0};
  /// [s] no velocity command for this long -> zero on /cmd_vel (monotonic clock: liveness).
  double cmd_timeout_s{0.5};
  /// [Hz] how often the watchdog checks, and repeats zero while the pipeline is quiet.
  double watchdog_hz{20.0};
  /// [ms] how often DDS is polled for samples (the bridge's inbound latency floor).
  /// [s of message time] an utterance stays on the markers this long after its decision.
  double utterance_display_s{5.0};
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("domain_id", domain_id, Range{-1, 232});
    v("ros_namespace", ros_namespace);
    v("topics", topics);
    v("map_frame", map_frame);
    v("odom_frame", odom_frame);
    v("odom_to_map_x_m", odom_to_map_x_m, Range{-1e6, 1e6});
    v("odom_to_map_y_m", odom_to_map_y_m, Range{-1e6, 1e6});
    v("odom_to_map_yaw_rad", odom_to_map_yaw_rad, Range{-7.0, 7.0});
    v("robot_radius_m", robot_radius_m, Range{0.01, 5.0});
    v("human_radius_m", human_radius_m, Range{0.01, 5.0});
    v("humans_from", humans_from, OneOf{{"tracked_agents", "people"}});
    v("body_segment_type", body_segment_type, Range{-128, 127});
    v("humans_max_age_s", humans_max_age_s, Range{0.0, 60.0});
    v("laser_x_m", laser_x_m, Range{-10.0, 10.0});
    v("laser_y_m", laser_y_m, Range{-10.0, 10.0});
    v("laser_yaw_rad", laser_yaw_rad, Range{-7.0, 7.0});
    v("cmd_timeout_s", cmd_timeout_s, Range{0.01, 60.0});
    v("watchdog_hz", watchdog_hz, Range{1.0, 1000.0});
    v("utterance_display_s", utterance_display_s, Range{0.0, 600.0});
    v("limits", limits);
  }
};

class Ros2BridgeNode {
 public:
  using Config = Ros2BridgeConfig;
  /// Creates the DDS participant, readers and writers; throws StartupError when DDS cannot.
  Ros2BridgeNode(const Config& config, Runtime& runtime);
  ~Ros2BridgeNode();
  Ros2BridgeNode(const Ros2BridgeNode&) = delete;
  Ros2BridgeNode& operator=(const Ros2BridgeNode&) = delete;

  /// Takes every pending DDS sample and handles it (the loop calls this when a reader's listener
  /// woke it).
  void pollDds();
  /// The watchdog tick (its timer calls this): zero on /cmd_vel while commands are stale.
  void watchdogTick();
  /// Number of zero commands the watchdog sent (tests, status).
  std::int64_t watchdogZeros() const { return watchdog_zeros_; }

 private:
  struct Dds;
  void onOdometry(const ros2::Odometry& msg);
  void onPose(const ros2::PoseWithCovarianceStamped& msg);
  void onTrackedAgents(const ros2::TrackedAgents& msg);
  void onPeople(const ros2::People& msg);
  void onGoal(const ros2::PoseStamped& msg);
  void onScan(const ros2::LaserScan& msg);
  void onCommand(const velocity_command_t& msg);
  void onBands(const bands_t& msg);
  void onSituation(const situation_t& msg);
  void onUtterance(const utterance_t& msg);
  void writeTwist(const ros2::Twist& t);
  void publishMarkers();
  double monotonicNowS() const;

  Config config_;
  Runtime& runtime_;
  ros2::FrameSet frames_;
  ros2::HumanOptions human_options_;
  Dds* dds_{nullptr};
  std::optional<ros2::Pose2> robot_in_odom_;  ///< latest odometry pose (odom frame)
  std::optional<ros2::Pose2> robot_in_map_;
  std::vector<agent_state_t> humans_;
  std::int64_t humans_utime_{-1};
  std::optional<double> last_command_s_;  ///< monotonic [s] of the last command forwarded
  std::int64_t watchdog_zeros_{0};
  bool holding_{false};  ///< the watchdog is sending zero
  std::string running_detail_;
  std::optional<bands_t> bands_;
  std::map<std::int32_t, situation_t> situations_;
  std::optional<utterance_t> utterance_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace coopnav
