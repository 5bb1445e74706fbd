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
  return PathProjector(path).project(p);
}

PathProjector::PathProjector(const Path2& path) : path_(&path) {
  if (path.size() < 2) return;
  arc_m_.resize(path.size());
  seg_len_m_.resize(path.size() - 1);
  double arc_m = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    arc_m_[i] = arc_m;
    seg_len_m_[i] = std::sqrt((path[i + 1] - path[i]).squaredNorm());
    arc_m += seg_len_m_[i];
  }
  arc_m_.back() = arc_m;
  can_skip_ = std::isfinite(arc_m);
}

std::optional<PathProjection> PathProjector::project(const Eigen::Vector2d& p,
                                                     std::size_t hint_segment) const {
  const Path2& path = *path_;
  if (path.empty() || !p.allFinite()) return std::nullopt;
  PathProjection best;
  best.distance_m = std::numeric_limits<double>::infinity();
  if (path.size() == 1) {
    best.closest = path[0];
    best.distance_m = (p - path[0]).norm();
    best.signed_distance_m = best.distance_m;
    return best;
  }
  const std::size_t num_segments = path.size() - 1;
  auto distanceTo = [&](std::size_t i, double* s_out, Eigen::Vector2d* c_out) {
    const Eigen::Vector2d a = path[i];
    const Eigen::Vector2d ab = path[i + 1] - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    *s_out = s;
    *c_out = a + s * ab;
    return (p - *c_out).norm();
  };
  // Segments farther than `bound` cannot be the answer. The margin keeps the skip exact under
  // rounding (distances here are metres; rounding errors are ~1e-15 of them).
  constexpr double kMargin_m = 1e-9;
  double s_hint = 0.0;
  Eigen::Vector2d c_hint;
  double bound = distanceTo(std::min(hint_segment, num_segments - 1), &s_hint, &c_hint);
  for (std::size_t i = 0; i < num_segments;) {
    double s = 0.0;
    Eigen::Vector2d c;
    const double d = distanceTo(i, &s, &c);
    if (d < best.distance_m) {
      best.distance_m = d;
      best.closest = c;
      best.segment = i;
      best.arc_length_m = arc_m_[i] + s * seg_len_m_[i];
      // Sign from the segment direction; a zero-length segment gives no side.
      const Eigen::Vector2d ab = path[i + 1] - path[i];
      const double side = ab.squaredNorm() > 0.0 ? cross2(ab, p - path[i]) : 0.0;
      best.signed_distance_m = side >= 0.0 ? d : -d;
      bound = std::min(bound, d);
    }
    // Segment j > i is at least d - (arc_m_[j + 1] - arc_m_[i]) away: skip every j whose span
    // from here is shorter than d - bound.
    const double reach_m = arc_m_[i] + (d - bound) - kMargin_m;
    std::size_t next = i + 1;
    if (can_skip_ && next < num_segments && arc_m_[next + 1] < reach_m) {
      // First j >= next with arc_m_[j + 1] >= reach_m.
      const auto it = std::lower_bound(arc_m_.begin() + static_cast<std::ptrdiff_t>(next + 1),
                                       arc_m_.end(), reach_m);
      next = static_cast<std::size_t>(it - arc_m_.begin()) - 1;
    }
    i = next;
  }
  return best;
}

}  // namespace coopnav
