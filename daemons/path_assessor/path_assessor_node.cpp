#include "path_assessor_node.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "coopnav/geometry/track_continuity.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "profiles/forecast_profile.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"
#include "wire/assessment.hpp"

namespace coopnav {
namespace {

/// Paper §II-C: the human's initial shortest path; its start and first direction are where the
/// forecast measures the side step from. nullopt when the path has no segment of length > 0.
std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pathStartAndHeading(const Path2& path) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d d = path[i] - path.front();
    if (d.norm() > 1e-6) return std::make_pair(path.front(), Eigen::Vector2d(d.normalized()));
  }
  return std::nullopt;
}

/// The forecast profile named by the config, or nullopt when none is; a bad one stops the daemon.
std::optional<assessment::ForecastModel> loadForecast(const PathAssessorNodeConfig& config) {
  if (config.forecast_profile.empty()) return std::nullopt;
  try {
    return loadForecastProfile(config.forecast_profile);
  } catch (const std::exception& e) {
    throw StartupError(std::string("forecast_profile: ") + e.what());
  }
}

}  // namespace

void PathAssessorNodeConfig::resolvePaths(const std::string& base_dir) {
  forecast_profile = resolvePath(base_dir, forecast_profile);
}

PathAssessorNode::PathAssessorNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      forecast_(loadForecast(config)),
      clock_(runtime.limits().max_time_jump_s, runtime.limits().time_resync_messages),
      // Step k assesses after every recorder control of k-1 and every reference path up to k-1
      // are here (a lost one holds the step until the world publishes it again).
      steps_(runtime, StepNodeOptions{{{"dialogue_manager", -1, {channels::kPathAssessorControl}},
                                       {"band_source", -1, {channels::kReferencePaths}, true}},
                                      std::chrono::milliseconds(config.gate_timeout_ms)}) {
  runtime_.setLostStateNote(
      "the CA history and forecast tracks of the interactions in progress (their "
      "IsContributing and p_contributing stay unknown until the next START)");
  runtime_.setRunning();
  runtime_.subscribe<reference_paths_t>(
      channels::kReferencePaths,
      [this](const reference_paths_t& m, std::int64_t) { onReferencePaths(m); });
  runtime_.subscribe<path_assessor_control_t>(
      channels::kPathAssessorControl,
      [this](const path_assessor_control_t& m, std::int64_t) { onControl(m); });
  runtime_.subscribe<agent_states_t>(
      channels::kAgentStates, [this](const agent_states_t& m, std::int64_t) { onAgentStates(m); });
}

const assessment::PathRecorder* PathAssessorNode::recorder(std::int32_t human_id) const {
  const auto it = humans_.find(human_id);
  return it == humans_.end() || !it->second.seen_in_states ? nullptr : &it->second.recorder;
}

const assessment::CooperationForecaster* PathAssessorNode::forecaster(std::int32_t human_id) const {
  const auto it = humans_.find(human_id);
  return it == humans_.end() || !it->second.seen_in_states || !it->second.forecaster
             ? nullptr
             : &*it->second.forecaster;
}

std::size_t PathAssessorNode::referencePathsKept() const {
  std::size_t n = 0;
  for (const auto& [id, h] : humans_) n += h.references.size();
  return n;
}

PathAssessorNode::Human& PathAssessorNode::human(std::int32_t id) {
  auto it = humans_.find(id);
  if (it == humans_.end()) {
    it = humans_
             .emplace(
                 id,
                 Human{assessment::PathRecorder(config_.recorderConfig()),
                       forecast_ ? std::make_optional(assessment::CooperationForecaster(*forecast_))
                                 : std::nullopt,
                       {},
                       false,
                       0.0,
                       {0.0, 0.0},
                       {0.0, 0.0}})
             .first;
    hear(id);
  }
  return it->second;
}

void PathAssessorNode::hear(std::int32_t id) { recency_.touch(id, clock_.now().value_or(0)); }

void PathAssessorNode::offerTime(std::int64_t utime, const char* what) {
  // A jump is rejected: one message stamped INT64_MAX must not become the time base (every later
  // observation would be "before" it and ignored) nor age every human out. A message a little
  // behind is used as before: each recorder ignores what is not new.
  const bool ahead = clock_.take(utime, what, [&] {
    // A new time line (a new run, a restarted simulator, or a clock one bad first message had
    // set): the recorders' times are on the old one and cannot be compared with it.
    log().info(
        "path_assessor: message time resynced to {}: forgetting the {} humans of the previous "
        "time",
        utime, humans_.size());
    humans_.clear();
    recency_.clear();
    base_utime_ = utime;
    ++time_line_;
  });
  if (ahead && !base_utime_) base_utime_ = utime;
}

void PathAssessorNode::forgetHumans() {
  if (!clock_.now()) return;
  // A human not heard of for limits.forget_after_s (a minute) of message time has left (the
  // dialogue manager ended its interaction long before), and ids beyond limits.max_ids are a
  // flood: kept, recorders and paths grew with every id ever sent (docs/soak.md).
  const InputLimits& limits = runtime_.limits();
  const auto max_ids = static_cast<std::size_t>(std::max(limits.max_ids, 1));
  const IdRecency::Forgotten n = recency_.forgetOld(*clock_.now(), limits.forget_after_s, max_ids,
                                                    [&](std::int32_t id) { humans_.erase(id); });
  if (n.aged + n.over > 0)
    log().info(
        "path_assessor: forgot {} humans ({} not heard of for {} s, {} beyond limits.max_ids = "
        "{})",
        n.aged + n.over, n.aged, limits.forget_after_s, n.over, max_ids);
}

double PathAssessorNode::seconds(std::int64_t utime) {
  if (!base_utime_) base_utime_ = utime;
  return utimeDiffSeconds(utime, *base_utime_);
}

void PathAssessorNode::onReferencePaths(const reference_paths_t& msg) {
  steps_.input("band_source", channels::kReferencePaths, msg.step, "refs", [&] {
    const ReferencePaths paths = fromLcm(msg);  // throws RejectedMessage (NaN, bad counts)
    offerTime(paths.utime, "reference paths");  // throws RejectedMessage on a jump
    for (auto& e : paths.paths) {
      Human& h = human(e.agent_id);
      // Only a human not (yet) in the agent states is kept alive by its paths: one the tracker
      // lost is forgotten a minute later even if the band source still names it.
      if (!h.seen_in_states) hear(e.agent_id);
      if (e.path.empty()) continue;  // nothing to measure CA against; keep the previous one
      h.references[paths.step] = e.path;
      while (h.references.size() > kReferencesPerHuman) h.references.erase(h.references.begin());
    }
    forgetHumans();
  });
}

void PathAssessorNode::onControl(const path_assessor_control_t& msg) {
  // A repeat (the dialogue manager answered a re-published step again) is applied once.
  steps_.input(
      "dialogue_manager", channels::kPathAssessorControl, msg.step,
      std::to_string(msg.human_id) + "/" + std::to_string(msg.command), [&] {
        RecorderControl c = fromLcm(msg);  // throws RejectedMessage (command)
        c.reason = keptText(std::move(c.reason), runtime_.limits().maxTextBytes());
        if (c.step >= 0) {
          // A dialogue manager sends at most a few controls per human and step, and
          // they wait one step: more than limits.max_ids waiting is a flood.
          if (controls_.size() >= static_cast<std::size_t>(std::max(runtime_.limits().max_ids, 1)))
            throw RejectedMessage(std::to_string(controls_.size()) +
                                  " recorder controls wait already (limits.max_ids)");
          // Lockstep: applied at the start of step c.step + 1, in the gate's order, so
          // that a control re-sent after a loss has the effect it would have had.
          controls_.push_back(std::move(c));
          return;
        }
        applyControl(c);
      });
}

void PathAssessorNode::applyControlsBefore(std::int64_t step) {
  std::vector<RecorderControl> later;
  for (const RecorderControl& c : controls_) {
    if (step >= 0 && c.step >= step) {
      later.push_back(c);
      continue;
    }
    try {
      applyControl(c);
    } catch (const RejectedMessage& e) {
      runtime_.countRejected();
      log().warn("path_assessor: control of step {} rejected: {}", c.step, e.what());
    } catch (const DroppedMessage& e) {
      runtime_.countDropped();
      log().info("path_assessor: control of step {} dropped: {}", c.step, e.what());
    }
  }
  controls_ = std::move(later);
}

void PathAssessorNode::applyControl(const RecorderControl& c) {
  const auto it = humans_.find(c.human_id);
  if (it == humans_.end() || !it->second.seen_in_states || !base_utime_ || !clock_.now())
    throw DroppedMessage("control for unknown human id " + std::to_string(c.human_id));
  // Stamped far off the agent states' time, it would start or stop a recorder at a time its
  // observations never reach (a START at INT64_MAX: no sample ever after).
  if (std::fabs(utimeDiffSeconds(c.utime, *clock_.now())) > runtime_.limits().max_time_jump_s)
    throw RejectedMessage("control for human " + std::to_string(c.human_id) + ": " +
                          clock_.describe(c.utime) + " (over limits.max_time_jump_s)");
  Human& h = it->second;
  const double t_s = seconds(c.utime);
  switch (c.command) {
    case dialogue::RecorderCommand::kStart:
      // Paper §II-C: CA is measured from the human's initial shortest path: the reference path
      // in force when the recording starts.
      {
        // The latest reference path published at or before the control's step.
        const Path2* ref = nullptr;
        for (const auto& [step, path] : h.references)
          if (c.step < 0 || step <= c.step) ref = &path;
        if (!ref)
          throw DroppedMessage("START for human " + std::to_string(c.human_id) +
                               " without a reference path: recording not started");
        if (!h.recorder.start(t_s, *ref, assessment::lateralRoom(c.d_oh_m, c.d_h_m)))
          throw RejectedMessage("START for human " + std::to_string(c.human_id) +
                                ": unusable reference path or time");
        // The recorder accepted the path, so it has a segment: the forecast starts with it.
        if (h.forecaster) {
          if (const auto start = pathStartAndHeading(*ref))
            h.forecaster->start(start->first, start->second);
        }
        log().info("path_assessor: human {} recording started at step {} ({})", c.human_id, c.step,
                   c.reason);
        break;
      }
    case dialogue::RecorderCommand::kStop:
      h.recorder.stop(t_s);
      if (h.forecaster) h.forecaster->stop();
      log().info("path_assessor: human {} recording stopped at step {} ({})", c.human_id, c.step,
                 c.reason);
      break;
    case dialogue::RecorderCommand::kReset:
      h.recorder.reset(t_s);
      log().info("path_assessor: human {} window reset at step {} ({})", c.human_id, c.step,
                 c.reason);
      break;
  }
}

void PathAssessorNode::onAgentStates(const agent_states_t& msg) {
  steps_.open("world_sim", channels::kAgentStates, msg, [&]() -> StepNode::Work {
    const AgentStatesSnapshot states = fromLcm(msg);  // throws RejectedMessage
    offerTime(states.utime, "agent states");          // throws RejectedMessage on a jump
    return [this, states, time_line = time_line_](StepNode::Step& step) {
      if (time_line != time_line_) {
        // Accepted on a time line abandoned since (a resync while this step waited): its
        // observations would pin the new recorders to the old time.
        runtime_.countDropped();
        log().info("path_assessor: step {} dropped: its time {} is from before a time resync",
                   states.step, states.utime);
        return;
      }
      if (step.degraded())
        log().warn(
            "path_assessor: step {} assessed without {}'s ack: its recorder controls may "
            "be missing",
            states.step, step.missing());
      assess(states, step);
    };
  });
}

void PathAssessorNode::continueSwitchedIds(const AgentStatesSnapshot& states, double t_s) {
  std::set<std::int32_t> here;
  for (const auto& a : states.humans) here.insert(a.id);
  std::vector<LostTrack> lost;
  for (const auto& [id, h] : humans_)
    if (!here.count(id) && h.seen_in_states &&
        h.recorder.state() != assessment::RecorderState::kIdle)
      lost.push_back({id, h.last_seen_s, h.position_m, h.velocity_m_s});
  for (const auto& a : states.humans) {
    if (lost.empty()) return;
    const auto it = humans_.find(a.id);
    if (it != humans_.end() && it->second.seen_in_states) continue;  // not a new id
    const auto old = continuedTrack(lost, t_s, a.pose.position());
    if (!old) continue;
    // The recording moves; the new id's reference paths (published for it already) stay its own.
    Human moved = std::move(humans_.at(*old));
    if (it != humans_.end())
      moved.references = std::move(it->second.references);
    else
      moved.references.clear();
    humans_.erase(*old);
    recency_.erase(*old);
    humans_.insert_or_assign(a.id, std::move(moved));
    log().info(
        "path_assessor: human {} continues human {} (a tracker id switch at step {}): its "
        "recording goes on",
        a.id, *old, states.step);
    lost.erase(
        std::remove_if(lost.begin(), lost.end(), [&](const LostTrack& l) { return l.id == *old; }),
        lost.end());
  }
}

void PathAssessorNode::assess(const AgentStatesSnapshot& states, StepNode::Step& step) {
  applyControlsBefore(states.step);
  runtime_.noteLogicTime(states.utime);
  const double t_s = seconds(states.utime);
  const Eigen::Vector2d robot_m = states.robot.pose.position();
  continueSwitchedIds(states, t_s);
  for (const AgentState& a : states.humans) {
    Human& h = human(a.id);
    hear(a.id);
    h.seen_in_states = true;
    h.last_seen_s = t_s;
    h.position_m = a.pose.position();
    h.velocity_m_s = {a.velocity.vx_m_s, a.velocity.vy_m_s};
    // Paper §II-C: one observation; the recorder samples CA on its fixed grid from these.
    if (!h.recorder.observe(t_s, a.pose.position(), robot_m))
      log().debug(
          "path_assessor: observation of human {} at step {} ignored (time not after "
          "the previous one)",
          a.id, states.step);
    if (h.forecaster) h.forecaster->observe(t_s, a.pose.position(), robot_m);
    PathAssessmentRecord rec;
    rec.utime = states.utime;
    rec.step = states.step;
    rec.human_id = a.id;
    rec.snapshot = h.recorder.snapshot();
    rec.window_ca_m = h.recorder.windowCa();
    rec.gamma = config_.recorder.gamma;
    rec.profile = config_.profile;
    rec.side_rule = h.recorder.config().side_rule;
    if (h.forecaster && !std::isnan(h.forecaster->pContributing()))
      rec.p_contributing = h.forecaster->pContributing();
    step.publish(channels::kPathAssessment, toLcm(rec));
  }
  // After the step's humans are heard: those absent for a minute are forgotten now.
  forgetHumans();
}

}  // namespace coopnav
