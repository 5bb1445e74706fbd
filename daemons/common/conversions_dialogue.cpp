#include "common/conversions_dialogue.hpp"

#include <cmath>
#include <limits>

namespace coopnav {
namespace {

[[noreturn]] void reject(const std::string& why) { throw RejectedMessage(why); }

void requireStep(std::int64_t step) {
  if (step < -1) reject("step " + std::to_string(step) + " is neither -1 nor >= 0");
}

dialogue::SpeechAct speechActFromLcm(std::int8_t act) {
  if (act < utterance_t::ACT_INFORM_DIRECTION || act > utterance_t::ACT_THANK)
    reject("unknown speech_act " + std::to_string(act));
  return static_cast<dialogue::SpeechAct>(act);
}

}  // namespace

Side sideFromLcmDir(std::int8_t dir, const char* what) {
  switch (dir) {
    case situation_t::DIR_LEFT:
      return Side::kLeft;
    case situation_t::DIR_RIGHT:
      return Side::kRight;
    case situation_t::DIR_UNDEFINED:
      return Side::kUndefined;
    default:
      reject(std::string("unknown ") + what + " value " + std::to_string(dir));
  }
}

std::int8_t lcmDirFromSide(Side side) {
  switch (side) {
    case Side::kLeft:
      return situation_t::DIR_LEFT;
    case Side::kRight:
      return situation_t::DIR_RIGHT;
    case Side::kUndefined:
      break;
  }
  return situation_t::DIR_UNDEFINED;
}

Tristate tristateFromLcmPred(std::int8_t pred, const char* what) {
  switch (pred) {
    case situation_t::PRED_TRUE:
      return Tristate::kTrue;
    case situation_t::PRED_FALSE:
      return Tristate::kFalse;
    case situation_t::PRED_UNKNOWN:
      return Tristate::kUnknown;
    default:
      reject(std::string("unknown ") + what + " value " + std::to_string(pred));
  }
}

std::int8_t lcmPredFromTristate(Tristate t) {
  switch (t) {
    case Tristate::kTrue:
      return situation_t::PRED_TRUE;
    case Tristate::kFalse:
      return situation_t::PRED_FALSE;
    case Tristate::kUnknown:
      break;
  }
  return situation_t::PRED_UNKNOWN;
}

SituationForDecision situationForDecision(const situation_t& msg) {
  requireStep(msg.step);
  SituationForDecision out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  if (msg.crossing_status < situation_t::CROSSING_OK ||
      msg.crossing_status > situation_t::CROSSING_NO_REFERENCE)
    reject("unknown crossing_status " + std::to_string(msg.crossing_status));
  out.crossing_status = msg.crossing_status;
  auto& s = out.snapshot;
  if (msg.crossing_status == situation_t::CROSSING_OK) {
    // OK promises a crossing: a t_CROSS that is not a finite time from now is garbage, and a
    // decision on it could fire a round at the wrong moment.
    if (!std::isfinite(msg.t_cross_s) || msg.t_cross_s < 0.0)
      reject("crossing_status OK with t_cross_s " + std::to_string(msg.t_cross_s));
    s.t_cross_s = msg.t_cross_s;
  }
  s.human_needs_to_contribute =
      tristateFromLcmPred(msg.human_needs_to_contribute, "human_needs_to_contribute");
  s.human_is_constrained = tristateFromLcmPred(msg.human_is_constrained, "human_is_constrained");
  s.robot_is_constrained = tristateFromLcmPred(msg.robot_is_constrained, "robot_is_constrained");
  s.dir = sideFromLcmDir(msg.dir, "dir");
  if (!std::isnan(msg.d_h_m)) {
    if (!std::isfinite(msg.d_h_m) || msg.d_h_m < 0.0)
      reject("d_h_m " + std::to_string(msg.d_h_m) + " is not a distance");
    s.d_h_m = msg.d_h_m;
  }
  return out;
}

PathForDecision pathForDecision(const path_assessment_t& msg) {
  requireStep(msg.step);
  PathForDecision out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  if (msg.recording < path_assessment_t::REC_IDLE || msg.recording > path_assessment_t::REC_STOPPED)
    reject("unknown recording " + std::to_string(msg.recording));
  out.recording = msg.recording;
  if (msg.num_samples < 0 || msg.num_samples > path_assessment_t::MAX_SAMPLES ||
      static_cast<std::size_t>(msg.num_samples) != msg.ca_m.size())
    reject("num_samples " + std::to_string(msg.num_samples) + " invalid");
  for (double ca : msg.ca_m)
    if (!std::isfinite(ca)) reject("a CA sample is not finite");
  auto& p = out.snapshot;
  p.is_contributing = tristateFromLcmPred(msg.is_contributing, "is_contributing");
  if (std::isnan(msg.cm_m)) {
    if (p.is_contributing != Tristate::kUnknown)
      reject("cm_m is NaN (no samples) but is_contributing is known");
  } else {
    if (!std::isfinite(msg.cm_m)) reject("cm_m is infinite");
    p.cm_window_m = msg.cm_m;
  }
  return out;
}

utterance_t toLcm(const DialogueStamp& stamp, const dialogue::Utterance& u,
                  std::optional<double> t_cross_s) {
  utterance_t m;
  m.utime = stamp.utime;
  m.step = stamp.step;
  m.human_id = stamp.human_id;
  m.speech_act = static_cast<std::int8_t>(u.act);
  m.direction = lcmDirFromSide(u.direction);
  m.round = static_cast<std::int8_t>(u.round);
  m.t_cross_s = t_cross_s ? *t_cross_s : std::numeric_limits<double>::quiet_NaN();
  m.text = u.text;
  return m;
}

robot_action_t toLcm(const DialogueStamp& stamp, dialogue::RobotAction action,
                     const std::string& reason) {
  robot_action_t m;
  m.utime = stamp.utime;
  m.step = stamp.step;
  m.action = static_cast<std::int8_t>(action);
  m.human_id = stamp.human_id;
  m.reason = reason;
  return m;
}

path_assessor_control_t toLcm(const DialogueStamp& stamp, dialogue::RecorderCommand command,
                              const std::string& reason) {
  path_assessor_control_t m;
  m.utime = stamp.utime;
  m.step = stamp.step;
  m.human_id = stamp.human_id;
  m.command = static_cast<std::int8_t>(command);
  m.reason = reason;
  return m;
}

UtteranceMsg fromLcm(const utterance_t& msg) {
  requireStep(msg.step);
  UtteranceMsg out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  out.utterance.act = speechActFromLcm(msg.speech_act);
  out.utterance.direction = sideFromLcmDir(msg.direction, "direction");
  if (msg.round < 1 || msg.round > 3) reject("round " + std::to_string(msg.round) + " not 1..3");
  out.utterance.round = msg.round;
  out.utterance.text = msg.text;
  if (!std::isnan(msg.t_cross_s)) {
    if (!std::isfinite(msg.t_cross_s)) reject("t_cross_s is infinite");
    out.t_cross_s = msg.t_cross_s;
  }
  return out;
}

RobotActionMsg fromLcm(const robot_action_t& msg) {
  requireStep(msg.step);
  RobotActionMsg out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  if (msg.action != robot_action_t::ACTION_DOCK && msg.action != robot_action_t::ACTION_RESUME)
    reject("unknown action " + std::to_string(msg.action));
  out.action = static_cast<dialogue::RobotAction>(msg.action);
  out.reason = msg.reason;
  return out;
}

RecorderControlMsg fromLcm(const path_assessor_control_t& msg) {
  requireStep(msg.step);
  RecorderControlMsg out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  if (msg.command < path_assessor_control_t::COMMAND_START ||
      msg.command > path_assessor_control_t::COMMAND_RESET)
    reject("unknown command " + std::to_string(msg.command));
  out.command = static_cast<dialogue::RecorderCommand>(msg.command);
  out.reason = msg.reason;
  return out;
}

}  // namespace coopnav
