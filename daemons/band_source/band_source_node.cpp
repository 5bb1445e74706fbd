#include "band_source_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "coopnav/bands_t.hpp"
#include "coopnav/geometry/geometry.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "maps/map_loader.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"
#include "wire/robot_kinematics.hpp"

namespace coopnav {
namespace {

/// Cycles between two planning-time log lines.
constexpr std::size_t kPlanStatsEvery = 100;
/// Cap of the whole-run planning-time record (the exit summary); ~1 h at 20 Hz.
constexpr std::size_t kPlanStatsKeep = 100000;
/// Free-running: a message this fraction of a period early still starts a cycle, so that a
/// publisher at exactly control_hz with a little jitter is not halved.
constexpr double kThrottleSlack = 0.05;
/// Below this speed a human's heading is its pose's, not its direction of motion [m/s].
constexpr double kWalkingSpeed_m_s = 0.1;

std::int8_t bandsStatus(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk:
      return bands_t::STATUS_OK;
    case PlanStatus::kGoalReached:
      return bands_t::STATUS_GOAL_REACHED;
    case PlanStatus::kNoPath:
    case PlanStatus::kGoalInObstacle:
      return bands_t::STATUS_NO_PATH;
    case PlanStatus::kInvalidConfig:
      return bands_t::STATUS_SOLVER_FAILED;
    case PlanStatus::kInvalidInput:
    case PlanStatus::kOutsideMap:
    case PlanStatus::kStartInObstacle:
      return bands_t::STATUS_INVALID_INPUT;
  }
  return bands_t::STATUS_SOLVER_FAILED;
}

std::int8_t commandMode(RobotMode m) {
  switch (m) {
    case RobotMode::kNavigate:
      return velocity_command_t::MODE_NAVIGATING;
    case RobotMode::kDocking:
      return velocity_command_t::MODE_DOCKING;
    case RobotMode::kHolding:
      return velocity_command_t::MODE_HOLDING;
    case RobotMode::kResuming:
      return velocity_command_t::MODE_RESUMING;
    case RobotMode::kGoalReached:
      return velocity_command_t::MODE_GOAL_REACHED;
    case RobotMode::kRetreating:
      return velocity_command_t::MODE_RETREATING;
  }
  return velocity_command_t::MODE_STOPPED;
}

/// Position and heading of motion (the mode machine judges "passed" along where the human goes).
Pose2 motionPose(const AgentState& h) {
  Pose2 p = h.pose;
  const double vx = h.velocity.vx_m_s, vy = h.velocity.vy_m_s;
  if (std::hypot(vx, vy) > kWalkingSpeed_m_s) p.theta_rad = std::atan2(vy, vx);
  return p;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = static_cast<std::size_t>(std::llround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

std::string idList(const std::set<std::int32_t>& ids) {
  std::string s;
  for (const auto id : ids) s += (s.empty() ? "" : ",") + std::to_string(id);
  return s;
}

}  // namespace

void BandSourceConfig::resolvePaths(const std::string& base_dir) { map.resolvePaths(base_dir); }

BandSourceNode::BandSourceNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      scans_(config.scan),
      clock_(runtime.limits().max_time_jump_s, runtime.limits().time_resync_messages),
      goals_clock_(runtime.limits().max_time_jump_s, runtime.limits().time_resync_messages) {
  LoadedField loaded = loadDistanceField(config_.map, /*build_tree=*/false);
  map_ = loaded.field;
  const BandPlannerConfig& pc = config_.planner.config;
  planner_ = std::make_unique<DualBandPlanner>(pc, map_);
  if (!planner_->configErrors().empty()) {
    const auto& e = planner_->configErrors().front();
    throw ConfigError("planner." + e.key + " = " + std::to_string(e.value) +
                      " is outside the allowed range " + e.allowed);
  }
  ModeMachineOptions mo = config_.dock.options;
  mo.goal_tolerance_m = pc.xy_goal_tolerance_m;
  mo.dock.robot_radius_m = pc.robot.radius_m;
  modes_ = DockModeMachine(mo);
  limits_.holonomic = pc.robot.holonomic;
  limits_.max_forward_m_s = pc.robot.max_vel_x_m_s;
  limits_.max_backward_m_s = pc.robot.max_vel_x_backwards_m_s;
  limits_.max_lateral_m_s = pc.robot.max_vel_y_m_s;
  limits_.max_omega_rad_s = pc.robot.max_vel_theta_rad_s;

  StepNodeOptions steps;
  // Step k plans with every robot action of k-1 and the goals of k (a lost one is re-sent when
  // the world publishes the step again; docs/lockstep.md "Loss and restarts").
  // The scan of step k too, when the world's ack of k counts one (scan_obstacles.hpp).
  steps.requirements = {{kDialogueParticipant, -1, {channels::kRobotAction}},
                        {"world_sim", 0, {channels::kScan}, true}};
  steps.timeout = std::chrono::milliseconds(
      static_cast<std::int64_t>(std::llround(config_.step_gate_timeout_s * 1e3)));
  steps_ = std::make_unique<StepNode>(runtime_, steps);
  steps_->setCondition([this](std::int64_t step) -> std::string {
    const auto it = step_utime_.find(step);
    if (it == step_utime_.end() || steps_->lastAck("world_sim") < step) return "";
    return goal_utimes_.count(it->second) ? "" : "goals of step " + std::to_string(step);
  });
  runtime_.setLostStateNote(
      "its dock mode, reference-path revisions and planner memory (bands and reference paths "
      "restart from the current poses)");

  if (config_.goal_inference.enabled) {
    const GoalInferenceYaml& gi = config_.goal_inference;
    std::vector<GoalRegion> goals;
    if (gi.map_candidates) goals = mapGoalCandidates(*map_, gi.candidate_options);
    const std::size_t from_shape = goals.size();
    for (const auto& r : loaded.map.goal_regions) goals.push_back({r.a, r.b});
    for (const auto& c : gi.candidates) goals.push_back(GoalRegion::point({c.x_m, c.y_m}));
    if (goals.empty()) {
      log().warn(
          "band_source: goal_inference: no candidate goal (none from the map, none configured): "
          "humans without a given goal get constant-velocity bands");
    } else {
      goal_distances_ = std::make_shared<const GoalDistances>(map_, goals, gi.options);
      log().info(
          "band_source: goal inference over {} candidate goals ({} from the map's shape, {} "
          "annotated on it, {} configured)",
          goals.size(), from_shape, loaded.map.goal_regions.size(), gi.candidates.size());
    }
  }

  const auto& g = map_->grid();
  detail_ = "map " + config_.map.map_file + " " + std::to_string(g.width()) + "x" +
            std::to_string(g.height()) + " @ " + std::to_string(g.resolution_m()) + " m; " +
            robotKinematicsDetail(pc.robot.holonomic);
  log().info("band_source: {}; {} LM iterations per cycle, free-running at most {} Hz", detail_,
             config_.max_iterations > 0 ? config_.max_iterations
                                        : pc.no_inner_iterations * pc.no_outer_iterations,
             config_.control_hz);
  runtime_.setRunning(detail_);

  // Queue capacity 0 (unlimited): in lockstep every step must be answered, in order.
  runtime_.subscribe<agent_states_t>(
      channels::kAgentStates, [this](const agent_states_t& m, std::int64_t) { onAgentStates(m); },
      0);
  runtime_.subscribe<goals_t>(
      channels::kGoals, [this](const goals_t& m, std::int64_t) { onGoals(m); }, 0);
  runtime_.subscribe<robot_action_t>(
      channels::kRobotAction, [this](const robot_action_t& m, std::int64_t) { onRobotAction(m); },
      0);
  runtime_.subscribe<laser_scan_t>(
      channels::kScan, [this](const laser_scan_t& m, std::int64_t) { onScan(m); }, 0);
  // Free-running cycles run from the loop, after it has drained what is queued.
  runtime_.addTimer(std::chrono::milliseconds(5), [this] { planLatestFreeRunning(); });
}

BandSourceNode::~BandSourceNode() {
  if (all_plan_ms_.empty()) return;
  log().info(
      "band_source: {} planning cycles, planning time p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms",
      cycles_, percentile(all_plan_ms_, 0.5), percentile(all_plan_ms_, 0.99),
      *std::max_element(all_plan_ms_.begin(), all_plan_ms_.end()));
}

const std::string& BandSourceNode::pendingActionReason() const {
  static const std::string kNone;
  return action_ ? action_->reason : kNone;
}

void BandSourceNode::onAgentStates(const agent_states_t& msg) {
  steps_->open("world_sim", channels::kAgentStates, msg, [&]() -> StepNode::Work {
    AgentStatesSnapshot s = fromLcm(msg);  // throws RejectedMessage
    for (const auto& h : s.humans)
      if (h.id == s.robot.id)
        throw RejectedMessage("human id " + std::to_string(h.id) + " is the robot's id");
    if (!clock_.take(s.utime, "agent states", [&] { onResync(s.utime); }))
      throw DroppedMessage("agent states utime " + std::to_string(s.utime) + " before " +
                           std::to_string(*clock_.now()));
    leaveOutFarHumans(s);
    if (s.step >= 0) {
      // Only the steps that will be planned (cycle() erases them); the harness holds at most
      // max_pending_steps, and so does this map.
      step_utime_[s.step] = s.utime;
      while (step_utime_.size() > static_cast<std::size_t>(runtime_.limits().max_pending_steps))
        step_utime_.erase(step_utime_.begin());
    }
    runtime_.noteLogicTime(s.utime);
    if (s.step < 0) {
      // Free-running: at most control_hz by message time; the skipped ones are normal, not drops.
      const double period_us = 1e6 / config_.control_hz;
      if (last_cycle_utime_ &&
          utimeDiffSeconds(s.utime, *last_cycle_utime_) * 1e6 < period_us * (1.0 - kThrottleSlack))
        return nullptr;
      last_cycle_utime_ = s.utime;
      // A state stream: when inputs come faster than cycles run, only the newest is planned (the
      // loop drains what is queued before it runs its timers), so the daemon never falls further
      // and further behind with its queue growing. The superseded ones count as dropped.
      if (free_running_next_) runtime_.countDropped();
      free_running_next_ = s;
      return nullptr;
    }
    return [this, s](StepNode::Step& step) { cycle(s, step); };
  });
}

void BandSourceNode::onResync(std::int64_t utime) {
  log().warn(
      "band_source: agent states go on from utime {}: a new time base (throttle, "
      "republication and planner-memory times restart from it; goal beliefs restart)",
      utime);
  last_cycle_utime_.reset();
  if (last_refs_utime_) last_refs_utime_ = utime;
  if (planner_memory_check_utime_) planner_memory_check_utime_ = utime;
  // A goal belief is a track in the old time base: later observations would be refused as older.
  goal_beliefs_.clear();
  goal_belief_recency_.clear();
  inferred_goal_.clear();
  // The dock's hold timeout (dock.hold_timeout_s) is counted by the mode machine in message
  // time: after a resync backwards a hold ends when the human passes or a RESUME comes.
}

void BandSourceNode::leaveOutFarHumans(AgentStatesSnapshot& s) const {
  // A tracker glitch can put a human anywhere (10^300 m away): the planner would resample a
  // path of that length and never finish. Humans farther from the map than its own size are
  // left out of planning (no band, no reference path), with a log line.
  const auto& g = map_->grid();
  const Eigen::Vector2d size_m(g.width() * g.resolution_m(), g.height() * g.resolution_m());
  const Eigen::AlignedBox2d reach(g.origin_m() - size_m, g.origin_m() + 2.0 * size_m);
  const auto far = std::remove_if(s.humans.begin(), s.humans.end(), [&](const AgentState& h) {
    return !reach.contains(h.pose.position());
  });
  for (auto it = far; it != s.humans.end(); ++it)
    log().warn("band_source: human {} at ({:g}, {:g}) is far off the map: left out of planning",
               it->id, it->pose.x_m, it->pose.y_m);
  s.humans.erase(far, s.humans.end());
}

void BandSourceNode::planLatestFreeRunning() {
  if (!free_running_next_) return;
  const AgentStatesSnapshot s = std::move(*free_running_next_);
  free_running_next_.reset();
  steps_->schedule(s.step, s.utime, [this, s](StepNode::Step& step) { cycle(s, step); });
}

void BandSourceNode::onGoals(const goals_t& msg) {
  GoalsSnapshot g = fromLcm(msg);  // throws RejectedMessage
  // A repeat of an older step's goals never replaces newer ones.
  if (!goals_clock_.take(msg.utime, "goals")) return;
  goals_ = std::move(g);  // full state: replaces the previous goals
  goal_utimes_.insert(msg.utime);
  while (goal_utimes_.size() > 64) goal_utimes_.erase(goal_utimes_.begin());
  steps_->poke();
}

void BandSourceNode::onRobotAction(const robot_action_t& msg) {
  RobotActionMsg a = fromLcm(msg);  // throws RejectedMessage (unknown action, bad step)
  // Kept (and logged) no longer than limits.max_text_bytes: 3000 actions with a 60 kB reason
  // must not become 180 MB of memory or log.
  a.reason = keptText(std::move(a.reason), runtime_.limits().maxTextBytes());
  // A repeat (the dialogue manager answered a re-published step again) is applied once.
  steps_->input(kDialogueParticipant, channels::kRobotAction, msg.step,
                std::to_string(msg.action) + "/" + std::to_string(msg.human_id), [&] {
                  log().info("band_source: robot action {} for human {} at step {} ({})",
                             a.action == dialogue::RobotAction::kDock ? "DOCK" : "RESUME",
                             a.stamp.human_id, a.stamp.step, a.reason);
                  action_ = std::move(a);
                });
}

void BandSourceNode::onScan(const laser_scan_t& msg) {
  const LaserScanRecord r = fromLcm(msg);  // throws RejectedMessage
  steps_->input("world_sim", channels::kScan, msg.step, "scan",
                [&] { scans_.store(r, runtime_.limits().max_pending_steps); });
}

void BandSourceNode::cycle(const AgentStatesSnapshot& s, StepNode::Step& step) {
  scan_points_ = scans_.take(s, *map_);
  try {
    plan(s, step);
  } catch (const std::exception& e) {
    // A bug or an unforeseen input: never take the daemon down, never leave a step unanswered.
    runtime_.countRejected();
    log().error("band_source: step {} (utime {}) failed: {}", s.step, s.utime, e.what());
  }
  if (step.degraded()) {
    runtime_.setDegraded("step " + std::to_string(s.step) + " planned without " + step.missing());
  } else {
    runtime_.setRunning(detail_);
  }
  step.finish();
  step_utime_.erase(s.step);
}

void BandSourceNode::plan(const AgentStatesSnapshot& s, StepNode::Step& step) {
  const double stamp_s = utimeToSeconds(s.utime);

  // --- goals: the robot's (kind ROBOT; its own id preferred) and the humans' ---
  std::optional<Pose2> robot_goal;
  std::map<std::int32_t, Pose2> human_goals;
  if (goals_) {
    for (const auto& g : goals_->goals) {
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
  if (action_) {
    dock_req = action_->action == dialogue::RobotAction::kDock;
    resume_req = action_->action == dialogue::RobotAction::kResume;
    if (dock_req) dock_for = action_->stamp.human_id;
  }
  action_.reset();

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
    const AgentState* human = hid ? s.human(*hid) : nullptr;
    if (human) {
      in.has_human = true;
      in.human = motionPose(*human);
      in.human_velocity = {human->velocity.vx_m_s, human->velocity.vy_m_s};
      in.human_radius_m = human->radius_m;
    } else if (dock_req) {
      log().warn("band_source: DOCK for human {} who is not in the agent states: ignored",
                 dock_for);
    }
    mode_out = modes_.update(*map_, in);
    const ModeOutput& out = mode_out;
    if (out.dock_failure) {
      log().warn("band_source: DOCK for human {} at step {}: {}: the robot keeps avoiding",
                 dock_for, s.step,
                 *out.dock_failure == DockStatus::kNoWall
                     ? "no wall on the side away from the human and room to pass"
                     : "no reachable dock pose");
    }
    if (out.mode == RobotMode::kDocking || out.mode == RobotMode::kHolding ||
        out.mode == RobotMode::kRetreating) {
      if (dock_req && in.has_human) dock_human_id_ = dock_for;
    } else {
      dock_human_id_.reset();
    }
    if (out.changed) {
      log().info("band_source: mode {} at step {} (utime {}){}", toString(out.mode), s.step,
                 s.utime,
                 out.room != RoomMove::kUnknown
                     ? std::string(" for human ") +
                           std::to_string(dock_human_id_ ? *dock_human_id_ : dock_for) +
                           ", room: " + toString(out.room)
                     : std::string());
    }
    mode = out.mode;
    active_goal = out.active_goal;
    hold = out.hold_still;
  } else if (dock_req || resume_req) {
    log().warn("band_source: robot action ignored: the robot has no goal");
  }

  // --- plan ---
  PlanRequest req;
  req.stamp_s = stamp_s;
  req.agent = s.robot;
  req.goal = active_goal;
  req.obstacle_points = scan_points_.planner;
  req.max_iterations = config_.max_iterations;
  req.time_budget_s = s.step < 0 ? config_.free_running_time_budget_s : 0.0;
  // Wall clock for the free-running time budget and the reported solve time only; the plan
  // itself depends on message time alone (lockstep passes no budget).
  req.clock_s = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  // Humans the goals message gives no goal: the most likely inferred one (same step order as
  // the reference paths: published first).
  for (const auto& [id, goal] : inferGoals(s, human_goals, step)) human_goals.emplace(id, goal);
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
      log().info(
          "band_source: humans without a goal (constant-velocity band, no reference path): {}",
          idList(without_goal));
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const PlanResult r = planner_->plan(req);
  const double plan_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  notePlanTime(plan_ms);
  ++cycles_;
  const std::set<std::int32_t> unplanned(r.unplanned_ids.begin(), r.unplanned_ids.end());
  if (unplanned != humans_unplanned_) {
    humans_unplanned_ = unplanned;
    if (!unplanned.empty()) {
      log().info(
          "band_source: more than {} humans: a predicted band (not planned jointly) this cycle "
          "for {}",
          config_.planner.config.max_planned_others, idList(unplanned));
    }
  }
  if (r.status != PlanStatus::kOk && r.status != PlanStatus::kGoalReached) {
    log().warn("band_source: step {} (utime {}): planner {}", s.step, s.utime, toString(r.status));
  }
  log().debug("band_source: step {} {} mode {} {} iterations, cost {:.3g}, {:.2f} ms", s.step,
              toString(r.status), toString(mode), r.iterations, r.final_cost, plan_ms);

  // --- outputs, in the lockstep order: reference paths, bands, command ---
  publishReferencePaths(s, r, with_goal, step);
  boundPlannerMemory(s, r);

  const bool idle = !robot_goal;
  const bool usable = r.status == PlanStatus::kOk || r.status == PlanStatus::kGoalReached;
  std::int8_t cmd_mode = velocity_command_t::MODE_IDLE;
  // A dock or a retreat is driven without the planner's band (modeCommand).
  const bool driven = mode == RobotMode::kDocking || mode == RobotMode::kRetreating;
  if (!idle) cmd_mode = usable || driven ? commandMode(mode) : velocity_command_t::MODE_STOPPED;

  BandsSnapshot b;
  b.utime = s.utime;
  b.step = s.step;
  b.status = bandsStatus(r.status);
  b.robot_mode = cmd_mode;
  b.iterations = r.iterations;
  b.final_cost = r.final_cost;
  b.solve_time_ms = r.solver_time_s * 1e3;
  b.robot_id = s.robot.id;
  b.robot = r.agent_band;
  for (const auto& o : r.others) b.humans.emplace_back(o.id, o.band);
  b.room_plans = roomPlans(s, r);
  step.publish(channels::kBands, toLcm(b));

  VelocityCommand c;
  c.utime = s.utime;
  c.step = s.step;
  c.mode = cmd_mode;
  const GuardOutput g = guard(s, modeCommand(s, mode_out, r, hold, idle));
  c.body = g.command_body;
  c.guard = static_cast<std::int8_t>(g.action);
  step.publish(channels::kRobotCmd, toLcm(c));

  // The way back is the way the robot came while navigating: a dock or a retreat is no way back.
  if (mode != RobotMode::kDocking && mode != RobotMode::kHolding && mode != RobotMode::kRetreating)
    trail_.add(s.robot.pose.position());
}

std::vector<std::int8_t> BandSourceNode::roomPlans(const AgentStatesSnapshot& s,
                                                   const PlanResult& r) {
  std::vector<std::int8_t> plans;
  const ModeMachineOptions& mo = modes_.options();
  for (const auto& o : r.others) {
    std::int8_t plan = bands_t::ROOM_UNKNOWN;
    const AgentState* h = s.human(o.id);
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
        plan = static_cast<std::int8_t>(decideRoom(*map_, e, mo.dock, mo.room).move);
    }
    plans.push_back(plan);
  }
  return plans;
}

Velocity2 BandSourceNode::modeCommand(const AgentStatesSnapshot& s, const ModeOutput& m,
                                      const PlanResult& r, bool hold, bool idle) const {
  if (idle || hold) return {};
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

GuardOutput BandSourceNode::guard(const AgentStatesSnapshot& s, const Velocity2& command) {
  GuardInput in;
  in.robot = s.robot.pose;
  in.robot_radius_m = s.robot.radius_m;
  in.command_body = command;
  in.limits = limits_;
  for (const auto& h : s.humans)
    in.humans.push_back({h.pose.position(), {h.velocity.vx_m_s, h.velocity.vy_m_s}, h.radius_m});
  in.obstacle_points = scan_points_.guard;
  const GuardOutput g = guardCommand(*map_, in, config_.guard.options);
  if (g.action != last_guard_) {
    log().info("band_source: guard {} at step {} (utime {}, command x {:.2f})", toString(g.action),
               s.step, s.utime, g.scale);
    last_guard_ = g.action;
  }
  return g;
}

void BandSourceNode::publishReferencePaths(const AgentStatesSnapshot& s, const PlanResult& r,
                                           const std::set<std::int32_t>& with_goal,
                                           StepNode::Step& step) {
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
  const bool due =
      config_.reference_paths_republish_s > 0.0 && last_refs_utime_ &&
      utimeDiffSeconds(s.utime, *last_refs_utime_) >= config_.reference_paths_republish_s;
  if (!changed && !due) return;
  ReferencePaths out;
  out.utime = s.utime;
  out.step = s.step;
  for (const auto& [id, ref] : refs_) {
    ReferencePaths::Entry e;
    e.agent_id = id;
    e.revision = ref.revision;
    e.path = ref.path;
    out.paths.push_back(std::move(e));
  }
  step.publish(channels::kReferencePaths, toLcm(out));
  last_refs_utime_ = s.utime;
}

std::map<std::int32_t, Pose2> BandSourceNode::inferGoals(const AgentStatesSnapshot& s,
                                                         const std::map<std::int32_t, Pose2>& given,
                                                         StepNode::Step& step) {
  std::map<std::int32_t, Pose2> planned;
  if (!goal_distances_) return planned;
  const double stamp_s = utimeToSeconds(s.utime);
  const InputLimits& limits = runtime_.limits();
  GoalEstimates out;
  out.utime = s.utime;
  out.step = s.step;
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
                      config_.goal_inference.switch_margin_m);
    GoalEstimates::Human e;
    e.agent_id = h.id;
    e.most_likely = best;
    e.walked_m = b.walkedLength_m();
    e.observations = static_cast<std::int32_t>(
        std::min<std::size_t>(b.observations(), std::numeric_limits<std::int32_t>::max()));
    e.probability = b.probabilities();
    out.humans.push_back(std::move(e));
    if (best < 0 || b.walkedLength_m() < config_.goal_inference.min_walked_m) continue;
    // Where the human crosses the region is fixed when the region is chosen: re-projecting
    // every cycle would move the goal with the human's own avoidance, and the reference path
    // (the path it would have taken) with it.
    auto was = inferred_goal_.find(h.id);
    if (was == inferred_goal_.end() || was->second.index != best) {
      const GoalRegion& region = goal_distances_->goals()[static_cast<std::size_t>(best)];
      const Eigen::Vector2d target =
          region.target(h.pose.position(), config_.goal_inference.options.agent_radius_m);
      log().info(
          "band_source: human {} most likely walks to goal {} (centre {:.2f}, {:.2f}), p {:.2f}: "
          "planned to ({:.2f}, {:.2f})",
          h.id, best, region.centre().x(), region.centre().y(),
          b.probabilities()[static_cast<std::size_t>(best)], target.x(), target.y());
      was = inferred_goal_.insert_or_assign(h.id, InferredGoal{best, target}).first;
    }
    const Eigen::Vector2d& g = was->second.target;
    planned[h.id] = {g.x(), g.y(), std::numeric_limits<double>::quiet_NaN()};
  }
  // A belief is of one track: an id gone for forget_after_s (or a flood of ids) loses it.
  goal_belief_recency_.forgetOld(s.utime, limits.forget_after_s,
                                 static_cast<std::size_t>(limits.max_ids), [this](std::int32_t id) {
                                   goal_beliefs_.erase(id);
                                   inferred_goal_.erase(id);
                                 });
  if (!out.humans.empty()) step.publish(channels::kGoalEstimates, toLcm(out));
  return planned;
}

void BandSourceNode::boundPlannerMemory(const AgentStatesSnapshot& s, const PlanResult& r) {
  planner_ids_.insert(s.robot.id);
  for (const auto& o : r.others) planner_ids_.insert(o.id);
  if (!planner_memory_check_utime_) planner_memory_check_utime_ = s.utime;
  const InputLimits& limits = runtime_.limits();
  // The planner can only forget every id at once, and that re-plans the reference paths of the
  // humans present from where they stand (a new d_h reference mid-interaction). So, at most once
  // per forget_after_s of message time, ids no longer present are forgotten at the first cycle
  // without a reference path to keep; more ids than max_ids (a flood of new ids) are forgotten
  // at once whatever that costs.
  std::size_t gone = 0;
  const bool over = planner_ids_.size() > static_cast<std::size_t>(limits.max_ids);
  if (!over) {
    if (!refs_.empty() ||
        utimeDiffSeconds(s.utime, *planner_memory_check_utime_) <= limits.forget_after_s)
      return;
    std::set<std::int32_t> here{s.robot.id};
    for (const auto& h : s.humans) here.insert(h.id);
    for (const auto id : planner_ids_) gone += here.count(id) ? 0 : 1;
    planner_memory_check_utime_ = s.utime;  // checked at most once per forget_after_s
    if (gone == 0) return;
  }
  log().info("band_source: planner memory of {} agents cleared ({})", planner_ids_.size(),
             over ? "more than limits.max_ids"
                  : std::to_string(gone) + " no longer present after limits.forget_after_s");
  planner_->reset();
  planner_ids_.clear();
  planner_memory_check_utime_ = s.utime;
}

void BandSourceNode::notePlanTime(double ms) {
  plan_ms_.push_back(ms);
  if (all_plan_ms_.size() < kPlanStatsKeep) all_plan_ms_.push_back(ms);
  if (plan_ms_.size() >= kPlanStatsEvery) {
    log().info(
        "band_source: planning time over {} cycles: p50 {:.2f} ms, p99 {:.2f} ms, max "
        "{:.2f} ms",
        plan_ms_.size(), percentile(plan_ms_, 0.5), percentile(plan_ms_, 0.99),
        *std::max_element(plan_ms_.begin(), plan_ms_.end()));
    plan_ms_.clear();
  }
}

}  // namespace coopnav
