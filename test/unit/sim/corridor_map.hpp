#pragma once
/// @file An analytic straight corridor for the sim tests: free for y in (y_low, y_high), solid
/// beyond, unbounded along x. Exact answers for the three DistanceMap queries.

#include <cmath>
#include <limits>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav::test {

class CorridorMap final : public DistanceMap {
 public:
  CorridorMap(double y_low_m, double y_high_m) : y_low_m_(y_low_m), y_high_m_(y_high_m) {}

  Eigen::AlignedBox2d bounds() const override {
    return Eigen::AlignedBox2d(Eigen::Vector2d(-1e3, y_low_m_ - 1.0),
                               Eigen::Vector2d(1e3, y_high_m_ + 1.0));
  }
  double resolution_m() const override { return 0.0; }

  DistanceResult nearest(const Eigen::Vector2d& p) const override {
    DistanceResult r;
    if (!p.allFinite()) return r;
    if (p.y() <= y_low_m_ || p.y() >= y_high_m_) {
      r.status = DistanceStatus::kInObstacle;
      r.distance_m = 0.0;
      r.obstacle = p;
      return r;
    }
    const double d_low = p.y() - y_low_m_, d_high = y_high_m_ - p.y();
    r.status = DistanceStatus::kOk;
    r.distance_m = std::min(d_low, d_high);
    r.obstacle = {p.x(), d_low <= d_high ? y_low_m_ : y_high_m_};
    return r;
  }

  DistanceResult nearestInHalfPlane(const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                    double max_range_m) const override {
    DistanceResult best;
    if (!q.allFinite() || !n.allFinite() || n.norm() == 0.0 || !(max_range_m > 0.0)) return best;
    best.status = DistanceStatus::kNotFound;
    best.distance_m = std::numeric_limits<double>::infinity();
    for (double y_wall : {y_low_m_, y_high_m_}) {
      // Closest point (q.x + t, y_wall) of the wall face with (o - q).n >= 0.
      const double dy = y_wall - q.y();
      double t = 0.0;
      if (dy * n.y() < 0.0) {
        if (std::abs(n.x()) < 1e-12) continue;
        t = -dy * n.y() / n.x();
      }
      const double d = std::hypot(t, dy);
      if (d <= max_range_m && d < best.distance_m) {
        best.status = DistanceStatus::kOk;
        best.distance_m = d;
        best.obstacle = {q.x() + t, y_wall};
      }
    }
    if (best.status == DistanceStatus::kNotFound) best.distance_m = max_range_m;
    return best;
  }

  DistanceResult ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                     double max_range_m) const override {
    DistanceResult r;
    if (!p.allFinite() || !dir.allFinite() || dir.norm() == 0.0 || !(max_range_m > 0.0)) return r;
    if (p.y() <= y_low_m_ || p.y() >= y_high_m_) {
      r.status = DistanceStatus::kInObstacle;
      return r;
    }
    const Eigen::Vector2d u = dir.normalized();
    double t = std::numeric_limits<double>::infinity();
    if (u.y() > 0.0) t = (y_high_m_ - p.y()) / u.y();
    if (u.y() < 0.0) t = (y_low_m_ - p.y()) / u.y();
    if (t <= max_range_m) {
      r.status = DistanceStatus::kOk;
      r.distance_m = t;
      r.obstacle = p + t * u;
    } else {
      r.status = DistanceStatus::kNotFound;
      r.distance_m = max_range_m;
    }
    return r;
  }

 private:
  double y_low_m_;
  double y_high_m_;
};

}  // namespace coopnav::test
