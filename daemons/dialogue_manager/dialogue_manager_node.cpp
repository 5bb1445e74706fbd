#include "dialogue_manager_node.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <type_traits>
#include <variant>
#include <vector>

#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"

namespace coopnav {

dialogue::DecisionConfig DialogueManagerConfig::decisionConfig() const {
  dialogue::DecisionConfig c;
  c.round1_t_cross_s = round1_t_cross_s;
  c.round2_t_cross_s = round2_t_cross_s;
  c.round2_response_s = round2_response_s;
  c.round2_latest_t_cross_s = round2_latest_t_cross_s;
  c.precautionary_dock = precautionary_dock;
  c.crossing_range_m = crossing_range_m;
  dialogue::parseCooperationJudgement(judgement, c.judgement);  // validated by visit()
  c.forecast_threshold = forecast_threshold;
  c.templates = templates;
  c.resolve_stand_offs = stand_off.resolve;
  c.go_first_when_not_docked = stand_off.go_first;
  c.stand_off = stand_off;
  c.make_time = make_time;
  return c;
}

dialogue::SessionConfig DialogueManagerConfig::sessionConfig() const {
  dialogue::SessionConfig c;
  c.decision = decisionConfig();
  c.crowd = crowd;
  c.overtake = overtake;
  c.crossed_hysteresis_m = crossed_hysteresis_m;
  c.crossed_max_distance_m = crossed_max_distance_m;
  c.human_gone_s = human_gone_s;
  c.path_max_age_s = path_max_age_s;
  c.muted = muted;
  c.interrupt_for_change = interrupt_for_change;
  c.speech_rate_wpm = speech.rate_wpm;
  return c;
}

void DialogueManagerConfig::resolvePaths(const std::string& base_dir) {
  speech.wav_dir = resolvePath(base_dir, speech.wav_dir);
  if (speech.program.find('/') != std::string::npos)
    speech.program = resolvePath(base_dir, speech.program);
}

DialogueManagerNode::DialogueManagerNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      speech_(config.speech),
      session_(config.sessionConfig(), runtime.limits().forget_after_s,
               static_cast<std::size_t>(runtime.limits().max_ids)),
      clock_(runtime.limits().max_time_jump_s, runtime.limits().time_resync_messages),
      ack_steps_(runtime.limits().max_pending_steps, runtime.limits().time_resync_messages) {
  // Step k is decided with every situation and path assessment of k and the world's agent
  // states of k (a lost one holds the step until the world publishes it again).
  StepNodeOptions steps;
  steps.requirements = {{kSituationAssessor, 0, {channels::kSituation}},
                        {kPathAssessor, 0, {channels::kPathAssessment}},
                        {"world_sim", 0, {channels::kAgentStates}, true}};
  steps.timeout = std::chrono::milliseconds(config_.gate_timeout_ms);
  steps.wait_for_unseen = config_.gate_wait_for_unseen;
  steps_ = std::make_unique<StepNode>(runtime_, steps);
  runtime_.subscribe<situation_t>(channels::kSituation,
                                  [this](const situation_t& m, std::int64_t) { onSituation(m); });
  runtime_.subscribe<path_assessment_t>(
      channels::kPathAssessment,
      [this](const path_assessment_t& m, std::int64_t) { onPathAssessment(m); });
  runtime_.subscribe<agent_states_t>(
      channels::kAgentStates, [this](const agent_states_t& m, std::int64_t) { onAgentStates(m); });
  runtime_.subscribe<step_ack_t>(channels::kStepAck,
                                 [this](const step_ack_t& a, std::int64_t) { onStepAck(a); });
  if (config_.speech.enabled)
    runtime_.addTimer(std::chrono::milliseconds(50), [this] { speech_.poll(); });
  if (speech_.usable()) measureTemplates();
  runtime_.setLostStateNote(
      "which rounds it already fired: no utterance, dock or thanks for the humans already there");
  runtime_.setRunning(speech_.usable() ? "speech on" : "");
}

void DialogueManagerNode::measureTemplates() {
  using dialogue::SpeechAct;
  std::vector<std::string> texts;
  for (int a = static_cast<int>(SpeechAct::kInformDirection);
       a <= static_cast<int>(SpeechAct::kInformResuming); ++a) {
    const auto act = static_cast<SpeechAct>(a);
    for (const Side side : {Side::kLeft, Side::kRight})
      texts.push_back(dialogue::renderText(config_.templates, act, side));
  }
  texts.push_back(config_.templates.inform_precautionary_docking);
  for (const auto* t :
       {&config_.templates.inform_docking_short,
        &config_.templates.inform_precautionary_docking_short,
        &config_.templates.inform_wider_place_short, &config_.templates.inform_retreat_short,
        &config_.templates.inform_stopping_short})
    if (!t->empty()) texts.push_back(*t);
  std::sort(texts.begin(), texts.end());
  texts.erase(std::unique(texts.begin(), texts.end()), texts.end());
  const auto seconds = speech_.measure(texts);
  std::map<std::string, double> measured_s;
  for (std::size_t i = 0; i < texts.size(); ++i)
    if (seconds[i]) measured_s[texts[i]] = *seconds[i];
  log().info(
      "dialogue_manager: speech: measured {} of {} template texts with {} (the others are "
      "estimated)",
      measured_s.size(), texts.size(), config_.speech.program);
  for (const auto& [text, d] : measured_s)
    log().debug("dialogue_manager: speech: {:.3f} s \"{}\"", d, text);
  session_.setMeasuredDurations(std::move(measured_s));
}

std::size_t DialogueManagerNode::longestKeptTextBytes() const {
  std::size_t n = session_.longestKeptTextBytes();
  for (const auto& [step, bucket] : inputs_)
    for (const auto& [id, s] : bucket.in.situations) n = std::max(n, s.snapshot.reason.size());
  return n;
}

// ---- time ----

void DialogueManagerNode::onResync(std::int64_t utime) {
  // A new run, a restarted tracker, or a clock one stray first message had set: the times kept
  // per human are of the old time base, so their ages restart from now.
  log().warn("dialogue_manager: message time goes on from utime {}: per-human times restart",
             utime);
  session_.restamp(utime);
}

std::int64_t DialogueManagerNode::nearClock(std::int64_t utime) const {
  const auto now = clock_.now();
  if (!now) return utime;
  const double gap_us = std::fabs(static_cast<double>(utime) - static_cast<double>(*now));
  return gap_us <= runtime_.limits().max_time_jump_s * 1e6 ? utime : *now;
}

// ---- input ----

template <class Convert>
void DialogueManagerNode::fileInput(std::int64_t step, std::int64_t utime, const char* publisher,
                                    const char* channel, const std::string& key, Convert convert) {
  // The world's repeat of a step means someone waits: our answers go out again.
  const bool world = std::string(channel) == channels::kAgentStates;
  steps_->input(
      publisher, channel, step, key,
      [&] {
        if (step >= 0 && step <= last_done_step_)
          throw RejectedMessage("step " + std::to_string(step) +
                                " goes backwards (already decided " +
                                std::to_string(last_done_step_) + ")");
        const bool is_new = inputs_.find(step) == inputs_.end();
        // A step never seen that is older than the newest one seen goes backwards (a step
        // already decided was answered above).
        if (is_new && step >= 0 && step < newest_step_)
          throw RejectedMessage("step " + std::to_string(step) + " goes backwards (newest " +
                                std::to_string(newest_step_) + ")");
        // Converted before its time is offered to the clock: a message rejected for what it
        // holds does not move the clock.
        Store store;
        std::exception_ptr bad;
        try {
          store = convert();
        } catch (...) {
          bad = std::current_exception();
        }
        // A jump is rejected as bad content is. An input a little behind another (a situation is
        // stamped with its bands' time, older than the newest agent states) is used: lockstep
        // order is kept by the step numbers.
        bool on_time = false;
        if (!bad) {
          try {
            clock_.take(utime, channel, [&] { onResync(utime); });
            on_time = true;
          } catch (const RejectedMessage&) {
            bad = std::current_exception();
          }
        }
        StepInputs& bucket = inputs_[step];
        if (!bucket.has_utime) {
          bucket.in.utime = on_time ? utime : nearClock(utime);
          bucket.has_utime = true;
        }
        if (step > newest_step_) newest_step_ = step;
        // Scheduled before storing, so that a rejected input still has its step acknowledged; it
        // runs once this input is stored.
        if (is_new) schedule(step);
        if (bad) std::rethrow_exception(bad);
        store(bucket);
      },
      world);
}

void DialogueManagerNode::onSituation(const situation_t& msg) {
  fileInput(msg.step, msg.utime, kSituationAssessor, channels::kSituation,
            std::to_string(msg.human_id), [&]() -> Store {
              dialogue::StampedSituation in{{msg.utime, msg.step, msg.human_id},
                                            situationSnapshotFromLcm(msg)};
              in.snapshot.reason = keptText(std::move(in.snapshot.reason), maxTextBytes());
              return [this, in = std::move(in)](StepInputs& b) {
                const std::int32_t id = in.stamp.human_id;
                if (!b.in.situations.count(id) && b.in.situations.size() >= maxIds())
                  throw RejectedMessage("more than limits.max_ids situations in one step");
                b.in.situations[id] = in;
              };
            });
}

void DialogueManagerNode::onPathAssessment(const path_assessment_t& msg) {
  fileInput(msg.step, msg.utime, kPathAssessor, channels::kPathAssessment,
            std::to_string(msg.human_id), [&]() -> Store {
              dialogue::PathSnapshot p = pathSnapshotFromLcm(msg);
              // Two profiles judge the same walk differently: acting on the other one's verdict
              // would be acting on a τ and γ nobody configured here.
              if (msg.profile != config_.assessment_profile)
                throw RejectedMessage("path assessment of profile '" + msg.profile +
                                      "'; this dialogue manager acts on '" +
                                      config_.assessment_profile + "' (assessment_profile)");
              return [this, id = msg.human_id, p, utime = msg.utime](StepInputs& b) {
                if (!b.in.paths.count(id) && b.in.paths.size() >= maxIds())
                  throw RejectedMessage("more than limits.max_ids path assessments in one step");
                b.in.paths[id] = {p, utime};
              };
            });
}

void DialogueManagerNode::onAgentStates(const agent_states_t& msg) {
  fileInput(msg.step, msg.utime, "world_sim", channels::kAgentStates, "", [&]() -> Store {
    AgentStatesSnapshot a = fromLcm(msg);
    return [scene = dialogue::SceneSnapshot{a.utime, a.robot, std::move(a.humans)}](StepInputs& b) {
      b.in.agents = scene;
    };
  });
}

void DialogueManagerNode::onStepAck(const step_ack_t& ack) {
  // An upstream ack of a step we have no input for (no humans this step, or inputs lost) still
  // needs a work item, or the step would never be acknowledged downstream.
  if (ack.participant != kSituationAssessor && ack.participant != kPathAssessor) return;
  if (ack.step < 0) return;
  // An ack far from the others (a forged step 2^50) must not become the newest step: every real
  // step after it would be refused as going backwards.
  if (ack_steps_.offer(ack.step) == JumpGuard::Verdict::kJump)
    throw RejectedMessage("step ack " + std::to_string(ack.step) + " from " + ack.participant +
                          " is more than " + std::to_string(runtime_.limits().max_pending_steps) +
                          " steps from the acks so far (limits.max_pending_steps)");
  if (ack.step <= newest_step_ || ack.step <= last_done_step_ || inputs_.count(ack.step)) return;
  newest_step_ = ack.step;
  StepInputs& bucket = inputs_[ack.step];
  bucket.in.utime = nearClock(ack.utime);
  bucket.has_utime = true;
  schedule(ack.step);
}

void DialogueManagerNode::schedule(std::int64_t step) {
  steps_->schedule(step, inputs_.at(step).in.utime, [this](StepNode::Step& run) { runStep(run); });
}

// ---- one step ----

void DialogueManagerNode::runStep(StepNode::Step& run) {
  const std::int64_t step = run.step();
  auto it = inputs_.find(step);
  if (it == inputs_.end()) return;  // cannot happen: one work item per bucket
  dialogue::SessionInput in = std::move(it->second.in);
  inputs_.erase(it);
  in.step = step;
  in.clock_utime = clock_.now();
  if (step >= 0 && !first_step_seen_) {
    first_step_seen_ = true;
    // A journal replay starts at step 0, muted; a live first step after 0 is a restart that
    // lost what was said before: the humans already there may have heard rounds this process
    // does not know of, so nothing is decided for them (no repeated round, no dock on a guess).
    if (step > 0 && !runtime_.muted() && runtime_.joinedLate())
      log().warn("dialogue_manager: {}", session_.joinLate(in).text);
  }
  if (run.degraded()) {
    degraded_ = true;
    runtime_.setDegraded("step " + std::to_string(step) + " ran without " + run.missing());
  } else if (degraded_ && step >= 0) {
    degraded_ = false;
    runtime_.setRunning(speech_.usable() ? "speech on" : "");
  }
  try {
    publish(run, session_.step(in));
  } catch (const std::exception& e) {
    // A bug, never input (inputs were validated when filed): say so, and still acknowledge.
    runtime_.countRejected();
    log().error("dialogue_manager: step {} failed: {}", step, e.what());
  }
  runtime_.noteLogicTime(in.utime);
  run.finish();
  if (step > last_done_step_) last_done_step_ = step;
  // Speech only after everything of the step is out: it must never delay a message. Never
  // while rebuilding the state from the journal: that was said before the restart.
  if (!runtime_.muted())
    for (const auto& s : speech_pending_) speech_.say(s.text, s.wav_stem);
  speech_pending_.clear();
}

// ---- output ----

void DialogueManagerNode::publish(StepNode::Step& run, const dialogue::SessionOutput& out) {
  for (const auto& n : out.notes) {
    const auto level = n.level == dialogue::SessionNote::Level::kWarn   ? spdlog::level::warn
                       : n.level == dialogue::SessionNote::Level::kInfo ? spdlog::level::info
                                                                        : spdlog::level::debug;
    log().log(level, "dialogue_manager: {}", n.text);
  }
  // In the session's order (docs/lockstep.md row 4). The reasons hold the situation assessor's
  // text: published on no longer than it is kept.
  for (const auto& m : out.messages)
    std::visit(
        [&](const auto& o) {
          using T = std::decay_t<decltype(o)>;
          const DialogueStamp stamp{o.stamp.utime, o.stamp.step, o.stamp.human_id};
          if constexpr (std::is_same_v<T, dialogue::UtteranceOut>) {
            run.publish(channels::kUtterance,
                        toLcm(stamp, o.utterance, o.t_cross_s, o.slot, o.group));
          } else if constexpr (std::is_same_v<T, dialogue::RobotActionOut>) {
            run.publish(channels::kRobotAction,
                        toLcm(stamp, o.action, keptText(o.why, maxTextBytes())));
          } else {
            run.publish(channels::kPathAssessorControl,
                        toLcm(RecorderControl{stamp.utime, stamp.step, stamp.human_id, o.command,
                                              keptText(o.why, maxTextBytes()), o.d_oh_m, o.d_h_m}));
          }
        },
        m);
  speech_pending_.insert(speech_pending_.end(), out.speak.begin(), out.speak.end());
}

}  // namespace coopnav
