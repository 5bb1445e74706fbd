#include "coopnav/geometry/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopnav {

double wrapAngle(double a_rad) {
  double r = std::remainder(a_rad, 2.0 * M_PI);
  if (r <= -M_PI) r += 2.0 * M_PI;
  return r;
}

bool isFinite(const Pose2& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.theta_rad);
}

std::optional<PathProjection> projectOntoPath(const Path2& path, const Eigen::Vector2d& p) {
  if (path.empty() || !p.allFinite()) return std::nullopt;
  PathProjection best;
  best.distance_m = std::numeric_limits<double>::infinity();
  if (path.size() == 1) {
    best.closest = path[0];
    best.distance_m = (p - path[0]).norm();
    best.signed_distance_m = best.distance_m;
    return best;
  }
  double arc_m = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector2d a = path[i];
    const Eigen::Vector2d ab = path[i + 1] - a;
    const double len2 = ab.squaredNorm();
    double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d c = a + s * ab;
    const double d = (p - c).norm();
    if (d < best.distance_m) {
      best.distance_m = d;
      best.closest = c;
      best.segment = i;
      best.arc_length_m = arc_m + s * std::sqrt(len2);
      // Sign from the segment direction; a zero-length segment gives no side.
      const double side = len2 > 0.0 ? cross2(ab, p - a) : 0.0;
      best.signed_distance_m = side >= 0.0 ? d : -d;
    }
    arc_m += std::sqrt(len2);
  }
  return best;
}

}  // namespace coopnav
