#include "wire/dialogue.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace coopnav {
namespace {

[[noreturn]] void reject(const std::string& why) { throw RejectedMessage(why); }

void requireStep(std::int64_t step) {
  if (step < -1) reject("step " + std::to_string(step) + " is neither -1 nor >= 0");
}

dialogue::SpeechAct speechActFromLcm(std::int8_t act) {
  if (act < utterance_t::ACT_INFORM_DIRECTION || act > utterance_t::ACT_INFORM_RESUMING)
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

utterance_t toLcm(const DialogueStamp& stamp, const dialogue::Utterance& u,
                  std::optional<double> t_cross_s, const dialogue::SpeechSlot& slot,
                  const std::vector<std::int32_t>& group) {
  utterance_t m;
  m.utime = stamp.utime;
  m.step = stamp.step;
  m.human_id = stamp.human_id;
  m.speech_act = static_cast<std::int8_t>(u.act);
  m.direction = lcmDirFromSide(u.direction);
  m.round = static_cast<std::int8_t>(u.round);
  m.t_cross_s = t_cross_s ? *t_cross_s : std::numeric_limits<double>::quiet_NaN();
  m.text = u.text;
  m.delivery = static_cast<std::int8_t>(slot.delivery);
  m.speech_start_s = slot.start_s;
  m.speech_duration_s = slot.duration_s;
  m.group_ids.assign(group.begin(),
                     group.begin() + static_cast<std::ptrdiff_t>(
                                         std::min<std::size_t>(group.size(), kMaxGroupIds)));
  m.n_group = static_cast<std::int16_t>(m.group_ids.size());
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
  if (msg.delivery < utterance_t::DELIVERY_SAID || msg.delivery > utterance_t::DELIVERY_CONTRADICTS)
    reject("unknown delivery " + std::to_string(msg.delivery));
  out.slot.delivery = static_cast<dialogue::Delivery>(msg.delivery);
  for (const auto& [name, v] : {std::pair{"speech_start_s", msg.speech_start_s},
                                std::pair{"speech_duration_s", msg.speech_duration_s}})
    if (!(v >= 0.0 && v <= kMaxSpeechSeconds))
      reject(std::string(name) + " " + std::to_string(v) + " not in [0, 120] s");
  out.slot.start_s = msg.speech_start_s;
  out.slot.duration_s = msg.speech_duration_s;
  if (msg.n_group < 0 || static_cast<std::size_t>(msg.n_group) > kMaxGroupIds ||
      msg.group_ids.size() != static_cast<std::size_t>(msg.n_group))
    reject("n_group " + std::to_string(msg.n_group) + " not in [0, 64]");
  for (std::size_t i = 0; i < msg.group_ids.size(); ++i) {
    if (msg.group_ids[i] == msg.human_id) reject("group_ids holds human_id itself");
    if (i > 0 && msg.group_ids[i] <= msg.group_ids[i - 1])
      reject("group_ids not sorted and unique");
  }
  out.group = msg.group_ids;
  return out;
}

RobotActionMsg fromLcm(const robot_action_t& msg) {
  requireStep(msg.step);
  RobotActionMsg out;
  out.stamp = {msg.utime, msg.step, msg.human_id};
  if (msg.action != robot_action_t::ACTION_DOCK && msg.action != robot_action_t::ACTION_RESUME &&
      msg.action != robot_action_t::ACTION_GO_FIRST && msg.action != robot_action_t::ACTION_SLOW)
    reject("unknown action " + std::to_string(msg.action));
  out.action = static_cast<dialogue::RobotAction>(msg.action);
  out.reason = msg.reason;
  return out;
}

}  // namespace coopnav
