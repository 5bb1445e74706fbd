#include "path_assessor_node.hpp"

#include <utility>

#include "coopnav/path_assessment_t.hpp"
#include "runtime/log.hpp"
#include "wire/assessment.hpp"

namespace coopnav {

PathAssessorNode::PathAssessorNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      // Step k assesses after every recorder control of k-1 and every reference path up to k-1
      // are here (a lost one holds the step until the world publishes it again).
      steps_(runtime, StepNodeOptions{{{"dialogue_manager", -1, {channels::kPathAssessorControl}},
                                       {"band_source", -1, {channels::kReferencePaths}, true}},
                                      std::chrono::milliseconds(config.gate_timeout_ms)}) {
  runtime_.setLostStateNote(
      "the CA history of the interactions in progress (their IsContributing stays unknown "
      "until the next START)");
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

PathAssessorNode::Human& PathAssessorNode::human(std::int32_t id) {
  auto it = humans_.find(id);
  if (it == humans_.end())
    it = humans_.emplace(id, Human{assessment::PathRecorder(config_.recorderConfig()), {}, false})
             .first;
  return it->second;
}

double PathAssessorNode::seconds(std::int64_t utime) {
  if (!base_utime_) base_utime_ = utime;
  return utimeDiffSeconds(utime, *base_utime_);
}

void PathAssessorNode::onReferencePaths(const reference_paths_t& msg) {
  steps_.input("band_source", channels::kReferencePaths, msg.step, "refs", [&] {
    const ReferencePaths paths = fromLcm(msg);  // throws RejectedMessage (NaN, bad counts)
    for (auto& e : paths.paths) {
      Human& h = human(e.agent_id);
      if (e.path.empty()) continue;  // nothing to measure CA against; keep the previous one
      h.references[paths.step] = e.path;
      // The START of a step still waiting needs at most the paths of a few steps back.
      while (h.references.size() > 16) h.references.erase(h.references.begin());
    }
  });
}

void PathAssessorNode::onControl(const path_assessor_control_t& msg) {
  // A repeat (the dialogue manager answered a re-published step again) is applied once.
  steps_.input("dialogue_manager", channels::kPathAssessorControl, msg.step,
               std::to_string(msg.human_id) + "/" + std::to_string(msg.command), [&] {
                 const RecorderControl c = fromLcm(msg);  // throws RejectedMessage (command)
                 if (c.step >= 0) {
                   // Lockstep: applied at the start of step c.step + 1, in the gate's order, so
                   // that a control re-sent after a loss has the effect it would have had.
                   controls_.push_back(c);
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
  if (it == humans_.end() || !it->second.seen_in_states || !base_utime_)
    throw DroppedMessage("control for unknown human id " + std::to_string(c.human_id));
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
        if (!h.recorder.start(t_s, *ref))
          throw RejectedMessage("START for human " + std::to_string(c.human_id) +
                                ": unusable reference path or time");
        log().info("path_assessor: human {} recording started at step {} ({})", c.human_id, c.step,
                   c.reason);
        break;
      }
    case dialogue::RecorderCommand::kStop:
      h.recorder.stop(t_s);
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
    return [this, states](StepNode::Step& step) {
      if (step.degraded())
        log().warn(
            "path_assessor: step {} assessed without {}'s ack: its recorder controls may "
            "be missing",
            states.step, step.missing());
      assess(states, step);
    };
  });
}

void PathAssessorNode::assess(const AgentStatesSnapshot& states, StepNode::Step& step) {
  applyControlsBefore(states.step);
  runtime_.noteLogicTime(states.utime);
  const double t_s = seconds(states.utime);
  // A human absent for a minute of message time has left (the dialogue manager ended its
  // interaction long before): its recorder is forgotten, so that memory does not grow with
  // every person the robot ever met (docs/soak.md).
  for (const AgentState& a : states.humans) last_seen_utime_[a.id] = states.utime;
  for (auto it = last_seen_utime_.begin(); it != last_seen_utime_.end();) {
    if (utimeDiffSeconds(states.utime, it->second) > kForgetHumanAfter_s) {
      humans_.erase(it->first);
      it = last_seen_utime_.erase(it);
    } else {
      ++it;
    }
  }
  const Eigen::Vector2d robot_m = states.robot.pose.position();
  for (const AgentState& a : states.humans) {
    Human& h = human(a.id);
    h.seen_in_states = true;
    // Paper §II-C: one observation; the recorder samples CA on its fixed grid from these.
    if (!h.recorder.observe(t_s, a.pose.position(), robot_m))
      log().debug(
          "path_assessor: observation of human {} at step {} ignored (time not after "
          "the previous one)",
          a.id, states.step);
    PathAssessmentRecord rec;
    rec.utime = states.utime;
    rec.step = states.step;
    rec.human_id = a.id;
    rec.snapshot = h.recorder.snapshot();
    rec.window_ca_m = h.recorder.windowCa();
    rec.gamma = config_.recorder.gamma;
    rec.tau_m = config_.recorder.tau_m;
    step.publish(channels::kPathAssessment, toLcm(rec));
  }
}

}  // namespace coopnav
