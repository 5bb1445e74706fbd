#include "coopnav/geometry/same_way.hpp"

#include <cmath>

namespace coopnav {

std::optional<SameWayPerson> sameWayPerson(const Pose2& robot, double robot_radius_m,
                                           const AgentState& h, const SameWayOptions& o) {
  const Eigen::Vector2d dir(std::cos(robot.theta_rad), std::sin(robot.theta_rad));
  const Eigen::Vector2d left(-dir.y(), dir.x());
  const Eigen::Vector2d d = h.pose.position() - robot.position();
  SameWayPerson p;
  p.id = h.id;
  p.along_m = d.dot(dir);
  p.lateral_m = d.dot(left);
  p.radius_m = h.radius_m;
  p.gap_m = d.norm() - robot_radius_m - h.radius_m;
  p.speed_along_m_s = Eigen::Vector2d(h.velocity.vx_m_s, h.velocity.vy_m_s).dot(dir);
  if (!std::isfinite(p.along_m) || !std::isfinite(p.lateral_m) || !std::isfinite(p.speed_along_m_s))
    return std::nullopt;
  if (p.along_m <= 0.0) return std::nullopt;
  const double speed_m_s = std::hypot(h.velocity.vx_m_s, h.velocity.vy_m_s);
  if (speed_m_s >= o.standing_speed_m_s) {
    if (p.speed_along_m_s < o.min_speed_along_m_s) return std::nullopt;
  } else if (!(std::cos(h.pose.theta_rad - robot.theta_rad) > 0.0)) {
    return std::nullopt;
  }
  // The person faces the robot's way: the robot, at -lateral from them, is on their left when
  // lateral < 0.
  constexpr double kStraightBehind_m = 0.01;
  if (p.lateral_m < -kStraightBehind_m) p.robot_side = Side::kLeft;
  if (p.lateral_m > kStraightBehind_m) p.robot_side = Side::kRight;
  return p;
}

std::optional<SameWayPerson> sameWayAhead(const Pose2& robot, double robot_radius_m,
                                          const std::vector<AgentState>& humans,
                                          const SameWayOptions& o) {
  std::optional<SameWayPerson> best;
  for (const auto& h : humans) {
    const auto p = sameWayPerson(robot, robot_radius_m, h, o);
    if (!p || p->gap_m > o.ahead_range_m) continue;
    if (std::abs(p->lateral_m) >= robot_radius_m + p->radius_m + o.lane_margin_m) continue;
    if (!best || p->gap_m < best->gap_m) best = p;
  }
  return best;
}

double lateralClearance(const SameWayPerson& p, double robot_radius_m) {
  return std::abs(p.lateral_m) - robot_radius_m - p.radius_m;
}

}  // namespace coopnav
