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

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = static_cast<std::size_t>(std::llround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

spdlog::level::level_enum logLevel(BandCycleNote::Level l) {
  return l == BandCycleNote::Level::kWarn   ? spdlog::level::warn
         : l == BandCycleNote::Level::kInfo ? spdlog::level::info
                                            : spdlog::level::debug;
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
  if (const auto errors = pc.validate(); !errors.empty()) {
    const auto& e = errors.front();
    throw ConfigError("planner." + e.key + " = " + std::to_string(e.value) +
                      " is outside the allowed range " + e.allowed);
  }

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

  std::shared_ptr<const GoalDistances> goal_distances;
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
      goal_distances = std::make_shared<const GoalDistances>(map_, goals, gi.options);
      log().info(
          "band_source: goal inference over {} candidate goals ({} from the map's shape, {} "
          "annotated on it, {} configured)",
          goals.size(), from_shape, loaded.map.goal_regions.size(), gi.candidates.size());
    }
  }

  BandCycleConfig cc;
  cc.planner = pc;
  cc.modes = config_.dock.options;
  cc.guard = config_.guard.options;
  cc.go_first = config_.go_first;
  cc.overtake = config_.overtake;
  cc.slow = config_.slow;
  cc.max_iterations = config_.max_iterations;
  cc.free_running_time_budget_s = config_.free_running_time_budget_s;
  cc.reference_paths_republish_s = config_.reference_paths_republish_s;
  cc.goal_min_walked_m = config_.goal_inference.min_walked_m;
  cc.goal_switch_margin_m = config_.goal_inference.switch_margin_m;
  cc.goal_agent_radius_m = config_.goal_inference.options.agent_radius_m;
  cc.forget_after_s = runtime_.limits().forget_after_s;
  cc.max_ids = static_cast<std::size_t>(runtime_.limits().max_ids);
  // Wall clock for the free-running time budget and the reported solve and planning times only;
  // the plan itself depends on message time alone (lockstep passes no budget).
  cycle_ = std::make_unique<BandCycle>(cc, map_, std::move(goal_distances), [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  });

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
      cycle_->cycles(), percentile(all_plan_ms_, 0.5), percentile(all_plan_ms_, 0.99),
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
  cycle_->restamp(utime);
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
                             a.action == dialogue::RobotAction::kDock     ? "DOCK"
                             : a.action == dialogue::RobotAction::kResume ? "RESUME"
                             : a.action == dialogue::RobotAction::kSlow   ? "SLOW"
                                                                          : "GO_FIRST",
                             a.stamp.human_id, a.stamp.step, a.reason);
                  // One action per cycle (the latest): a SLOW or a RESUME for one human does not
                  // replace a DOCK or GO_FIRST for another decided at the same step.
                  const bool weak = a.action == dialogue::RobotAction::kSlow ||
                                    a.action == dialogue::RobotAction::kResume;
                  if (weak && action_ && action_->stamp.human_id != a.stamp.human_id &&
                      (action_->action == dialogue::RobotAction::kDock ||
                       action_->action == dialogue::RobotAction::kGoFirst))
                    return;
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
  BandCycleInput in;
  in.utime = s.utime;
  in.step = s.step;
  in.robot = s.robot;
  in.humans = s.humans;
  if (goals_) {
    in.goals.emplace();
    for (const auto& g : goals_->goals) in.goals->push_back({g.agent_id, g.kind, g.pose});
  }
  // The dialogue's actions since the last cycle: the latest one wins.
  if (action_)
    in.action =
        CycleAction{action_->action == dialogue::RobotAction::kDock, action_->stamp.human_id,
                    action_->action == dialogue::RobotAction::kGoFirst,
                    action_->action == dialogue::RobotAction::kSlow};
  action_.reset();
  in.planner_points = scan_points_.planner;
  in.guard_points = scan_points_.guard;

  const BandCycleOutput out = cycle_->step(in);
  notePlanTime(out.plan_ms);
  for (const auto& n : out.notes) log().log(logLevel(n.level), "band_source: {}", n.text);

  // --- outputs, in the lockstep order: goal estimates, reference paths, bands, command ---
  if (out.goal_estimates) {
    GoalEstimates e;
    e.utime = s.utime;
    e.step = s.step;
    e.goals = out.goal_estimates->goals;
    for (const auto& h : out.goal_estimates->humans)
      e.humans.push_back({h.agent_id, h.most_likely, h.walked_m, h.observations, h.probability});
    step.publish(channels::kGoalEstimates, toLcm(e));
  }
  if (out.reference_paths) {
    ReferencePaths r;
    r.utime = s.utime;
    r.step = s.step;
    for (const auto& p : *out.reference_paths) r.paths.push_back({p.agent_id, p.revision, p.path});
    step.publish(channels::kReferencePaths, toLcm(r));
  }
  const PlanResult& r = out.plan;
  const std::int8_t cmd_mode = out.idle      ? velocity_command_t::MODE_IDLE
                               : out.stopped ? velocity_command_t::MODE_STOPPED
                                             : commandMode(out.mode);
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
  for (const RoomMove m : out.room_plans) b.room_plans.push_back(static_cast<std::int8_t>(m));
  step.publish(channels::kBands, toLcm(b));

  VelocityCommand c;
  c.utime = s.utime;
  c.step = s.step;
  c.mode = cmd_mode;
  c.body = out.command_body;
  c.guard = static_cast<std::int8_t>(out.guard);
  step.publish(channels::kRobotCmd, toLcm(c));
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
