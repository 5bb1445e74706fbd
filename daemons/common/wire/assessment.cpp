#include "wire/assessment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopnav {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

[[noreturn]] void reject(const std::string& why) { throw RejectedMessage(why); }

double orNaN(const std::optional<double>& v) { return v ? *v : kNaN; }

/// NaN = unknown; +inf is a known "nothing within range"; negative or -inf is garbage.
std::optional<double> distanceFromWire(double v, const char* what) {
  if (std::isnan(v)) return std::nullopt;
  if (!(v >= 0.0)) reject(std::string(what) + " is negative");
  return v;
}

Tristate tristateFromWire(std::int8_t v, const char* what) {
  switch (v) {
    case situation_t::PRED_UNKNOWN:
      return Tristate::kUnknown;
    case situation_t::PRED_FALSE:
      return Tristate::kFalse;
    case situation_t::PRED_TRUE:
      return Tristate::kTrue;
    default:
      reject(std::string(what) + " has an unknown value " + std::to_string(v));
  }
}

Side sideFromWire(std::int8_t v) {
  switch (v) {
    case situation_t::DIR_UNDEFINED:
      return Side::kUndefined;
    case situation_t::DIR_LEFT:
      return Side::kLeft;
    case situation_t::DIR_RIGHT:
      return Side::kRight;
    default:
      reject("dir has an unknown value " + std::to_string(v));
  }
}

}  // namespace

situation_t toLcm(const SituationRecord& r) {
  const auto& c = r.crossing;
  const auto& a = r.assessment;
  situation_t m;
  m.utime = r.utime;
  m.step = r.step;
  m.human_id = r.human_id;
  m.crossing_status = static_cast<std::int8_t>(c.status);
  if (c.status == assessment::CrossingStatus::kOk && !r.has_reference)
    m.crossing_status = situation_t::CROSSING_NO_REFERENCE;
  const bool ok = c.status == assessment::CrossingStatus::kOk;
  m.i_star = ok ? c.i_star : -1;
  m.t_cross_s = ok && c.t_cross_s ? *c.t_cross_s : kNaN;
  m.cp_h_x_m = ok ? c.cp_h.x() : kNaN;
  m.cp_h_y_m = ok ? c.cp_h.y() : kNaN;
  m.cp_r_x_m = ok ? c.cp_r.x() : kNaN;
  m.cp_r_y_m = ok ? c.cp_r.y() : kNaN;
  m.dir = ok ? static_cast<std::int8_t>(c.dir) : situation_t::DIR_UNDEFINED;
  m.d_h_m = orNaN(a.d_h_m);
  m.d_oh_m = orNaN(a.d_oh_m);
  m.d_or_m = orNaN(a.d_or_m);
  m.d_hr_m = orNaN(a.d_hr_m);
  m.human_needs_to_contribute = static_cast<std::int8_t>(a.human_needs_to_contribute);
  m.human_is_constrained = static_cast<std::int8_t>(a.human_is_constrained);
  m.robot_is_constrained = static_cast<std::int8_t>(a.robot_is_constrained);
  m.tau_h_m = r.thresholds.tau_h_m;
  m.tau_oh_m = r.thresholds.tau_oh_m;
  m.tau_or_m = r.thresholds.tau_or_m;
  m.tau_hr_m = r.thresholds.tau_hr_m;
  m.room_plan = r.room_plan;
  m.robot_mode = r.robot_mode;
  m.reason = a.reason;
  return m;
}

SituationRecord fromLcm(const situation_t& msg) {
  SituationRecord r;
  r.utime = msg.utime;
  r.step = msg.step;
  r.human_id = msg.human_id;
  auto& c = r.crossing;
  switch (msg.crossing_status) {
    case situation_t::CROSSING_OK:
      c.status = assessment::CrossingStatus::kOk;
      break;
    case situation_t::CROSSING_NO_REFERENCE:
      c.status = assessment::CrossingStatus::kOk;
      r.has_reference = false;
      break;
    case situation_t::CROSSING_BEYOND_HORIZON:
      c.status = assessment::CrossingStatus::kBeyondHorizon;
      break;
    case situation_t::CROSSING_BAD_BANDS:
      c.status = assessment::CrossingStatus::kBadBands;
      break;
    default:
      reject("crossing_status has an unknown value " + std::to_string(msg.crossing_status));
  }
  c.dir = sideFromWire(msg.dir);
  if (c.status == assessment::CrossingStatus::kOk) {
    const Eigen::Vector2d cp_h{msg.cp_h_x_m, msg.cp_h_y_m};
    const Eigen::Vector2d cp_r{msg.cp_r_x_m, msg.cp_r_y_m};
    if (!cp_h.allFinite() || !cp_r.allFinite()) reject("crossing ok but CP_h / CP_r not finite");
    if (!std::isfinite(msg.t_cross_s) || msg.t_cross_s < 0.0)
      reject("crossing ok but t_cross_s is not a finite time >= 0");
    if (msg.i_star < 0) reject("crossing ok but i_star < 0");
    c.cp_h = cp_h;
    c.cp_r = cp_r;
    c.t_cross_s = msg.t_cross_s;
    c.i_star = msg.i_star;
  }
  auto& a = r.assessment;
  a.d_h_m = distanceFromWire(msg.d_h_m, "d_h_m");
  a.d_oh_m = distanceFromWire(msg.d_oh_m, "d_oh_m");
  a.d_or_m = distanceFromWire(msg.d_or_m, "d_or_m");
  a.d_hr_m = distanceFromWire(msg.d_hr_m, "d_hr_m");
  a.human_needs_to_contribute =
      tristateFromWire(msg.human_needs_to_contribute, "human_needs_to_contribute");
  a.human_is_constrained = tristateFromWire(msg.human_is_constrained, "human_is_constrained");
  a.robot_is_constrained = tristateFromWire(msg.robot_is_constrained, "robot_is_constrained");
  a.reason = msg.reason;
  r.thresholds.tau_h_m = msg.tau_h_m;
  r.thresholds.tau_oh_m = msg.tau_oh_m;
  r.thresholds.tau_or_m = msg.tau_or_m;
  r.thresholds.tau_hr_m = msg.tau_hr_m;
  if (msg.room_plan < bands_t::ROOM_UNKNOWN || msg.room_plan > bands_t::ROOM_NONE)
    reject("room_plan has an unknown value " + std::to_string(msg.room_plan));
  if (msg.robot_mode < velocity_command_t::MODE_IDLE ||
      msg.robot_mode > velocity_command_t::MODE_RETREATING)
    reject("robot_mode has an unknown value " + std::to_string(msg.robot_mode));
  r.room_plan = msg.room_plan;
  r.robot_mode = msg.robot_mode;
  return r;
}

dialogue::SituationSnapshot situationSnapshotFromLcm(const situation_t& msg) {
  const SituationRecord r = fromLcm(msg);
  dialogue::SituationSnapshot s;
  s.t_cross_s = r.crossing.t_cross_s;
  s.human_needs_to_contribute = r.assessment.human_needs_to_contribute;
  s.human_is_constrained = r.assessment.human_is_constrained;
  s.robot_is_constrained = r.assessment.robot_is_constrained;
  s.dir = r.crossing.dir;
  s.d_h_m = r.assessment.d_h_m;
  s.d_oh_m = r.assessment.d_oh_m;
  s.d_hr_m = r.assessment.d_hr_m;
  s.reason = r.assessment.reason;
  s.room_plan = static_cast<dialogue::RoomPlan>(r.room_plan);
  s.robot_retreating = r.robot_mode == velocity_command_t::MODE_RETREATING;
  return s;
}

namespace {
/// A profile name: 1 to MAX_PROFILE_LENGTH of [A-Za-z0-9_-] (it is logged and compared).
bool isProfileName(const std::string& name) {
  if (name.empty() || name.size() > static_cast<std::size_t>(path_assessment_t::MAX_PROFILE_LENGTH))
    return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}
}  // namespace

path_assessment_t toLcm(const PathAssessmentRecord& r) {
  const auto& s = r.snapshot;
  path_assessment_t m;
  m.utime = r.utime;
  m.step = r.step;
  m.human_id = r.human_id;
  m.recording = static_cast<std::int8_t>(s.state);
  const std::size_t n = std::min<std::size_t>(r.window_ca_m.size(), path_assessment_t::MAX_SAMPLES);
  m.ca_m.assign(r.window_ca_m.end() - static_cast<std::ptrdiff_t>(n), r.window_ca_m.end());
  m.num_samples = static_cast<std::int16_t>(n);
  m.window_samples = static_cast<std::int32_t>(
      std::min<std::size_t>(s.window_samples, std::numeric_limits<std::int32_t>::max()));
  m.cm_m = orNaN(s.cm_window_m);
  m.is_contributing = static_cast<std::int8_t>(s.is_contributing_window);
  m.interaction_samples = static_cast<std::int32_t>(
      std::min<std::size_t>(s.interaction_samples, std::numeric_limits<std::int32_t>::max()));
  m.cm_interaction_m = orNaN(s.cm_interaction_m);
  m.is_contributing_interaction = static_cast<std::int8_t>(s.is_contributing_interaction);
  m.gamma = r.gamma;
  m.tau_m = s.tau_m;
  m.tau_mode = static_cast<std::int8_t>(s.tau_mode);
  m.tau_fixed_m = s.tau_fixed_m;
  m.room_m = orNaN(s.room_m);
  m.tau_room_m = s.tau_room_m;
  m.profile = r.profile;
  m.side_rule = static_cast<std::int8_t>(r.side_rule);
  m.p_contributing = orNaN(r.p_contributing);
  return m;
}

PathAssessmentRecord fromLcm(const path_assessment_t& msg) {
  if (msg.num_samples < 0 || msg.num_samples > path_assessment_t::MAX_SAMPLES)
    reject("CA sample count " + std::to_string(msg.num_samples) + " outside [0, " +
           std::to_string(path_assessment_t::MAX_SAMPLES) + "]");
  if (static_cast<std::size_t>(msg.num_samples) != msg.ca_m.size()) reject("CA count mismatch");
  if (msg.window_samples < msg.num_samples) reject("window_samples < num_samples");
  if (msg.interaction_samples < msg.window_samples) reject("interaction_samples < window_samples");
  if (!(msg.gamma > 0.0 && msg.gamma <= 1.0)) reject("gamma outside (0, 1]");
  if (!std::isfinite(msg.tau_m)) reject("tau_m is not finite");
  if (!std::isfinite(msg.tau_fixed_m)) reject("tau_fixed_m is not finite");
  if (!std::isfinite(msg.tau_room_m)) reject("tau_room_m is not finite");
  PathAssessmentRecord r;
  r.utime = msg.utime;
  r.step = msg.step;
  r.human_id = msg.human_id;
  switch (msg.recording) {
    case path_assessment_t::REC_IDLE:
      r.snapshot.state = assessment::RecorderState::kIdle;
      break;
    case path_assessment_t::REC_RECORDING:
      r.snapshot.state = assessment::RecorderState::kRecording;
      break;
    case path_assessment_t::REC_STOPPED:
      r.snapshot.state = assessment::RecorderState::kStopped;
      break;
    default:
      reject("recording has an unknown value " + std::to_string(msg.recording));
  }
  for (double ca : msg.ca_m)
    if (!std::isfinite(ca)) reject("a CA value is not finite");
  r.window_ca_m = msg.ca_m;
  r.snapshot.window_samples = static_cast<std::size_t>(msg.window_samples);
  r.snapshot.interaction_samples = static_cast<std::size_t>(msg.interaction_samples);
  if (std::isnan(msg.cm_m) != (msg.window_samples == 0))
    reject("cm_m must be NaN exactly when the window has no samples");
  if (std::isnan(msg.cm_interaction_m) != (msg.interaction_samples == 0))
    reject("cm_interaction_m must be NaN exactly when the interaction has no samples");
  if (std::isinf(msg.cm_m) || std::isinf(msg.cm_interaction_m)) reject("CM is infinite");
  if (!std::isnan(msg.cm_m)) r.snapshot.cm_window_m = msg.cm_m;
  if (!std::isnan(msg.cm_interaction_m)) r.snapshot.cm_interaction_m = msg.cm_interaction_m;
  r.snapshot.is_contributing_window = tristateFromWire(msg.is_contributing, "is_contributing");
  r.snapshot.is_contributing_interaction =
      tristateFromWire(msg.is_contributing_interaction, "is_contributing_interaction");
  r.gamma = msg.gamma;
  switch (msg.tau_mode) {
    case path_assessment_t::TAU_FIXED:
      r.snapshot.tau_mode = assessment::TauMode::kFixed;
      break;
    case path_assessment_t::TAU_ROOM:
      r.snapshot.tau_mode = assessment::TauMode::kRoom;
      break;
    default:
      reject("tau_mode has an unknown value " + std::to_string(msg.tau_mode));
  }
  r.snapshot.tau_m = msg.tau_m;
  r.snapshot.tau_fixed_m = msg.tau_fixed_m;
  r.snapshot.room_m = distanceFromWire(msg.room_m, "room_m");
  r.snapshot.tau_room_m = msg.tau_room_m;
  if (!isProfileName(msg.profile))
    reject("profile is not a name of 1 to " +
           std::to_string(path_assessment_t::MAX_PROFILE_LENGTH) + " letters, digits, - or _");
  r.profile = msg.profile;
  switch (msg.side_rule) {
    case path_assessment_t::SIDE_RULE_PATH:
      r.side_rule = assessment::SideRule::kPathSide;
      break;
    case path_assessment_t::SIDE_RULE_HUMAN:
      r.side_rule = assessment::SideRule::kHumanSide;
      break;
    default:
      reject("side_rule has an unknown value " + std::to_string(msg.side_rule));
  }
  // A probability: NaN (unknown) or in [0, 1]; ±inf and anything else is garbage.
  if (!std::isnan(msg.p_contributing)) {
    if (!(msg.p_contributing >= 0.0 && msg.p_contributing <= 1.0))
      reject("p_contributing is neither NaN nor in [0, 1]");
    r.p_contributing = msg.p_contributing;
  }
  return r;
}

dialogue::PathSnapshot pathSnapshotFromLcm(const path_assessment_t& msg) {
  const PathAssessmentRecord r = fromLcm(msg);
  dialogue::PathSnapshot s;
  s.cm_window_m = r.snapshot.cm_window_m;
  s.is_contributing = r.snapshot.is_contributing_window;
  s.p_contributing = r.p_contributing;
  return s;
}

std::optional<double> cmForGamma(const path_assessment_t& msg, double gamma) {
  const std::size_t n = std::min<std::size_t>(
      msg.ca_m.size(), static_cast<std::size_t>(std::max<std::int16_t>(msg.num_samples, 0)));
  return assessment::discountedMean(std::vector<double>(msg.ca_m.begin(), msg.ca_m.begin() + n),
                                    gamma);
}

path_assessor_control_t toLcm(const RecorderControl& c) {
  path_assessor_control_t m;
  m.utime = c.utime;
  m.step = c.step;
  m.human_id = c.human_id;
  m.command = static_cast<std::int8_t>(c.command);
  m.reason = c.reason;
  m.d_oh_m = orNaN(c.d_oh_m);
  m.d_h_m = orNaN(c.d_h_m);
  return m;
}

RecorderControl fromLcm(const path_assessor_control_t& msg) {
  RecorderControl c;
  c.utime = msg.utime;
  c.step = msg.step;
  c.human_id = msg.human_id;
  switch (msg.command) {
    case path_assessor_control_t::COMMAND_START:
      c.command = dialogue::RecorderCommand::kStart;
      break;
    case path_assessor_control_t::COMMAND_STOP:
      c.command = dialogue::RecorderCommand::kStop;
      break;
    case path_assessor_control_t::COMMAND_RESET:
      c.command = dialogue::RecorderCommand::kReset;
      break;
    default:
      reject("unknown recorder command " + std::to_string(msg.command));
  }
  c.reason = msg.reason;
  c.d_oh_m = distanceFromWire(msg.d_oh_m, "d_oh_m");
  c.d_h_m = distanceFromWire(msg.d_h_m, "d_h_m");
  if (c.d_h_m && std::isinf(*c.d_h_m)) reject("d_h_m is infinite");
  return c;
}

}  // namespace coopnav
