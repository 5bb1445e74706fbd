#include "coopnav/distance/point_obstacle_map.hpp"

#include <cmath>
#include <limits>

namespace coopnav {
namespace {

/// Merges the base's answer with the nearest point found (index < 0: none).
DistanceResult merge(const DistanceResult& base, const Eigen::Vector2d& from,
                     const std::vector<Eigen::Vector2d>& points, int best) {
  if (best < 0) return base;
  const bool base_counts =
      base.status == DistanceStatus::kOk || base.status == DistanceStatus::kNotFound;
  if (!base_counts) return base;
  const double d = (points[static_cast<std::size_t>(best)] - from).norm();
  if (base.status == DistanceStatus::kOk && base.distance_m <= d) return base;
  DistanceResult r;
  r.status = DistanceStatus::kOk;
  r.distance_m = d;
  r.obstacle = points[static_cast<std::size_t>(best)];
  return r;
}

}  // namespace

PointObstacleMap::PointObstacleMap(const DistanceMap& base,
                                   const std::vector<Eigen::Vector2d>& points)
    : base_(base) {
  points_.reserve(points.size());
  for (const Eigen::Vector2d& p : points)
    if (p.allFinite()) points_.push_back(p);
}

DistanceResult PointObstacleMap::nearest(const Eigen::Vector2d& p) const {
  DistanceResult base = base_.nearest(p);
  if (!p.allFinite()) return base;
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const double d2 = (points_[i] - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return merge(base, p, points_, best);
}

DistanceResult PointObstacleMap::nearestInHalfPlane(const Eigen::Vector2d& q,
                                                    const Eigen::Vector2d& n,
                                                    double max_range_m) const {
  DistanceResult base = base_.nearestInHalfPlane(q, n, max_range_m);
  if (!q.allFinite() || !n.allFinite() || !(max_range_m > 0.0)) return base;
  int best = -1;
  double best_d2 = max_range_m * max_range_m;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if ((points_[i] - q).dot(n) < 0.0) continue;
    const double d2 = (points_[i] - q).squaredNorm();
    if (d2 <= best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return merge(base, q, points_, best);
}

}  // namespace coopnav
