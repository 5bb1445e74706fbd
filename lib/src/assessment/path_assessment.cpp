#include "coopnav/assessment/path_assessment.hpp"

#include <algorithm>
#include <cmath>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::assessment {

namespace {

// Grid times within this of an observation count as coinciding with it (float noise of k * dt).
constexpr double kTimeEps_s = 1e-9;

}  // namespace

std::optional<double> discountedMean(const std::vector<double>& ca_m, double gamma) {
  if (ca_m.empty() || !std::isfinite(gamma) || !(gamma > 0.0)) return std::nullopt;
  // Paper §II-C: CM = Σ_{i=1..N} γ^(N−i) CA_i / Σ_{i=1..N} γ^(N−i).
  // Evaluated by Horner's scheme so that no power of γ is ever formed: for γ <= 1 from the oldest
  // sample (num <- γ num + CA_i keeps every partial sum bounded by N max|CA|); for γ > 1 the same
  // ratio scaled by γ^-(N−1), i.e. weights (1/γ)^(i−1), from the newest sample.
  double num = 0.0;
  double den = 0.0;
  if (gamma <= 1.0) {
    for (double ca : ca_m) {
      num = gamma * num + ca;
      den = gamma * den + 1.0;
    }
  } else {
    const double beta = 1.0 / gamma;
    for (auto it = ca_m.rbegin(); it != ca_m.rend(); ++it) {
      num = beta * num + *it;
      den = beta * den + 1.0;
    }
  }
  return num / den;
}

Tristate isContributing(std::optional<double> cm_m, double tau_m) {
  // Paper §II-C: IsContributing = CM > τ.
  if (!cm_m || std::isnan(*cm_m)) return Tristate::kUnknown;
  return toTristate(*cm_m > tau_m);
}

const char* toString(TauMode m) {
  switch (m) {
    case TauMode::kFixed:
      return "fixed";
    case TauMode::kRoom:
      return "room";
  }
  return "?";
}

std::optional<TauMode> tauModeFromString(const std::string& name) {
  for (const TauMode m : {TauMode::kFixed, TauMode::kRoom})
    if (name == toString(m)) return m;
  return std::nullopt;
}

std::optional<double> lateralRoom(std::optional<double> d_oh_m, std::optional<double> d_h_m) {
  if (!d_oh_m || !d_h_m || std::isnan(*d_oh_m) || std::isnan(*d_h_m)) return std::nullopt;
  if (*d_oh_m < 0.0 || *d_h_m < 0.0 || std::isinf(*d_h_m)) return std::nullopt;
  return *d_oh_m + *d_h_m;  // +inf stays +inf: no obstacle within range on that side
}

double roomTau(double tau_m, std::optional<double> room_m, double room_fraction, double floor_m) {
  if (!room_m || std::isnan(*room_m)) return tau_m;
  return std::min(tau_m, std::max(floor_m, room_fraction * *room_m));
}

const char* toString(SideRule r) {
  switch (r) {
    case SideRule::kPathSide:
      return "path_side";
    case SideRule::kHumanSide:
      return "human_side";
  }
  return "?";
}

std::optional<SideRule> sideRuleFromString(const std::string& name) {
  for (const SideRule r : {SideRule::kPathSide, SideRule::kHumanSide})
    if (name == toString(r)) return r;
  return std::nullopt;
}

std::optional<ContributionSample> contributionAt(const Path2& reference_path,
                                                 const Eigen::Vector2d& human_m,
                                                 const Eigen::Vector2d& robot_m,
                                                 Side previous_robot_side, double side_deadband_m,
                                                 SideRule rule) {
  const auto proj_h = projectOntoPath(reference_path, human_m);
  const auto proj_r = projectOntoPath(reference_path, robot_m);
  if (!proj_h || !proj_r) return std::nullopt;
  ContributionSample s;
  s.human_offset_m = proj_h->signed_distance_m;
  const double robot_offset_m = proj_r->signed_distance_m;
  if (rule == SideRule::kHumanSide) {
    const double rel_m = robot_offset_m - s.human_offset_m;  // robot relative to the human
    if (std::abs(rel_m) > side_deadband_m) {
      s.robot_side = rel_m > 0.0 ? Side::kLeft : Side::kRight;
      s.side_from_path = true;
    } else {
      s.robot_side = previous_robot_side;  // hysteresis: level with the human across the path
    }
  } else if (std::abs(robot_offset_m) > side_deadband_m) {
    s.robot_side = robot_offset_m > 0.0 ? Side::kLeft : Side::kRight;
    s.side_from_path = true;
  } else if (previous_robot_side != Side::kUndefined) {
    s.robot_side = previous_robot_side;  // hysteresis: robot back near the path
    s.side_from_path = true;
  } else {
    const double rel_m = robot_offset_m - s.human_offset_m;  // robot relative to the human
    if (std::abs(rel_m) > side_deadband_m) s.robot_side = rel_m > 0.0 ? Side::kLeft : Side::kRight;
  }
  // Paper §II-C / Fig. 4, CA_i: distance from the initial shortest path, signed > 0 on the side
  // away from the robot (design-readings, "CA sign"). Left offsets are > 0, so a robot on the left
  // makes right (negative) offsets positive contributions.
  // Under kHumanSide the same: the human's offset signed away from the side the robot is on.
  if (s.robot_side == Side::kLeft) s.ca_m = -s.human_offset_m;
  if (s.robot_side == Side::kRight) s.ca_m = s.human_offset_m;
  return s;
}

PathRecorder::PathRecorder(const PathAssessorConfig& config) : config_(config) {}

bool PathRecorder::start(double t_s, const Path2& reference_path, std::optional<double> room_m) {
  if (reference_path.empty() || !std::isfinite(t_s)) return false;
  for (const auto& p : reference_path) {
    if (!p.allFinite()) return false;
  }
  state_ = RecorderState::kRecording;
  reference_ = reference_path;
  room_m_ = room_m && !std::isnan(*room_m) && *room_m >= 0.0 ? room_m : std::nullopt;
  samples_.clear();
  start_t_s_ = t_s;
  next_k_ = 0;
  stop_t_s_.reset();
  reset_t_s_.reset();
  robot_side_memory_ = Side::kUndefined;
  sampleDue();
  return true;
}

void PathRecorder::stop(double t_s) {
  if (state_ != RecorderState::kRecording || !std::isfinite(t_s)) return;
  state_ = RecorderState::kStopped;
  stop_t_s_ = t_s;
  while (!samples_.empty() && samples_.back().t_s > t_s + kTimeEps_s) samples_.pop_back();
  sampleDue();  // grid times up to t_s that observations already cover
}

void PathRecorder::reset(double t_s) {
  if (std::isfinite(t_s)) reset_t_s_ = t_s;
}

bool PathRecorder::observe(double t_s, const Eigen::Vector2d& human_m,
                           const Eigen::Vector2d& robot_m) {
  if (!std::isfinite(t_s) || !human_m.allFinite() || !robot_m.allFinite()) return false;
  if (!history_.empty() && !(t_s > history_.back().t_s)) return false;
  history_.push_back({t_s, human_m, robot_m});
  sampleDue();
  while (history_.size() > 1 && history_[1].t_s < t_s - config_.history_s) history_.pop_front();
  return true;
}

void PathRecorder::sampleDue() {
  if (history_.empty() || !(config_.sample_period_s > 0.0)) return;
  const bool sampling = state_ == RecorderState::kRecording ||
                        (state_ == RecorderState::kStopped && stop_t_s_.has_value());
  if (!sampling) return;
  const double latest_t_s = history_.back().t_s;
  for (;;) {
    const double t_k = start_t_s_ + static_cast<double>(next_k_) * config_.sample_period_s;
    if (stop_t_s_ && t_k > *stop_t_s_ + kTimeEps_s) return;
    if (t_k > latest_t_s + kTimeEps_s) return;
    if (t_k < history_.front().t_s - kTimeEps_s) {
      // No observation that early (start stamped before the data): skip to the first covered one.
      next_k_ = std::max(
          next_k_ + 1, static_cast<long>(std::ceil(
                           (history_.front().t_s - start_t_s_) / config_.sample_period_s - 1e-6)));
      continue;
    }
    // Bracketing observations a.t <= t_k <= b.t; interpolate linearly between them.
    std::size_t b = 0;
    while (history_[b].t_s < t_k - kTimeEps_s) ++b;
    if (b > 0 && history_[b].t_s - history_[b - 1].t_s > config_.max_gap_s &&
        history_[b].t_s > t_k + kTimeEps_s) {
      // Nothing is known of the human inside a gap: go to the first grid time at its end (one
      // step, not one per grid time: a clock jumping years ahead must not mean 10^10 samples).
      next_k_ = std::max(next_k_ + 1,
                         static_cast<long>(std::ceil(
                             (history_[b].t_s - start_t_s_) / config_.sample_period_s - 1e-6)));
      continue;
    }
    const Observation& ob = history_[b];
    Eigen::Vector2d human_m = ob.human_m;
    Eigen::Vector2d robot_m = ob.robot_m;
    if (b > 0 && ob.t_s > t_k + kTimeEps_s) {
      const Observation& oa = history_[b - 1];
      const double s = (t_k - oa.t_s) / (ob.t_s - oa.t_s);
      human_m = oa.human_m + s * (ob.human_m - oa.human_m);
      robot_m = oa.robot_m + s * (ob.robot_m - oa.robot_m);
    }
    const auto c = contributionAt(reference_, human_m, robot_m, robot_side_memory_,
                                  config_.side_deadband_m, config_.side_rule);
    if (c) {
      if (c->side_from_path) robot_side_memory_ = c->robot_side;
      samples_.push_back({t_k, c->ca_m, c->robot_side});
    }
    ++next_k_;
  }
}

std::size_t PathRecorder::windowBegin() const {
  if (!reset_t_s_) return 0;
  std::size_t i = 0;
  while (i < samples_.size() && samples_[i].t_s <= *reset_t_s_ + kTimeEps_s) ++i;
  return i;
}

std::vector<double> PathRecorder::windowCa() const {
  std::vector<double> out;
  for (std::size_t i = windowBegin(); i < samples_.size(); ++i) out.push_back(samples_[i].ca_m);
  return out;
}

std::vector<double> PathRecorder::interactionCa() const {
  std::vector<double> out;
  out.reserve(samples_.size());
  for (const auto& s : samples_) out.push_back(s.ca_m);
  return out;
}

PathAssessmentSnapshot PathRecorder::snapshot() const {
  PathAssessmentSnapshot snap;
  snap.state = state_;
  const std::vector<double> window = windowCa();
  snap.window_samples = window.size();
  snap.tau_mode = config_.tau_mode;
  snap.tau_fixed_m = config_.tau_m;
  snap.room_m = room_m_;
  snap.tau_room_m =
      roomTau(config_.tau_m, room_m_, config_.room_fraction, config_.room_tau_floor_m);
  snap.tau_m = config_.tau_mode == TauMode::kRoom ? snap.tau_room_m : snap.tau_fixed_m;
  snap.cm_window_m = discountedMean(window, config_.gamma);
  snap.is_contributing_window = isContributing(snap.cm_window_m, snap.tau_m);
  snap.interaction_samples = samples_.size();
  snap.cm_interaction_m = discountedMean(interactionCa(), config_.gamma);
  snap.is_contributing_interaction = isContributing(snap.cm_interaction_m, snap.tau_m);
  return snap;
}

}  // namespace coopnav::assessment
