#include "dialogue_manager_node.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <set>
#include <vector>

#include "coopnav/geometry/track_continuity.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"

namespace coopnav {
namespace {

/// Ids listed in one log line about a batch of them; the rest are counted.
constexpr std::size_t kIdsPerLogLine = 8;

std::string formatTCross(std::optional<double> t_cross_s) {
  return t_cross_s ? fmt::format("{:.2f} s", *t_cross_s) : std::string("-");
}

std::string formatOptional(std::optional<double> v) {
  return v ? fmt::format("{:.3f}", *v) : std::string("unknown");
}

const char* tristateName(Tristate t) {
  return t == Tristate::kTrue ? "TRUE" : (t == Tristate::kFalse ? "FALSE" : "UNKNOWN");
}

std::string idList(const std::vector<std::int32_t>& ids) {
  std::string s;
  for (std::size_t i = 0; i < ids.size() && i < kIdsPerLogLine; ++i)
    s += (s.empty() ? "" : ",") + std::to_string(ids[i]);
  if (ids.size() > kIdsPerLogLine) s += fmt::format(" and {} more", ids.size() - kIdsPerLogLine);
  return s;
}

}  // namespace

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
  c.stand_off = stand_off;
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
      speech_(config.speech),
      crowd_(config.crowd),
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
  for (std::size_t i = 0; i < texts.size(); ++i)
    if (seconds[i]) measured_s_[texts[i]] = *seconds[i];
  log().info(
      "dialogue_manager: speech: measured {} of {} template texts with {} (the others are "
      "estimated)",
      measured_s_.size(), texts.size(), config_.speech.program);
  for (const auto& [text, d] : measured_s_)
    log().debug("dialogue_manager: speech: {:.3f} s \"{}\"", d, text);
}

double DialogueManagerNode::speechDuration(const std::string& text) const {
  const auto it = measured_s_.find(text);
  if (it != measured_s_.end()) return it->second;
  return dialogue::estimateSpeechDuration(text, config_.speech.rate_wpm);
}

const dialogue::HumanDecision* DialogueManagerNode::decision(std::int32_t id) const {
  auto it = humans_.find(id);
  return it == humans_.end() ? nullptr : &it->second.decision;
}

std::size_t DialogueManagerNode::longestKeptTextBytes() const {
  std::size_t n = 0;
  for (const auto& [id, h] : humans_) n = std::max(n, h.last_situation.reason.size());
  for (const auto& [step, in] : inputs_)
    for (const auto& [id, s] : in.situations) n = std::max(n, s.snapshot.reason.size());
  return n;
}

// ---- time ----

bool DialogueManagerNode::clockAccepts(std::int64_t utime) {
  switch (clock_.offer(utime)) {
    case MessageClock::Verdict::kJump:
      return false;
    case MessageClock::Verdict::kResynced:
      // A new run, a restarted tracker, or a clock one stray first message had set: the times
      // kept per human are of the old time base, so their ages restart from now.
      log().warn("dialogue_manager: message time goes on from utime {}: per-human times restart",
                 utime);
      heard_.restamp(utime);
      present_.restamp(utime);
      for (auto& [id, t] : tracked_) t.last_seen_utime = utime;
      if (latest_agents_utime_) latest_agents_utime_ = utime;
      return true;
    case MessageClock::Verdict::kBackwards:
      // A little behind another input (a situation is stamped with its bands' time, older than
      // the newest agent states): used. Lockstep order is kept by the step numbers.
    case MessageClock::Verdict::kAccepted:
      return true;
  }
  return true;
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
        const bool on_time = !bad && clockAccepts(utime);
        StepInputs& bucket = inputs_[step];
        if (!bucket.has_utime) {
          bucket.utime = on_time ? utime : nearClock(utime);
          bucket.has_utime = true;
        }
        if (step > newest_step_) newest_step_ = step;
        // Scheduled before storing, so that a rejected input still has its step acknowledged; it
        // runs once this input is stored.
        if (is_new) schedule(step);
        if (bad) std::rethrow_exception(bad);
        if (!on_time)
          throw RejectedMessage(std::string(channel) + ": " + clock_.describe(utime) +
                                " (limits.max_time_jump_s)");
        store(bucket);
      },
      world);
}

void DialogueManagerNode::onSituation(const situation_t& msg) {
  fileInput(msg.step, msg.utime, kSituationAssessor, channels::kSituation,
            std::to_string(msg.human_id), [&]() -> Store {
              SituationIn in{{msg.utime, msg.step, msg.human_id}, situationSnapshotFromLcm(msg)};
              in.snapshot.reason = keptText(std::move(in.snapshot.reason), maxTextBytes());
              return [this, in = std::move(in)](StepInputs& b) {
                const std::int32_t id = in.stamp.human_id;
                if (!b.situations.count(id) && b.situations.size() >= maxIds())
                  throw RejectedMessage("more than limits.max_ids situations in one step");
                b.situations[id] = in;
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
                if (!b.paths.count(id) && b.paths.size() >= maxIds())
                  throw RejectedMessage("more than limits.max_ids path assessments in one step");
                b.paths[id] = {p, utime};
              };
            });
}

void DialogueManagerNode::onAgentStates(const agent_states_t& msg) {
  fileInput(msg.step, msg.utime, "world_sim", channels::kAgentStates, "",
            [&]() -> Store { return [a = fromLcm(msg)](StepInputs& b) { b.agents = a; }; });
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
  bucket.utime = nearClock(ack.utime);
  bucket.has_utime = true;
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
  const std::int64_t now = clockNow(in.utime);
  // 1. Where the agents are: crossed detection and presence, for every human in the scene.
  std::set<std::int32_t> crossed_now;
  if (in.agents) {
    const AgentStatesSnapshot& a = *in.agents;
    robot_pose_ = a.robot.pose;
    robot_speed_m_s_ = std::hypot(a.robot.velocity.vx_m_s, a.robot.velocity.vy_m_s);
    robot_radius_m_ = a.robot.radius_m;
    robot_known_ = true;
    latest_agents_utime_ =
        latest_agents_utime_ ? std::max(*latest_agents_utime_, a.utime) : a.utime;
    continueSwitchedIds(a);
    for (const auto& h : a.humans) {
      Tracked& t = tracked_[h.id];
      t.position_m = h.pose.position();
      t.velocity_m_s = {h.velocity.vx_m_s, h.velocity.vy_m_s};
      t.radius_m = h.radius_m;
      const bool was = t.crossed.crossed;
      t.crossed = dialogue::updateCrossed(t.crossed, h.pose, a.robot.pose.position(),
                                          config_.crossed_hysteresis_m);
      t.last_seen_utime = a.utime;
      present_.touch(h.id, a.utime);
      heard_.touch(h.id, now);
      if (!was && t.crossed.crossed) crossed_now.insert(h.id);
    }
  }
  // 2. The latest path assessment of each human, read before the decisions of this step.
  for (const auto& [id, p] : in.paths) {
    latest_path_[id] = p;
    heard_.touch(id, now);
  }

  // 3. Decisions, humans in id order (deterministic output order), emitted together.
  std::set<std::int32_t> ids;
  for (const auto& [id, s] : in.situations) ids.insert(id);
  for (std::int32_t id : crossed_now)
    if (humans_.count(id)) ids.insert(id);
  std::vector<Decided> decided;
  for (std::int32_t id : ids) {
    auto sit = in.situations.find(id);
    if (sit != in.situations.end()) {
      decided.push_back(decide(run, id, sit->second.stamp, sit->second.snapshot));
    } else {
      // Crossed on this step's agent states, no situation for it: round 3 on the last one.
      const DialogueStamp stamp{in.agents->utime, step, id};
      decided.push_back(decide(run, id, stamp, humans_.at(id).last_situation));
    }
  }
  emitDecided(run, decided);

  // 4. Humans that left the scene end their interaction (stop the recorder, resume a dock).
  if (in.agents) endAbsent(run, *in.agents);
  // 5. Forget humans long gone (as the assessors do): a robot running for hours meets
  // thousands of tracker ids, and a tracker that reuses an id after a minute means someone
  // new, whose rounds start afresh. Ids never seen in the agent states age the same way.
  forgetStale(run);
}

void DialogueManagerNode::continueSwitchedIds(const AgentStatesSnapshot& agents) {
  std::set<std::int32_t> here;
  for (const auto& h : agents.humans) here.insert(h.id);
  std::vector<LostTrack> lost;
  for (const auto& [id, t] : tracked_) {
    const auto h = humans_.find(id);
    // An ended interaction continues too: the person was told what it was told, and a new id
    // must not start round 1 again for someone who has already passed.
    if (here.count(id) || h == humans_.end()) continue;
    lost.push_back({id, utimeToSeconds(t.last_seen_utime), t.position_m, t.velocity_m_s});
  }
  TrackContinuityOptions options;
  options.max_gap_s = config_.human_gone_s;  // an absence this long ends the interaction anyway
  for (const auto& h : agents.humans) {
    if (lost.empty()) return;
    if (tracked_.count(h.id) || humans_.count(h.id)) continue;  // not a new id
    const auto old = continuedTrack(lost, utimeToSeconds(agents.utime), h.pose.position(), options);
    if (!old) continue;
    auto human = humans_.extract(*old);
    human.key() = h.id;
    humans_.insert(std::move(human));
    auto tracked = tracked_.extract(*old);
    tracked.key() = h.id;
    tracked_.insert(std::move(tracked));
    if (auto path = latest_path_.extract(*old)) {
      path.key() = h.id;
      latest_path_.insert(std::move(path));
    }
    if (history_unknown_.erase(*old)) history_unknown_.insert(h.id);
    if (judge_absence_.erase(*old)) judge_absence_.insert(h.id);
    present_.erase(*old);
    heard_.erase(*old);
    log().info(
        "dialogue_manager: human {} continues human {} (a tracker id switch at utime {}): its "
        "interaction goes on, no round repeated",
        h.id, *old, agents.utime);
    lost.erase(
        std::remove_if(lost.begin(), lost.end(), [&](const LostTrack& l) { return l.id == *old; }),
        lost.end());
  }
}

void DialogueManagerNode::endAbsent(StepNode::Step& run, const AgentStatesSnapshot& agents) {
  const std::int64_t latest = *latest_agents_utime_;
  std::set<std::int32_t> gone;  // in id order: the order of the outputs
  while (const IdRecency::Entry* e = present_.oldest()) {
    if (utimeDiffSeconds(latest, e->utime) <= config_.human_gone_s) break;
    gone.insert(e->id);
    present_.erase(e->id);
  }
  // Humans whose decision began while they were already absent (the situation assessor still
  // reported someone the tracker had lost): judged now, as every absent human.
  for (const std::int32_t id : judge_absence_) {
    const auto t = tracked_.find(id);
    if (!present_.contains(id) && t != tracked_.end() &&
        utimeDiffSeconds(latest, t->second.last_seen_utime) > config_.human_gone_s)
      gone.insert(id);
  }
  judge_absence_.clear();
  for (const std::int32_t id : gone) {
    const auto h = humans_.find(id);
    if (h == humans_.end() || h->second.decision.ended()) continue;
    const double absent_s = utimeDiffSeconds(latest, tracked_.at(id).last_seen_utime);
    const std::string why =
        fmt::format("human {} absent from the agent states for {:.1f} s", id, absent_s);
    const DialogueStamp stamp{agents.utime, run.step(), id};
    emit(run, stamp, h->second.decision.endInteraction(utimeToSeconds(agents.utime), why),
         std::nullopt);
  }
}

void DialogueManagerNode::forgetStale(StepNode::Step& run) {
  const auto now = clock_.now();
  if (!now) return;
  const double max_age_s = std::max(runtime_.limits().forget_after_s, config_.human_gone_s);
  std::vector<std::int32_t> forgotten;  // least recent first: the aged ones, then the others
  std::vector<std::int32_t> ended;      // of these, those whose interaction was still open
  const IdRecency::Forgotten n = heard_.forgetOld(*now, max_age_s, maxIds(), [&](std::int32_t id) {
    forgotten.push_back(id);
    const auto h = humans_.find(id);
    if (h != humans_.end() && !h->second.decision.ended()) {
      // Never forgotten in the middle of it: the recorder is stopped and a dock resumed.
      ended.push_back(id);
      const DialogueStamp stamp{run.utime(), run.step(), id};
      emit(run, stamp,
           h->second.decision.endInteraction(utimeToSeconds(run.utime()),
                                             "forgotten (limits.max_ids / forget_after_s)"),
           std::nullopt, /*quiet=*/true);
    }
    forget(id);
  });
  if (forgotten.empty()) return;
  const auto aged_end = forgotten.begin() + static_cast<std::ptrdiff_t>(n.aged);
  log().info(
      "dialogue_manager: forgot {} humans not heard of for {:.0f} s ({}) and {} beyond "
      "limits.max_ids {} ({}); interactions ended: {}",
      n.aged, max_age_s, idList({forgotten.begin(), aged_end}), n.over, maxIds(),
      idList({aged_end, forgotten.end()}), ended.empty() ? "-" : idList(ended));
}

void DialogueManagerNode::forget(std::int32_t id) {
  crowd_.forget(id);
  humans_.erase(id);
  tracked_.erase(id);
  latest_path_.erase(id);
  history_unknown_.erase(id);
  judge_absence_.erase(id);
  present_.erase(id);
  heard_.erase(id);
}

DialogueManagerNode::Decided DialogueManagerNode::decide(
    const StepNode::Step& run, std::int32_t id, const DialogueStamp& stamp,
    const dialogue::SituationSnapshot& situation) {
  heard_.touch(id, clockNow(stamp.utime));
  // See joined_late_: never a round or dock on a guess.
  if (history_unknown_.count(id)) return {stamp, {}, situation.t_cross_s};
  auto hit = humans_.find(id);
  if (hit == humans_.end()) {
    hit = humans_.emplace(id, Human(decision_config_)).first;
    log().info("dialogue_manager: human {} seen first at step {} (t_cross {})", id, run.step(),
               formatTCross(situation.t_cross_s));
    if (tracked_.count(id) && !present_.contains(id)) judge_absence_.insert(id);
  }
  Human& h = hit->second;
  h.last_situation = situation;
  dialogue::DecisionInput in;
  in.t_s = utimeToSeconds(stamp.utime);
  in.situation = situation;
  if (auto p = latest_path_.find(id); p != latest_path_.end()) {
    const double age_s = utimeDiffSeconds(stamp.utime, p->second.utime);
    if (age_s <= config_.path_max_age_s) {
      in.path = p->second.snapshot;
    } else if (h.stale_path_logged_utime != p->second.utime) {
      h.stale_path_logged_utime = p->second.utime;  // once per stale assessment
      log().warn(
          "dialogue_manager: step {} human {}: the latest path assessment is {:.1f} s old (over "
          "path_max_age_s {:.1f} s): CM and IsContributing unknown",
          stamp.step, id, age_s, config_.path_max_age_s);
    }
  }
  auto t = tracked_.find(id);
  in.crossed = t != tracked_.end() && t->second.crossed.crossed;
  in.heard_by_s = h.heard_by_s;
  if (t != tracked_.end() && present_.contains(id) && robot_known_) {
    // The stand-off watch sees the robot and this person as the latest agent states have them.
    dialogue::StandOffInput m;
    m.t_s = in.t_s;
    m.robot_speed_m_s = robot_speed_m_s_;
    m.human_speed_m_s = t->second.velocity_m_s.norm();
    m.centre_distance_m = (t->second.position_m - robot_pose_.position()).norm();
    m.gap_m = m.centre_distance_m - robot_radius_m_ - t->second.radius_m;
    m.t_cross_s = situation.t_cross_s;
    in.motion = m;
  }
  const dialogue::DecisionOutput out = h.decision.step(in);
  for (const auto& r : out.rounds)
    if (r.round == 2)
      log().info(
          "dialogue_manager: step {} human {} round 2 on CM {} m against d_h {} m, "
          "IsContributing {}, p_contributing {}, RobotIsConstrained {}{}",
          stamp.step, id, formatOptional(in.path.cm_window_m), formatOptional(situation.d_h_m),
          tristateName(in.path.is_contributing), formatOptional(in.path.p_contributing),
          tristateName(situation.robot_is_constrained),
          h.heard_by_s
              ? fmt::format(" ({:.2f} s after round 1's words ended)", in.t_s - *h.heard_by_s)
              : "");
  return {stamp, out, situation.t_cross_s};
}

void DialogueManagerNode::emitDecided(StepNode::Step& run, std::vector<Decided>& decided) {
  std::vector<dialogue::DecidedUtterance> utterances;
  for (std::size_t i = 0; i < decided.size(); ++i)
    for (std::size_t k = 0; k < decided[i].out.utterances.size(); ++k)
      utterances.push_back({decided[i].stamp.human_id, decided[i].out.utterances[k],
                            (i << 16) | k});  // ≤ 64 k utterances per decision: never near
  std::vector<dialogue::CoordinatedUtterance> coordinated;
  if (!utterances.empty()) {
    std::vector<dialogue::CrowdMember> scene;
    for (const auto& [id, t] : tracked_)
      if (present_.contains(id)) scene.push_back({id, t.position_m, t.velocity_m_s});
    bool making_room = false;
    for (const auto& [id, h] : humans_)
      making_room = making_room || h.decision.docked() || h.last_situation.robot_retreating;
    coordinated = crowd_.coordinate(robot_pose_, scene, std::move(utterances), making_room);
  }
  for (std::size_t i = 0; i < decided.size(); ++i) {
    std::vector<const dialogue::CoordinatedUtterance*> mine(decided[i].out.utterances.size());
    for (const auto& c : coordinated)
      if ((c.tag >> 16) == i) mine[c.tag & 0xffff] = &c;
    emit(run, decided[i].stamp, decided[i].out, decided[i].t_cross_s, false, &mine);
  }
}

// ---- output ----

void DialogueManagerNode::emit(
    StepNode::Step& run, const DialogueStamp& stamp, const dialogue::DecisionOutput& out,
    std::optional<double> t_cross_s, bool quiet,
    const std::vector<const dialogue::CoordinatedUtterance*>* coordinated) {
  std::string why;
  for (const auto& r : out.rounds) {
    if (!quiet)
      log().log(r.degraded ? spdlog::level::warn : spdlog::level::info,
                "dialogue_manager: step {} human {} round {} (t_cross {}): {}{}{}", stamp.step,
                stamp.human_id, r.round, formatTCross(r.t_cross_s), r.branch,
                r.reason.empty() ? "" : "; ", r.reason);
    if (why.empty())
      why = (r.round > 0 ? "round " + std::to_string(r.round) + ": " : std::string()) + r.branch +
            (r.reason.empty() ? "" : " (" + r.reason + ")");
  }
  // The reasons hold the situation assessor's text: published on no longer than it is kept.
  why = keptText(std::move(why), maxTextBytes());
  // Order of docs/lockstep.md row 4: utterances, robot actions, recorder controls.
  const double t_s = utimeToSeconds(stamp.utime);
  for (std::size_t k = 0; k < out.utterances.size(); ++k) {
    const dialogue::CoordinatedUtterance* c =
        coordinated && k < coordinated->size() ? (*coordinated)[k] : nullptr;
    dialogue::Utterance u = c ? c->utterance : out.utterances[k];
    const std::vector<std::int32_t> group = c ? c->group : std::vector<std::int32_t>{};
    const std::optional<double> t = u.round == 3 ? std::nullopt : t_cross_s;
    // Words that end a stand-off have no crossing to be late for: nobody is going yet.
    const bool has_deadline = !dialogue::endsStandOff(u.act);
    if (c && c->verdict != dialogue::CrowdVerdict::kSay) {
      // Decided, not said (crowd.hpp): published all the same, as every decided utterance is.
      dialogue::SpeechSlot slot;
      slot.delivery = c->verdict == dialogue::CrowdVerdict::kToldToGroup
                          ? dialogue::Delivery::kToldToGroup
                          : dialogue::Delivery::kContradicts;
      slot.duration_s = 0.0;
      run.publish(channels::kUtterance, toLcm(stamp, u, t, slot, group));
      log().info("dialogue_manager: not said to human {}: \"{}\" ({}, round {}): {}",
                 stamp.human_id, u.text, dialogue::toString(u.act), u.round, c->reason);
      continue;
    }
    // A cue is worth saying only if its words end before the crossing; thanks have no deadline.
    const std::optional<double> deadline_s =
        has_deadline && t && std::isfinite(*t) ? std::optional<double>(t_s + *t) : std::nullopt;
    // Short of time, a making-room sentence is said in its shorter wording rather than not at all.
    const std::vector<std::string> wordings = dialogue::wordings(config_.templates, u);
    std::vector<double> durations_s;
    durations_s.reserve(wordings.size());
    for (const auto& w : wordings) durations_s.push_back(speechDuration(w));
    const double free_in_s = std::max(0.0, voice_.freeAt() - t_s);
    const auto choice = voice_.planFirstFitting(t_s, durations_s, deadline_s, config_.muted);
    const dialogue::SpeechSlot slot = choice.slot;
    if (choice.index > 0) {
      log().info(
          "dialogue_manager: to human {}: \"{}\" ({:.2f} s) would end {:.2f} s after the "
          "crossing: said as \"{}\"",
          stamp.human_id, u.text, durations_s[0],
          t_s + free_in_s + durations_s[0] - deadline_s.value_or(t_s), wordings[choice.index]);
      u.text = wordings[choice.index];
    }
    run.publish(channels::kUtterance, toLcm(stamp, u, t, slot, group));
    switch (slot.delivery) {
      case dialogue::Delivery::kToldToGroup:
      case dialogue::Delivery::kContradicts:
        break;  // never planned by the voice
      case dialogue::Delivery::kSaid:
        // The group hears it too: its round 2 judges them from when the words ended.
        for (const std::int32_t id : group)
          if (const auto h = humans_.find(id); h != humans_.end())
            h->second.heard_by_s = t_s + slot.end_s();
        if (const auto h = humans_.find(stamp.human_id); h != humans_.end())
          h->second.heard_by_s = t_s + slot.end_s();
        log().info("dialogue_manager: to human {}: \"{}\" ({}, round {}; {:.2f} s{})",
                   stamp.human_id, u.text, dialogue::toString(u.act), u.round, slot.duration_s,
                   slot.start_s > 0.0 ? fmt::format(", after {:.2f} s", slot.start_s) : "");
        speech_pending_.push_back(
            {u.text, fmt::format("u{}_h{}_r{}_{}", stamp.utime, stamp.human_id, u.round,
                                 dialogue::toString(u.act))});
        break;
      case dialogue::Delivery::kMuted:
        log().info("dialogue_manager: muted: not said to human {}: \"{}\" ({}, round {})",
                   stamp.human_id, u.text, dialogue::toString(u.act), u.round);
        break;
      case dialogue::Delivery::kTooLate:
        log().info(
            "dialogue_manager: not said to human {}: \"{}\" ({}, round {}): its {:.2f} s of "
            "speech would end {:.2f} s after the crossing",
            stamp.human_id, u.text, dialogue::toString(u.act), u.round, slot.duration_s,
            t_s + slot.end_s() - deadline_s.value_or(t_s));
        break;
    }
  }
  for (const auto a : out.robot_actions) {
    run.publish(channels::kRobotAction, toLcm(stamp, a, why));
    log().info("dialogue_manager: robot action {} for human {}", dialogue::toString(a),
               stamp.human_id);
  }
  for (const auto c : out.recorder_commands) {
    const bool start = c == dialogue::RecorderCommand::kStart;
    const RecorderControl control{stamp.utime,
                                  stamp.step,
                                  stamp.human_id,
                                  c,
                                  why,
                                  start ? out.start_d_oh_m : std::nullopt,
                                  start ? out.start_d_h_m : std::nullopt};
    run.publish(channels::kPathAssessorControl, toLcm(control));
    log().debug("dialogue_manager: recorder {} for human {}", dialogue::toString(c),
                stamp.human_id);
  }
}

}  // namespace coopnav
