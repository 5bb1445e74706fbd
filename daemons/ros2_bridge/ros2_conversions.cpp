#include "ros2_conversions.hpp"

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>

#include "runtime/runtime.hpp"

namespace coopnav::ros2 {
namespace {

void requireFinite(double v, const char* what) {
  if (!std::isfinite(v)) throw RejectedMessage(std::string(what) + " is not finite");
}

std::string str(const char* s) { return s == nullptr ? std::string() : std::string(s); }

}  // namespace

Pose2 Transform2::apply(const Pose2& p) const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {x_m + c * p.x_m - s * p.y_m, y_m + s * p.x_m + c * p.y_m, p.yaw_rad + yaw_rad};
}

void Transform2::rotate(double vx, double vy, double& out_vx, double& out_vy) const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  out_vx = c * vx - s * vy;
  out_vy = s * vx + c * vy;
}

Transform2 Transform2::inverse() const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {-(c * x_m + s * y_m), -(-s * x_m + c * y_m), -yaw_rad};
}

Transform2 Transform2::compose(const Transform2& other) const {
  const Pose2 p = apply({other.x_m, other.y_m, other.yaw_rad});
  return {p.x_m, p.y_m, p.yaw_rad};
}

Transform2 frameToMap(const char* frame_id, const FrameSet& frames) {
  const std::string f = str(frame_id);
  if (f.empty() || f == frames.map_frame) return {};
  if (f == frames.odom_frame) return frames.odom_to_map;
  throw RejectedMessage("frame '" + f + "' is neither the map frame '" + frames.map_frame +
                        "' nor the odometry frame '" + frames.odom_frame + "'");
}

std::int64_t stampToUtime(const Time& t) {
  if (t.sec < 0) throw RejectedMessage("negative stamp");
  if (t.nanosec >= 1000000000U) throw RejectedMessage("stamp nanosec >= 1e9");
  return static_cast<std::int64_t>(t.sec) * 1000000 + static_cast<std::int64_t>(t.nanosec) / 1000;
}

Time utimeToStamp(std::int64_t utime) {
  Time t{};
  if (utime <= 0) return t;
  const std::int64_t sec = utime / 1000000;
  t.sec = sec > std::numeric_limits<std::int32_t>::max() ? std::numeric_limits<std::int32_t>::max()
                                                         : static_cast<std::int32_t>(sec);
  t.nanosec = static_cast<std::uint32_t>((utime % 1000000) * 1000);
  return t;
}

double yawOf(const Quaternion& q) {
  for (double v : {q.x, q.y, q.z, q.w}) requireFinite(v, "quaternion");
  const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (n < 1e-9) throw RejectedMessage("zero quaternion");
  const double x = q.x / n, y = q.y / n, z = q.z / n, w = q.w / n;
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

Quaternion quaternionOfYaw(double yaw_rad) {
  return {0.0, 0.0, std::sin(0.5 * yaw_rad), std::cos(0.5 * yaw_rad)};
}

Transform2 odomToMapFromPoses(const Pose2& base_in_map, const Pose2& base_in_odom) {
  const Transform2 map_base{base_in_map.x_m, base_in_map.y_m, base_in_map.yaw_rad};
  const Transform2 odom_base{base_in_odom.x_m, base_in_odom.y_m, base_in_odom.yaw_rad};
  return map_base.compose(odom_base.inverse());
}

Pose2 pose2Of(const Pose& p) {
  requireFinite(p.position.x, "position.x");
  requireFinite(p.position.y, "position.y");
  return {p.position.x, p.position.y, yawOf(p.orientation)};
}

agent_state_t robotFromOdometry(const Odometry& odom, const FrameSet& frames, double radius_m) {
  const Transform2 to_map = frameToMap(odom.header.frame_id, frames);
  const Pose2 pose = to_map.apply(pose2Of(odom.pose.pose));
  const auto& tw = odom.twist.twist;
  requireFinite(tw.linear.x, "twist.linear.x");
  requireFinite(tw.linear.y, "twist.linear.y");
  requireFinite(tw.angular.z, "twist.angular.z");
  agent_state_t s{};
  s.id = 0;
  s.kind = agent_state_t::KIND_ROBOT;
  s.x_m = pose.x_m;
  s.y_m = pose.y_m;
  s.theta_rad = std::remainder(pose.yaw_rad, 2.0 * M_PI);
  // The twist is in the base frame (child_frame_id): rotate by the base's heading in the map.
  const Transform2 base_rot{0.0, 0.0, pose.yaw_rad};
  base_rot.rotate(tw.linear.x, tw.linear.y, s.vx_m_s, s.vy_m_s);
  s.omega_rad_s = tw.angular.z;
  s.radius_m = radius_m;
  return s;
}

namespace {

agent_state_t humanAt(std::int32_t id, const Transform2& to_map, double x, double y, double yaw,
                      double vx, double vy, double omega, double radius_m) {
  for (double v : {x, y, yaw, vx, vy, omega}) requireFinite(v, "human state");
  const Pose2 p = to_map.apply({x, y, yaw});
  agent_state_t s{};
  s.id = id;
  s.kind = agent_state_t::KIND_HUMAN;
  s.x_m = p.x_m;
  s.y_m = p.y_m;
  s.theta_rad = std::remainder(p.yaw_rad, 2.0 * M_PI);
  to_map.rotate(vx, vy, s.vx_m_s, s.vy_m_s);
  s.omega_rad_s = omega;
  s.radius_m = radius_m;
  return s;
}

void checkCount(std::size_t n, const HumanOptions& options) {
  if (n > static_cast<std::size_t>(options.max_humans))
    throw RejectedMessage(std::to_string(n) + " humans, more than " +
                          std::to_string(options.max_humans));
}

}  // namespace

std::vector<agent_state_t> humansFromTrackedAgents(const TrackedAgents& msg, const FrameSet& frames,
                                                   const HumanOptions& options) {
  constexpr std::int8_t kAgentTypeHuman = 1;  // cohan_msgs/AgentType: ROBOT 0, HUMAN 1
  const Transform2 to_map = frameToMap(msg.header.frame_id, frames);
  std::vector<agent_state_t> out;
  std::set<std::int32_t> ids;
  for (std::uint32_t i = 0; i < msg.agents._length; ++i) {
    const auto& a = msg.agents._buffer[i];
    if (a.type != kAgentTypeHuman) continue;
    if (a.segments._length == 0) throw RejectedMessage("tracked agent without segments");
    if (a.track_id < 1 || a.track_id > static_cast<std::uint64_t>(INT32_MAX))
      throw RejectedMessage("track_id " + std::to_string(a.track_id) + " outside 1..2^31-1");
    const auto* seg = &a.segments._buffer[0];
    for (std::uint32_t k = 0; k < a.segments._length; ++k)
      if (a.segments._buffer[k].type == options.body_segment_type) {
        seg = &a.segments._buffer[k];
        break;
      }
    const auto id = static_cast<std::int32_t>(a.track_id);
    if (!ids.insert(id).second) throw RejectedMessage("track_id " + std::to_string(id) + " twice");
    const double radius =
        std::isfinite(a.radius) && a.radius > 0.0 ? a.radius : options.default_radius_m;
    const Pose2 p = pose2Of(seg->pose.pose);
    const auto& tw = seg->twist.twist;
    out.push_back(humanAt(id, to_map, p.x_m, p.y_m, p.yaw_rad, tw.linear.x, tw.linear.y,
                          tw.angular.z, radius));
  }
  checkCount(out.size(), options);
  return out;
}

std::vector<agent_state_t> humansFromPeople(const People& msg, const FrameSet& frames,
                                            const HumanOptions& options) {
  const Transform2 to_map = frameToMap(msg.header.frame_id, frames);
  std::vector<agent_state_t> out;
  std::set<std::int32_t> ids;
  checkCount(msg.people._length, options);
  for (std::uint32_t i = 0; i < msg.people._length; ++i) {
    const auto& p = msg.people._buffer[i];
    const std::string name = str(p.name);
    std::size_t start = name.size();
    while (start > 0 && std::isdigit(static_cast<unsigned char>(name[start - 1])) != 0) --start;
    const std::string digits = name.substr(start);
    if (digits.empty() || digits.size() > 9)
      throw RejectedMessage("person name '" + name + "' does not end in an id (1..999999999)");
    const auto id = static_cast<std::int32_t>(std::stol(digits));
    if (id < 1) throw RejectedMessage("person id 0 (the robot's)");
    if (!ids.insert(id).second) throw RejectedMessage("person id " + std::to_string(id) + " twice");
    const double vx = p.velocity.x;
    const double vy = p.velocity.y;
    const double speed = std::hypot(vx, vy);
    const double yaw = std::isfinite(speed) && speed > 1e-3 ? std::atan2(vy, vx) : 0.0;
    out.push_back(humanAt(id, to_map, p.position.x, p.position.y, yaw, vx, vy, 0.0,
                          options.default_radius_m));
  }
  return out;
}

goals_t goalsFromPoseStamped(const PoseStamped& msg, const FrameSet& frames,
                             std::int32_t robot_id) {
  const Transform2 to_map = frameToMap(msg.header.frame_id, frames);
  const Pose2 p = to_map.apply(pose2Of(msg.pose));
  goals_t g{};
  g.utime = stampToUtime(msg.header.stamp);
  goal_t goal{};
  goal.agent_id = robot_id;
  goal.kind = agent_state_t::KIND_ROBOT;
  goal.x_m = p.x_m;
  goal.y_m = p.y_m;
  goal.theta_rad = std::remainder(p.yaw_rad, 2.0 * M_PI);
  g.goals.push_back(goal);
  g.num_goals = 1;
  return g;
}

laser_scan_t scanFromLaserScan(const LaserScan& msg, const Pose2& robot_in_map,
                               const Pose2& sensor_on_base, std::int64_t step) {
  if (msg.ranges._length > static_cast<std::uint32_t>(laser_scan_t::MAX_RANGES))
    throw RejectedMessage(std::to_string(msg.ranges._length) + " ranges, more than " +
                          std::to_string(laser_scan_t::MAX_RANGES));
  for (double v : {double{msg.angle_min}, double{msg.angle_increment}, double{msg.range_min},
                   double{msg.range_max}})
    requireFinite(v, "scan geometry");
  if (!(msg.angle_increment > 0.0F))
    throw RejectedMessage("angle_increment <= 0 (a clockwise scan): not supported");
  if (!(msg.range_min >= 0.0F) || !(msg.range_max > msg.range_min))
    throw RejectedMessage("range_min/range_max not 0 <= min < max");
  const Transform2 base{robot_in_map.x_m, robot_in_map.y_m, robot_in_map.yaw_rad};
  const Pose2 sensor = base.apply(sensor_on_base);
  laser_scan_t s{};
  s.utime = stampToUtime(msg.header.stamp);
  s.step = step;
  s.sensor_x_m = sensor.x_m;
  s.sensor_y_m = sensor.y_m;
  s.sensor_yaw_rad = std::remainder(sensor.yaw_rad, 2.0 * M_PI);
  s.angle_min_rad = msg.angle_min;
  s.angle_increment_rad = msg.angle_increment;
  s.range_min_m = msg.range_min;
  s.range_max_m = msg.range_max;
  s.num_ranges = static_cast<std::int16_t>(msg.ranges._length);
  s.ranges_m.assign(msg.ranges._buffer, msg.ranges._buffer + msg.ranges._length);
  return s;
}

Twist twistOfCommand(const velocity_command_t& cmd) {
  requireFinite(cmd.vx_m_s, "vx_m_s");
  requireFinite(cmd.vy_m_s, "vy_m_s");
  requireFinite(cmd.omega_rad_s, "omega_rad_s");
  Twist t{};
  t.linear.x = cmd.vx_m_s;
  t.linear.y = cmd.vy_m_s;
  t.angular.z = cmd.omega_rad_s;
  return t;
}

bool commandStale(std::optional<double> last_command_s, double now_s, double cmd_timeout_s) {
  if (!last_command_s) return true;
  return now_s - *last_command_s > cmd_timeout_s;
}

const char* predicateText(std::int8_t pred) {
  switch (pred) {
    case situation_t::PRED_TRUE:
      return "true";
    case situation_t::PRED_FALSE:
      return "false";
    default:
      return "unknown";
  }
}

namespace {

std::string fmt(double v) {
  if (!std::isfinite(v)) return "?";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

MarkerSpec bandMarker(const char* ns, std::int32_t id, const band_t& band, float r, float g,
                      float b) {
  MarkerSpec m;
  m.ns = ns;
  m.id = id;
  m.type = kMarkerLineStrip;
  m.pose.yaw_rad = 0.0;
  m.scale_x = 0.05;
  m.r = r;
  m.g = g;
  m.b = b;
  for (const auto& p : band.poses)
    if (std::isfinite(p.x_m) && std::isfinite(p.y_m)) m.points.push_back({p.x_m, p.y_m, 0.0});
  return m;
}

}  // namespace

std::vector<MarkerSpec> markersOf(const bands_t& bands, const std::vector<situation_t>& situations,
                                  const utterance_t* utterance) {
  std::vector<MarkerSpec> out;
  MarkerSpec clear;
  clear.action = kMarkerDeleteAll;
  out.push_back(clear);
  if (bands.status == bands_t::STATUS_OK) {
    out.push_back(bandMarker("robot_band", 0, bands.robot, 0.1F, 0.4F, 1.0F));
    for (const auto& h : bands.humans)
      out.push_back(bandMarker("human_bands", h.agent_id, h, 1.0F, 0.5F, 0.0F));
  }
  for (const auto& s : situations) {
    const bool cp_known = std::isfinite(s.cp_h_x_m) && std::isfinite(s.cp_h_y_m) &&
                          std::isfinite(s.cp_r_x_m) && std::isfinite(s.cp_r_y_m);
    if (cp_known) {
      MarkerSpec cph;
      cph.ns = "cp_h";
      cph.id = s.human_id;
      cph.type = kMarkerSphere;
      cph.pose = {s.cp_h_x_m, s.cp_h_y_m, 0.0};
      cph.scale_x = cph.scale_y = cph.scale_z = 0.2;
      cph.r = 1.0F;
      cph.g = 0.2F;
      cph.b = 0.2F;
      out.push_back(cph);
      MarkerSpec cpr = cph;
      cpr.ns = "cp_r";
      cpr.pose = {s.cp_r_x_m, s.cp_r_y_m, 0.0};
      cpr.r = 0.2F;
      cpr.g = 0.2F;
      cpr.b = 1.0F;
      out.push_back(cpr);
      if (s.dir != situation_t::DIR_UNDEFINED) {
        // Dir as the human sees it: the robot passes on the human's left (+90 deg of the
        // human's walking direction, CP_r -> CP_h reversed) or right. Drawn at CP_r, pointing
        // from CP_h's side towards the side the robot takes.
        const double to_robot = std::atan2(s.cp_r_y_m - s.cp_h_y_m, s.cp_r_x_m - s.cp_h_x_m);
        MarkerSpec dir;
        dir.ns = "dir";
        dir.id = s.human_id;
        dir.type = kMarkerArrow;
        dir.pose = {s.cp_r_x_m, s.cp_r_y_m, to_robot};
        dir.scale_x = 0.5;
        dir.scale_y = 0.08;
        dir.scale_z = 0.08;
        dir.r = 0.0F;
        dir.g = 0.8F;
        dir.b = 0.2F;
        out.push_back(dir);
      }
    }
    MarkerSpec text;
    text.ns = "assessment";
    text.id = s.human_id;
    text.type = kMarkerText;
    text.pose = {cp_known ? s.cp_h_x_m : 0.0, cp_known ? s.cp_h_y_m : 0.0, 0.0};
    text.z_m = 1.0;
    text.scale_z = 0.15;
    text.text = "human " + std::to_string(s.human_id) + " t_cross " + fmt(s.t_cross_s) +
                " s\nDir " +
                (s.dir == situation_t::DIR_LEFT    ? "left"
                 : s.dir == situation_t::DIR_RIGHT ? "right"
                                                   : "undefined") +
                "\nd_h " + fmt(s.d_h_m) + " d_OH " + fmt(s.d_oh_m) + " d_OR " + fmt(s.d_or_m) +
                "\nhuman_needs_to_contribute " + predicateText(s.human_needs_to_contribute) +
                "\nhuman_is_constrained " + predicateText(s.human_is_constrained) +
                "\nrobot_is_constrained " + predicateText(s.robot_is_constrained);
    if (!s.reason.empty()) text.text += "\n" + s.reason;
    out.push_back(text);
  }
  if (utterance != nullptr) {
    MarkerSpec say;
    say.ns = "utterance";
    say.id = 0;
    say.type = kMarkerText;
    const auto& p = bands.robot.poses;
    if (!p.empty()) say.pose = {p.front().x_m, p.front().y_m, 0.0};
    say.z_m = 1.6;
    say.scale_z = 0.2;
    say.r = 1.0F;
    say.g = 1.0F;
    say.b = 0.3F;
    say.text = utterance->text;
    out.push_back(say);
  }
  return out;
}

}  // namespace coopnav::ros2

namespace coopnav::ros2 {
std::string ddsTopicName(const std::string& ros_namespace, const std::string& topic) {
  if (topic.empty()) return "";
  if (topic.front() == '/') return "rt" + topic;
  std::string ns = ros_namespace;
  while (!ns.empty() && ns.back() == '/') ns.pop_back();
  if (!ns.empty() && ns.front() != '/') ns.insert(ns.begin(), '/');
  return "rt" + ns + "/" + topic;
}
}  // namespace coopnav::ros2
