#pragma once
/// @file Test helpers for band tests: head-on scenario requests and band measurements (speeds,
/// accelerations, time-paired clearance, deviation from a path).

#include <algorithm>
#include <cmath>
#include <limits>

#include "coopnav/band/band_config.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/geometry/geometry.hpp"

namespace coopnav::test {

inline AgentState makeAgent(std::int32_t id, AgentKind kind, double x, double y, double th,
                            double speed, double radius) {
  AgentState s;
  s.id = id;
  s.kind = kind;
  s.pose = {x, y, th};
  s.velocity = {speed * std::cos(th), speed * std::sin(th), 0.0};
  s.radius_m = radius;
  return s;
}

/// Robot (id 0) at (x_r, y) heading +x to (x_r + length, y); one human (id 1) at (x_h, y + dy)
/// heading −x to (x_r, y + dy), walking at 1 m/s.
inline PlanRequest headOn(double x_r, double x_h, double y, double goal_x, double dy = 0.0) {
  PlanRequest r;
  r.stamp_s = 100.0;
  r.agent = makeAgent(0, AgentKind::kRobot, x_r, y, 0.0, 0.0, 0.34);
  r.goal = {goal_x, y, 0.0};
  OtherAgentInput h;
  h.state = makeAgent(1, AgentKind::kHuman, x_h, y + dy, M_PI, 1.0, 0.30);
  h.goal = {x_r, y + dy, M_PI};
  r.others.push_back(h);
  return r;
}

/// Linear interpolation of a published band at time t (clamped).
inline Eigen::Vector2d positionAt(const Band& b, double t) {
  if (b.poses.empty()) return {NAN, NAN};
  if (t <= b.poses.front().t_s) return b.poses.front().pose.position();
  for (std::size_t i = 0; i + 1 < b.poses.size(); ++i) {
    const auto& p0 = b.poses[i];
    const auto& p1 = b.poses[i + 1];
    if (t <= p1.t_s) {
      const double s = p1.t_s > p0.t_s ? (t - p0.t_s) / (p1.t_s - p0.t_s) : 0.0;
      return (1.0 - s) * p0.pose.position() + s * p1.pose.position();
    }
  }
  return b.poses.back().pose.position();
}

/// Minimum centre distance between two bands sampled on a common 20 ms time grid over their
/// common time span.
inline double minPairedDistance(const Band& a, const Band& b) {
  const double t_end = std::min(a.poses.back().t_s, b.poses.back().t_s);
  double best = std::numeric_limits<double>::infinity();
  for (double t = 0.0; t <= t_end; t += 0.02) {
    best = std::min(best, (positionAt(a, t) - positionAt(b, t)).norm());
  }
  return best;
}

/// Largest distance of band poses from a path.
inline double maxDeviation(const Band& b, const Path2& path) {
  double m = 0.0;
  for (const auto& p : b.poses) {
    const auto pr = projectOntoPath(path, p.pose.position());
    if (pr) m = std::max(m, pr->distance_m);
  }
  return m;
}

struct Kinematics {
  double max_vx{0.0}, min_vx{0.0}, max_abs_vy{0.0}, max_abs_omega{0.0};
  double max_abs_ax{0.0}, max_abs_ay{0.0};
  double max_speed{0.0};
};

/// Body-frame speeds (heading of each segment's first pose) and accelerations of a band.
inline Kinematics measure(const Band& b) {
  Kinematics k;
  double pvx = 0, pvy = 0, pdt = 0;
  for (std::size_t i = 0; i + 1 < b.poses.size(); ++i) {
    const auto& a = b.poses[i];
    const auto& c = b.poses[i + 1];
    const double dt = c.t_s - a.t_s;
    const double dx = c.pose.x_m - a.pose.x_m, dy = c.pose.y_m - a.pose.y_m;
    const double ct = std::cos(a.pose.theta_rad), st = std::sin(a.pose.theta_rad);
    const double vx = (ct * dx + st * dy) / dt, vy = (-st * dx + ct * dy) / dt;
    const double om = wrapAngle(c.pose.theta_rad - a.pose.theta_rad) / dt;
    k.max_vx = std::max(k.max_vx, vx);
    k.min_vx = std::min(k.min_vx, vx);
    k.max_abs_vy = std::max(k.max_abs_vy, std::abs(vy));
    k.max_abs_omega = std::max(k.max_abs_omega, std::abs(om));
    k.max_speed = std::max(k.max_speed, std::hypot(dx, dy) / dt);
    if (i > 0) {
      k.max_abs_ax = std::max(k.max_abs_ax, std::abs(2.0 * (vx - pvx) / (dt + pdt)));
      k.max_abs_ay = std::max(k.max_abs_ay, std::abs(2.0 * (vy - pvy) / (dt + pdt)));
    }
    pvx = vx, pvy = vy, pdt = dt;
  }
  return k;
}

}  // namespace coopnav::test
