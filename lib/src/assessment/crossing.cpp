#include "coopnav/assessment/crossing.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::assessment {

namespace {

// Grid times closer than this to the overlap end are merged with it (float noise of k * dt).
constexpr double kTimeEps_s = 1e-9;

Side sideOf(double lateral_m, double tolerance_m) {
  if (lateral_m > tolerance_m) return Side::kLeft;
  if (lateral_m < -tolerance_m) return Side::kRight;
  return Side::kUndefined;
}

// A number for a reason: up to 10 digits as such, beyond in exponent form ("1e+300").
std::string number(double x) {
  std::ostringstream out;
  out << std::setprecision(10) << x;
  return out.str();
}

// "" when the band's time span is within config.max_band_span_s, else why not. Precondition:
// validateBand(band) == "" (finite, increasing times).
std::string checkSpan(const Band& band, const CrossingConfig& config) {
  const double span_s = band.poses.back().t_s - band.poses.front().t_s;  // may be +inf
  if (span_s <= config.max_band_span_s) return "";
  return "band spans " + number(span_s) + " s, more than max_band_span_s (" +
         number(config.max_band_span_s) + " s)";
}

}  // namespace

const char* toString(CrossingStatus s) {
  switch (s) {
    case CrossingStatus::kOk:
      return "ok";
    case CrossingStatus::kBeyondHorizon:
      return "beyond_horizon";
    case CrossingStatus::kBadBands:
      return "bad_bands";
  }
  return "?";
}

/// [m] bands beyond this are not of a robot's world (see validateBand).
constexpr double kMaxCoordinate_m = 1e6;

std::string validateBand(const Band& band) {
  if (band.poses.size() < 2) {
    return "band has " + std::to_string(band.poses.size()) + " poses (need >= 2)";
  }
  for (std::size_t i = 0; i < band.poses.size(); ++i) {
    const TimedPose& p = band.poses[i];
    if (!std::isfinite(p.t_s) || !isFinite(p.pose)) {
      return "non-finite pose or time at index " + std::to_string(i);
    }
    // Finite is not enough: a pose 10^300 m away (a tracker glitch) gave a crossing and a
    // definite HumanNeedsToContribute. No corridor is a thousand kilometres long.
    if (std::abs(p.pose.x_m) > kMaxCoordinate_m || std::abs(p.pose.y_m) > kMaxCoordinate_m) {
      return "pose farther than " + std::to_string(static_cast<long>(kMaxCoordinate_m)) +
             " m from the origin at index " + std::to_string(i);
    }
    if (i > 0 && !(p.t_s > band.poses[i - 1].t_s)) {
      return "times not increasing at index " + std::to_string(i);
    }
  }
  return "";
}

Pose2 interpolateBand(const Band& band, double t_s) {
  const auto& poses = band.poses;
  if (t_s <= poses.front().t_s) return poses.front().pose;
  if (t_s >= poses.back().t_s) return poses.back().pose;
  // First pose with time > t_s; the segment is [it - 1, it].
  const auto it = std::upper_bound(poses.begin(), poses.end(), t_s,
                                   [](double t, const TimedPose& p) { return t < p.t_s; });
  const TimedPose& a = *(it - 1);
  const TimedPose& b = *it;
  const double s = (t_s - a.t_s) / (b.t_s - a.t_s);
  Pose2 out;
  out.x_m = a.pose.x_m + s * (b.pose.x_m - a.pose.x_m);
  out.y_m = a.pose.y_m + s * (b.pose.y_m - a.pose.y_m);
  // Angle-aware: interpolate along the shorter arc so that pi -> -pi does not spin through 0.
  out.theta_rad = wrapAngle(a.pose.theta_rad + s * wrapAngle(b.pose.theta_rad - a.pose.theta_rad));
  return out;
}

CrossingInfo computeCrossing(const Band& robot_band, const Band& human_band,
                             const CrossingConfig& config) {
  CrossingInfo info;
  if (!(config.grid_dt_s > 0.0) || !std::isfinite(config.grid_dt_s)) {
    info.reason = "grid_dt_s must be > 0";
    return info;
  }
  if (std::string why = validateBand(robot_band); !why.empty()) {
    info.reason = "robot " + why;
    return info;
  }
  if (std::string why = validateBand(human_band); !why.empty()) {
    info.reason = "human " + why;
    return info;
  }
  if (std::string why = checkSpan(robot_band, config); !why.empty()) {
    info.reason = "robot " + why;
    return info;
  }
  if (std::string why = checkSpan(human_band, config); !why.empty()) {
    info.reason = "human " + why;
    return info;
  }
  const double t_lo_s = std::max(robot_band.poses.front().t_s, human_band.poses.front().t_s);
  const double t_hi_s = std::min(robot_band.poses.back().t_s, human_band.poses.back().t_s);
  // An overlap within the merging tolerance would leave a grid of one point (the end alone),
  // with no "previous point" for the closing test below.
  if (!(t_hi_s - t_lo_s > kTimeEps_s)) {
    info.reason = "bands share no time span";
    return info;
  }

  // Common time grid: t_lo + k dt, closed by the overlap end itself (CoHAN pairs poses by index,
  // which is wrong as soon as the bands' ΔT differ: the poses paired are then at different times).
  // Its size is bounded before it is allocated: first about, in double (a span of 10^300 s must not
  // overflow an integer), then exactly while it is built.
  const auto max_points = static_cast<std::size_t>(std::max(config.max_grid_points, 2));
  const double about_points = std::floor((t_hi_s - kTimeEps_s - t_lo_s) / config.grid_dt_s) + 2.0;
  const auto over_cap = [&] {
    info.reason = "the common time grid would have " + number(about_points) +
                  " points, more than max_grid_points (" + std::to_string(max_points) + ")";
    return info;
  };
  if (!(about_points <= static_cast<double>(max_points) + 1.0)) return over_cap();
  std::vector<double> grid_t_s;
  grid_t_s.reserve(std::min(static_cast<std::size_t>(about_points), max_points));
  for (std::size_t k = 0;; ++k) {
    const double t = t_lo_s + static_cast<double>(k) * config.grid_dt_s;
    if (t > t_hi_s - kTimeEps_s) break;
    if (grid_t_s.size() + 1 >= max_points) return over_cap();  // no room left for the end point
    grid_t_s.push_back(t);
  }
  grid_t_s.push_back(t_hi_s);
  info.grid_size = static_cast<int>(grid_t_s.size());  // <= max_grid_points, an int

  // Paper §II-B, crossing info: i* = argmin_i ||R(t_i) - H(t_i)|| (first minimum on ties).
  std::vector<double> dist_m(grid_t_s.size());
  std::size_t i_star = 0;
  for (std::size_t i = 0; i < grid_t_s.size(); ++i) {
    const Pose2 r = interpolateBand(robot_band, grid_t_s[i]);
    const Pose2 h = interpolateBand(human_band, grid_t_s[i]);
    dist_m[i] = (r.position() - h.position()).norm();
    if (dist_m[i] < dist_m[i_star]) i_star = i;
  }

  const std::size_t last = grid_t_s.size() - 1;
  if (i_star == last && dist_m[last] < dist_m[last - 1] - config.closing_epsilon_m) {
    // Closest at the horizon while still closing: the true crossing lies beyond the bands, so its
    // time is unknown, not the band's last time (design-readings, "Scale and horizon").
    info.status = CrossingStatus::kBeyondHorizon;
    info.reason =
        "agents still closing at the end of the common horizon (" + std::to_string(t_hi_s) + " s)";
    return info;
  }

  // Paper §II-B: CP_h = H(t_i*), CP_r = R(t_i*), t_CROSS = t_i*.
  const double t_star_s = grid_t_s[i_star];
  const Pose2 h_star = interpolateBand(human_band, t_star_s);
  info.status = CrossingStatus::kOk;
  info.i_star = static_cast<int>(i_star);
  info.t_cross_s = t_star_s;
  info.cp_h = h_star.position();
  info.cp_r = interpolateBand(robot_band, t_star_s).position();
  info.human_heading_rad = h_star.theta_rad;

  // Dir (design-readings): LEFT when cross(h, CP_r - CP_h) > 0, RIGHT when < 0, h the human's
  // heading at CP_h.
  const Eigen::Vector2d h = headingVector(h_star.theta_rad);
  info.dir = sideOf(cross2(h, info.cp_r - info.cp_h), config.dir_tolerance_m);
  if (info.dir != Side::kUndefined) return info;

  // Dead-on course: take the side the robot band moves to over the following poses, measured the
  // same way (lateral offset in the human's frame at CP_h), up to dir_lookahead_s after t_CROSS.
  const double t_end_s = std::min(robot_band.poses.back().t_s, t_star_s + config.dir_lookahead_s);
  for (long k = 1;; ++k) {
    const double t = t_star_s + static_cast<double>(k) * config.grid_dt_s;
    if (t > t_end_s + kTimeEps_s) break;
    const Side s = sideOf(cross2(h, interpolateBand(robot_band, t).position() - info.cp_h),
                          config.dir_tolerance_m);
    if (s != Side::kUndefined) {
      info.dir = s;
      info.dir_from_fallback = true;
      return info;
    }
  }
  info.reason = "Dir undefined: dead-on course and the robot band shows no lateral move";
  return info;
}

}  // namespace coopnav::assessment
