#pragma once
/// @file Small planar geometry helpers used across areas (one place each).

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// z-component of the 2-D cross product a x b.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a_rad);

/// A world-frame vector in the frame of a body with heading theta_rad (x forward, y left).
inline Eigen::Vector2d worldToBody(const Eigen::Vector2d& w, double theta_rad) {
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  return {c * w.x() + s * w.y(), -s * w.x() + c * w.y()};
}

/// Unit heading vector of an angle.
inline Eigen::Vector2d headingVector(double theta_rad) {
  return {std::cos(theta_rad), std::sin(theta_rad)};
}

/// Result of projecting a point onto a polyline.
struct PathProjection {
  double distance_m{0.0};         ///< unsigned distance from the point to the polyline
  double signed_distance_m{0.0};  ///< > 0 when the point lies left of the path's direction
  Eigen::Vector2d closest{0.0, 0.0};
  std::size_t segment{0};    ///< index of the segment holding the closest point
  double arc_length_m{0.0};  ///< arc length from the path start to the closest point
};

/// Projects p onto a polyline of >= 1 points. Returns nullopt for an empty path or a non-finite p.
/// The closest point is the first one of least distance along the path.
std::optional<PathProjection> projectOntoPath(const Path2& path, const Eigen::Vector2d& p);

/// projectOntoPath() for many points on one path (the planner's via-points: every band pose, a
/// few times per cycle, onto paths of hundreds of segments). Its arc lengths are computed once,
/// and segments that cannot hold the closest point are skipped: a segment whose arc-length span
/// from the nearest one examined so far is shorter than their distance difference is farther
/// (triangle inequality along the path). The result is exactly projectOntoPath()'s.
class PathProjector {
 public:
  /// path must outlive the projector.
  explicit PathProjector(const Path2& path);
  /// As projectOntoPath(path, p). hint_segment (any value; best: the answer for a point nearby)
  /// only makes the search faster.
  std::optional<PathProjection> project(const Eigen::Vector2d& p,
                                        std::size_t hint_segment = 0) const;
  const Path2& path() const { return *path_; }

 private:
  const Path2* path_;
  std::vector<double> arc_m_;      ///< arc length at each point, summed from the start
  std::vector<double> seg_len_m_;  ///< length of each segment
  bool can_skip_{true};            ///< false for a path with a non-finite point
};

/// True when every coordinate of the pose is finite.
bool isFinite(const Pose2& p);

}  // namespace coopnav
