#pragma once
/// @file Geometric assessment of paper §II-B: d_h, d_OH, d_OR, d_HR and the three predicates
/// HumanNeedsToContribute, HumanIsConstrained, RobotIsConstrained, each three-valued.
///
/// Unknown inputs are std::nullopt (NaN passed in a std::optional is also read as unknown).
/// +infinity is a KNOWN distance: "no obstacle within the server's range".
///
/// Kleene logic: RobotIsConstrained = (d_HR < τ_HR) ∧ (d_OR < τ_OR) is FALSE as soon as one
/// conjunct is known false, even if the other is unknown. This is exact logic (the conjunction is
/// false whatever the unknown value), and it is safe for the decision logic of §II-D: FALSE only
/// ever leads to stating Dir, never to a dock; the flowchart's dock needs RobotIsConstrained ==
/// TRUE, the dialogue manager's precautionary dock at least UNKNOWN (lib/dialogue).

#include <Eigen/Core>
#include <optional>
#include <string>

#include "coopnav/assessment/crossing.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav::assessment {

/// Thresholds of §II-B / §III. Defaults in this one place.
struct SituationThresholds {
  /// [m] τ_h on d_h. Not given by the paper; 0.3 m = the human's body radius (CoHAN agent_radius
  /// 0.30): an anticipated deviation smaller than the human's own radius is within band-optimiser
  /// and tracker noise and is not something a person would notice being asked for, while the
  /// shifts that matter (Table I: 0.5–0.9 m by facilitating humans) are well above it.
  double tau_h_m{0.3};
  double tau_oh_m{1.0};  ///< [m] τ_OH, paper §III: latitude the human needs to contribute
  double tau_or_m{0.3};  ///< [m] τ_OR, paper §III: robot clearance to obstacles
  double tau_hr_m{1.2};  ///< [m] τ_HR, paper §III: social distance at the crossing point
  /// [m] Body radii: d_OH and d_OR are clearances of the body, not of its centre. Paper §III sets
  /// τ_OR = 0.3 m "to avoid collision with the obstacle", a clearance as CoHAN/TEB measure it from
  /// the footprint; measured from the centre, a 0.47 m robot could never be constrained.
  /// Defaults: CoHAN's PR2 footprint and agent radius.
  double robot_radius_m{0.47};
  double human_radius_m{0.3};
  /// [m] |CP_h - CP_r| below this: the CP_r -> CP_h direction is meaningless, so the half-plane
  /// normals fall back to the human's heading (design-readings, "Half-plane queries").
  double coincident_tolerance_m{0.05};
};

/// One SIDE query for the distance server: nearest obstacle o with (o - point) . normal >= 0.
struct HalfPlaneQuery {
  Eigen::Vector2d point{0.0, 0.0};   ///< [m] world frame (CP_h or CP_r)
  Eigen::Vector2d normal{0.0, 0.0};  ///< unit, world frame, pointing away from the other agent
};

/// The two SIDE queries of §II-B.
struct HalfPlaneQueries {
  HalfPlaneQuery human;  ///< for d_OH: at CP_h, normal from CP_r to CP_h (away from the robot)
  HalfPlaneQuery robot;  ///< for d_OR: at CP_r, normal from CP_h to CP_r (away from the human)
  /// True when CP_h ≈ CP_r and the normals came from the human's heading and Dir instead.
  bool from_heading_fallback{false};
};

/// Query specs for d_OH and d_OR. When |CP_h - CP_r| < coincident_tolerance_m, the human normal is
/// the normal to the human's heading on the side away from Dir, the robot's is its opposite.
/// nullopt when crossing.status != kOk, or CP_h ≈ CP_r while Dir is undefined (no side to use).
std::optional<HalfPlaneQueries> halfPlaneQueries(const CrossingInfo& crossing,
                                                 const SituationThresholds& thresholds = {});

/// Converts a distance-server answer (from the agent's centre) into a d_OH / d_OR value, the
/// clearance of a body of `body_radius_m`: kOk -> max(0, distance - radius), kInObstacle -> 0,
/// kNotFound -> +inf (known: nothing within range); any other status -> nullopt (unknown).
std::optional<double> obstacleDistanceFrom(const DistanceResult& result,
                                           double body_radius_m = 0.0);

/// [m] Paper §II-B, d_h: unsigned distance from CP_h to the human's reference path.
/// nullopt when the path is empty or CP_h non-finite.
std::optional<double> distanceToReferencePath(const Eigen::Vector2d& cp_h, const Path2& reference);

/// Paper §II-B: HumanNeedsToContribute = d_h > τ_h (unknown when d_h is).
Tristate humanNeedsToContribute(std::optional<double> d_h_m, double tau_h_m);
/// Paper §II-B: HumanIsConstrained = d_OH < τ_OH (unknown when d_OH is; +inf -> false).
Tristate humanIsConstrained(std::optional<double> d_oh_m, double tau_oh_m);
/// Paper §II-B: RobotIsConstrained = d_HR < τ_HR ∧ d_OR < τ_OR, Kleene conjunction (see @file).
Tristate robotIsConstrained(std::optional<double> d_hr_m, std::optional<double> d_or_m,
                            double tau_hr_m, double tau_or_m);

/// Everything the situation assessor states about one human (one situation message).
struct SituationAssessment {
  std::optional<double> d_h_m;   ///< [m] nullopt = unknown
  std::optional<double> d_oh_m;  ///< [m] nullopt = unknown, +inf = no obstacle within range
  std::optional<double> d_or_m;  ///< [m] as d_oh_m
  std::optional<double> d_hr_m;  ///< [m] |CP_h - CP_r|; nullopt when the crossing is not kOk
  Tristate human_needs_to_contribute{Tristate::kUnknown};
  Tristate human_is_constrained{Tristate::kUnknown};
  Tristate robot_is_constrained{Tristate::kUnknown};
  /// Why something is unknown (semicolon-separated); "" when every predicate is known.
  std::string reason;
};

/// Geometric assessment of one human (paper §II-B). reference_path: the human's shortest path
/// (empty = not received -> d_h and HumanNeedsToContribute unknown). d_oh_m / d_or_m: answers to
/// the halfPlaneQueries() (nullopt = server silent or erroring). Distances are ignored (unknown)
/// when crossing.status != kOk, since CP_h / CP_r would then be garbage.
SituationAssessment assessSituation(const CrossingInfo& crossing, const Path2& reference_path,
                                    std::optional<double> d_oh_m, std::optional<double> d_or_m,
                                    const SituationThresholds& thresholds = {});

}  // namespace coopnav::assessment
