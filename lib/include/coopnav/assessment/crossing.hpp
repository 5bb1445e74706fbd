#pragma once
/// @file Crossing info of paper §II-B: where and when a robot band and one anticipated human band
/// come closest (i*, CP_h, CP_r, t_CROSS) and on which side the robot passes (Dir).
/// World frame, metres, radians; band times t_s are seconds from the bands' common start stamp.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav::assessment {

/// Outcome of the crossing computation; values mirror coopnav_situation_t.CROSSING_*.
enum class CrossingStatus : std::int8_t {
  kOk = 0,             ///< i*, CP_h, CP_r, t_CROSS and Dir are meaningful
  kBeyondHorizon = 1,  ///< still closing at the last common time: t_CROSS unknown (design-readings)
  kBadBands = 2,       ///< a band is too short, non-finite, has non-increasing times, or no overlap
};

const char* toString(CrossingStatus s);

/// Tuning of the crossing computation. Defaults in this one place.
struct CrossingConfig {
  /// [s] step of the common time grid both bands are resampled on (> 0).
  double grid_dt_s{0.05};
  /// [m] |cross(h, CP_r - CP_h)| below this is a dead-on course: Dir falls back (see below).
  double dir_tolerance_m{0.05};
  /// [s] how far past t_CROSS the Dir fallback looks at the robot band for a lateral move.
  double dir_lookahead_s{2.0};
  /// [m] decrease of distance over the last grid step that still counts as "closing".
  double closing_epsilon_m{1e-6};
  /// [s] longest time span (last pose time - first pose time) a band may have; a longer band is
  /// not a plan (kBadBands, reason naming this cap). Why: the common grid grows with the span
  /// (one point per grid_dt_s), so an unchecked span is an unbounded allocation; two 2-pose
  /// bands spanning 10^7 s asked for 2*10^8 points (> 1.9 GB). Planner bands cover a few seconds
  /// to ~40 s (a stretched robot band); 600 s is the band planner's own limit on anticipated
  /// horizons (other_horizon_s), so no band it may publish is refused.
  double max_band_span_s{600.0};
  /// Most points of the common time grid (overlap span / grid_dt_s, plus its end point); more is
  /// kBadBands, checked before anything is allocated. Why: the grid costs 16 bytes and two band
  /// interpolations per point, per human: 50000 points = 0.8 MB and ~6 ms a human, a bound on
  /// what one message can cost whatever grid_dt_s is. The default grid of a 600 s overlap has
  /// 12001 points; a 40 s band on the finest grid_dt_s (0.001 s) 40001.
  int max_grid_points{50000};
};

/// Crossing info of one human band against the robot band.
struct CrossingInfo {
  CrossingStatus status{CrossingStatus::kBadBands};
  /// Index of the closest approach on the common grid; -1 when status != kOk.
  int i_star{-1};
  /// [s] t_CROSS = t_{i*}, time from the bands' start stamp; nullopt unless status == kOk.
  std::optional<double> t_cross_s;
  /// [m] CP_h = H(t_{i*}), world frame; NaN unless status == kOk.
  Eigen::Vector2d cp_h{Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN())};
  /// [m] CP_r = R(t_{i*}), world frame; NaN unless status == kOk.
  Eigen::Vector2d cp_r{Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN())};
  /// [rad] the human band's (interpolated) heading at CP_h; NaN unless status == kOk.
  double human_heading_rad{std::numeric_limits<double>::quiet_NaN()};
  /// Side on which the robot passes the human, as the human sees it (design-readings, "Dir").
  Side dir{Side::kUndefined};
  /// True when Dir came from the fallback (robot band's later lateral motion), not from CP_r.
  bool dir_from_fallback{false};
  /// Number of common grid points compared (0 for bad bands; at most max_grid_points).
  int grid_size{0};
  /// Why the status is not kOk or Dir is undefined; "" otherwise.
  std::string reason;
};

/// Checks a band for the crossing computation: >= 2 poses, all finite, strictly increasing times.
/// Returns "" when valid, else a human-readable reason.
std::string validateBand(const Band& band);

/// Pose of a band at time t_s [s], linearly interpolated (theta along the shorter arc); clamped to
/// the first/last pose outside the band's time span. Precondition: validateBand(band) == "".
Pose2 interpolateBand(const Band& band, double t_s);

/// Computes the crossing info of one human band against the robot band (paper §II-B). Both bands
/// are resampled on a common grid t_lo + k * grid_dt_s over their overlapping time span (plus its
/// end point), so bands with different ΔT or pose counts are paired by time, never by index.
/// A band spanning more than config.max_band_span_s, or a grid of more than
/// config.max_grid_points, is kBadBands (checked before allocating). Call once per human.
CrossingInfo computeCrossing(const Band& robot_band, const Band& human_band,
                             const CrossingConfig& config = {});

}  // namespace coopnav::assessment
