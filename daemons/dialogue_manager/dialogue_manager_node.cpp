#include "dialogue_manager_node.hpp"

#include <cmath>
#include <set>

#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"

namespace coopnav {
namespace {

std::string formatTCross(std::optional<double> t_cross_s) {
  return t_cross_s ? fmt::format("{:.2f} s", *t_cross_s) : std::string("-");
}

}  // namespace

dialogue::DecisionConfig DialogueManagerConfig::decisionConfig() const {
  dialogue::DecisionConfig c;
  c.round1_t_cross_s = round1_t_cross_s;
  c.round2_t_cross_s = round2_t_cross_s;
  c.precautionary_dock = precautionary_dock;
  c.templates = templates;
  return c;
}

void DialogueManagerConfig::resolvePaths(const std::string& base_dir) {
  speech.wav_dir = resolvePath(base_dir, speech.wav_dir);
  if (speech.program.find('/') != std::string::npos)
    speech.program = resolvePath(base_dir, speech.program);
}

DialogueManagerNode::DialogueManagerNode(const Config& config, Runtime& runtime)
    : config_(config),
      decision_config_(config.decisionConfig()),
      runtime_(runtime),
      speech_(config.speech) {
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
  runtime_.setLostStateNote(
      "which rounds it already fired: no utterance, dock or thanks for the humans already there");
  runtime_.setRunning(speech_.usable() ? "speech on" : "");
}

const dialogue::HumanDecision* DialogueManagerNode::decision(std::int32_t id) const {
  auto it = humans_.find(id);
  return it == humans_.end() ? nullptr : &it->second.decision;
}

// ---- input ----

template <class Fill>
void DialogueManagerNode::fileInput(std::int64_t step, std::int64_t utime, const char* publisher,
                                    const char* channel, const std::string& key, Fill fill) {
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
        StepInputs& bucket = inputs_[step];
        if (bucket.utime < 0) bucket.utime = utime;
        if (step > newest_step_) newest_step_ = step;
        // Scheduled before filling, so that a rejected input still has its step acknowledged; it
        // runs once this input is stored.
        if (is_new) schedule(step);
        fill(bucket);
      },
      world);
}

void DialogueManagerNode::onSituation(const situation_t& msg) {
  fileInput(msg.step, msg.utime, kSituationAssessor, channels::kSituation,
            std::to_string(msg.human_id), [&](StepInputs& b) {
              b.situations[msg.human_id] = {{msg.utime, msg.step, msg.human_id},
                                            situationSnapshotFromLcm(msg)};
            });
}

void DialogueManagerNode::onPathAssessment(const path_assessment_t& msg) {
  fileInput(msg.step, msg.utime, kPathAssessor, channels::kPathAssessment,
            std::to_string(msg.human_id),
            [&](StepInputs& b) { b.paths[msg.human_id] = pathSnapshotFromLcm(msg); });
}

void DialogueManagerNode::onAgentStates(const agent_states_t& msg) {
  fileInput(msg.step, msg.utime, "world_sim", channels::kAgentStates, "",
            [&](StepInputs& b) { b.agents = fromLcm(msg); });
}

void DialogueManagerNode::onStepAck(const step_ack_t& ack) {
  // An upstream ack of a step we have no input for (no humans this step, or inputs lost) still
  // needs a work item, or the step would never be acknowledged downstream.
  if (ack.participant != kSituationAssessor && ack.participant != kPathAssessor) return;
  if (ack.step < 0 || ack.step <= newest_step_ || ack.step <= last_done_step_ ||
      inputs_.count(ack.step))
    return;
  newest_step_ = ack.step;
  inputs_[ack.step].utime = ack.utime;
  schedule(ack.step);
}

void DialogueManagerNode::schedule(std::int64_t step) {
  steps_->schedule(step, inputs_.at(step).utime, [this](StepNode::Step& run) { runStep(run); });
}

// ---- one step ----

void DialogueManagerNode::runStep(StepNode::Step& run) {
  const std::int64_t step = run.step();
  auto it = inputs_.find(step);
  if (it == inputs_.end()) return;  // cannot happen: one work item per bucket
  StepInputs in = std::move(it->second);
  inputs_.erase(it);
  if (step >= 0 && !first_step_seen_) {
    first_step_seen_ = true;
    // A journal replay starts at step 0, muted; a live first step after 0 is a restart that
    // lost what was said before.
    joined_late_ = step > 0 && !runtime_.muted() && runtime_.joinedLate();
    if (joined_late_) {
      for (const auto& [id, s] : in.situations) history_unknown_.insert(id);
      if (in.agents)
        for (const auto& h : in.agents->humans) history_unknown_.insert(h.id);
      std::string ids;
      for (const auto id : history_unknown_) ids += (ids.empty() ? "" : ",") + std::to_string(id);
      log().warn(
          "dialogue_manager: joined the run at step {} without its state: no decisions for "
          "humans {} (rounds already fired unknown)",
          step, ids.empty() ? "-" : ids);
    }
  }
  if (run.degraded()) {
    degraded_ = true;
    runtime_.setDegraded("step " + std::to_string(step) + " ran without " + run.missing());
  } else if (degraded_ && step >= 0) {
    degraded_ = false;
    runtime_.setRunning(speech_.usable() ? "speech on" : "");
  }
  try {
    process(run, in);
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

void DialogueManagerNode::process(StepNode::Step& run, StepInputs& in) {
  const std::int64_t step = run.step();
  // 1. Where the agents are: crossed detection and presence, for every human in the scene.
  std::set<std::int32_t> crossed_now;
  if (in.agents) {
    const AgentStatesSnapshot& a = *in.agents;
    latest_agents_utime_ = std::max(latest_agents_utime_, a.utime);
    for (const auto& h : a.humans) {
      Tracked& t = tracked_[h.id];
      const bool was = t.crossed.crossed;
      t.crossed = dialogue::updateCrossed(t.crossed, h.pose, a.robot.pose.position(),
                                          config_.crossed_hysteresis_m);
      t.last_seen_utime = a.utime;
      if (!was && t.crossed.crossed) crossed_now.insert(h.id);
    }
  }
  // 2. The latest path assessment of each human, read before the decisions of this step.
  for (const auto& [id, p] : in.paths) latest_path_[id] = p;

  // 3. Decisions, humans in id order (deterministic output order).
  std::set<std::int32_t> ids;
  for (const auto& [id, s] : in.situations) ids.insert(id);
  for (std::int32_t id : crossed_now)
    if (humans_.count(id)) ids.insert(id);
  for (std::int32_t id : ids) {
    auto sit = in.situations.find(id);
    if (sit != in.situations.end()) {
      decide(run, id, sit->second.stamp, sit->second.snapshot);
    } else {
      // Crossed on this step's agent states, no situation for it: round 3 on the last one.
      const DialogueStamp stamp{in.agents->utime, step, id};
      decide(run, id, stamp, humans_.at(id).last_situation);
    }
  }

  // 4. Humans that left the scene end their interaction (stop the recorder, resume a dock).
  if (in.agents) {
    for (auto& [id, h] : humans_) {
      if (h.decision.ended()) continue;
      const Tracked& t = tracked_[id];
      const double absent_s =
          t.last_seen_utime < 0 ? 0.0 : utimeDiffSeconds(latest_agents_utime_, t.last_seen_utime);
      if (absent_s <= config_.human_gone_s) continue;
      const std::string why =
          fmt::format("human {} absent from the agent states for {:.1f} s", id, absent_s);
      const DialogueStamp stamp{in.agents->utime, step, id};
      emit(run, stamp, h.decision.endInteraction(utimeToSeconds(in.agents->utime), why),
           std::nullopt);
    }
    // 5. Forget humans long gone (as the assessors do): a robot running for hours meets
    // thousands of tracker ids, and a tracker that reuses an id after a minute means someone
    // new, whose rounds start afresh.
    for (auto it = tracked_.begin(); it != tracked_.end();) {
      const std::int32_t id = it->first;
      const bool gone = it->second.last_seen_utime >= 0 &&
                        utimeDiffSeconds(latest_agents_utime_, it->second.last_seen_utime) >
                            std::max(kForgetHumanAfter_s, config_.human_gone_s);
      const auto h = humans_.find(id);
      if (!gone || (h != humans_.end() && !h->second.decision.ended())) {
        ++it;
        continue;
      }
      if (h != humans_.end()) humans_.erase(h);
      latest_path_.erase(id);
      history_unknown_.erase(id);
      it = tracked_.erase(it);
    }
  }
}

void DialogueManagerNode::decide(StepNode::Step& run, std::int32_t id, const DialogueStamp& stamp,
                                 const dialogue::SituationSnapshot& situation) {
  if (history_unknown_.count(id)) return;  // see joined_late_: never a round or dock on a guess
  auto hit = humans_.find(id);
  if (hit == humans_.end()) {
    hit = humans_.emplace(id, Human(decision_config_)).first;
    log().info("dialogue_manager: human {} seen first at step {} (t_cross {})", id, run.step(),
               formatTCross(situation.t_cross_s));
  }
  Human& h = hit->second;
  h.last_situation = situation;
  dialogue::DecisionInput in;
  in.t_s = utimeToSeconds(stamp.utime);
  in.situation = situation;
  auto p = latest_path_.find(id);
  if (p != latest_path_.end()) in.path = p->second;
  auto t = tracked_.find(id);
  in.crossed = t != tracked_.end() && t->second.crossed.crossed;
  emit(run, stamp, h.decision.step(in), situation.t_cross_s);
}

// ---- output ----

void DialogueManagerNode::emit(StepNode::Step& run, const DialogueStamp& stamp,
                               const dialogue::DecisionOutput& out,
                               std::optional<double> t_cross_s) {
  std::string why;
  for (const auto& r : out.rounds) {
    log().log(r.degraded ? spdlog::level::warn : spdlog::level::info,
              "dialogue_manager: step {} human {} round {} (t_cross {}): {}{}{}", stamp.step,
              stamp.human_id, r.round, formatTCross(r.t_cross_s), r.branch,
              r.reason.empty() ? "" : "; ", r.reason);
    if (why.empty())
      why = (r.round > 0 ? "round " + std::to_string(r.round) + ": " : std::string()) + r.branch +
            (r.reason.empty() ? "" : " (" + r.reason + ")");
  }
  // Order of docs/lockstep.md row 4: utterances, robot actions, recorder controls.
  for (const auto& u : out.utterances) {
    const std::optional<double> t = u.round == 3 ? std::nullopt : t_cross_s;
    run.publish(channels::kUtterance, toLcm(stamp, u, t));
    log().info("dialogue_manager: to human {}: \"{}\" ({}, round {})", stamp.human_id, u.text,
               dialogue::toString(u.act), u.round);
    speech_pending_.push_back({u.text, fmt::format("u{}_h{}_r{}_{}", stamp.utime, stamp.human_id,
                                                   u.round, dialogue::toString(u.act))});
  }
  for (const auto a : out.robot_actions) {
    run.publish(channels::kRobotAction, toLcm(stamp, a, why));
    log().info("dialogue_manager: robot action {} for human {}", dialogue::toString(a),
               stamp.human_id);
  }
  for (const auto c : out.recorder_commands) {
    run.publish(channels::kPathAssessorControl,
                toLcm(RecorderControl{stamp.utime, stamp.step, stamp.human_id, c, why}));
    log().debug("dialogue_manager: recorder {} for human {}", dialogue::toString(c),
                stamp.human_id);
  }
}

}  // namespace coopnav
