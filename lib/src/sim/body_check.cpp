#include "coopnav/sim/body_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Ray range for the room beside the robot; beyond it a side is free.
constexpr double kRoomProbeRange_m = 6.0;
/// Below this a model's desired speed means "standing": the check does not start it walking.
constexpr double kStandingSpeed_m_s = 0.05;
/// Squeezing past, a human walks at least this fraction of its preferred speed: a model that
/// slows down in front of the robot (the social force's deceleration term) does not creep past it.
constexpr double kSqueezeSpeedFraction = 0.6;
/// Shortest carrot distance of the steering round the robot: right beside the robot the human
/// still moves forward while it finishes its sidestep.
constexpr double kMinLookahead_m = 0.3;

Eigen::Vector2d leftNormal(const Eigen::Vector2d& t) { return {-t.y(), t.x()}; }

double freeAlong(const DistanceMap* map, const Eigen::Vector2d& from, const Eigen::Vector2d& dir) {
  if (map == nullptr) return kInf;
  const DistanceResult r = map->ray(from, dir, kRoomProbeRange_m);
  if (r.status == DistanceStatus::kOk) return r.distance_m;
  if (r.status == DistanceStatus::kInObstacle) return 0.0;
  return kInf;  // no wall in range (or the map cannot tell): free
}

}  // namespace

const char* toString(BodyCheckMode m) {
  switch (m) {
    case BodyCheckMode::kOff:
      return "off";
    case BodyCheckMode::kClear:
      return "clear";
    case BodyCheckMode::kSqueeze:
      return "squeeze";
    case BodyCheckMode::kWait:
      return "wait";
  }
  return "?";
}

RoomBesideRobot roomBesideRobot(const DistanceMap* map, const AgentState& robot,
                                const Eigen::Vector2d& n_left) {
  const Eigen::Vector2d q = robot.pose.position();
  return {freeAlong(map, q, n_left) - robot.radius_m, freeAlong(map, q, -n_left) - robot.radius_m};
}

Velocity2 BodyCheck::apply(const BehaviourContext& ctx, const Velocity2& want,
                           double planned_offset_m) {
  mode_ = BodyCheckMode::kOff;
  if (ctx.robot == nullptr || ctx.self == nullptr) {
    latched_ = false;
    return want;
  }
  const Eigen::Vector2d p = ctx.self->pose.position();
  const Eigen::Vector2d q = ctx.robot->pose.position();
  const double r_h = ctx.self->radius_m;
  const double r_r = ctx.robot->radius_m;
  const Eigen::Vector2d d = q - p;
  const double dist_m = d.norm();
  if (!(dist_m > 1e-9)) return want;
  const Eigen::Vector2d e = d / dist_m;  // towards the robot
  const double gap_m = dist_m - r_r - r_h;
  const Eigen::Vector2d v_r{ctx.robot->velocity.vx_m_s, ctx.robot->velocity.vy_m_s};
  // A robot coming at the human is the paper's encounter: the model's own reaction decides.
  if (-v_r.dot(e) > p_.rest_speed_m_s) {
    latched_ = false;
    return want;
  }
  mode_ = BodyCheckMode::kClear;

  // The human's path frame: along its reference path where it is, else towards the robot.
  Eigen::Vector2d t = e;
  double offset_now_m = 0.0;
  if (ctx.reference_path != nullptr && ctx.reference_path->size() >= 2) {
    if (const auto proj = projectOntoPath(*ctx.reference_path, p)) {
      t = pointAtArc(*ctx.reference_path, proj->arc_length_m).tangent;
      offset_now_m = proj->signed_distance_m;
    }
  }
  const Eigen::Vector2d n = leftNormal(t);
  const double ahead_m = d.dot(t);  // the robot's centre ahead of the human's, along the path
  const double robot_off_m = offset_now_m + d.dot(n);     // the robot's offset from the path
  const double pass_m = r_r + r_h + p_.squeeze_margin_m;  // centre distance when squeezing past

  Eigen::Vector2d out{want.vx_m_s, want.vy_m_s};
  bool wait = false;
  if (ahead_m <= 0.0) {
    latched_ = false;  // beside or behind: passed (the disc below still keeps it off the body)
  } else if (latched_ || ahead_m - (r_r + r_h) < p_.engage_distance_m) {
    const bool in_the_way = std::abs(planned_offset_m - robot_off_m) < pass_m;
    if (in_the_way || latched_) {
      // Like a wall: pass where the human's body fits between the robot's and the wall.
      const RoomBesideRobot room = roomBesideRobot(ctx.map, *ctx.robot, n);
      const double need_m = 2.0 * r_h + 2.0 * p_.squeeze_margin_m;
      const bool fits_left = room.left_m >= need_m, fits_right = room.right_m >= need_m;
      if (!latched_ || !(side_ > 0.0 ? fits_left : fits_right)) {
        latched_ = fits_left || fits_right;
        if (fits_left && fits_right) {
          // The side nearer to where the model means to be; dead-on, its right (keep-right bias
          // of pedestrians, Moussaïd et al. 2009, as behaviours.cpp).
          const double move_left_m = std::abs(robot_off_m + pass_m - planned_offset_m);
          const double move_right_m = std::abs(robot_off_m - pass_m - planned_offset_m);
          side_ = move_left_m < move_right_m - 1e-9 ? 1.0 : -1.0;
        } else if (latched_) {
          side_ = fits_left ? 1.0 : -1.0;
        }
      }
      if (latched_) target_offset_m_ = robot_off_m + side_ * pass_m;
      // A model that means to pass farther out on that side keeps its own way (the paper's
      // minimal human beside a docked robot): the check only makes up for what it lacks.
      if (latched_ && side_ * (planned_offset_m - target_offset_m_) < 0.0) {
        mode_ = BodyCheckMode::kSqueeze;
        const double lateral_error_m = target_offset_m_ - offset_now_m;
        const double lookahead_m = std::clamp(ahead_m, kMinLookahead_m, p_.lookahead_m);
        const Eigen::Vector2d dir = (lookahead_m * t + lateral_error_m * n).normalized();
        const double want_m_s = out.norm();
        const double speed_m_s =
            want_m_s < kStandingSpeed_m_s
                ? 0.0
                : std::max(want_m_s, kSqueezeSpeedFraction * ctx.preferred_speed_m_s);
        out = speed_m_s * dir;
      } else if (!latched_) {
        mode_ = BodyCheckMode::kWait;
        wait = true;
      }
    }
  }

  // Never into the robot's body: the velocity towards it (relative to the robot's own, when it
  // moves away) is held to what the human can still brake from before the stopping gap.
  const double stop_gap_m = wait ? p_.wait_gap_m : 0.5 * p_.squeeze_margin_m;
  const double brake_m_s2 = p_.brake_fraction * ctx.max_acc_m_s2;
  const double cap_m_s =
      std::max(0.0, v_r.dot(e)) + std::sqrt(2.0 * brake_m_s2 * std::max(0.0, gap_m - stop_gap_m));
  const double towards_m_s = out.dot(e);
  if (towards_m_s > cap_m_s) {
    if (wait) {
      out *= cap_m_s / towards_m_s;  // slows down on its own line and stops: it waits
    } else {
      out -= (towards_m_s - cap_m_s) * e;  // slides along the robot's body
    }
  }
  return {out.x(), out.y(), want.omega_rad_s};
}

}  // namespace coopnav::sim
