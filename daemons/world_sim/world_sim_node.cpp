#include "world_sim_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/geometry/geometry.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/sim/band_human_adapter.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "maps/map_loader.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"
#include "wire/dialogue.hpp"
#include "wire/robot_kinematics.hpp"

namespace coopnav {

namespace {

/// What the words of an utterance ask of the person (the side as the person sees it).
sim::Cue cueOf(const UtteranceMsg& u) {
  using dialogue::SpeechAct;
  sim::Cue c;
  const Side dir = u.utterance.direction;
  switch (u.utterance.act) {
    case SpeechAct::kInformDirection:
    case SpeechAct::kRepeatDirection:
      // The robot names the side it passes on: the person keeps to the other one.
      c.kind = sim::CueKind::kKeepSide;
      c.side = opposite(dir);
      c.repeat = u.utterance.act == SpeechAct::kRepeatDirection;
      break;
    case SpeechAct::kInformDockIfNeeded:
    case SpeechAct::kInformGoingFirst:
    case SpeechAct::kInformResuming:
      // "It is narrow here. I will wait at the side if needed.", "Thank you, I will go first.",
      // "I will go now.": keep clear, away from the robot.
      c.kind = sim::CueKind::kKeepSide;
      break;
    case SpeechAct::kAskToMove:
    case SpeechAct::kAskToMoveMore:
      c.kind = sim::CueKind::kMoveToSide;
      c.side = dir;
      c.repeat = u.utterance.act == SpeechAct::kAskToMoveMore;
      break;
    case SpeechAct::kThank:
      c.kind = sim::CueKind::kThank;
      break;
    case SpeechAct::kInformDocking:
    case SpeechAct::kInformWiderPlace:
    case SpeechAct::kInformRetreat:
    case SpeechAct::kInformStopping:
      c.kind = sim::CueKind::kRobotMakesRoom;
      break;
  }
  // Heard once the words have ended.
  c.t_s = utimeToSeconds(u.stamp.utime) + u.slot.start_s + u.slot.duration_s;
  return c;
}

/// Longest stretch of stepping in one loop iteration when running as fast as possible, so that
/// signals, status and incoming messages are still served.
constexpr auto kFastSlice = std::chrono::milliseconds(10);
/// Real time: most steps caught up in one iteration (a CPU that cannot keep up falls behind
/// gracefully instead of freezing the loop).
constexpr int kMaxCatchUpSteps = 100;

std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::int8_t toSimStatusState(sim::RunEnd e) {
  switch (e) {
    case sim::RunEnd::kGoalsReached:
      return sim_status_t::STATE_GOAL_REACHED;
    case sim::RunEnd::kCollision:
      return sim_status_t::STATE_COLLISION;
    case sim::RunEnd::kTimeLimit:
      return sim_status_t::STATE_TIME_LIMIT;
    case sim::RunEnd::kStandstill:
      return sim_status_t::STATE_STANDSTILL;
    case sim::RunEnd::kParticipantTimeout:
      return sim_status_t::STATE_PARTICIPANT_TIMEOUT;
    case sim::RunEnd::kError:
      break;
  }
  return sim_status_t::STATE_ERROR;
}

/// Two decimals, as a time or speed in a sentence.
std::string fixed2(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}

/// A command mode as the end of a run's sentence says it ("robot was navigating").
std::string commandModeText(std::int8_t mode) {
  if (mode == velocity_command_t::MODE_GOAL_REACHED) return "at its goal";
  const std::string name = commandModeName(mode);
  return name == "unknown" ? "in an unknown mode" : name;
}

}  // namespace

sim::TrackerParams TrackerOverrides::apply(sim::TrackerParams p) const {
  auto set = [](auto& field, auto value) {
    if (static_cast<double>(value) != -1.0) field = value;
  };
  set(p.position_sigma_m, position_sigma_m);
  set(p.velocity_window_steps, velocity_window_steps);
  set(p.miss_probability, miss_probability);
  set(p.drop_after_s, drop_after_s);
  set(p.id_switches, id_switches);
  set(p.id_switch_window_s, id_switch_window_s);
  set(p.range_m, range_m);
  return p;
}

void WorldSimConfig::resolvePaths(const std::string& base_dir) {
  scenario = resolvePath(base_dir, scenario);
}

WorldSimNode::WorldSimNode(const Config& config, Runtime& runtime)
    : config_(config), runtime_(runtime), outputs_(runtime), run_({}, 0.0) {
  try {
    scenario_ = world_sim::loadScenario(config_.scenario);
    LoadedMap map = world_sim::loadScenarioMap(scenario_);
    // The world holds what the robot's map does not (the daemons load the `map:` section alone).
    world_sim::addUnmappedObstacles(scenario_.unmapped_obstacles, map.grid);
    // Unknown cells are walls for the simulator as for the distance server (open.pgm's pillar).
    field_ = std::make_shared<GridDistanceField>(std::move(map.grid), UnknownPolicy::kObstacle);
    world_sim::checkScenarioAgainstMap(scenario_, *field_);
    sim::WorldSpec spec = world_sim::toWorldSpec(scenario_);
    if (config_.avoidance_timing != "scenario")
      sim::parseAvoidanceTiming(config_.avoidance_timing, spec.avoidance_timing);
    spec.onset = config_.realistic_onset;
    sim_ = std::make_unique<sim::Simulation>(
        spec, field_.get(), sim::dualBandAdapterFactory(config_.human_planner.config, field_));
    std::vector<std::int32_t> ids;
    for (const auto& h : scenario_.humans) ids.push_back(h.id);
    // Its own random streams from the seed: the humans' draws are the same with it on or off.
    tracker_ = std::make_unique<sim::Tracker>(config_.tracker.apply(scenario_.tracker),
                                              scenario_.seed, ids, scenario_.time_limit_s);
    sensing_ = std::make_unique<world_sim::WorldSensing>(scenario_, config_.laser != "off");
    if (!config_.cue_outcomes_file.empty()) {
      cue_outcomes_.open(config_.cue_outcomes_file, std::ios::binary | std::ios::trunc);
      if (!cue_outcomes_)
        throw StartupError("cue_outcomes_file: cannot write " + config_.cue_outcomes_file);
    }
  } catch (const world_sim::ScenarioError& e) {
    throw StartupError(e.what());
  } catch (const MapLoadError& e) {
    throw StartupError(config_.scenario + ": map: " + e.what());
  } catch (const std::invalid_argument& e) {
    throw StartupError(config_.scenario + ": " + e.what());
  }
  lockstep_ = config_.mode == "scenario" ? scenario_.lockstep.enabled : config_.mode == "lockstep";
  run_ = sim::WorldRun(lockstep_ ? scenario_.lockstep.participants : std::vector<std::string>{},
                       scenario_.lockstep.step_timeout_s);
  real_time_factor_ =
      config_.real_time_factor > 0.0 ? config_.real_time_factor : scenario_.rates.real_time_factor;
  step_period_s_ = 1.0 / scenario_.rates.publish_hz;
  agents_ = sim_->agents();
  publish_human_goals_ = config_.publish_human_goals == "scenario"
                             ? scenario_.publish_human_goals
                             : config_.publish_human_goals == "true";

  runtime_.subscribe<daemon_status_t>(
      channels::kStatus, [this](const daemon_status_t& m, std::int64_t) { onStatus(m); });
  runtime_.subscribe<velocity_command_t>(
      channels::kRobotCmd, [this](const velocity_command_t& m, std::int64_t) { onCommand(m); });
  runtime_.subscribe<utterance_t>(channels::kUtterance,
                                  [this](const utterance_t& m, std::int64_t) { onUtterance(m); });
  runtime_.subscribe<bands_t>(channels::kBands,
                              [this](const bands_t& m, std::int64_t) { onBands(m); });

  const auto& participants = scenario_.lockstep.participants;
  if (lockstep_ && !participants.empty()) {
    StepGateOptions opts;
    for (const auto& p : participants) {
      // What the world itself applies at the step's end must all be here, not only the ack.
      std::vector<std::string> chans;
      if (p == "band_source") chans = {channels::kRobotCmd, channels::kBands};
      if (p == "dialogue_manager") chans = {channels::kUtterance};
      opts.requirements.push_back({p, 0, chans});
    }
    opts.timeout = std::chrono::milliseconds(
        static_cast<std::int64_t>(std::llround(scenario_.lockstep.step_timeout_s * 1000.0)));
    opts.wait_for_unseen = true;  // every participant is required from step 0
    gate_ = std::make_unique<StepGate>(runtime_, opts);
  }
  phase_since_ = std::chrono::steady_clock::now();
  runtime_.addTimer(std::chrono::milliseconds(20), [this] { checkReady(); });
  if (gate_ && config_.retransmit_period_s > 0.0)
    runtime_.addTimer(std::chrono::milliseconds(20), [this] { retransmitIfOverdue(); });
  if (!lockstep_) {
    runtime_.addTimer(std::chrono::milliseconds(1), [this] { tickRealTime(); });
  } else if (!gate_) {
    runtime_.addTimer(std::chrono::milliseconds(1), [this] { tickFast(); });
  }

  std::string who;
  for (const auto& p : participants) who += (who.empty() ? "" : ", ") + p;
  const std::string mode = lockstep_ ? "lockstep" : "real time x" + fmt(real_time_factor_);
  log().info("world_sim: scenario '{}' ({}), {} human(s), {}, participants: {}", scenario_.name,
             scenario_.source, scenario_.humans.size(), mode, who.empty() ? "none" : who);
  const sim::TrackerParams& tp = tracker_->params();
  if (tp.active())
    log().info(
        "world_sim: tracker model on: position sigma {} m, velocity over {} samples, miss "
        "probability {}, drop after {} s, {} id switch(es), range {} m",
        tp.position_sigma_m, tp.velocity_window_steps, tp.miss_probability, tp.drop_after_s,
        tp.id_switches, tp.range_m > 0.0 ? fmt(tp.range_m) : std::string("unlimited"));
  if (!publish_human_goals_) log().info("world_sim: the humans' goals are not published");
  const auto onsets = sim_->onsets();
  for (std::size_t i = 0; i < onsets.size(); ++i)
    if (onsets[i])
      log().info(
          "world_sim: human {} avoids from {} s before the closest approach (realistic "
          "timing)",
          scenario_.humans[i].id, fmt(*onsets[i]));
  runtime_.setRunning("scenario " + scenario_.name + ", " + mode +
                      (lockstep_ && gate_ ? ", waiting for " + who : ""));
}

// ---- inputs

void WorldSimNode::onStatus(const daemon_status_t& msg) {
  // The band source announces the kinematics it plans for: a scenario whose robot moves
  // otherwise is refused (wire/robot_kinematics.hpp), before the first step when the
  // announcement comes while waiting for the participants, which it does in lockstep.
  if (msg.name == "band_source" && !run_.ended()) {
    const std::optional<bool> planned = holonomicFromStatusDetail(msg.detail);
    const bool simulated = scenario_.robot.kinematics == sim::Kinematics::kHolonomic;
    if (planned && *planned != simulated) {
      const std::string why = robotKinematicsMismatch(simulated, *planned);
      log().error("world_sim: {}", why);
      finish(sim_status_t::STATE_ERROR, why);
      return;
    }
  }
  if (msg.name == runtime_.name()) return;
  if (run_.heard(msg.name)) checkReady();
}

template <class Store>
void WorldSimNode::accept(const char* participant, const char* channel, std::int64_t step,
                          const std::string& key, Store&& store) {
  if (gate_) {
    gate_->accept(participant, channel, step, key, std::forward<Store>(store));
  } else {
    store();
  }
}

void WorldSimNode::onCommand(const velocity_command_t& msg) {
  accept("band_source", channels::kRobotCmd, msg.step, "cmd", [&] {
    VelocityCommand c = fromLcm(msg);  // throws RejectedMessage on a non-finite command
    last_mode_ = c.mode;
    // A late repeat of an older step's command never replaces a newer one.
    if (!command_ || c.step < 0 || c.step >= command_->step) command_ = c;
  });
}

void WorldSimNode::onUtterance(const utterance_t& msg) {
  // A repeat (the step re-published) is heard once.
  accept("dialogue_manager", channels::kUtterance, msg.step,
         std::to_string(msg.human_id) + "/" + std::to_string(msg.speech_act) + "/" +
             std::to_string(msg.round),
         [&] { hear(msg); });
}

void WorldSimNode::hear(const utterance_t& msg) {
  const UtteranceMsg u = fromLcm(msg);  // throws RejectedMessage
  // Addressed by the id the tracker published the person under (its own after a switch).
  const std::optional<std::size_t> person = tracker_->personOf(msg.human_id);
  const sim::HumanSpec* human = person ? &scenario_.humans[*person] : nullptr;
  if (human == nullptr)
    throw DroppedMessage("utterance to human " + std::to_string(msg.human_id) +
                         ", who is not in the scenario");
  const bool ask = u.utterance.act == dialogue::SpeechAct::kAskToMove ||
                   u.utterance.act == dialogue::SpeechAct::kAskToMoveMore;
  if (ask && u.utterance.direction == Side::kUndefined)
    throw RejectedMessage("utterance asks human " + std::to_string(msg.human_id) +
                          " to move without a side");
  if (u.slot.delivery != dialogue::Delivery::kSaid) return;  // decided, not said: nobody hears it
  sim::Cue cue = cueOf(u);
  cue.human_id = human->id;
  std::vector<std::int32_t> group;
  for (const std::int32_t id : u.group)
    if (const std::optional<std::size_t> member = tracker_->personOf(id))
      group.push_back(scenario_.humans[*member].id);  // else: left the scene, nobody to hear it
  const double now_s = sim_->time_s();
  const InputLimits& limits = runtime_.limits();
  const std::string to = "utterance to human " + std::to_string(msg.human_id);
  switch (heard_.offer(cue, msg.step, group, now_s, limits.max_time_jump_s, limits.forget_after_s,
                       *sim_)) {
    case sim::HeardWords::Verdict::kEndsTooFarAhead:
      throw RejectedMessage(
          to + " ends at t " + fixed2(cue.t_s) + " s, more than limits.max_time_jump_s = " +
          fmt(limits.max_time_jump_s) + " s after the simulation's t " + fixed2(now_s) + " s");
    case sim::HeardWords::Verdict::kEndedTooLongAgo:
      throw DroppedMessage(to + " ended at t " + fixed2(cue.t_s) +
                           " s, more than limits.forget_after_s = " + fmt(limits.forget_after_s) +
                           " s before the simulation's t " + fixed2(now_s) +
                           " s: nobody acts on it any more");
    case sim::HeardWords::Verdict::kFull:
      throw DroppedMessage(to + ": " + std::to_string(heard_.maxUnendedPerHuman()) +
                           " utterances to that person have not ended yet");
    case sim::HeardWords::Verdict::kKept:
      break;
  }
  last_said_ = "\"" + keptText(msg.text, limits.maxTextBytes()) + "\" to human " +
               std::to_string(msg.human_id);
}

void WorldSimNode::onBands(const bands_t& msg) {
  accept("band_source", channels::kBands, msg.step, "bands", [&] { storeBands(msg); });
}

void WorldSimNode::storeBands(const bands_t& msg) {
  if (msg.step >= 0 && msg.step < band_step_) return;  // a late repeat of an older step
  BandsSnapshot b = fromLcm(msg);                      // throws RejectedMessage
  // A failed cycle tells nothing about where the robot goes: humans keep the last good band.
  if (b.status != bands_t::STATUS_OK || b.robot.poses.size() < 2) return;
  for (const auto& p : b.robot.poses)
    if (!std::isfinite(p.t_s) || !isFinite(p.pose))
      throw RejectedMessage("robot band with a non-finite pose");
  band_step_ = msg.step;
  band_ = std::move(b);
}

// ---- run

void WorldSimNode::checkReady() {
  if (run_.phase() != sim::WorldRun::Phase::kWaitingReady) return;
  if (run_.missing().empty()) {
    start();
    return;
  }
  announce();
  const double waited_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - phase_since_).count();
  if (waited_s > config_.wait_ready_timeout_s) {
    const sim::WorldRun::Finish f = run_.neverReady(config_.wait_ready_timeout_s);
    finish(toSimStatusState(f.end), f.detail);
  }
}

void WorldSimNode::start() {
  run_.start();
  phase_since_ = std::chrono::steady_clock::now();
  log().info("world_sim: running '{}'", scenario_.name);
  publishStep();
  if (gate_) submitCurrentStep();
}

void WorldSimNode::submitCurrentStep() {
  gate_->submit(step_, [this](bool degraded, const std::string& missing) {
    onStepAcknowledged(degraded, missing);
  });
}

void WorldSimNode::onStepAcknowledged(bool degraded, const std::string& missing) {
  if (run_.phase() != sim::WorldRun::Phase::kRunning) return;
  if (const auto f = run_.stepAcknowledged(step_, degraded, missing)) {
    if (f->last_step_unacknowledged)
      log().warn("world_sim: last step {} not acknowledged by {}", step_, missing);
    finish(toSimStatusState(f->end), f->detail);
    return;
  }
  if (advance() || run_.ending()) submitCurrentStep();
}

void WorldSimNode::tickFast() {
  if (run_.phase() != sim::WorldRun::Phase::kRunning) return;
  const auto until = std::chrono::steady_clock::now() + kFastSlice;
  while (advance() && std::chrono::steady_clock::now() < until) {
  }
}

void WorldSimNode::tickRealTime() {
  if (run_.phase() != sim::WorldRun::Phase::kRunning) return;
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - phase_since_).count();
  const auto due =
      static_cast<std::int64_t>(std::floor(wall_s * real_time_factor_ / step_period_s_));
  int n = 0;
  while (step_ < due && n < kMaxCatchUpSteps && advance()) ++n;
  if (step_ < due && run_.phase() == sim::WorldRun::Phase::kRunning && !behind_logged_) {
    behind_logged_ = true;
    log().warn("world_sim: cannot keep up with real_time_factor {} ({} steps behind)",
               real_time_factor_, due - step_);
  }
}

void WorldSimNode::applyInputs() {
  Velocity2 cmd{0.0, 0.0, 0.0};
  if (command_) {
    cmd = command_->body;
    if (lockstep_ && command_->step != step_ && stale_commands_++ == 0) {
      log().info("world_sim: step {}: latest robot command is of step {}; using it (logged once)",
                 step_, command_->step);
    }
  }
  for (const sim::HeardWords::Pending& c : heard_.take(sim_->time_s())) {
    if (lockstep_ && c.step != step_)
      log().info("world_sim: step {}: utterance of step {} to human {}", step_, c.step,
                 c.cue.human_id);
    sim_->addCue(c.cue);
  }
  if (band_) {
    sim_->setRobotBand(band_->robot, utimeToSeconds(band_->utime));
    band_.reset();
  }
  last_command_ = cmd;
}

bool WorldSimNode::advance() {
  if (run_.phase() != sim::WorldRun::Phase::kRunning) return false;
  applyInputs();
  const double t_before_s = sim_->time_s();
  const sim::StepResult r = sim_->step(last_command_);
  ++step_;
  agents_ = r.agents;
  sensing_->noteRobot(agents_.front(), r.t_s);
  for (const sim::CueOutcome& o : r.cues) logCue(o);
  publishStep();
  if (r.status != sim::SimStatus::kRunning) {
    // Lockstep (a gate): the last step is answered like every other one before the run ends, and
    // published again while its acks are overdue (sim::WorldRun).
    if (const auto f =
            run_.simulationEnded(sim::runEndOf(r.status), endDetail(r), gate_ != nullptr))
      finish(toSimStatusState(f->end), f->detail);
    return false;
  }
  // Once per simulated second (a whole second crossed during this step).
  if (std::floor(r.t_s + 1e-9) > std::floor(t_before_s + 1e-9))
    publishSimStatus(sim_status_t::STATE_RUNNING, "");
  return true;
}

void WorldSimNode::logCue(const sim::CueOutcome& o) {
  if (cue_outcomes_.is_open()) {
    // Flushed a line at a time: a run stopped half-way keeps the cues it had.
    const nlohmann::ordered_json record{
        {"t_s", o.cue.t_s},
        {"human_id", o.cue.human_id},
        {"cue", sim::toString(o.cue.kind)},
        {"side", o.cue.side == Side::kLeft    ? "left"
                 : o.cue.side == Side::kRight ? "right"
                                              : "undefined"},
        {"repeat", o.cue.repeat},
        {"distance_m", o.distance_m},
        {"responds", o.responds},
        {"heard", o.heard},
        {"complies", o.complies},
        {"act_s", o.complies ? nlohmann::ordered_json(o.act_s) : nlohmann::ordered_json()}};
    cue_outcomes_ << record.dump() << '\n' << std::flush;
  }
  const std::string what = std::string(sim::toString(o.cue.kind)) +
                           (o.cue.side == Side::kLeft    ? " left"
                            : o.cue.side == Side::kRight ? " right"
                                                         : "") +
                           (o.cue.repeat ? " (repeat)" : "");
  if (!o.responds) {
    log().debug("world_sim: t = {:.2f} s: human {} does not react to words ({})", o.cue.t_s,
                o.cue.human_id, what);
  } else if (!o.heard) {
    log().info("world_sim: t = {:.2f} s: human {} did not hear {}: {:.1f} m from the robot",
               o.cue.t_s, o.cue.human_id, what, o.distance_m);
  } else if (!o.complies) {
    log().info("world_sim: t = {:.2f} s: human {} heard {} at {:.1f} m and does not comply",
               o.cue.t_s, o.cue.human_id, what, o.distance_m);
  } else {
    log().info("world_sim: t = {:.2f} s: human {} heard {} at {:.1f} m; acts at {:.2f} s",
               o.cue.t_s, o.cue.human_id, what, o.distance_m, o.act_s);
  }
}

void WorldSimNode::announce() {
  if (!lockstep_) return;
  GoalsSnapshot goals;
  goals.utime = secondsToUtime(sim_->time_s());
  goals.goals.push_back({sim::kRobotId, AgentKind::kRobot, scenario_.robot.goal});
  if (publish_human_goals_) {
    for (std::size_t i = 0; i < scenario_.humans.size(); ++i)
      goals.goals.push_back({tracker_->currentId(i), AgentKind::kHuman, scenario_.humans[i].goal});
  }
  runtime_.publish(channels::kGoals, toLcm(goals));
  step_ack_t here{};
  here.utime = goals.utime;
  here.step = -1;
  here.participant = runtime_.name();
  runtime_.publish(channels::kStepAck, here);
}

void WorldSimNode::publishStep() {
  const std::int64_t utime = secondsToUtime(sim_->time_s());
  const std::int64_t step = lockstep_ ? step_ : -1;
  // What a tracker makes of the true humans (the truth itself while its model is off); the goals
  // are those of the persons behind the published ids.
  const std::vector<AgentState> truth(agents_.begin() + 1, agents_.end());
  const std::vector<sim::TrackedHuman> seen =
      tracker_->observe(sim_->time_s(), agents_.front(), truth);
  GoalsSnapshot goals;
  goals.utime = utime;
  goals.goals.push_back({sim::kRobotId, AgentKind::kRobot, scenario_.robot.goal});
  if (publish_human_goals_) {
    for (const sim::TrackedHuman& h : seen)
      goals.goals.push_back({h.state.id, AgentKind::kHuman, scenario_.humans[h.person].goal});
  }
  outputs_.publish(step, channels::kGoals, toLcm(goals));
  // The robot's scan of this instant, before the states that open the step: the world's ack
  // counts it, and the band source waits for it as for the goals (docs/lockstep.md).
  if (sensing_->laserOn())
    outputs_.publish(step, channels::kScan, sensing_->scan(*field_, agents_, utime, step));

  AgentStatesSnapshot s;
  s.utime = utime;
  s.step = step;
  s.robot = agents_.front();
  for (const sim::TrackedHuman& h : seen) s.humans.push_back(h.state);
  outputs_.publish(step, channels::kAgentStates, toLcm(s));
  // The world's own ack: the daemons check with it that they have this step's goals and states.
  outputs_.ack(utime, step);
  step_published_at_ = std::chrono::steady_clock::now();
  runtime_.noteLogicTime(utime);
}

void WorldSimNode::retransmitIfOverdue() {
  if (run_.phase() != sim::WorldRun::Phase::kRunning || !gate_ || gate_->pending() == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - step_published_at_).count() < config_.retransmit_period_s)
    return;
  if (retransmits_++ % 20 == 0)
    log().info(
        "world_sim: step {} not yet acknowledged by everyone ({}); publishing it again "
        "({} repeats so far)",
        step_, gate_->missing(step_), retransmits_);
  outputs_.republish(step_);
  step_published_at_ = now;
}

void WorldSimNode::publishSimStatus(std::int8_t state, const std::string& detail) {
  const sim::SimSummary& sum = sim_->summary();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  sim_status_t m;
  m.utime = secondsToUtime(sim_->time_s());
  m.step = step_;
  m.state = state;
  m.scenario = scenario_.name;
  m.min_clearance_m =
      std::isfinite(sum.min_robot_human_clearance_m) ? sum.min_robot_human_clearance_m : kNaN;
  m.robot_time_to_goal_s = sum.robot_goal_time_s >= 0.0 ? sum.robot_goal_time_s : kNaN;
  m.min_clearance_t_s =
      std::isfinite(sum.min_robot_human_clearance_m) ? sum.min_robot_human_clearance_t_s : kNaN;
  m.contact = sim_status_t::CONTACT_NONE;
  m.contact_human_id = -1;
  m.contact_t_s = kNaN;
  m.contact_robot_speed_m_s = kNaN;
  if (const auto& c = sum.first_contact) {
    m.contact = c->robot_at_fault ? sim_status_t::CONTACT_ROBOT_AT_FAULT
                                  : sim_status_t::CONTACT_HUMAN_AT_FAULT;
    m.contact_human_id = c->human_id;
    m.contact_t_s = c->t_s;
    m.contact_robot_speed_m_s = c->robot_speed_towards_m_s;
  }
  m.detail = detail;
  runtime_.publish(channels::kSimStatus, m);
}

void WorldSimNode::finish(std::int8_t state, const std::string& detail) {
  run_.finish();
  publishSimStatus(state, detail);
  if (state == sim_status_t::STATE_PARTICIPANT_TIMEOUT) {
    runtime_.setDegraded(detail);
  } else {
    runtime_.setRunning("ended: " + detail);
  }
  log().info("world_sim: '{}' ended at t = {} s (step {}): {}", scenario_.name, sim_->time_s(),
             step_, detail);
  const sim::SimSummary& sum = sim_->summary();
  if (std::isfinite(sum.min_robot_human_clearance_m))
    log().info("world_sim: min robot-human clearance {} m at t = {} s; {}",
               fixed2(sum.min_robot_human_clearance_m), fixed2(sum.min_robot_human_clearance_t_s),
               sum.first_contact
                   ? "first contact: " +
                         sim::contactDetail(*sum.first_contact,
                                            sim_->spec().settings.contact_fault_speed_m_s) +
                         (sum.first_contact->robot_at_fault ? " (robot at fault)"
                                                            : " (robot not at fault)")
                   : std::string("no robot-human contact"));
  if (sensing_->hasUnmapped())
    log().info("world_sim: min robot clearance to the unmapped obstacles {} m at t = {} s",
               fixed2(sensing_->minUnmappedClearance_m()),
               fixed2(sensing_->minUnmappedClearanceT_s()));
  if (retransmits_ > 0)
    log().info("world_sim: steps published again {} times (acks overdue)", retransmits_);
  if (tracker_->params().active()) {
    const sim::TrackerStats& ts = tracker_->stats();
    log().info(
        "world_sim: tracker published {} human entries; missed {}, out of range {}, tracks "
        "dropped and renewed {}, id switches {}",
        ts.published, ts.missed, ts.out_of_range, ts.dropped, ts.switches);
  }
  if (config_.exit_at_end) runtime_.requestStop();
}

std::string WorldSimNode::endDetail(const sim::StepResult& r) const {
  sim::EndContext c;
  c.time_limit_s = scenario_.time_limit_s;
  c.standstill_distance_m = scenario_.standstill_distance_m;
  c.standstill_time_s = scenario_.standstill_time_s;
  c.contact_fault_speed_m_s = sim_->spec().settings.contact_fault_speed_m_s;
  if (last_mode_) {
    c.robot_mode = commandModeText(*last_mode_);
    c.robot_mode_at_goal = *last_mode_ == velocity_command_t::MODE_GOAL_REACHED;
  }
  c.last_said = last_said_;
  return sim::endDetail(r, sim_->summary(), c);
}

}  // namespace coopnav
