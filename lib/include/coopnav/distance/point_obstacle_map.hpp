#pragma once
/// @file A static map plus obstacles of the moment (issue 45): points a laser returned that the
/// static map may not hold (a chair, a trolley, an open door). The band planner's obstacle term
/// and every other nearest-obstacle query then see the nearer of the map's obstacle and the
/// nearest point, so the scan needs no term of its own. The points have no extent (a laser
/// return is a point on a surface; the consumer's clearance and radius keep the distance).

#include <memory>
#include <vector>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav {

class PointObstacleMap final : public DistanceMap {
 public:
  /// base must outlive this map; non-finite points are dropped.
  PointObstacleMap(const DistanceMap& base, const std::vector<Eigen::Vector2d>& points);

  Eigen::AlignedBox2d bounds() const override { return base_.bounds(); }
  double resolution_m() const override { return base_.resolution_m(); }

  /// The base map's answer, unless a point is nearer (or the base found nothing): then kOk with
  /// that point. Outside the map, inside an obstacle, in unknown space or an invalid query: the
  /// base's answer stands (a point cannot make such a pose acceptable).
  DistanceResult nearest(const Eigen::Vector2d& p) const override;
  /// The same for the half-plane {o : (o - q).n >= 0}, points within max_range_m of q.
  DistanceResult nearestInHalfPlane(const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                    double max_range_m) const override;
  /// The base map's ray: a point has no width a ray could hit.
  DistanceResult ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                     double max_range_m) const override {
    return base_.ray(p, dir, max_range_m);
  }

  const std::vector<Eigen::Vector2d>& points() const { return points_; }

 private:
  const DistanceMap& base_;
  std::vector<Eigen::Vector2d> points_;
};

}  // namespace coopnav
