#include "coopnav/band/band_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>

#include "coopnav/distance/point_obstacle_map.hpp"
#include "coopnav/geometry/geometry.hpp"
#include "coopnav/planning/global_planner.hpp"

namespace coopnav {
namespace {

/// Below this speed a human's heading is its pose's, not its direction of motion [m/s].
constexpr double kWalkingSpeed_m_s = 0.1;

// Message time: utime [us] -> seconds, and differences in double (a hostile stamp may be
// INT64_MIN or INT64_MAX; exact while both are below 2^53 us).
double seconds(std::int64_t utime) { return static_cast<double>(utime) * 1e-6; }
double diffSeconds(std::int64_t later_utime, std::int64_t earlier_utime) {
  return (static_cast<double>(later_utime) - static_cast<double>(earlier_utime)) * 1e-6;
}

/// printf-style text for a note.
std::string format(const char* f, ...) {
  char buf[512];
  va_list args;
  va_start(args, f);
  std::vsnprintf(buf, sizeof buf, f, args);
  va_end(args);
  return buf;
}

void note(BandCycleOutput& out, BandCycleNote::Level level, std::string text) {
  out.notes.push_back({level, std::move(text)});
}

/// Position and heading of motion (the mode machine judges "passed" along where the human goes).
Pose2 motionPose(const AgentState& h) {
  Pose2 p = h.pose;
  const double vx = h.velocity.vx_m_s, vy = h.velocity.vy_m_s;
  if (std::hypot(vx, vy) > kWalkingSpeed_m_s) p.theta_rad = std::atan2(vy, vx);
  return p;
}

const AgentState* human(const BandCycleInput& s, std::int32_t id) {
  for (const auto& h : s.humans)
    if (h.id == id) return &h;
  return nullptr;
}

std::string idList(const std::set<std::int32_t>& ids) {
  std::string s;
  for (const auto id : ids) s += (s.empty() ? "" : ",") + std::to_string(id);
  return s;
}

}  // namespace

BandCycle::BandCycle(const BandCycleConfig& config, std::shared_ptr<const DistanceMap> map,
                     std::shared_ptr<const GoalDistances> goals, std::function<double()> clock_s)
    : config_(config),
      map_(std::move(map)),
      clock_s_(std::move(clock_s)),
      planner_(std::make_unique<DualBandPlanner>(config_.planner, map_)),
      goal_distances_(std::move(goals)) {
  const BandPlannerConfig& pc = config_.planner;
  ModeMachineOptions mo = config_.modes;
  mo.goal_tolerance_m = pc.xy_goal_tolerance_m;
  mo.dock.robot_radius_m = pc.robot.radius_m;
  modes_ = DockModeMachine(mo);
  limits_.holonomic = pc.robot.holonomic;
  limits_.max_forward_m_s = pc.robot.max_vel_x_m_s;
  limits_.max_backward_m_s = pc.robot.max_vel_x_backwards_m_s;
  limits_.max_lateral_m_s = pc.robot.max_vel_y_m_s;
  limits_.max_omega_rad_s = pc.robot.max_vel_theta_rad_s;
}

void BandCycle::restamp(std::int64_t utime) {
  if (last_refs_utime_) last_refs_utime_ = utime;
  if (go_first_) go_first_->since_s = seconds(utime);
  if (passing_) passing_->since_s = seconds(utime);
  if (slow_) slow_->since_s = seconds(utime);
  if (planner_memory_check_utime_) planner_memory_check_utime_ = utime;
  // A goal belief is a track in the old time base: later observations would be refused as older.
  goal_beliefs_.clear();
  goal_belief_recency_.clear();
  inferred_goal_.clear();
  // The dock's hold timeout (dock.hold_timeout_s) is counted by the mode machine in message
  // time: after a resync backwards a hold ends when the human passes or a RESUME comes.
}

BandCycleOutput BandCycle::step(const BandCycleInput& s) {
  BandCycleOutput result;
  const double stamp_s = seconds(s.utime);
  // The map with the obstacles of the moment (the scan's returns, less the tracked people's).
  std::optional<PointObstacleMap> with_points;
  if (!s.planner_points.empty()) with_points.emplace(*map_, s.planner_points);
  const DistanceMap& obstacles =
      with_points ? static_cast<const DistanceMap&>(*with_points) : *map_;

  // --- goals: the robot's (kind ROBOT; its own id preferred) and the humans' ---
  std::optional<Pose2> robot_goal;
  std::map<std::int32_t, Pose2> human_goals;
  if (s.goals) {
    for (const auto& g : *s.goals) {
      if (g.kind == AgentKind::kRobot) {
        if (!robot_goal || g.agent_id == s.robot.id) robot_goal = g.pose;
      } else {
        human_goals[g.agent_id] = g.pose;
      }
    }
  }

  // --- the dialogue's actions since the last cycle; the latest one wins ---
  bool dock_req = false, resume_req = false;
  std::int32_t dock_for = -1;
  if (s.action) {
    dock_req = s.action->dock;
    // A RESUME ends the dock of the human it is for: one for someone else (the end of their
    // slowing, their crossing) leaves a dock for another human in place.
    resume_req = !s.action->dock && !s.action->go_first && !s.action->slow &&
                 (!dock_human_id_ || *dock_human_id_ == s.action->human_id);
    if (dock_req) dock_for = s.action->human_id;
    // Any newer action ends going first (and a pass) and slowing; GO_FIRST and SLOW start them.
    go_first_.reset();
    passing_.reset();
    slow_.reset();
    if (s.action->go_first) go_first_ = GoingFirst{s.action->human_id, stamp_s};
    if (s.action->slow) slow_ = GoingFirst{s.action->human_id, stamp_s};
  }

  // --- mode: navigate / dock / hold / retreat / resume ---
  RobotMode mode = RobotMode::kNavigate;
  Pose2 active_goal = s.robot.pose;
  bool hold = false;
  ModeOutput mode_out;
  if (robot_goal) {
    ModeInput in;
    in.stamp_s = stamp_s;
    in.robot = s.robot.pose;
    in.robot_radius_m = s.robot.radius_m;
    in.trail = &trail_.points();
    in.limits = limits_;
    in.goal = *robot_goal;
    in.dock_requested = dock_req;
    in.resume_requested = resume_req;
    const std::optional<std::int32_t> hid =
        dock_req ? std::optional<std::int32_t>(dock_for) : dock_human_id_;
    const AgentState* h = hid ? human(s, *hid) : nullptr;
    if (h) {
      in.has_human = true;
      in.human = motionPose(*h);
      in.human_velocity = {h->velocity.vx_m_s, h->velocity.vy_m_s};
      in.human_radius_m = h->radius_m;
    } else if (dock_req) {
      note(result, BandCycleNote::Level::kWarn,
           format("DOCK for human %d who is not in the agent states: ignored", dock_for));
    }
    // The dock and room choices see the obstacles of the moment too: a spot behind or in an
    // unmapped box fails the clearance of its approach and is not chosen.
    mode_out = modes_.update(obstacles, in);
    const ModeOutput& out = mode_out;
    if (out.dock_failure) {
      note(result, BandCycleNote::Level::kWarn,
           format("DOCK for human %d at step %lld: %s: the robot keeps avoiding", dock_for,
                  static_cast<long long>(s.step),
                  *out.dock_failure == DockStatus::kNoWall
                      ? "no wall on the side away from the human and room to pass"
                      : "no reachable dock pose"));
    }
    if (out.mode == RobotMode::kDocking || out.mode == RobotMode::kHolding ||
        out.mode == RobotMode::kRetreating) {
      if (dock_req && in.has_human) dock_human_id_ = dock_for;
    } else {
      dock_human_id_.reset();
    }
    if (out.changed) {
      note(result, BandCycleNote::Level::kInfo,
           format("mode %s at step %lld (utime %lld)", toString(out.mode),
                  static_cast<long long>(s.step), static_cast<long long>(s.utime)) +
               (out.room != RoomMove::kUnknown
                    ? std::string(" for human ") +
                          std::to_string(dock_human_id_ ? *dock_human_id_ : dock_for) +
                          ", room: " + toString(out.room)
                    : std::string()));
    }
    mode = out.mode;
    active_goal = out.active_goal;
    hold = out.hold_still;
  } else if (dock_req || resume_req) {
    note(result, BandCycleNote::Level::kWarn, "robot action ignored: the robot has no goal");
  }

  // --- plan ---
  PlanRequest req;
  req.stamp_s = stamp_s;
  req.agent = s.robot;
  req.goal = active_goal;
  req.obstacle_points = s.planner_points;
  req.max_iterations = config_.max_iterations;
  req.time_budget_s = s.step < 0 ? config_.free_running_time_budget_s : 0.0;
  // The caller's clock for the free-running time budget and the reported solve time only; the
  // plan itself depends on message time alone (lockstep passes no budget).
  req.clock_s = clock_s_;
  // Humans the goals message gives no goal: the most likely inferred one (same step order as
  // the reference paths: published first).
  for (const auto& [id, goal] : inferGoals(s, human_goals, result)) human_goals.emplace(id, goal);
  std::set<std::int32_t> with_goal, without_goal;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (const auto& h : s.humans) {
    OtherAgentInput o;
    o.state = h;
    const auto it = human_goals.find(h.id);
    if (it != human_goals.end()) {
      o.goal = it->second;
      with_goal.insert(h.id);
    } else {
      o.goal = {kNaN, kNaN, kNaN};  // unknown: the planner predicts constant velocity
      without_goal.insert(h.id);
    }
    req.others.push_back(o);
  }
  if (without_goal != humans_without_goal_) {
    humans_without_goal_ = without_goal;
    if (!without_goal.empty()) {
      note(result, BandCycleNote::Level::kInfo,
           "humans without a goal (constant-velocity band, no reference path): " +
               idList(without_goal));
    }
  }
  const double t0_s = clock_s_ ? clock_s_() : 0.0;
  result.plan = planner_->plan(req);
  const PlanResult& r = result.plan;
  result.plan_ms = clock_s_ ? (clock_s_() - t0_s) * 1e3 : 0.0;
  ++cycles_;
  const std::set<std::int32_t> unplanned(r.unplanned_ids.begin(), r.unplanned_ids.end());
  if (unplanned != humans_unplanned_) {
    humans_unplanned_ = unplanned;
    if (!unplanned.empty()) {
      note(result, BandCycleNote::Level::kInfo,
           format("more than %d humans: a predicted band (not planned jointly) this cycle for ",
                  config_.planner.max_planned_others) +
               idList(unplanned));
    }
  }
  if (r.status != PlanStatus::kOk && r.status != PlanStatus::kGoalReached) {
    note(result, BandCycleNote::Level::kWarn,
         format("step %lld (utime %lld): planner %s", static_cast<long long>(s.step),
                static_cast<long long>(s.utime), toString(r.status)));
  }
  note(result, BandCycleNote::Level::kDebug,
       format("step %lld %s mode %s %d iterations, cost %.3g, %.2f ms",
              static_cast<long long>(s.step), toString(r.status), toString(mode),
              static_cast<int>(r.iterations), r.final_cost, result.plan_ms));

  // --- outputs, in the lockstep order: reference paths, bands, command ---
  referencePaths(s, r, with_goal, result);
  boundPlannerMemory(s, r, result);

  const bool idle = !robot_goal;
  const bool usable = r.status == PlanStatus::kOk || r.status == PlanStatus::kGoalReached;
  // A dock or a retreat is driven without the planner's band (modeCommand).
  const bool driven = mode == RobotMode::kDocking || mode == RobotMode::kRetreating;
  result.idle = idle;
  result.stopped = !idle && !(usable || driven);
  result.mode = mode;
  result.room_plans = roomPlans(s, r, obstacles);

  Velocity2 command = modeCommand(s, mode_out, r, hold, idle);
  if (mode == RobotMode::kNavigate && !idle && !hold && r.status == PlanStatus::kOk)
    command = overtakeCommand(s, *robot_goal, r, command, result);
  if (go_first_ && !passing_ && mode == RobotMode::kNavigate && !idle)
    command = goFirstCommand(s, r, command, result);
  if (slow_ && mode == RobotMode::kNavigate && !idle) command = slowCommand(s, command, result);
  const GuardOutput g = guard(s, command, result);
  result.command_body = g.command_body;
  result.guard = g.action;

  // The way back is the way the robot came while navigating: a dock or a retreat is no way back.
  if (mode != RobotMode::kDocking && mode != RobotMode::kHolding && mode != RobotMode::kRetreating)
    trail_.add(s.robot.pose.position());
  return result;
}

std::vector<RoomMove> BandCycle::roomPlans(const BandCycleInput& s, const PlanResult& r,
                                           const DistanceMap& obstacles) const {
  std::vector<RoomMove> plans;
  const ModeMachineOptions& mo = modes_.options();
  for (const auto& o : r.others) {
    RoomMove plan = RoomMove::kUnknown;
    const AgentState* h = human(s, o.id);
    if (h) {
      Encounter e;
      e.robot = s.robot.pose;
      e.robot_radius_m = s.robot.radius_m;
      e.human_position = h->pose.position();
      e.human_velocity = {h->velocity.vx_m_s, h->velocity.vy_m_s};
      e.human_radius_m = h->radius_m;
      e.trail = &trail_.points();
      e.limits = limits_;
      // Only a human ahead and closing may need room: a few distance queries each.
      // Ahead: in front of the robot as it heads, and not yet past it (one overtaking the robot
      // from behind needs no room made).
      const bool ahead =
          (h->pose.position() - s.robot.pose.position())
                  .dot(headingVector(s.robot.pose.theta_rad)) > 0.0 &&
          !DockModeMachine::humanHasPassed(s.robot.pose, motionPose(*h), mo.human_passed_margin_m);
      if (ahead && closingSpeed(e) > mo.room.closing_speed_m_s)
        plan = decideRoom(obstacles, e, mo.dock, mo.room).move;
    }
    plans.push_back(plan);
  }
  return plans;
}

Velocity2 BandCycle::modeCommand(const BandCycleInput& s, const ModeOutput& m, const PlanResult& r,
                                 bool hold, bool idle) const {
  if (idle) return {};
  if (hold) {
    if (!m.settle) return {};
    return settleOn(s.robot.pose, m.active_goal.position(),
                    modes_.options().dock_settle_tolerance_m, limits_);
  }
  // The robot drives a dock or a retreat itself: the planner's band keeps
  // planner.min_obstacle_dist_m from walls, so it would stop short of a flush dock pose.
  if (m.mode == RobotMode::kDocking && !m.route.empty())
    return followRoute(s.robot.pose, m.route, limits_.max_forward_m_s, limits_);
  if (m.mode == RobotMode::kRetreating) {
    if (!m.retreat_direction) return {};
    return driveAlong(s.robot.pose, *m.retreat_direction, modes_.options().room.wider_search_m,
                      limits_);
  }
  return r.status == PlanStatus::kOk ? r.command_body : Velocity2{};
}

// The person made room and waits; the robot's band still bends round them and the
// relative-velocity and safety terms hold it back (a mutual wait). Going first, the robot
// drives its own global path past them, shifted to the side away from them by what clears
// their body where the walls allow, at a modest speed; the guard scales or stops it near them as
// it does every command, so going first never drives into anyone.
Velocity2 BandCycle::goFirstCommand(const BandCycleInput& s, const PlanResult& r,
                                    const Velocity2& planned, BandCycleOutput& out) {
  const GoFirstOptions& gf = config_.go_first;
  const double stamp_s = seconds(s.utime);
  const AgentState* h = human(s, go_first_->human_id);
  const char* end = nullptr;
  if (h == nullptr) {
    end = "the person is not tracked";
  } else if (DockModeMachine::humanHasPassed(s.robot.pose, motionPose(*h),
                                             modes_.options().human_passed_margin_m)) {
    end = "the person is passed";
  } else if (stamp_s - go_first_->since_s > gf.max_s) {
    end = "go_first.max_s is over";
  } else if (r.status != PlanStatus::kOk || r.agent_path.size() < 2) {
    end = "no path to the goal";
  }
  if (end != nullptr) {
    note(out, BandCycleNote::Level::kInfo,
         format("going first for human %d ends at step %lld: %s", go_first_->human_id,
                static_cast<long long>(s.step), end));
    go_first_.reset();
    return planned;
  }
  if (std::hypot(planned.vx_m_s, planned.vy_m_s) >= gf.speed_m_s) return planned;
  const Eigen::Vector2d pos = s.robot.pose.position();
  const auto foot = projectOntoPath(r.agent_path, pos);
  const Path2 ahead = subPath(r.agent_path, foot ? foot->arc_length_m : 0.0, gf.lookahead_m);
  if (ahead.size() < 2 || (ahead.back() - ahead.front()).norm() < 1e-3) return planned;
  const Eigen::Vector2d dir = (ahead.back() - ahead.front()).normalized();
  const Eigen::Vector2d left(-dir.y(), dir.x());
  const Eigen::Vector2d person = h->pose.position();
  const double person_lat = left.dot(person - ahead.front());
  const double side = person_lat > 0.0 ? -1.0 : 1.0;  // away from the person
  // Lateral place of the robot's centre: beside the person by both radii and the clearance,
  // no nearer the wall on that side than its radius and the guard's clearance.
  const double wanted = side * person_lat + h->radius_m + s.robot.radius_m + gf.clearance_m;
  const double room = map_->ray(ahead.back(), side * left, 5.0).distance_m - s.robot.radius_m -
                      config_.guard.min_clearance_m;
  const double lateral = side * std::max(0.0, std::min(wanted, room));
  const Path2 route{pos, ahead.back() + lateral * left};
  return followRoute(s.robot.pose, route, gf.speed_m_s, limits_);
}

// Not in the paper (issue 44): the planner's band behind a slower person walking the robot's way
// neither follows at a distance nor passes; it keeps a step behind and beside them at their pace
// (its relative-velocity and safety terms), or stops short of them in a narrow corridor.
Velocity2 BandCycle::overtakeCommand(const BandCycleInput& s, const Pose2& goal,
                                     const PlanResult& r, const Velocity2& planned,
                                     BandCycleOutput& out) {
  const OvertakeOptions& o = config_.overtake;
  const double stamp_s = seconds(s.utime);
  // The robot's way: its global path's direction ahead (a holonomic robot's body heading need not
  // be it), else its heading.
  Pose2 frame = s.robot.pose;
  if (r.agent_path.size() >= 2) {
    const auto foot = projectOntoPath(r.agent_path, s.robot.pose.position());
    const Path2 ahead = subPath(r.agent_path, foot ? foot->arc_length_m : 0.0, o.lookahead_m);
    if (ahead.size() >= 2 && (ahead.back() - ahead.front()).norm() > 1e-3) {
      const Eigen::Vector2d d = ahead.back() - ahead.front();
      frame.theta_rad = std::atan2(d.y(), d.x());
    }
  }
  const Eigen::Vector2d dir = headingVector(frame.theta_rad);
  // GO_FIRST for a person ahead walking the robot's way: the words to pass them were said.
  if (go_first_ && !passing_) {
    const AgentState* h = human(s, go_first_->human_id);
    const auto p =
        h ? sameWayPerson(frame, s.robot.radius_m, *h, o.same_way) : std::optional<SameWayPerson>();
    if (p) {
      const PassLane lane = passLane(*map_, frame, s.robot.radius_m, *p, o);
      passing_ = Passing{p->id, stamp_s, lane.fits ? lane.side : p->robot_side};
      note(out, BandCycleNote::Level::kInfo,
           format("passing human %d on their %s at step %lld%s", p->id,
                  passing_->side == Side::kLeft ? "left" : "right", static_cast<long long>(s.step),
                  lane.fits ? "" : " (no lane fits now)"));
    }
  }
  if (passing_) {
    const AgentState* h = human(s, passing_->human_id);
    const char* end = nullptr;
    if (h == nullptr) {
      end = "the person is not tracked";
    } else {
      const double along_m = (h->pose.position() - s.robot.pose.position()).dot(dir);
      if (-along_m > h->radius_m + s.robot.radius_m + o.passed_margin_m)
        end = "the person is passed";
      // The last stretch to the goal is the planner's, which stops on it.
      if ((goal.position() - s.robot.pose.position()).dot(dir) < o.lookahead_m)
        end = "the goal is near";
      if (stamp_s - passing_->since_s > o.max_pass_s) end = "overtake.max_pass_s is over";
    }
    if (end != nullptr) {
      note(out, BandCycleNote::Level::kInfo,
           format("passing human %d ends at step %lld: %s", passing_->human_id,
                  static_cast<long long>(s.step), end));
      passing_.reset();
      go_first_.reset();
      return planned;
    }
    // In the frame of the way, without the "ahead" test: beside the person the robot is still
    // passing them.
    SameWayPerson p;
    p.id = h->id;
    p.radius_m = h->radius_m;
    const Eigen::Vector2d d = h->pose.position() - s.robot.pose.position();
    p.along_m = d.dot(dir);
    p.lateral_m = d.dot(Eigen::Vector2d(-dir.y(), dir.x()));
    const PassLane lane = laneOnSide(*map_, frame, s.robot.radius_m, p, passing_->side, o);
    return passCommand(s.robot.pose, frame, lane, o, limits_);
  }
  auto p = sameWayAhead(frame, s.robot.radius_m, s.humans, o.same_way);
  // Nearer its goal than where it would reach them, the person is not in the robot's way.
  const double goal_along_m = (goal.position() - s.robot.pose.position()).dot(dir);
  if (p && p->along_m - p->radius_m - s.robot.radius_m > goal_along_m) p.reset();
  const std::optional<std::int32_t> id = p ? std::optional<std::int32_t>(p->id) : std::nullopt;
  if (id != following_id_) {
    note(out, BandCycleNote::Level::kInfo,
         id ? format("following human %d (ahead, walking the robot's way) from step %lld", *id,
                     static_cast<long long>(s.step))
            : format("following human %d ends at step %lld", *following_id_,
                     static_cast<long long>(s.step)));
    following_id_ = id;
  }
  if (!p) return planned;
  const double follow_m_s = followSpeed(*p, o, limits_.max_forward_m_s);
  // The gap does not bind yet: the planner drives on.
  if (follow_m_s >= limits_.max_forward_m_s) return planned;
  // Someone else near (an oncoming person): the planner's band keeps its steering round them;
  // only its pace is held to the person followed.
  for (const auto& h : s.humans) {
    if (h.id == p->id) continue;
    const double gap =
        (h.pose.position() - s.robot.pose.position()).norm() - h.radius_m - s.robot.radius_m;
    if (gap < o.same_way.ahead_range_m) {
      Velocity2 v = planned;
      if (v.vx_m_s > follow_m_s) v.vx_m_s = follow_m_s;
      return v;
    }
  }
  const PassLane lane = passLane(*map_, frame, s.robot.radius_m, *p, o);
  return followCommand(s.robot.pose, frame, *p, lane, o, limits_);
}

// The dialogue waits for the person's cooperation to show (make_time): the robot drives on along
// its plan, slower, so that the crossing comes later and a late dock stays possible. The cap
// scales the whole command (its direction and curvature kept); the guard then applies as always.
Velocity2 BandCycle::slowCommand(const BandCycleInput& s, const Velocity2& command,
                                 BandCycleOutput& out) {
  const AgentState* h = human(s, slow_->human_id);
  const char* end = nullptr;
  if (h == nullptr)
    end = "the person is not tracked";
  else if (DockModeMachine::humanHasPassed(s.robot.pose, motionPose(*h),
                                           modes_.options().human_passed_margin_m))
    end = "the person is passed";
  else if (seconds(s.utime) - slow_->since_s > config_.slow.max_s)
    end = "slow.max_s is over";
  if (end != nullptr) {
    note(out, BandCycleNote::Level::kInfo,
         format("slowing for human %d ends at step %lld: %s", slow_->human_id,
                static_cast<long long>(s.step), end));
    slow_.reset();
    return command;
  }
  const double speed_m_s = std::hypot(command.vx_m_s, command.vy_m_s);
  if (speed_m_s <= config_.slow.speed_m_s) return command;
  const double k = config_.slow.speed_m_s / speed_m_s;
  return {command.vx_m_s * k, command.vy_m_s * k, command.omega_rad_s * k};
}

GuardOutput BandCycle::guard(const BandCycleInput& s, const Velocity2& command,
                             BandCycleOutput& out) {
  GuardInput in;
  in.robot = s.robot.pose;
  in.robot_radius_m = s.robot.radius_m;
  in.command_body = command;
  in.limits = limits_;
  for (const auto& h : s.humans)
    in.humans.push_back({h.pose.position(), {h.velocity.vx_m_s, h.velocity.vy_m_s}, h.radius_m});
  in.obstacle_points = s.guard_points;
  const GuardOutput g = guardCommand(*map_, in, config_.guard);
  if (g.action != last_guard_) {
    note(out, BandCycleNote::Level::kInfo,
         format("guard %s at step %lld (utime %lld, command x %.2f)", toString(g.action),
                static_cast<long long>(s.step), static_cast<long long>(s.utime), g.scale));
    last_guard_ = g.action;
  }
  return g;
}

void BandCycle::referencePaths(const BandCycleInput& s, const PlanResult& r,
                               const std::set<std::int32_t>& with_goal, BandCycleOutput& out) {
  bool changed = false;
  // Forget humans who left, or whose goal became unknown (their path is no longer a reference).
  for (auto it = refs_.begin(); it != refs_.end();) {
    if (!with_goal.count(it->first)) {
      it = refs_.erase(it);
      changed = true;
    } else {
      ++it;
    }
  }
  for (const auto& o : r.others) {
    if (!with_goal.count(o.id) || o.reference_path.size() < 2) continue;
    auto it = refs_.find(o.id);
    if (it == refs_.end()) {
      refs_[o.id] = {o.reference_path, 1};
      changed = true;
    } else if (it->second.path != o.reference_path) {
      it->second.path = o.reference_path;
      ++it->second.revision;
      changed = true;
    }
  }
  const bool due = config_.reference_paths_republish_s > 0.0 && last_refs_utime_ &&
                   diffSeconds(s.utime, *last_refs_utime_) >= config_.reference_paths_republish_s;
  if (!changed && !due) return;
  std::vector<CycleReferencePath> paths;
  for (const auto& [id, ref] : refs_) paths.push_back({id, ref.revision, ref.path});
  out.reference_paths = std::move(paths);
  last_refs_utime_ = s.utime;
}

std::map<std::int32_t, Pose2> BandCycle::inferGoals(const BandCycleInput& s,
                                                    const std::map<std::int32_t, Pose2>& given,
                                                    BandCycleOutput& result) {
  std::map<std::int32_t, Pose2> planned;
  if (!goal_distances_) return planned;
  const double stamp_s = seconds(s.utime);
  CycleGoalEstimates out;
  for (const auto& g : goal_distances_->goals()) out.goals.push_back(g.centre());
  for (const auto& h : s.humans) {
    if (given.count(h.id)) continue;
    auto it = goal_beliefs_.find(h.id);
    if (it == goal_beliefs_.end())
      it = goal_beliefs_.emplace(h.id, GoalBelief(goal_distances_)).first;
    goal_belief_recency_.touch(h.id, s.utime);
    GoalBelief& b = it->second;
    b.observe(stamp_s, h.pose.position());
    const auto planned_now = inferred_goal_.find(h.id);
    const int best =
        b.plannedGoal(planned_now == inferred_goal_.end() ? -1 : planned_now->second.index,
                      config_.goal_switch_margin_m);
    CycleGoalEstimates::Human e;
    e.agent_id = h.id;
    e.most_likely = best;
    e.walked_m = b.walkedLength_m();
    e.observations = static_cast<std::int32_t>(
        std::min<std::size_t>(b.observations(), std::numeric_limits<std::int32_t>::max()));
    e.probability = b.probabilities();
    out.humans.push_back(std::move(e));
    if (best < 0 || b.walkedLength_m() < config_.goal_min_walked_m) continue;
    // Where the human crosses the region is fixed when the region is chosen: re-projecting
    // every cycle would move the goal with the human's own avoidance, and the reference path
    // (the path it would have taken) with it.
    auto was = inferred_goal_.find(h.id);
    if (was == inferred_goal_.end() || was->second.index != best) {
      const GoalRegion& region = goal_distances_->goals()[static_cast<std::size_t>(best)];
      const Eigen::Vector2d target = region.target(h.pose.position(), config_.goal_agent_radius_m);
      note(result, BandCycleNote::Level::kInfo,
           format("human %d most likely walks to goal %d (centre %.2f, %.2f), p %.2f: planned to "
                  "(%.2f, %.2f)",
                  h.id, best, region.centre().x(), region.centre().y(),
                  b.probabilities()[static_cast<std::size_t>(best)], target.x(), target.y()));
      was = inferred_goal_.insert_or_assign(h.id, InferredGoal{best, target}).first;
    }
    const Eigen::Vector2d& g = was->second.target;
    planned[h.id] = {g.x(), g.y(), std::numeric_limits<double>::quiet_NaN()};
  }
  // A belief is of one track: an id gone for forget_after_s (or a flood of ids) loses it.
  goal_belief_recency_.forgetOld(s.utime, config_.forget_after_s, config_.max_ids,
                                 [this](std::int32_t id) {
                                   goal_beliefs_.erase(id);
                                   inferred_goal_.erase(id);
                                 });
  if (!out.humans.empty()) result.goal_estimates = std::move(out);
  return planned;
}

void BandCycle::boundPlannerMemory(const BandCycleInput& s, const PlanResult& r,
                                   BandCycleOutput& out) {
  planner_ids_.insert(s.robot.id);
  for (const auto& o : r.others) planner_ids_.insert(o.id);
  if (!planner_memory_check_utime_) planner_memory_check_utime_ = s.utime;
  // The planner can only forget every id at once, and that re-plans the reference paths of the
  // humans present from where they stand (a new d_h reference mid-interaction). So, at most once
  // per forget_after_s of message time, ids no longer present are forgotten at the first cycle
  // without a reference path to keep; more ids than max_ids (a flood of new ids) are forgotten
  // at once whatever that costs.
  std::size_t gone = 0;
  const bool over = planner_ids_.size() > config_.max_ids;
  if (!over) {
    if (!refs_.empty() ||
        diffSeconds(s.utime, *planner_memory_check_utime_) <= config_.forget_after_s)
      return;
    std::set<std::int32_t> here{s.robot.id};
    for (const auto& h : s.humans) here.insert(h.id);
    for (const auto id : planner_ids_) gone += here.count(id) ? 0 : 1;
    planner_memory_check_utime_ = s.utime;  // checked at most once per forget_after_s
    if (gone == 0) return;
  }
  note(out, BandCycleNote::Level::kInfo,
       "planner memory of " + std::to_string(planner_ids_.size()) + " agents cleared (" +
           (over ? std::string("more than limits.max_ids")
                 : std::to_string(gone) + " no longer present after limits.forget_after_s") +
           ")");
  planner_->reset();
  planner_ids_.clear();
  planner_memory_check_utime_ = s.utime;
}

}  // namespace coopnav
