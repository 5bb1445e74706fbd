#pragma once
/// @file Test helper: an analytic DistanceMap made of axis-aligned solid boxes inside a bounding
/// box (e.g. a corridor = two wall boxes). Exact distances, no grid.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav::test {

class BoxMap final : public DistanceMap {
 public:
  BoxMap(Eigen::AlignedBox2d bounds, std::vector<Eigen::AlignedBox2d> boxes)
      : bounds_(bounds), boxes_(std::move(boxes)) {}

  /// A corridor along x from x0 to x1 with free width between y_lo and y_hi, walls 0.5 m thick
  /// and closed ends.
  static std::shared_ptr<BoxMap> corridor(double x0, double x1, double y_lo, double y_hi) {
    constexpr double kWall = 0.5;
    Eigen::AlignedBox2d b(Eigen::Vector2d(x0 - kWall, y_lo - kWall),
                          Eigen::Vector2d(x1 + kWall, y_hi + kWall));
    std::vector<Eigen::AlignedBox2d> walls{
        {Eigen::Vector2d(x0 - kWall, y_lo - kWall), Eigen::Vector2d(x1 + kWall, y_lo)},
        {Eigen::Vector2d(x0 - kWall, y_hi), Eigen::Vector2d(x1 + kWall, y_hi + kWall)},
        {Eigen::Vector2d(x0 - kWall, y_lo), Eigen::Vector2d(x0, y_hi)},
        {Eigen::Vector2d(x1, y_lo), Eigen::Vector2d(x1 + kWall, y_hi)}};
    return std::make_shared<BoxMap>(b, walls);
  }

  void addBox(const Eigen::AlignedBox2d& b) { boxes_.push_back(b); }

  Eigen::AlignedBox2d bounds() const override { return bounds_; }
  double resolution_m() const override { return 0.0; }

  DistanceResult nearest(const Eigen::Vector2d& p) const override {
    DistanceResult r;
    if (!p.allFinite()) return r;
    if (!bounds_.contains(p)) {
      r.status = DistanceStatus::kOutsideMap;
      return r;
    }
    double best = std::numeric_limits<double>::infinity();
    for (const auto& b : boxes_) {
      const Eigen::Vector2d c = p.cwiseMax(b.min()).cwiseMin(b.max());
      const double d = (p - c).norm();
      if (d == 0.0) {
        r.status = DistanceStatus::kInObstacle;
        r.distance_m = 0.0;
        r.obstacle = p;
        return r;
      }
      if (d < best) {
        best = d;
        r.obstacle = c;
      }
    }
    if (!std::isfinite(best)) {
      r.status = DistanceStatus::kNotFound;
      return r;
    }
    r.status = DistanceStatus::kOk;
    r.distance_m = best;
    return r;
  }

  DistanceResult nearestInHalfPlane(const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                    double max_range_m) const override {
    // Sampled box boundaries (2 cm): good enough for tests.
    DistanceResult r;
    r.status = DistanceStatus::kNotFound;
    r.distance_m = max_range_m;
    double best = max_range_m;
    for (const auto& b : boxes_) {
      const Eigen::Vector2d mn = b.min(), mx = b.max();
      const Eigen::Vector2d corners[4] = {mn, {mx.x(), mn.y()}, mx, {mn.x(), mx.y()}};
      for (int e = 0; e < 4; ++e) {
        const Eigen::Vector2d a = corners[e], c = corners[(e + 1) % 4];
        const int k = std::max(1, static_cast<int>((c - a).norm() / 0.02));
        for (int i = 0; i <= k; ++i) {
          const Eigen::Vector2d o = a + (c - a) * (static_cast<double>(i) / k);
          if ((o - q).dot(n) < 0.0) continue;
          const double d = (o - q).norm();
          if (d < best) {
            best = d;
            r.status = DistanceStatus::kOk;
            r.distance_m = d;
            r.obstacle = o;
          }
        }
      }
    }
    return r;
  }

  DistanceResult ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                     double max_range_m) const override {
    DistanceResult r;
    r.status = DistanceStatus::kNotFound;
    r.distance_m = max_range_m;
    const Eigen::Vector2d d = dir.normalized();
    double best = max_range_m;
    for (const auto& b : boxes_) {
      double t0 = 0.0, t1 = max_range_m;
      bool hit = true;
      for (int a = 0; a < 2 && hit; ++a) {
        if (std::abs(d[a]) < 1e-12) {
          if (p[a] < b.min()[a] || p[a] > b.max()[a]) hit = false;
        } else {
          double ta = (b.min()[a] - p[a]) / d[a], tb = (b.max()[a] - p[a]) / d[a];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          if (t0 > t1) hit = false;
        }
      }
      if (hit && t0 < best) {
        best = t0;
        r.status = DistanceStatus::kOk;
        r.distance_m = t0;
        r.obstacle = p + d * t0;
      }
    }
    return r;
  }

 private:
  Eigen::AlignedBox2d bounds_;
  std::vector<Eigen::AlignedBox2d> boxes_;
};

}  // namespace coopnav::test
