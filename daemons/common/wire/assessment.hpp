#pragma once
/// @file lcmtypes <-> lib/ types of the assessment area: situation_t (situation assessor ->
/// dialogue manager), path_assessment_t (path assessor -> dialogue manager) and
/// path_assessor_control_t (dialogue manager -> path assessor). Same rules as conversions.hpp:
/// `fromLcm` validates and throws RejectedMessage with the reason; `toLcm` sets every count.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/assessment/crossing.hpp"
#include "coopnav/assessment/path_assessment.hpp"
#include "coopnav/assessment/situation.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// Everything one situation_t says about one human at one bands message.
struct SituationRecord {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int32_t human_id{0};
  /// Crossing info (§II-B). Only status, i_star, t_cross_s, cp_h, cp_r and dir travel on the wire.
  assessment::CrossingInfo crossing;
  /// False: the human had no reference path (wire: CROSSING_NO_REFERENCE when the crossing is ok).
  bool has_reference{true};
  assessment::SituationAssessment assessment;
  assessment::SituationThresholds thresholds;
  /// Copied from the bands assessed (bands_t.ROOM_* for this human, velocity_command_t.MODE_*).
  std::int8_t room_plan{bands_t::ROOM_UNKNOWN};
  std::int8_t robot_mode{velocity_command_t::MODE_IDLE};
};

/// crossing_status on the wire: the lib's CrossingStatus, except that an ok crossing of a human
/// without reference path is CROSSING_NO_REFERENCE (its crossing fields are still filled in).
situation_t toLcm(const SituationRecord& r);
/// Rejects unknown enum values, a t_cross_s < 0 and CROSSING_OK with non-finite crossing points.
SituationRecord fromLcm(const situation_t& msg);
/// What the decision logic reads from a situation message (validated as fromLcm).
dialogue::SituationSnapshot situationSnapshotFromLcm(const situation_t& msg);

/// Everything one path_assessment_t says about one human at one agent-states message.
struct PathAssessmentRecord {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int32_t human_id{0};
  assessment::PathAssessmentSnapshot snapshot;
  /// [m] CA values of the decision window (since the last reset), oldest first. toLcm keeps only
  /// the newest path_assessment_t::MAX_SAMPLES of them; fromLcm gives what the message carried.
  std::vector<double> window_ca_m;
  double gamma{0.98};
  std::string profile{"paper"};  ///< assessment profile in force (path_assessor `profile`)
  assessment::SideRule side_rule{assessment::SideRule::kPathSide};
  /// Forecast (assessment/forecast.hpp): probability in [0, 1] that the human will have made room
  /// by the crossing; nullopt = unknown (NaN on the wire).
  std::optional<double> p_contributing;
};

path_assessment_t toLcm(const PathAssessmentRecord& r);
/// Rejects unknown enum values, counts out of bounds, non-finite CA values, a gamma outside
/// (0, 1], a CM that is NaN while samples are claimed, or a profile name that is empty, longer
/// than MAX_PROFILE_LENGTH or not [A-Za-z0-9_-], or a p_contributing that is neither NaN nor in
/// [0, 1].
PathAssessmentRecord fromLcm(const path_assessment_t& msg);
/// What the decision logic reads from a path assessment (window since the last reset, and the
/// forecast p_contributing, nullopt when NaN).
dialogue::PathSnapshot pathSnapshotFromLcm(const path_assessment_t& msg);

/// Paper §II-C, CM for another γ (the γ sweep figure), from the CA values a path assessment
/// carries. Equal to the published cm_m for msg.gamma when the message carries the whole window
/// (num_samples == window_samples, i.e. fewer than MAX_SAMPLES samples); nullopt when it carries
/// none or γ is not > 0. For interaction-wide sweeps use PathRecorder::interactionCa() with
/// assessment::discountedMean directly.
std::optional<double> cmForGamma(const path_assessment_t& msg, double gamma);

/// One recorder command (coopnav_path_assessor_control_t).
struct RecorderControl {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int32_t human_id{0};
  dialogue::RecorderCommand command{dialogue::RecorderCommand::kStart};
  std::string reason;
  /// [m] START: the decision's d_OH and d_h (the room TauMode::kRoom judges by); nullopt unknown.
  std::optional<double> d_oh_m;
  std::optional<double> d_h_m;
};

path_assessor_control_t toLcm(const RecorderControl& c);
/// Rejects an unknown command value and a negative (or -inf) d_OH / d_h, or an infinite d_h.
RecorderControl fromLcm(const path_assessor_control_t& msg);

}  // namespace coopnav
