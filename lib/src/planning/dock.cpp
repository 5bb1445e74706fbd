#include "coopnav/planning/dock.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav {

const char* toString(RobotMode m) {
  switch (m) {
    case RobotMode::kNavigate:
      return "navigate";
    case RobotMode::kDocking:
      return "docking";
    case RobotMode::kHolding:
      return "holding";
    case RobotMode::kResuming:
      return "resuming";
    case RobotMode::kGoalReached:
      return "goal_reached";
    case RobotMode::kRetreating:
      return "retreating";
  }
  return "unknown";
}

Eigen::Vector2d sideAwayFrom(const Eigen::Vector2d& axis, const Eigen::Vector2d& robot,
                             const Eigen::Vector2d& human) {
  const Eigen::Vector2d left(-axis.y(), axis.x());
  // Which side the human is on, as the robot sees it; dock on the other one. Dead ahead (a
  // head-on course) gives no side: keep right.
  constexpr double kDeadAhead_m = 0.1;
  const double lateral = cross2(axis, human - robot);
  const double away = std::abs(lateral) < kDeadAhead_m ? -1.0 : (lateral > 0.0 ? -1.0 : 1.0);
  return away * left;
}

DockResult findDockPose(const DistanceMap& map, const Pose2& robot, const Pose2& human,
                        const DockOptions& o) {
  if (!isFinite(robot) || !std::isfinite(human.x_m) || !std::isfinite(human.y_m)) return {};
  const Eigen::Vector2d h = headingVector(robot.theta_rad);
  return findDockPoseAlong(map, robot, h, sideAwayFrom(h, robot.position(), human.position()),
                           o.robot_radius_m, o);
}

DockResult findDockPoseAlong(const DistanceMap& map, const Pose2& robot,
                             const Eigen::Vector2d& axis, const Eigen::Vector2d& towards_wall,
                             double radius_m, const DockOptions& options,
                             const std::function<bool(const Eigen::Vector2d&)>& accept) {
  const Eigen::Vector2d& h = axis;
  const Eigen::Vector2d& n = towards_wall;
  const DockOptions& o = options;
  DockResult out;
  if (!isFinite(robot) || !h.allFinite() || !n.allFinite() || !(radius_m > 0.0)) return out;
  constexpr int kBackOffTries = 4;
  const double need_m = radius_m + o.margin_m;
  double best_cost = std::numeric_limits<double>::infinity();
  bool wall_seen = false;
  for (double a = -o.max_ahead_m; a <= o.max_ahead_m + 1e-9; a += o.step_m) {
    const Eigen::Vector2d base = robot.position() + a * h;
    const DistanceResult hit = map.ray(base, n, o.search_range_m);
    if (hit.status != DistanceStatus::kOk) continue;
    wall_seen = true;
    double travel = std::max(hit.distance_m - need_m, 0.0);
    Eigen::Vector2d p = base + travel * n;
    DistanceResult c = map.nearest(p);
    // A grid field measures RAY and NEAREST to slightly different surfaces (cell edge vs cell
    // centre, up to half a cell) and real walls are ragged: back off from the wall by the
    // shortfall until the clearance holds, never past the robot's own line.
    for (int i = 0; i < kBackOffTries && c.status == DistanceStatus::kOk &&
                    c.distance_m < need_m - 1e-3 && travel > 0.0;
         ++i) {
      travel = std::max(travel - (need_m - c.distance_m + 1e-3), 0.0);
      p = base + travel * n;
      c = map.nearest(p);
    }
    if (c.status != DistanceStatus::kOk || c.distance_m < need_m - 1e-3) continue;
    // Straight approach: sampled clearance along robot → p of at least the radius, or of what
    // the robot has now when it already stands nearer a wall.
    const DistanceResult c0 = map.nearest(robot.position());
    const double approach_m =
        c0.status == DistanceStatus::kOk ? std::min(radius_m, c0.distance_m) : radius_m;
    bool clear = true;
    const double len = (p - robot.position()).norm();
    const int k = std::max(1, static_cast<int>(std::ceil(len / 0.05)));
    for (int i = 1; i <= k && clear; ++i) {
      const DistanceResult s = map.nearest(robot.position() + (p - robot.position()) * i / k);
      clear = s.status == DistanceStatus::kOk && s.distance_m >= approach_m - 1e-3;
    }
    if (!clear) continue;
    if (accept && !accept(p)) continue;
    // Prefer short moves; moving towards the human costs extra (it shortens the gap).
    const double cost = len + (a > 0.0 ? 0.5 * a : 0.0);
    if (cost < best_cost) {
      best_cost = cost;
      out.pose = {p.x(), p.y(), robot.theta_rad};
      out.wall_distance_m = c.distance_m;
    }
  }
  if (std::isfinite(best_cost)) {
    out.status = DockStatus::kOk;
    out.side = cross2(h, n) > 0.0 ? Side::kLeft : Side::kRight;
  } else {
    out.status = wall_seen ? DockStatus::kUnreachable : DockStatus::kNoWall;
  }
  return out;
}

Encounter encounterOf(const ModeInput& in) {
  Encounter e;
  e.robot = in.robot;
  e.robot_radius_m = in.robot_radius_m;
  e.human_position = in.human.position();
  e.human_velocity = in.human_velocity;
  e.human_radius_m = in.human_radius_m;
  e.trail = in.trail;
  e.limits = in.limits;
  return e;
}

bool DockModeMachine::humanHasPassed(const Pose2& robot, const Pose2& human, double margin_m) {
  return (robot.position() - human.position()).dot(headingVector(human.theta_rad)) < -margin_m;
}

void DockModeMachine::holdHere(const ModeInput& in) {
  // Holding is at the dock pose only after docking; a hold after a retreat, or where no move
  // left room, is where the robot stands (its goal for the planner's band, which the assessors
  // read: a stale dock pose there may lie in a wall, and the band would fail).
  dock_ = in.robot;
  route_.clear();
  on_dock_ = false;
}

bool DockModeMachine::start(const RoomDecision& d, const ModeInput& in, ModeOutput& out) {
  out.room = d.move;
  switch (d.move) {
    case RoomMove::kDockHere:
    case RoomMove::kWiderPlace:
      dock_ = d.target;
      route_ = d.route;
      dock_move_ = d.move;
      mode_ = RobotMode::kDocking;
      return true;
    case RoomMove::kRetreat:
      mode_ = RobotMode::kRetreating;
      return true;
    case RoomMove::kNone:
      // No move leaves room: stop where it stands (and the guard moves it off a human).
      holdHere(in);
      dock_move_ = d.move;
      mode_ = RobotMode::kHolding;
      hold_since_s_ = in.stamp_s;
      return true;
    case RoomMove::kUnknown:
      break;
  }
  return false;
}

ModeOutput DockModeMachine::update(const DistanceMap& map, const ModeInput& in) {
  ModeOutput out;
  const RobotMode before = mode_;
  const bool at_goal = (in.robot.position() - in.goal.position()).norm() < opt_.goal_tolerance_m;
  const double human_dist_m =
      in.has_human ? (in.robot.position() - in.human.position()).norm() : 0.0;
  const Encounter e = encounterOf(in);
  const bool closing = in.has_human && closingSpeed(e) > opt_.room.closing_speed_m_s;
  // Far means going away: a dock asked for while the human is still far off (t_CROSS 4 s at a
  // closing speed of 1.7 m/s is ~7 m) must wait for it to come and pass.
  auto human_gone = [&] {
    if (!in.has_human) return true;
    // Passed along the way they came at the dock request (from them to the robot), not along
    // their heading now: a tracker's heading of someone standing and waiting is the direction of
    // its velocity noise, and would have them "passed" while they wait in front of the robot.
    const bool passed =
        (in.robot.position() - in.human.position()).dot(dock_axis_) < -opt_.human_passed_margin_m;
    return passed || (human_dist_m > opt_.human_far_m &&
                      human_dist_m > dock_start_dist_m_ + opt_.human_receding_m);
  };
  // The human comes on and cannot pass beside the robot where it stands. The robot holds up to
  // the reached tolerance off its dock pose, whose passage held: that much is not "blocked" (it
  // would make a docked robot flap between holding and retreating).
  auto blocked_here = [&] {
    const double margin_m =
        std::max(opt_.room.passage_margin_m - opt_.dock_reached_tolerance_m, 0.0);
    return closing && !passageHere(map, e, margin_m).ok;
  };
  auto retreat_or_hold = [&] {
    out.retreat_direction = retreatDirection(map, e, opt_.room);
    if (out.retreat_direction) {
      mode_ = RobotMode::kRetreating;
    } else if (mode_ != RobotMode::kHolding) {
      mode_ = RobotMode::kHolding;
      hold_since_s_ = in.stamp_s;
      holdHere(in);
    }
  };
  switch (mode_) {
    case RobotMode::kNavigate:
    case RobotMode::kResuming:
    case RobotMode::kGoalReached:
      // At its goal too: a robot parked in a corridor blocks it as much as one on its way, and a
      // dock asked for there makes room as anywhere (it drives back to the goal afterwards).
      mode_ = at_goal ? RobotMode::kGoalReached : RobotMode::kNavigate;
      if (in.dock_requested && in.has_human) {
        dock_start_dist_m_ = human_dist_m;
        dock_axis_ =
            human_dist_m > 0.0
                ? Eigen::Vector2d((in.robot.position() - in.human.position()) / human_dist_m)
                : headingVector(in.human.theta_rad);
        const RoomDecision d = decideRoom(map, e, opt_.dock, opt_.room);
        if (!start(d, in, out)) {
          // Nothing to make room in (no wall away from the human, room to pass): keep
          // navigating (and avoiding). Holding where it stands would not be safer: in the open
          // corridor a minimally contributing human walks into a standing robot (scripts/faults.sh,
          // open_minimal without the distance server).
          out.dock_failure = DockStatus::kNoWall;
        } else if (mode_ == RobotMode::kRetreating) {
          retreat_or_hold();
        }
      }
      break;
    case RobotMode::kDocking:
      if (in.resume_requested || human_gone()) {
        mode_ = RobotMode::kResuming;
      } else if ((in.robot.position() - dock_.position()).norm() < opt_.dock_reached_tolerance_m) {
        mode_ = RobotMode::kHolding;
        hold_since_s_ = in.stamp_s;
        on_dock_ = true;
      } else if (dock_move_ == RoomMove::kWiderPlace && closing) {
        // Will the human be at the wider place before the robot? Then back away instead. (It
        // was chosen with reach_margin_s to spare: that much is hysteresis.)
        const Eigen::Vector2d to = dock_.position() - in.robot.position();
        const double robot_s =
            travelTime(lengthLeft(route_, in.robot.position()), to, in.robot.theta_rad, in.limits);
        const double gap_m = std::max(
            (in.human.position() - dock_.position()).norm() - in.robot_radius_m - in.human_radius_m,
            0.0);
        const double human_s = gap_m / std::max(in.human_velocity.norm(), 1e-9);
        if (human_s < robot_s) {
          out.room = RoomMove::kRetreat;
          retreat_or_hold();
        }
      }
      break;
    case RobotMode::kHolding:
      if (in.resume_requested || human_gone() || in.stamp_s - hold_since_s_ > opt_.hold_timeout_s) {
        mode_ = RobotMode::kResuming;
      } else if (blocked_here()) {
        out.room = RoomMove::kRetreat;
        retreat_or_hold();
      }
      break;
    case RobotMode::kRetreating:
      if (in.resume_requested || human_gone()) {
        mode_ = RobotMode::kResuming;
      } else if (!closing) {
        // The human stopped or turns away: stay, and go on when it has passed.
        mode_ = RobotMode::kHolding;
        hold_since_s_ = in.stamp_s;
        holdHere(in);
      } else {
        // Backing away may have brought a place to dock within reach.
        const RoomDecision d = decideRoom(map, e, opt_.dock, opt_.room);
        if (d.move == RoomMove::kDockHere || d.move == RoomMove::kWiderPlace) {
          start(d, in, out);
        } else {
          retreat_or_hold();
        }
      }
      break;
  }
  out.mode = mode_;
  out.changed = mode_ != before;
  out.active_goal =
      (mode_ == RobotMode::kDocking || mode_ == RobotMode::kHolding) ? dock_ : in.goal;
  if (mode_ == RobotMode::kRetreating) {
    // The planner's band shows the retreat (the assessors read it): a goal back along the
    // retreat direction, as far as the look-ahead and the free room allow.
    out.active_goal = in.robot;
    if (out.retreat_direction) {
      const Eigen::Vector2d d = *out.retreat_direction;
      const DistanceResult free =
          map.ray(in.robot.position(), d, opt_.room.retreat_lookahead_m + in.robot_radius_m);
      const double room_m = free.status == DistanceStatus::kOk ? free.distance_m - in.robot_radius_m
                                                               : opt_.room.retreat_lookahead_m;
      const double back_m = std::clamp(room_m, 0.0, opt_.room.retreat_lookahead_m);
      out.active_goal.x_m += back_m * d.x();
      out.active_goal.y_m += back_m * d.y();
    }
  }
  if (mode_ == RobotMode::kDocking) out.route = route_;
  if (mode_ != RobotMode::kRetreating) out.retreat_direction.reset();
  out.hold_still = mode_ == RobotMode::kHolding || mode_ == RobotMode::kGoalReached;
  if (mode_ != RobotMode::kHolding) on_dock_ = false;
  out.settle = mode_ == RobotMode::kHolding && on_dock_;
  return out;
}

}  // namespace coopnav
