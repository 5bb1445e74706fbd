#pragma once
/// @file Small planar geometry helpers used across areas (one place each).

#include <Eigen/Core>
#include <cmath>
#include <optional>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// z-component of the 2-D cross product a x b.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a_rad);

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
std::optional<PathProjection> projectOntoPath(const Path2& path, const Eigen::Vector2d& p);

/// True when every coordinate of the pose is finite.
bool isFinite(const Pose2& p);

}  // namespace coopnav
