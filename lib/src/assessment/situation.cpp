#include "coopnav/assessment/situation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::assessment {

namespace {

// NaN inside an optional is still "unknown"; +inf stays a known "nothing within range".
std::optional<double> known(std::optional<double> v) {
  if (!v || std::isnan(*v)) return std::nullopt;
  return v;
}

void appendReason(std::string& reason, const std::string& what) {
  if (!reason.empty()) reason += "; ";
  reason += what;
}

}  // namespace

std::optional<HalfPlaneQueries> halfPlaneQueries(const CrossingInfo& crossing,
                                                 const SituationThresholds& thresholds) {
  if (crossing.status != CrossingStatus::kOk) return std::nullopt;
  HalfPlaneQueries q;
  q.human.point = crossing.cp_h;
  q.robot.point = crossing.cp_r;
  const Eigen::Vector2d r_to_h = crossing.cp_h - crossing.cp_r;
  const double d_m = r_to_h.norm();
  if (d_m >= thresholds.coincident_tolerance_m) {
    // Paper §II-B, d_OH "away from the robot": normal from CP_r to CP_h; d_OR "away from the
    // human": normal from CP_h to CP_r (design-readings, "Half-plane queries").
    q.human.normal = r_to_h / d_m;
    q.robot.normal = -q.human.normal;
    return q;
  }
  if (crossing.dir == Side::kUndefined) return std::nullopt;
  // CP_h ≈ CP_r: the human moves away from the robot, i.e. to the side opposite Dir; the normal
  // on the human's left is its heading rotated by +90°.
  const Eigen::Vector2d h = headingVector(crossing.human_heading_rad);
  const Eigen::Vector2d left{-h.y(), h.x()};
  q.human.normal = crossing.dir == Side::kLeft ? Eigen::Vector2d(-left) : left;
  q.robot.normal = -q.human.normal;
  q.from_heading_fallback = true;
  return q;
}

std::optional<double> obstacleDistanceFrom(const DistanceResult& result, double body_radius_m) {
  switch (result.status) {
    case DistanceStatus::kOk:
      return std::max(0.0, result.distance_m - body_radius_m);
    case DistanceStatus::kInObstacle:
      return 0.0;
    case DistanceStatus::kNotFound:
      return std::numeric_limits<double>::infinity();
    default:
      return std::nullopt;
  }
}

std::optional<double> distanceToReferencePath(const Eigen::Vector2d& cp_h, const Path2& reference) {
  // Paper §II-B: d_h = deviation of the anticipated human band at CP_h from its shortest path.
  const auto proj = projectOntoPath(reference, cp_h);
  if (!proj) return std::nullopt;
  return proj->distance_m;
}

Tristate humanNeedsToContribute(std::optional<double> d_h_m, double tau_h_m) {
  // Paper §II-B: HumanNeedsToContribute = d_h > τ_h.
  d_h_m = known(d_h_m);
  if (!d_h_m) return Tristate::kUnknown;
  return toTristate(*d_h_m > tau_h_m);
}

Tristate humanIsConstrained(std::optional<double> d_oh_m, double tau_oh_m) {
  // Paper §II-B: HumanIsConstrained = d_OH < τ_OH.
  d_oh_m = known(d_oh_m);
  if (!d_oh_m) return Tristate::kUnknown;
  return toTristate(*d_oh_m < tau_oh_m);
}

Tristate robotIsConstrained(std::optional<double> d_hr_m, std::optional<double> d_or_m,
                            double tau_hr_m, double tau_or_m) {
  // Paper §II-B: RobotIsConstrained = d_HR < τ_HR ∧ d_OR < τ_OR, with Kleene ∧ (header @file).
  d_hr_m = known(d_hr_m);
  d_or_m = known(d_or_m);
  const Tristate close = d_hr_m ? toTristate(*d_hr_m < tau_hr_m) : Tristate::kUnknown;
  const Tristate tight = d_or_m ? toTristate(*d_or_m < tau_or_m) : Tristate::kUnknown;
  if (close == Tristate::kFalse || tight == Tristate::kFalse) return Tristate::kFalse;
  if (close == Tristate::kTrue && tight == Tristate::kTrue) return Tristate::kTrue;
  return Tristate::kUnknown;
}

SituationAssessment assessSituation(const CrossingInfo& crossing, const Path2& reference_path,
                                    std::optional<double> d_oh_m, std::optional<double> d_or_m,
                                    const SituationThresholds& thresholds) {
  SituationAssessment a;
  if (crossing.status != CrossingStatus::kOk) {
    appendReason(a.reason, std::string("crossing ") + toString(crossing.status) +
                               (crossing.reason.empty() ? "" : ": " + crossing.reason));
  } else {
    if (!crossing.reason.empty()) appendReason(a.reason, crossing.reason);  // e.g. Dir undefined
    if (reference_path.empty()) {
      appendReason(a.reason, "no reference path for the human");
    } else {
      a.d_h_m = distanceToReferencePath(crossing.cp_h, reference_path);
      if (!a.d_h_m) appendReason(a.reason, "d_h not computable");
    }
    // Paper §II-B: d_HR = |CP_h - CP_r|.
    a.d_hr_m = (crossing.cp_h - crossing.cp_r).norm();
    a.d_oh_m = known(d_oh_m);
    a.d_or_m = known(d_or_m);
    if (!a.d_oh_m) appendReason(a.reason, "d_OH unknown (no distance answer)");
    if (!a.d_or_m) appendReason(a.reason, "d_OR unknown (no distance answer)");
  }
  a.human_needs_to_contribute = humanNeedsToContribute(a.d_h_m, thresholds.tau_h_m);
  a.human_is_constrained = humanIsConstrained(a.d_oh_m, thresholds.tau_oh_m);
  a.robot_is_constrained =
      robotIsConstrained(a.d_hr_m, a.d_or_m, thresholds.tau_hr_m, thresholds.tau_or_m);
  return a;
}

}  // namespace coopnav::assessment
