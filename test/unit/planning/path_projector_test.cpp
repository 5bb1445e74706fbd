// PathProjector skips segments by the triangle inequality; its answers must be exactly those of
// the plain scan over every segment (the oracle below), whatever the hint.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

// Every segment, first least distance wins: what projectOntoPath computed before the projector.
std::optional<PathProjection> scanAll(const Path2& path, const Eigen::Vector2d& p) {
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
    const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d c = a + s * ab;
    const double d = (p - c).norm();
    if (d < best.distance_m) {
      best.distance_m = d;
      best.closest = c;
      best.segment = i;
      best.arc_length_m = arc_m + s * std::sqrt(len2);
      const double side = len2 > 0.0 ? cross2(ab, p - a) : 0.0;
      best.signed_distance_m = side >= 0.0 ? d : -d;
    }
    arc_m += std::sqrt(len2);
  }
  return best;
}

void expectSame(const std::optional<PathProjection>& want,
                const std::optional<PathProjection>& got) {
  ASSERT_EQ(want.has_value(), got.has_value());
  if (!want) return;
  // Bit for bit: the planner's bands and the scenario transcripts depend on it (NaN as NaN).
  auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  EXPECT_EQ(want->segment, got->segment);
  EXPECT_PRED2(same, want->distance_m, got->distance_m);
  EXPECT_PRED2(same, want->signed_distance_m, got->signed_distance_m);
  EXPECT_PRED2(same, want->arc_length_m, got->arc_length_m);
  EXPECT_PRED2(same, want->closest.x(), got->closest.x());
  EXPECT_PRED2(same, want->closest.y(), got->closest.y());
}

TEST(PathProjector, SameAnswerAsTheFullScanOnRandomPathsWithAnyHint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.3, 0.3), where(-3.0, 12.0);
  int checks = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // A grid path (A* steps, with repeated points), a random walk that crosses itself, and a
    // path that goes out and comes back along itself (equal distances: ties).
    Path2 path{{0.0, 0.0}};
    const int n = 2 + trial % 150;
    for (int k = 1; k < n; ++k) {
      Eigen::Vector2d next = path.back();
      switch (trial % 3) {
        case 0:
          next += Eigen::Vector2d(0.05 * (k % 7 != 0), 0.05 * (k % 5 == 0));
          break;
        case 1:
          next += Eigen::Vector2d(step(rng), step(rng));
          break;
        default:
          next = k < n / 2 ? Eigen::Vector2d(0.1 * k, 0.0) : path[n - 1 - k];
          break;
      }
      path.push_back(next);
    }
    const PathProjector projector(path);
    for (int q = 0; q < 30; ++q) {
      const Eigen::Vector2d p(where(rng) / 3.0, where(rng) / 6.0);
      const auto want = scanAll(path, p);
      expectSame(want, projectOntoPath(path, p));
      for (std::size_t hint : {std::size_t{0}, path.size() / 2, path.size() + 5,
                               static_cast<std::size_t>(rng() % path.size())}) {
        expectSame(want, projector.project(p, hint));
        ++checks;
      }
    }
  }
  EXPECT_EQ(checks, 200 * 30 * 4);
}

TEST(PathProjector, DegenerateInputsAsTheFullScan) {
  const Eigen::Vector2d p(1.0, 2.0);
  for (const Path2& path : {Path2{}, Path2{{3.0, 4.0}}, Path2{{0.0, 0.0}, {0.0, 0.0}},
                            Path2{{0.0, 0.0}, {0.0, 0.0}, {1.0, 0.0}, {1.0, 0.0}}}) {
    const PathProjector projector(path);
    expectSame(scanAll(path, p), projector.project(p, 1));
    EXPECT_FALSE(projector.project({std::nan(""), 0.0}).has_value());
  }
  // A non-finite point in the path: no skipping, the scan's answer.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Path2 bad{{0.0, 0.0}, {1.0, 0.0}, {nan, 0.0}, {5.0, 0.0}, {6.0, 0.0}};
  expectSame(scanAll(bad, {5.5, 0.1}), PathProjector(bad).project({5.5, 0.1}, 0));
}

}  // namespace
}  // namespace coopnav
