#include "coopnav/planning/safety_guard.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "coopnav/distance/point_obstacle_map.hpp"
#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

/// A factor below this stops the robot: a crawl towards a human says nothing the stop does not.
constexpr double kStopBelow = 0.02;
constexpr int kBisections = 12;
/// At rest: speeds below these [m/s], [rad/s].
constexpr double kRest_m_s = 1e-3;
constexpr double kRest_rad_s = 1e-2;
/// A human closes while the gap shrinks faster than this [m/s].
constexpr double kClosing_m_s = 0.05;
/// An evasion must gain at least this much predicted gap over standing still [m].
constexpr double kGain_m = 0.01;
/// Spacing of the free-room samples of an evasion [m].
constexpr double kSample_m = 0.05;

/// Robot position after t under a constant body-frame twist (exact for the arc).
Eigen::Vector2d predict(const Pose2& p, const Velocity2& b, double t_s) {
  const double th = p.theta_rad, w = b.omega_rad_s;
  double s = 0.0, c = 0.0;  // ∫ cos(th + w u) du, ∫ sin(th + w u) du over [0, t]
  if (std::abs(w) < 1e-9) {
    s = std::cos(th) * t_s;
    c = std::sin(th) * t_s;
  } else {
    s = (std::sin(th + w * t_s) - std::sin(th)) / w;
    c = (std::cos(th) - std::cos(th + w * t_s)) / w;
  }
  return {p.x_m + b.vx_m_s * s - b.vy_m_s * c, p.y_m + b.vx_m_s * c + b.vy_m_s * s};
}

struct Predictor {
  const GuardInput& in;
  const GuardOptions& o;
  int samples() const {
    return std::max(1, static_cast<int>(std::ceil(o.horizon_s / o.sample_dt_s - 1e-9)));
  }
  double t(int k) const { return std::min(o.horizon_s, k * o.sample_dt_s); }
  double gap(const Eigen::Vector2d& robot, const GuardHuman& h, double t_s) const {
    return (robot - (h.position + h.velocity * t_s)).norm() - in.robot_radius_m - h.radius_m;
  }
  /// Wherever the command brings a gap below the clearance, it is no smaller than at rest and the
  /// robot has not moved towards the human. (At rest alone is no bound: a human walking into
  /// the robot makes that gap negative, and a command back into its way would pass.)
  bool allowed(const Velocity2& cmd) const {
    for (int k = 1; k <= samples(); ++k) {
      const Eigen::Vector2d r = predict(in.robot, cmd, t(k));
      const Eigen::Vector2d moved = r - in.robot.position();
      for (const GuardHuman& h : in.humans) {
        const double g = gap(r, h, t(k));
        if (g >= o.min_clearance_m) continue;
        if (g < gap(in.robot.position(), h, t(k)) - 1e-9) return false;
        if (moved.dot(h.position + h.velocity * t(k) - r) > 1e-9) return false;
      }
      for (const Eigen::Vector2d& q : in.obstacle_points) {
        const double g = (r - q).norm() - in.robot_radius_m;
        if (g >= o.min_clearance_m) continue;
        if (g < (in.robot.position() - q).norm() - in.robot_radius_m - 1e-9) return false;
        if (moved.dot(q - r) > 1e-9) return false;
      }
    }
    return true;
  }
  /// Smallest predicted gap to any human over the horizon under cmd.
  double minGap(const Velocity2& cmd) const {
    double m = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= samples(); ++k) {
      const Eigen::Vector2d r = predict(in.robot, cmd, t(k));
      for (const GuardHuman& h : in.humans) m = std::min(m, gap(r, h, t(k)));
    }
    return m;
  }
};

Velocity2 scaled(const Velocity2& v, double f) {
  return {v.vx_m_s * f, v.vy_m_s * f, v.omega_rad_s * f};
}

bool atRest(const Velocity2& v) {
  return std::abs(v.vx_m_s) < kRest_m_s && std::abs(v.vy_m_s) < kRest_m_s &&
         std::abs(v.omega_rad_s) < kRest_rad_s;
}

/// The straight move under cmd over the horizon keeps the evasion's clearance from walls.
bool roomFor(const DistanceMap& map, const GuardInput& in, const GuardOptions& o,
             const Velocity2& cmd) {
  const DistanceResult now = map.nearest(in.robot.position());
  const double want = in.robot_radius_m + o.evade_wall_margin_m;
  const double need = now.status == DistanceStatus::kOk ? std::min(want, now.distance_m) : want;
  const Eigen::Vector2d end = predict(in.robot, cmd, o.horizon_s);
  const double len = (end - in.robot.position()).norm();
  const int k = std::max(1, static_cast<int>(std::ceil(len / kSample_m)));
  for (int i = 1; i <= k; ++i) {
    const DistanceResult r = map.nearest(predict(in.robot, cmd, o.horizon_s * i / k));
    if (r.status != DistanceStatus::kOk || r.distance_m < need - 1e-3) return false;
  }
  return true;
}

}  // namespace

const char* toString(GuardAction a) {
  switch (a) {
    case GuardAction::kNone:
      return "none";
    case GuardAction::kSlowed:
      return "slowed";
    case GuardAction::kStopped:
      return "stopped";
    case GuardAction::kEvading:
      return "evading";
  }
  return "unknown";
}

GuardOutput guardCommand(const DistanceMap& map, const GuardInput& in, const GuardOptions& o) {
  GuardOutput out;
  out.command_body = in.command_body;
  if ((in.humans.empty() && in.obstacle_points.empty()) || !isFinite(in.robot) ||
      !(o.sample_dt_s > 0.0))
    return out;
  const Predictor pr{in, o};

  // 1. Never close on a human below the clearance.
  if (!pr.allowed(in.command_body)) {
    double lo = 0.0, hi = 1.0;  // lo allowed (at rest never is the robot's doing), hi not
    for (int i = 0; i < kBisections; ++i) {
      const double mid = 0.5 * (lo + hi);
      (pr.allowed(scaled(in.command_body, mid)) ? lo : hi) = mid;
    }
    out.scale = lo < kStopBelow ? 0.0 : lo;
    out.command_body = scaled(in.command_body, out.scale);
    out.action = out.scale > 0.0 ? GuardAction::kSlowed : GuardAction::kStopped;
  }
  // 2. A human closing in, predicted within the evasion gap under what would be sent (at rest,
  // stopped, or the planner's own slow avoidance): move away if there is room.
  const GuardHuman* threat = nullptr;
  double threat_gap = std::numeric_limits<double>::infinity();
  for (const GuardHuman& h : in.humans) {
    const Eigen::Vector2d rel = h.position - in.robot.position();
    const double d = rel.norm();
    const double closing = d > 1e-9 ? -h.velocity.dot(rel / d) : 0.0;
    if (closing <= kClosing_m_s) continue;
    double g = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= pr.samples(); ++k)
      g = std::min(g, pr.gap(predict(in.robot, out.command_body, pr.t(k)), h, pr.t(k)));
    if (g < o.evade_gap_m && g < threat_gap) {
      threat_gap = g;
      threat = &h;
    }
  }
  if (!threat) return out;
  // The evasion's room: the walls, and the obstacles of the moment where there are some.
  std::optional<PointObstacleMap> with_points;
  if (!in.obstacle_points.empty()) with_points.emplace(map, in.obstacle_points);
  const DistanceMap& room = with_points ? static_cast<const DistanceMap&>(*with_points) : map;
  const double sent_gap = pr.minGap(out.command_body);
  std::vector<Eigen::Vector2d> dirs;
  if (in.limits.holonomic) {
    Eigen::Vector2d away = in.robot.position() - threat->position;
    away = away.norm() > 1e-9 ? Eigen::Vector2d(away.normalized())
                              : Eigen::Vector2d(-headingVector(in.robot.theta_rad));
    // Straight away first, then fanning out to the sides (the free side wins by its gap).
    for (const double deg : {0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0}) {
      const double a = deg * M_PI / 180.0;
      dirs.emplace_back(std::cos(a) * away.x() - std::sin(a) * away.y(),
                        std::sin(a) * away.x() + std::cos(a) * away.y());
    }
  } else {
    const Eigen::Vector2d h = headingVector(in.robot.theta_rad);
    dirs = {-h, h};  // backwards first: a robot facing the human backs away
  }
  double best_gap = sent_gap + kGain_m;
  bool found = false;
  for (const Eigen::Vector2d& d : dirs) {
    constexpr double kFar = 1e3;  // clampToLimits scales it down to the fastest allowed
    const Eigen::Vector2d b = worldToBody(d, in.robot.theta_rad);
    const Velocity2 cmd = clampToLimits({b.x() * kFar, b.y() * kFar, 0.0}, in.limits);
    // An evasion is held to rule 1 as any command is: it never moves the robot towards a
    // human it is within the clearance of (a differential drive's heading may point at them;
    // a sideways move turns towards a person who walks past), else the robot would step into
    // the contact it evades.
    if (atRest(cmd) || !pr.allowed(cmd) || !roomFor(room, in, o, cmd)) continue;
    const double g = pr.minGap(cmd);
    if (g > best_gap) {
      best_gap = g;
      out.command_body = cmd;
      found = true;
    }
  }
  if (found) out.action = GuardAction::kEvading;
  return out;
}

}  // namespace coopnav
