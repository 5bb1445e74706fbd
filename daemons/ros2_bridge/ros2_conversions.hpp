#pragma once
/// @file The one place where ROS 2 messages (the DDS structs idlc generates from
/// idl/ros2_types.idl) meet coopnav's lcmtypes. Pure functions: no DDS entity, no clock, no I/O.
/// Inbound conversions validate (finite numbers, unit quaternions, known frames, counts within
/// the lcmtype's MAX_*) and throw RejectedMessage with the reason; outbound ones build
/// self-contained C++ values (MarkerSpec) that the node points the DDS structs at to write.
///
/// Frames: coopnav's world frame is the robot's map frame. A ROS message stamped in the map
/// frame is taken as is; one in the odometry frame goes through odom -> map (configured, or
/// from the AMCL pose: odomToMapFromPoses). Any other frame is rejected: the bridge has no TF.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/agent_state_t.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "ros2_types.h"

namespace coopnav::ros2 {

using Time = builtin_interfaces_msg_dds__Time_;
using Quaternion = geometry_msgs_msg_dds__Quaternion_;
using Pose = geometry_msgs_msg_dds__Pose_;
using Twist = geometry_msgs_msg_dds__Twist_;
using Odometry = nav_msgs_msg_dds__Odometry_;
using PoseStamped = geometry_msgs_msg_dds__PoseStamped_;
using PoseWithCovarianceStamped = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
using LaserScan = sensor_msgs_msg_dds__LaserScan_;
using People = people_msgs_msg_dds__People_;
using TrackedAgents = cohan_msgs_msg_dds__TrackedAgents_;

/// A planar pose [m, m, rad].
struct Pose2 {
  double x_m{0.0};
  double y_m{0.0};
  double yaw_rad{0.0};
};

/// The rigid transform that takes coordinates of a frame into the map frame (the pose of that
/// frame's origin in the map).
struct Transform2 {
  double x_m{0.0};
  double y_m{0.0};
  double yaw_rad{0.0};
  Pose2 apply(const Pose2& p) const;
  /// Rotates a free vector (a velocity) into the map frame.
  void rotate(double vx, double vy, double& out_vx, double& out_vy) const;
  Transform2 inverse() const;
  /// this * other: first other, then this.
  Transform2 compose(const Transform2& other) const;
};

/// The frames the bridge knows, and the transform of the odometry frame into the map frame.
struct FrameSet {
  std::string map_frame{"map"};
  std::string odom_frame{"odom"};
  Transform2 odom_to_map;
};

/// The transform of `frame_id` into the map frame; "" is taken as the map frame (ROS
/// publishers that leave the frame empty mean their fixed frame). Throws RejectedMessage for an
/// unknown frame.
Transform2 frameToMap(const char* frame_id, const FrameSet& frames);

/// ROS time (sec, nanosec) <-> utime [us]. Negative or non-normalised stamps are rejected.
std::int64_t stampToUtime(const Time& t);
Time utimeToStamp(std::int64_t utime);

/// Yaw [rad] of a quaternion (rotation about z of a planar pose). A non-finite or zero-norm
/// quaternion is rejected; a non-unit one is normalised (rviz2 sends exactly unit ones).
double yawOf(const Quaternion& q);
Quaternion quaternionOfYaw(double yaw_rad);

/// map <- odom from the same robot pose seen in both frames (AMCL's map pose and the odometry
/// pose at that stamp): map_T_odom = map_T_base * (odom_T_base)^-1.
Transform2 odomToMapFromPoses(const Pose2& base_in_map, const Pose2& base_in_odom);

/// The planar pose of a ROS pose (rejects non-finite numbers).
Pose2 pose2Of(const Pose& p);

/// The robot's agent state from odometry: pose in header.frame_id (map or odom) into the map
/// frame; the twist is in child_frame_id (the base, REP 105), rotated into the map frame.
agent_state_t robotFromOdometry(const Odometry& odom, const FrameSet& frames, double radius_m);

/// What the human conversions need besides the message.
struct HumanOptions {
  double default_radius_m{0.3};  ///< used when the message gives none (People, radius <= 0)
  /// cohan_msgs/TrackedSegmentType of the segment that stands for the body (TORSO); an agent
  /// without it uses its first segment.
  std::int8_t body_segment_type{1};
  std::int32_t max_humans{agent_states_t::MAX_HUMANS};
};

/// Humans of a cohan_msgs/TrackedAgents message (agents of type HUMAN only; the robot's own
/// track, type ROBOT, is skipped): id = track_id (must fit 1 .. INT32_MAX), position, heading
/// and velocity of the body segment, in the map frame. Ids unique.
std::vector<agent_state_t> humansFromTrackedAgents(const TrackedAgents& msg, const FrameSet& frames,
                                                   const HumanOptions& options);

/// Humans of a people_msgs/People message: id from the digits that end `name` ("3", "person_3";
/// a name without them is rejected: ids must be stable), heading from the velocity (0 standing).
std::vector<agent_state_t> humansFromPeople(const People& msg, const FrameSet& frames,
                                            const HumanOptions& options);

/// The robot's goal from a /goal_pose (rviz2 "2D Goal Pose", Nav2), in the map frame.
goals_t goalsFromPoseStamped(const PoseStamped& msg, const FrameSet& frames, std::int32_t robot_id);

/// A /scan as laser_scan_t: the sensor pose in the map frame is the robot's map pose composed
/// with the configured mounting offset of the laser on the base. Ranges copied as they are
/// (NaN / inf / out of [range_min, range_max] mean no return, as in both types).
laser_scan_t scanFromLaserScan(const LaserScan& msg, const Pose2& robot_in_map,
                               const Pose2& sensor_on_base, std::int64_t step);

/// /cmd_vel from a velocity command (body frame, REP 103: x forward, z up). Non-finite
/// components are rejected: a NaN must never reach a base controller.
Twist twistOfCommand(const velocity_command_t& cmd);

/// The watchdog (I/O liveness, not logic): whether the base must be stopped now, given the
/// monotonic time [s] of the last command received (nullopt: none yet) and of now.
bool commandStale(std::optional<double> last_command_s, double now_s, double cmd_timeout_s);

/// One rviz2 marker, self-contained (strings and points owned). Field meaning as in
/// visualization_msgs/Marker; the node points a Marker_ at it to write.
struct MarkerSpec {
  std::string ns;
  std::int32_t id{0};
  std::int32_t type{0};    ///< Marker.type: ARROW 0, SPHERE 2, LINE_STRIP 4, TEXT_VIEW_FACING 9
  std::int32_t action{0};  ///< ADD 0, DELETEALL 3
  Pose2 pose;
  double z_m{0.0};
  double scale_x{0.1}, scale_y{0.1}, scale_z{0.1};
  float r{1.0F}, g{1.0F}, b{1.0F}, a{1.0F};
  std::vector<Pose2> points;  ///< LINE_STRIP vertices (z = z_m)
  std::string text;
};

inline constexpr std::int32_t kMarkerArrow = 0;
inline constexpr std::int32_t kMarkerSphere = 2;
inline constexpr std::int32_t kMarkerLineStrip = 4;
inline constexpr std::int32_t kMarkerText = 9;
inline constexpr std::int32_t kMarkerAdd = 0;
inline constexpr std::int32_t kMarkerDeleteAll = 3;

/// What the robot thinks, for rviz2: a DELETEALL first (people come and go), then the robot
/// band and every human band (LINE_STRIP), per assessed human CP_h and CP_r (SPHERE), Dir (ARROW
/// at CP_r pointing to the side the robot passes on), d_h / d_OH / d_OR and the three predicates
/// (TEXT), and the current utterance above the robot (TEXT). `situations` are the latest per
/// human assessed in this bands message; `utterance` the last one said (nullptr: none).
std::vector<MarkerSpec> markersOf(const bands_t& bands, const std::vector<situation_t>& situations,
                                  const utterance_t* utterance);

/// Marker text of a predicate value (situation_t.PRED_*).
const char* predicateText(std::int8_t pred);

}  // namespace coopnav::ros2

namespace coopnav::ros2 {
/// The DDS topic of a ROS 2 topic name (rmw_cyclonedds_cpp): "rt" + the fully qualified name.
/// A relative `topic` ("cmd_vel") is put in `ros_namespace` ("" or "/" = the root, "/robot1");
/// an absolute one ("/cmd_vel") is kept. "" for an empty topic (disabled).
std::string ddsTopicName(const std::string& ros_namespace, const std::string& topic);
}  // namespace coopnav::ros2
