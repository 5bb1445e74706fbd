#pragma once
/// @file lcmtypes <-> lib/dialogue types: what the dialogue manager reads (situation_t,
/// path_assessment_t, reduced to the decision's snapshots) and what it emits (utterance_t,
/// robot_action_t, path_assessor_control_t). Readers validate and throw RejectedMessage with the
/// reason (unknown enum values, non-finite numbers where the type allows none, inconsistent
/// crossing status); NaN where the type documents "NaN = unknown" becomes std::nullopt.

#include <cstdint>
#include <optional>
#include <string>

#include "common/runtime.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/utterance_t.hpp"

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

/// The part of a situation_t the decision reads.
struct SituationForDecision {
  DialogueStamp stamp;
  std::int8_t crossing_status{situation_t::CROSSING_OK};
  dialogue::SituationSnapshot snapshot;  ///< t_cross_s nullopt unless crossing_status is OK
};

/// Validates and converts. Rejects: step < -1, unknown crossing_status / dir / predicate values,
/// crossing_status OK with a t_CROSS that is NaN, infinite or negative, an infinite or negative
/// d_h.
SituationForDecision situationForDecision(const situation_t& msg);

/// The part of a path_assessment_t the decision reads (the window since the last reset).
struct PathForDecision {
  DialogueStamp stamp;
  std::int8_t recording{path_assessment_t::REC_IDLE};
  dialogue::PathSnapshot snapshot;
};

/// Validates and converts. Rejects: step < -1, unknown recording / is_contributing values,
/// num_samples outside [0, MAX_SAMPLES] or not matching ca_m, a non-finite CA sample, an infinite
/// CM, a CM that is NaN while is_contributing is known.
PathForDecision pathForDecision(const path_assessment_t& msg);

/// Emission. t_cross_s nullopt -> NaN on the wire (round 3).
utterance_t toLcm(const DialogueStamp& stamp, const dialogue::Utterance& u,
                  std::optional<double> t_cross_s);
robot_action_t toLcm(const DialogueStamp& stamp, dialogue::RobotAction action,
                     const std::string& reason);
path_assessor_control_t toLcm(const DialogueStamp& stamp, dialogue::RecorderCommand command,
                              const std::string& reason);

/// Reading the emitted messages back (consumers: world_sim's responsive humans, band_source,
/// path_assessor; tests). Unknown enum values and bad steps throw RejectedMessage.
struct UtteranceMsg {
  DialogueStamp stamp;
  dialogue::Utterance utterance;
  std::optional<double> t_cross_s;
};
UtteranceMsg fromLcm(const utterance_t& msg);

struct RobotActionMsg {
  DialogueStamp stamp;
  dialogue::RobotAction action{dialogue::RobotAction::kDock};
  std::string reason;
};
RobotActionMsg fromLcm(const robot_action_t& msg);

struct RecorderControlMsg {
  DialogueStamp stamp;
  dialogue::RecorderCommand command{dialogue::RecorderCommand::kStart};
  std::string reason;
};
RecorderControlMsg fromLcm(const path_assessor_control_t& msg);

}  // namespace coopnav
