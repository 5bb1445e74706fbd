#include "coopnav/planning/room.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coopnav/geometry/geometry.hpp"
#include "coopnav/planning/dock.hpp"

namespace coopnav {
namespace {

/// Below this speed a human counts as standing [m/s].
constexpr double kStanding_m_s = 0.1;
/// Spacing of the samples of a straight move checked against the distance field [m].
constexpr double kSample_m = 0.05;
/// Route following: the point followed lies this far ahead of the robot's foot on the route [m],
/// and the speed is this gain times the distance left [1/s], at least kCreep_m_s.
constexpr double kLookahead_m = 0.4;
constexpr double kApproachGain_1_s = 1.0;
constexpr double kCreep_m_s = 0.05;
/// Differential drive: yaw-rate gain [1/s]; it drives only while within kAligned_rad of its course.
constexpr double kYawGain_1_s = 2.0;
constexpr double kAligned_rad = 0.5;
/// Distances from the grid field are good to about half a cell.
constexpr double kEps_m = 1e-3;

/// Point at arc length s along a polyline (clamped to its ends).
Eigen::Vector2d pointAt(const Path2& path, double s_m) {
  if (path.empty()) return {0.0, 0.0};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double len = (path[i] - path[i - 1]).norm();
    if (s_m <= len && len > 0.0) return path[i - 1] + (path[i] - path[i - 1]) * (s_m / len);
    s_m -= len;
  }
  return path.back();
}

double pathLength(const Path2& path) {
  double l = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) l += (path[i] - path[i - 1]).norm();
  return l;
}

/// Every sample of the straight move a → b keeps `clearance_m` from obstacles.
bool straightClear(const DistanceMap& map, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   double clearance_m) {
  const double len = (b - a).norm();
  const int k = std::max(1, static_cast<int>(std::ceil(len / kSample_m)));
  for (int i = 1; i <= k; ++i) {
    const DistanceResult r = map.nearest(a + (b - a) * (static_cast<double>(i) / k));
    if (r.status != DistanceStatus::kOk || r.distance_m < clearance_m - kEps_m) return false;
  }
  return true;
}

Velocity2 bodyFromWorld(const Pose2& robot, const Eigen::Vector2d& v_world, double omega_rad_s,
                        const RobotLimits& limits) {
  const Eigen::Vector2d b = worldToBody(v_world, robot.theta_rad);
  return clampToLimits({b.x(), limits.holonomic ? b.y() : 0.0, omega_rad_s}, limits);
}

/// Differential drive: yaw towards `course` (world angle) and drive along it at `speed_m_s`
/// (negative: backwards, the course being the heading) once aligned.
Velocity2 diffDrive(const Pose2& robot, double course_rad, double speed_m_s,
                    const RobotLimits& limits) {
  const double err = wrapAngle(course_rad - robot.theta_rad);
  const double v = std::abs(err) < kAligned_rad ? speed_m_s * std::cos(err) : 0.0;
  return clampToLimits({v, 0.0, kYawGain_1_s * err}, limits);
}

}  // namespace

Velocity2 clampToLimits(const Velocity2& body, const RobotLimits& l) {
  Velocity2 v = body;
  if (!l.holonomic) v.vy_m_s = 0.0;
  double f = 1.0;
  if (v.vx_m_s > l.max_forward_m_s) f = std::min(f, l.max_forward_m_s / v.vx_m_s);
  if (v.vx_m_s < -l.max_backward_m_s) f = std::min(f, l.max_backward_m_s / -v.vx_m_s);
  if (std::abs(v.vy_m_s) > l.max_lateral_m_s)
    f = std::min(f, l.max_lateral_m_s / std::abs(v.vy_m_s));
  if (std::abs(v.omega_rad_s) > l.max_omega_rad_s)
    f = std::min(f, l.max_omega_rad_s / std::abs(v.omega_rad_s));
  f = std::max(f, 0.0);
  return {v.vx_m_s * f, v.vy_m_s * f, v.omega_rad_s * f};
}

double travelTime(double distance_m, const Eigen::Vector2d& dir, double theta_rad,
                  const RobotLimits& l) {
  if (!(distance_m > 0.0)) return 0.0;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // A holonomic robot just moves (keeping its heading): the speed along dir within the
  // body-frame limits.
  const Eigen::Vector2d b = worldToBody(dir.normalized(), theta_rad);
  if (l.holonomic) {
    const Velocity2 v = clampToLimits({b.x() * 1e3, b.y() * 1e3, 0.0}, l);
    const double speed = std::hypot(v.vx_m_s, v.vy_m_s);
    return speed > 0.0 ? distance_m / speed : kInf;
  }
  // A differential drive turns to face the way (forwards or backwards, whichever turn is
  // shorter) and drives; or turns round and drives forward, if that is faster.
  const double course = std::atan2(dir.y(), dir.x());
  const double fwd_turn = std::abs(wrapAngle(course - theta_rad));
  const double back_turn = std::abs(wrapAngle(course + M_PI - theta_rad));
  const double w = l.max_omega_rad_s > 0.0 ? l.max_omega_rad_s : 1e-9;
  const double fwd = l.max_forward_m_s > 0.0 ? fwd_turn / w + distance_m / l.max_forward_m_s : kInf;
  const double back =
      l.max_backward_m_s > 0.0 ? back_turn / w + distance_m / l.max_backward_m_s : kInf;
  return std::min(fwd, back);
}

Velocity2 driveTowards(const Pose2& robot, const Eigen::Vector2d& target, double speed_m_s,
                       double slow_radius_m, const RobotLimits& l, double distance_m) {
  const Eigen::Vector2d d = target - robot.position();
  const double dist = d.norm();
  if (!(dist > 1e-6)) return {};
  double speed = speed_m_s;
  if (slow_radius_m > 0.0 && dist < slow_radius_m) speed *= dist / slow_radius_m;
  if (l.holonomic) return bodyFromWorld(robot, d / dist * speed, 0.0, l);
  // Backs or drives forward, whichever covers the way sooner (travelTime's choice).
  const double course = std::atan2(d.y(), d.x());
  const double way_m = std::max(distance_m, dist);
  const double w = std::max(l.max_omega_rad_s, 1e-9);
  const double fwd_s =
      std::abs(wrapAngle(course - robot.theta_rad)) / w + way_m / std::max(l.max_forward_m_s, 1e-9);
  const double back_s = std::abs(wrapAngle(course + M_PI - robot.theta_rad)) / w +
                        way_m / std::max(l.max_backward_m_s, 1e-9);
  if (back_s < fwd_s) return diffDrive(robot, wrapAngle(course + M_PI), -speed, l);
  return diffDrive(robot, course, speed, l);
}

Velocity2 driveAlong(const Pose2& robot, const Eigen::Vector2d& dir, double distance_m,
                     const RobotLimits& l) {
  constexpr double kFar = 1e3;  // clampToLimits scales it down to the fastest allowed
  if (l.holonomic) return bodyFromWorld(robot, dir.normalized() * kFar, 0.0, l);
  return driveTowards(robot, robot.position() + dir.normalized() * distance_m, kFar, 0.0, l,
                      distance_m);
}

Velocity2 settleOn(const Pose2& robot, const Eigen::Vector2d& target, double tolerance_m,
                   const RobotLimits& l) {
  const double dist = (target - robot.position()).norm();
  if (!(dist > tolerance_m)) return {};
  return driveTowards(robot, target, kApproachGain_1_s * dist, 0.0, l, dist);
}

double lengthLeft(const Path2& route, const Eigen::Vector2d& p) {
  const auto proj = projectOntoPath(route, p);
  if (!proj) return 0.0;
  return std::max(pathLength(route) - proj->arc_length_m, 0.0) + proj->distance_m;
}

Velocity2 followRoute(const Pose2& robot, const Path2& route, double speed_m_s,
                      const RobotLimits& l) {
  if (route.empty()) return {};
  const auto proj = projectOntoPath(route, robot.position());
  if (!proj) return {};
  const double left = lengthLeft(route, robot.position());
  const Eigen::Vector2d aim =
      left < kLookahead_m ? route.back() : pointAt(route, proj->arc_length_m + kLookahead_m);
  const double speed = std::min(speed_m_s, std::max(kApproachGain_1_s * left, kCreep_m_s));
  return driveTowards(robot, aim, speed, 0.0, l, left);
}

const char* toString(RoomMove m) {
  switch (m) {
    case RoomMove::kUnknown:
      return "unknown";
    case RoomMove::kDockHere:
      return "dock_here";
    case RoomMove::kWiderPlace:
      return "wider_place";
    case RoomMove::kRetreat:
      return "retreat";
    case RoomMove::kNone:
      return "none";
  }
  return "unknown";
}

PassageCheck checkPassage(const DistanceMap& map, const Eigen::Vector2d& robot_position,
                          double robot_radius_m, const Eigen::Vector2d& axis,
                          const Eigen::Vector2d& towards_wall, double human_radius_m,
                          double passage_margin_m) {
  PassageCheck out;
  out.needed_m = 2.0 * human_radius_m + passage_margin_m;
  // Only whether the width reaches the need matters: a ray a little longer suffices.
  const double range_m = out.needed_m + 0.5;
  const double half_m = robot_radius_m + human_radius_m;
  constexpr int kSamples = 9;
  double narrowest = range_m;
  for (int i = 0; i < kSamples; ++i) {
    const double a = -half_m + 2.0 * half_m * i / (kSamples - 1);
    const Eigen::Vector2d from = robot_position + a * axis - robot_radius_m * towards_wall;
    const DistanceResult r = map.ray(from, -towards_wall, range_m);
    double w = 0.0;
    if (r.status == DistanceStatus::kOk || r.status == DistanceStatus::kNotFound) w = r.distance_m;
    narrowest = std::min(narrowest, w);
  }
  out.free_width_m = narrowest;
  out.ok = narrowest >= out.needed_m - kEps_m;
  return out;
}

Eigen::Vector2d encounterAxis(const Encounter& e) {
  Eigen::Vector2d base = headingVector(e.robot.theta_rad);
  const Eigen::Vector2d rel = e.human_position - e.robot.position();
  if (e.human_velocity.norm() > kStanding_m_s) {
    base = -e.human_velocity.normalized();
  } else if (rel.norm() > 1e-3) {
    base = rel.normalized();
  }
  // A human side-stepping walks askew to the corridor, and a passage measured across its askew
  // course comes out narrower than it is: where the robot came along a path near here and the
  // human comes along it too, the path's direction is the corridor's.
  constexpr double kNearTrail_m = 2.0;
  constexpr double kHalfSpan_m = 0.5;
  const double kAlongCos = std::cos(M_PI / 4);
  if (e.trail && e.trail->size() >= 2) {
    const auto foot = projectOntoPath(*e.trail, e.robot.position());
    if (foot && foot->distance_m < kNearTrail_m) {
      Eigen::Vector2d t = pointAt(*e.trail, foot->arc_length_m + kHalfSpan_m) -
                          pointAt(*e.trail, std::max(foot->arc_length_m - kHalfSpan_m, 0.0));
      if (t.norm() > 1e-6) {
        t.normalize();
        const double c = t.dot(base);
        if (std::abs(c) >= kAlongCos) return c >= 0.0 ? t : Eigen::Vector2d(-t);
      }
    }
  }
  return base;
}

double closingSpeed(const Encounter& e) {
  const Eigen::Vector2d rel = e.human_position - e.robot.position();
  const double d = rel.norm();
  if (!(d > 1e-9)) return 0.0;
  return -e.human_velocity.dot(rel / d);
}

PassageCheck passageHere(const DistanceMap& map, const Encounter& e, double passage_margin_m) {
  const Eigen::Vector2d axis = encounterAxis(e);
  const Eigen::Vector2d n = sideAwayFrom(axis, e.robot.position(), e.human_position);
  return checkPassage(map, e.robot.position(), e.robot_radius_m, axis, n, e.human_radius_m,
                      passage_margin_m);
}

RoomDecision decideRoom(const DistanceMap& map, const Encounter& e, const DockOptions& dock,
                        const RoomOptions& room) {
  RoomDecision out;
  if (!isFinite(e.robot) || !e.human_position.allFinite() || !e.human_velocity.allFinite())
    return out;
  const Eigen::Vector2d axis = encounterAxis(e);
  const Eigen::Vector2d robot = e.robot.position();
  const Eigen::Vector2d n = sideAwayFrom(axis, robot, e.human_position);
  auto passes = [&](const Eigen::Vector2d& at, const Eigen::Vector2d& side) {
    return checkPassage(map, at, e.robot_radius_m, axis, side, e.human_radius_m,
                        room.passage_margin_m);
  };
  out.passage = passes(robot, n);

  // 1. A dock pose nearby, flush to the wall away from the human, whose passage holds.
  const DockResult here =
      findDockPoseAlong(map, e.robot, axis, n, e.robot_radius_m, dock,
                        [&](const Eigen::Vector2d& p) { return passes(p, n).ok; });
  if (here.status == DockStatus::kOk) {
    out.move = RoomMove::kDockHere;
    out.target = here.pose;
    out.route = {robot, here.pose.position()};
    out.passage = passes(here.pose.position(), n);
    return out;
  }
  // Nothing to make room in: no wall on the side away from the human and room to pass here.
  if (here.status == DockStatus::kNoWall && out.passage.ok) return out;

  // 2. A wider place back along the way the robot came, reached first.
  const double human_speed = e.human_velocity.norm();
  if (e.trail && e.trail->size() >= 2) {
    const Path2& trail = *e.trail;
    const auto foot = projectOntoPath(trail, robot);
    if (foot) {
      // Route back: the robot, its foot on the trail, then the trail backwards.
      Path2 back{robot, foot->closest};
      for (std::size_t i = foot->segment + 1; i-- > 0;) back.push_back(trail[i]);
      const double back_len = pathLength(back);
      const double limit = std::min(room.wider_search_m, back_len);
      for (double s = room.wider_step_m; s <= limit + 1e-9; s += room.wider_step_m) {
        const Eigen::Vector2d c = pointAt(back, s);
        const Eigen::Vector2d behind = pointAt(back, s + room.wider_step_m);
        const Eigen::Vector2d ahead = pointAt(back, std::max(s - room.wider_step_m, 0.0));
        Eigen::Vector2d along = ahead - behind;  // the trail's direction of travel there
        if (along.norm() < 1e-6) along = axis;
        along.normalize();
        const Eigen::Vector2d left(-along.y(), along.x());
        // The side the dock here would take (as seen along the way the robot came), then the
        // other one.
        const double sgn = cross2(axis, n) >= 0.0 ? 1.0 : -1.0;
        for (const double side : {sgn, -sgn}) {
          const Eigen::Vector2d sn = side * left;
          const DistanceResult wall = map.ray(c, sn, dock.search_range_m);
          const double flush = wall.status == DistanceStatus::kOk
                                   ? wall.distance_m - e.robot_radius_m - dock.margin_m
                                   : dock.search_range_m;
          // The shortest step aside from the trail whose passage holds, up to flush.
          for (double t = 0.0; t <= std::max(flush, 0.0) + 1e-9; t += room.wider_step_m) {
            const Eigen::Vector2d p = c + t * sn;
            const DistanceResult cl = map.nearest(p);
            if (cl.status != DistanceStatus::kOk ||
                cl.distance_m < e.robot_radius_m + dock.margin_m - kEps_m)
              continue;
            // The human passes along the corridor there: its axis is the trail's.
            const PassageCheck pc = checkPassage(map, p, e.robot_radius_m, along, sn,
                                                 e.human_radius_m, room.passage_margin_m);
            if (!pc.ok || !straightClear(map, c, p, e.robot_radius_m)) continue;
            const double dist_m = s + t;
            const double robot_s = travelTime(
                dist_m,
                (c - robot).norm() > 1e-6 ? Eigen::Vector2d((c - robot).normalized()) : -axis,
                e.robot.theta_rad, e.limits);
            const double gap_m =
                std::max((e.human_position - p).norm() - e.robot_radius_m - e.human_radius_m, 0.0);
            const double human_s = human_speed > kStanding_m_s
                                       ? gap_m / human_speed
                                       : std::numeric_limits<double>::infinity();
            if (robot_s + room.reach_margin_s > human_s) break;  // farther aside is later still
            out.move = RoomMove::kWiderPlace;
            out.target = {p.x(), p.y(), e.robot.theta_rad};
            out.route = {robot};
            for (double u = room.wider_step_m; u < s; u += room.wider_step_m)
              out.route.push_back(pointAt(back, u));
            out.route.push_back(c);
            if (t > 0.0) out.route.push_back(p);
            out.passage = pc;
            out.robot_time_s = robot_s;
            out.human_time_s = human_s;
            return out;
          }
        }
      }
    }
  }
  // 3. Back away, when there is room behind; 4. else stop.
  out.move = retreatDirection(map, e, room) ? RoomMove::kRetreat : RoomMove::kNone;
  return out;
}

std::optional<Eigen::Vector2d> retreatDirection(const DistanceMap& map, const Encounter& e,
                                                const RoomOptions& room) {
  const Eigen::Vector2d robot = e.robot.position();
  const Eigen::Vector2d away = -encounterAxis(e);
  std::vector<Eigen::Vector2d> tries;
  if (e.trail && e.trail->size() >= 2) {
    const auto foot = projectOntoPath(*e.trail, robot);
    if (foot) {
      // Along the trail's direction at the robot's foot, backwards: the robot keeps its offset
      // from the trail (a docked robot stays by its wall) ...
      const Eigen::Vector2d to =
          pointAt(*e.trail, std::max(foot->arc_length_m - room.retreat_lookahead_m, 0.0));
      if ((foot->closest - to).norm() > 1e-3) {
        tries.push_back((to - foot->closest).normalized());
        // ... or, where that is blocked, heads for the trail point itself.
        if ((to - robot).norm() > 1e-3) tries.push_back((to - robot).normalized());
      }
    }
  }
  tries.push_back(away);
  const double reach = room.retreat_min_room_m;
  for (const Eigen::Vector2d& d : tries) {
    if (d.dot(away) < 0.0) continue;  // never towards the human
    const DistanceResult now = map.nearest(robot);
    // Already nearer a wall than the radius (the grid, a flush dock): do not get nearer.
    const double need = now.status == DistanceStatus::kOk
                            ? std::min(e.robot_radius_m, now.distance_m)
                            : e.robot_radius_m;
    if (straightClear(map, robot, robot + reach * d, need)) return d;
  }
  return std::nullopt;
}

void Trail::add(const Eigen::Vector2d& p) {
  if (!p.allFinite()) return;
  if (points_.empty()) {
    points_.push_back(p);
    return;
  }
  // Back near an earlier point (the robot came back this way): the loop after it is dropped.
  // Points within a few spacings of the end are the robot's latest steps, not a way back.
  const double cut_m = 2.0 * spacing_m_;
  double from_end_m = 0.0;
  std::size_t checked = 0;  // points_[0 .. checked) may be a way back
  for (std::size_t i = points_.size() - 1; i > 0; --i) {
    from_end_m += (points_[i] - points_[i - 1]).norm();
    if (from_end_m > 2.0 * cut_m) {
      checked = i;
      break;
    }
  }
  for (std::size_t i = 0; i < checked; ++i) {
    if ((points_[i] - p).norm() < cut_m) {
      points_.resize(i + 1);
      break;
    }
  }
  // A jump (relocalisation): the old trail is no way back.
  constexpr double kJump_m = 2.0;
  if ((points_.back() - p).norm() > kJump_m) points_.clear();
  if (points_.empty() || (points_.back() - p).norm() >= spacing_m_) points_.push_back(p);
  double len = pathLength(points_);
  std::size_t drop = 0;
  while (drop + 2 < points_.size() && len > max_length_m_) {
    len -= (points_[drop + 1] - points_[drop]).norm();
    ++drop;
  }
  if (drop > 0) points_.erase(points_.begin(), points_.begin() + static_cast<std::ptrdiff_t>(drop));
}

}  // namespace coopnav
