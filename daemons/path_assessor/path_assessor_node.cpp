#include "path_assessor_node.hpp"

#include <utility>

#include "common/conversions_assessment.hpp"
#include "common/log.hpp"
#include "coopnav/path_assessment_t.hpp"

namespace coopnav {

PathAssessorNode::PathAssessorNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      gate_(runtime, StepGateOptions{{{"dialogue_manager", -1}},
                                     std::chrono::milliseconds(config.gate_timeout_ms),
                                     false}) {
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
    it =
        humans_.emplace(id, Human{assessment::PathRecorder(config_.recorderConfig()), {}, 0, false})
            .first;
  return it->second;
}

double PathAssessorNode::seconds(std::int64_t utime) {
  if (!base_utime_) base_utime_ = utime;
  return utimeDiffSeconds(utime, *base_utime_);
}

void PathAssessorNode::onReferencePaths(const reference_paths_t& msg) {
  const ReferencePaths paths = fromLcm(msg);  // throws RejectedMessage (NaN, bad counts)
  for (auto& e : paths.paths) {
    Human& h = human(e.agent_id);
    if (e.path.empty()) continue;  // nothing to measure CA against; keep the previous one
    h.reference = e.path;
    h.reference_revision = e.revision;
  }
}

void PathAssessorNode::onControl(const path_assessor_control_t& msg) {
  const RecorderControl c = fromLcm(msg);  // throws RejectedMessage on an unknown command
  const auto it = humans_.find(c.human_id);
  if (it == humans_.end() || !it->second.seen_in_states || !base_utime_)
    throw DroppedMessage("control for unknown human id " + std::to_string(c.human_id));
  Human& h = it->second;
  const double t_s = seconds(c.utime);
  switch (c.command) {
    case dialogue::RecorderCommand::kStart:
      // Paper §II-C: CA is measured from the human's initial shortest path: the reference path
      // in force when the recording starts.
      if (!h.reference)
        throw DroppedMessage("START for human " + std::to_string(c.human_id) +
                             " without a reference path: recording not started");
      if (!h.recorder.start(t_s, *h.reference))
        throw RejectedMessage("START for human " + std::to_string(c.human_id) +
                              ": unusable reference path or time");
      log().info("path_assessor: human {} recording started at step {} ({})", c.human_id, c.step,
                 c.reason);
      break;
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
  AgentStatesSnapshot states;
  try {
    states = fromLcm(msg);
  } catch (const RejectedMessage&) {
    // Still acknowledged, in its turn, so that a lockstep run goes on (docs/lockstep.md).
    const std::int64_t utime = msg.utime;
    const std::int64_t step = msg.step;
    gate_.submit(step,
                 [this, utime, step](bool, const std::string&) { runtime_.ackStep(utime, step); });
    throw;
  }
  gate_.submit(states.step, [this, states](bool degraded, const std::string& missing) {
    if (degraded)
      log().warn(
          "path_assessor: step {} assessed without {}'s ack: its recorder controls may "
          "be missing",
          states.step, missing);
    assess(states);
  });
}

void PathAssessorNode::assess(const AgentStatesSnapshot& states) {
  runtime_.noteLogicTime(states.utime);
  const double t_s = seconds(states.utime);
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
    runtime_.publish(channels::kPathAssessment, toLcm(rec));
  }
  runtime_.ackStep(states.utime, states.step);
}

}  // namespace coopnav
