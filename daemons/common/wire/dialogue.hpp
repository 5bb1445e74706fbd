#pragma once
/// @file lcmtypes <-> lib/dialogue types of what the dialogue manager emits: utterance_t and
/// robot_action_t (path_assessor_control_t, situation_t and path_assessment_t are in
/// conversions_assessment.hpp). Readers validate and throw RejectedMessage with the reason
/// (unknown enum values, a step below -1, an infinite t_CROSS); NaN t_CROSS becomes nullopt.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/dialogue/decision.hpp"
#include "coopnav/dialogue/speech_timing.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// situation_t.DIR_* <-> Side. Unknown values throw RejectedMessage naming `what`.
Side sideFromLcmDir(std::int8_t dir, const char* what = "dir");
std::int8_t lcmDirFromSide(Side side);

/// situation_t.PRED_* <-> Tristate. Unknown values throw RejectedMessage naming `what`.
Tristate tristateFromLcmPred(std::int8_t pred, const char* what);
std::int8_t lcmPredFromTristate(Tristate t);

/// Who and when an input or output is about: message time, lockstep step, human.
struct DialogueStamp {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int32_t human_id{0};
};

/// Most ids of an utterance's group_ids (agent_states_t.MAX_HUMANS: a group of the scene).
inline constexpr std::size_t kMaxGroupIds = 64;
/// Emission. t_cross_s nullopt -> NaN on the wire (round 3); `slot`: when and whether it is said;
/// `group`: the other people with the human (crowd.hpp), at most kMaxGroupIds kept.
utterance_t toLcm(const DialogueStamp& stamp, const dialogue::Utterance& u,
                  std::optional<double> t_cross_s, const dialogue::SpeechSlot& slot,
                  const std::vector<std::int32_t>& group = {});
robot_action_t toLcm(const DialogueStamp& stamp, dialogue::RobotAction action,
                     const std::string& reason);
/// (path_assessor_control_t: conversions_assessment.hpp, RecorderControl.)

/// Reading the emitted messages back (consumers: world_sim's responsive humans, band_source,
/// tests). Unknown enum values, bad steps, and a speech start or duration that is not in
/// [0, kMaxSpeechSeconds] throw RejectedMessage.
struct UtteranceMsg {
  DialogueStamp stamp;
  dialogue::Utterance utterance;
  std::optional<double> t_cross_s;
  dialogue::SpeechSlot slot;
  std::vector<std::int32_t> group;  ///< group_ids: sorted, unique, without human_id
};
/// No sentence of the robot's takes longer, nor waits longer for the voice [s].
inline constexpr double kMaxSpeechSeconds = 120.0;
UtteranceMsg fromLcm(const utterance_t& msg);

struct RobotActionMsg {
  DialogueStamp stamp;
  dialogue::RobotAction action{dialogue::RobotAction::kDock};
  std::string reason;
};
RobotActionMsg fromLcm(const robot_action_t& msg);

}  // namespace coopnav
