#include "coopnav/planning/overtake.hpp"

#include <algorithm>
#include <cmath>

namespace coopnav {
namespace {

Eigen::Vector2d heading(const Pose2& p) { return {std::cos(p.theta_rad), std::sin(p.theta_rad)}; }

/// The world point `ahead_m` along the robot's way at lateral offset `lateral_m` (robot frame).
Eigen::Vector2d aimPoint(const Pose2& robot, double ahead_m, double lateral_m) {
  const Eigen::Vector2d dir = heading(robot);
  const Eigen::Vector2d left(-dir.y(), dir.x());
  return robot.position() + ahead_m * dir + lateral_m * left;
}

}  // namespace

PassLane passLane(const DistanceMap& map, const Pose2& frame, double robot_radius_m,
                  const SameWayPerson& p, const OvertakeOptions& o) {
  PassLane lane;
  const Eigen::Vector2d dir = heading(frame);
  const Eigen::Vector2d left(-dir.y(), dir.x());
  const Eigen::Vector2d person = frame.position() + p.along_m * dir + p.lateral_m * left;
  const double offset_m = p.radius_m + o.pass_clearance_m + robot_radius_m;
  const double need_m = offset_m + robot_radius_m + o.wall_clearance_m;
  const double range_m = need_m + 1.0;
  lane.room_left_m = map.ray(person, left, range_m).distance_m;
  lane.room_right_m = map.ray(person, -left, range_m).distance_m;
  const bool left_fits = std::isfinite(lane.room_left_m) && lane.room_left_m >= need_m;
  const bool right_fits = std::isfinite(lane.room_right_m) && lane.room_right_m >= need_m;
  if (!left_fits && !right_fits) return lane;
  // The robot is on the person's left when it is to the right of the person's centre in its
  // own frame (lateral > 0: the person is to the robot's left).
  bool go_left;
  if (left_fits && right_fits) {
    if (p.robot_side != Side::kUndefined)
      go_left = p.robot_side == Side::kLeft;
    else
      go_left = lane.room_left_m >= lane.room_right_m;
  } else {
    go_left = left_fits;
  }
  lane.fits = true;
  lane.side = go_left ? Side::kLeft : Side::kRight;
  lane.lateral_m = p.lateral_m + (go_left ? offset_m : -offset_m);
  return lane;
}

PassLane laneOnSide(const DistanceMap& map, const Pose2& frame, double robot_radius_m,
                    const SameWayPerson& p, Side side, const OvertakeOptions& o) {
  PassLane lane;
  if (side == Side::kUndefined) return lane;
  const Eigen::Vector2d dir = heading(frame);
  const Eigen::Vector2d left(-dir.y(), dir.x());
  const Eigen::Vector2d person = frame.position() + p.along_m * dir + p.lateral_m * left;
  const double sign = side == Side::kLeft ? 1.0 : -1.0;
  const double offset_m = p.radius_m + o.pass_clearance_m + robot_radius_m;
  const double room_m = map.ray(person, sign * left, offset_m + robot_radius_m + 1.0).distance_m;
  const double wall_m =
      std::isfinite(room_m) ? room_m - robot_radius_m - o.wall_clearance_m : offset_m;
  (side == Side::kLeft ? lane.room_left_m : lane.room_right_m) = room_m;
  lane.fits = wall_m >= offset_m;
  lane.side = side;
  lane.lateral_m = p.lateral_m + sign * std::max(0.0, std::min(offset_m, wall_m));
  return lane;
}

double followSpeed(const SameWayPerson& p, const OvertakeOptions& o, double max_m_s) {
  const double pace = std::max(0.0, p.speed_along_m_s);
  const double v = pace + (p.gap_m - o.follow_gap_m) / std::max(o.follow_time_s, 1e-3);
  return std::clamp(v, 0.0, max_m_s);
}

Velocity2 followCommand(const Pose2& robot, const Pose2& frame, const SameWayPerson& p,
                        const PassLane& lane, const OvertakeOptions& o, const RobotLimits& limits) {
  const double speed = followSpeed(p, o, limits.max_forward_m_s);
  if (speed <= 0.0 && !lane.fits) return {};
  // Towards the lane while following: at a standstill behind a person who stopped, the robot
  // still steps into the lane (slowly), so that it can pass once told.
  const double lateral = lane.fits ? lane.lateral_m : 0.0;
  const double step_speed = std::max(speed, std::min(std::abs(lateral), 0.2));
  const Eigen::Vector2d aim = aimPoint(frame, speed > 0.0 ? o.lookahead_m : 0.0, lateral);
  Velocity2 v = driveTowards(robot, aim, step_speed, 0.0, limits);
  // Never faster along the way than the following speed.
  if (v.vx_m_s > speed && v.vx_m_s > 0.0) {
    const double k = speed > 0.0 ? speed / v.vx_m_s : 0.0;
    v.vx_m_s *= k;
    if (!limits.holonomic) v.omega_rad_s *= std::max(k, 0.5);
  }
  return v;
}

Velocity2 passCommand(const Pose2& robot, const Pose2& frame, const PassLane& lane,
                      const OvertakeOptions& o, const RobotLimits& limits) {
  const Eigen::Vector2d aim = aimPoint(frame, o.lookahead_m, lane.lateral_m);
  return driveTowards(robot, aim, limits.max_forward_m_s, 0.0, limits);
}

}  // namespace coopnav
