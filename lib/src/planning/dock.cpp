#include "coopnav/planning/dock.hpp"

#include <cmath>
#include <limits>

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
  }
  return "unknown";
}

DockResult findDockPose(const DistanceMap& map, const Pose2& robot, const Pose2& human,
                        const DockOptions& o) {
  DockResult out;
  if (!isFinite(robot) || !std::isfinite(human.x_m) || !std::isfinite(human.y_m)) return out;
  const Eigen::Vector2d h = headingVector(robot.theta_rad);
  const Eigen::Vector2d left(-h.y(), h.x());
  const Eigen::Vector2d rel = human.position() - robot.position();
  // Which side the human is on, as the robot sees it; dock on the other one. Dead ahead (a
  // head-on course) gives no side: keep right.
  constexpr double kDeadAhead_m = 0.1;
  constexpr int kBackOffTries = 4;
  const double lateral = cross2(h, rel);
  const double away = std::abs(lateral) < kDeadAhead_m ? -1.0 : (lateral > 0.0 ? -1.0 : 1.0);
  const Eigen::Vector2d n = away * left;
  const double need_m = o.robot_radius_m + o.margin_m;
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
    // Straight approach: sampled clearance along robot → p of at least the radius.
    bool clear = true;
    const double len = (p - robot.position()).norm();
    const int k = std::max(1, static_cast<int>(std::ceil(len / 0.05)));
    for (int i = 1; i <= k && clear; ++i) {
      const DistanceResult s = map.nearest(robot.position() + (p - robot.position()) * i / k);
      clear = s.status == DistanceStatus::kOk && s.distance_m >= o.robot_radius_m - 1e-3;
    }
    if (!clear) continue;
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
    out.side = away > 0.0 ? Side::kLeft : Side::kRight;
  } else {
    out.status = wall_seen ? DockStatus::kUnreachable : DockStatus::kNoWall;
  }
  return out;
}

bool DockModeMachine::humanHasPassed(const Pose2& robot, const Pose2& human, double margin_m) {
  return (robot.position() - human.position()).dot(headingVector(human.theta_rad)) < -margin_m;
}

ModeOutput DockModeMachine::update(const DistanceMap& map, const ModeInput& in) {
  ModeOutput out;
  const RobotMode before = mode_;
  const bool at_goal = (in.robot.position() - in.goal.position()).norm() < opt_.goal_tolerance_m;
  const double human_dist_m =
      in.has_human ? (in.robot.position() - in.human.position()).norm() : 0.0;
  // Far means going away: a dock asked for while the human is still far off (t_CROSS 4 s at a
  // closing speed of 1.7 m/s is ~7 m) must wait for it to come and pass.
  auto human_gone = [&] {
    if (!in.has_human) return true;
    return humanHasPassed(in.robot, in.human, opt_.human_passed_margin_m) ||
           (human_dist_m > opt_.human_far_m &&
            human_dist_m > dock_start_dist_m_ + opt_.human_receding_m);
  };
  switch (mode_) {
    case RobotMode::kNavigate:
    case RobotMode::kResuming:
      mode_ = RobotMode::kNavigate;
      if (at_goal) {
        mode_ = RobotMode::kGoalReached;
      } else if (in.dock_requested && in.has_human) {
        const DockResult d = findDockPose(map, in.robot, in.human, opt_.dock);
        dock_start_dist_m_ = human_dist_m;
        if (d.status == DockStatus::kOk) {
          dock_ = d.pose;
          mode_ = RobotMode::kDocking;
        } else {
          // No wall to dock at: keep navigating (and avoiding). Holding where it stands was
          // tried: in the open corridor a minimally contributing human then walked into the
          // standing robot (scripts/faults.sh, open_minimal without the distance server).
          out.dock_failure = d.status;
        }
      }
      break;
    case RobotMode::kDocking:
      if (in.resume_requested || human_gone()) {
        mode_ = RobotMode::kResuming;
      } else if ((in.robot.position() - dock_.position()).norm() < opt_.dock_reached_tolerance_m) {
        mode_ = RobotMode::kHolding;
        hold_since_s_ = in.stamp_s;
      }
      break;
    case RobotMode::kHolding:
      if (in.resume_requested || human_gone() || in.stamp_s - hold_since_s_ > opt_.hold_timeout_s) {
        mode_ = RobotMode::kResuming;
      }
      break;
    case RobotMode::kGoalReached:
      if (!at_goal) mode_ = RobotMode::kNavigate;
      break;
  }
  out.mode = mode_;
  out.changed = mode_ != before;
  out.active_goal =
      (mode_ == RobotMode::kDocking || mode_ == RobotMode::kHolding) ? dock_ : in.goal;
  out.hold_still = mode_ == RobotMode::kHolding || mode_ == RobotMode::kGoalReached;
  return out;
}

}  // namespace coopnav
