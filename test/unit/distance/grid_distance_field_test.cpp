// Grid distance field vs brute force on random maps (fixed seeds), and status codes.
#include "coopnav/distance/grid_distance_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace coopnav {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Random grid: obstacles with probability p_occ, unknown with p_unknown; origin deliberately not a
// multiple of the resolution.
OccupancyGrid2 randomGrid(std::uint32_t seed, int w, int h, double p_occ, double p_unknown) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  OccupancyGrid2 grid(w, h, 0.05, Eigen::Vector2d(-1.23, 0.417), CellState::kFree);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const double x = u(rng);
      if (x < p_occ) {
        grid.set(i, j, CellState::kOccupied);
      } else if (x < p_occ + p_unknown) {
        grid.set(i, j, CellState::kUnknown);
      }
    }
  }
  return grid;
}

bool bruteObstacle(const OccupancyGrid2& g, int i, int j, UnknownPolicy policy) {
  const CellState s = g.at(i, j);
  return s == CellState::kOccupied ||
         (s == CellState::kUnknown && policy == UnknownPolicy::kObstacle);
}

std::int64_t bruteSquaredDistance(const OccupancyGrid2& g, int ci, int cj, UnknownPolicy policy) {
  std::int64_t best = -1;
  for (int j = 0; j < g.height(); ++j) {
    for (int i = 0; i < g.width(); ++i) {
      if (!bruteObstacle(g, i, j, policy)) continue;
      const std::int64_t sq = std::int64_t(i - ci) * (i - ci) + std::int64_t(j - cj) * (j - cj);
      if (best < 0 || sq < best) best = sq;
    }
  }
  return best;
}

// Reference SIDE: scan every obstacle cell with the documented half-plane test.
DistanceResult bruteSide(const GridDistanceField& f, const Eigen::Vector2d& q,
                         const Eigen::Vector2d& n, double max_range_m) {
  const OccupancyGrid2& g = f.grid();
  const auto c = *g.cellOf(q);
  const Eigen::Vector2d n_unit = n / n.norm();
  const double res = g.resolution_m();
  const Eigen::Vector2d base = g.origin_m() + Eigen::Vector2d(0.5 * res, 0.5 * res) - q;
  std::int64_t best = -1;
  for (int j = 0; j < g.height(); ++j) {
    for (int i = 0; i < g.width(); ++i) {
      if (!f.isObstacle(i, j)) continue;
      if ((base + res * Eigen::Vector2d(i, j)).dot(n_unit) < -f.sideTolerance_m()) continue;
      const std::int64_t sq =
          std::int64_t(i - c.x()) * (i - c.x()) + std::int64_t(j - c.y()) * (j - c.y());
      if (f.cellDistanceToMetres(sq) > max_range_m) continue;
      if (best < 0 || sq < best) best = sq;
    }
  }
  DistanceResult r;
  r.status = best < 0 ? DistanceStatus::kNotFound : DistanceStatus::kOk;
  r.distance_m = best < 0 ? max_range_m : f.cellDistanceToMetres(best);
  return r;
}

// Reference RAY: the smallest entry parameter over all obstacle squares (slab method), else the
// exit from the grid box.
DistanceResult bruteRay(const GridDistanceField& f, const Eigen::Vector2d& p,
                        const Eigen::Vector2d& dir, double max_range_m) {
  const OccupancyGrid2& g = f.grid();
  const Eigen::Vector2d d = dir.normalized();
  const auto entry = [&](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double* t_in,
                         double* t_out) {
    double t0 = -kInf, t1 = kInf;
    for (int a = 0; a < 2; ++a) {
      if (d[a] == 0.0) {
        if (p[a] < lo[a] || p[a] > hi[a]) return false;
        continue;
      }
      double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    *t_in = t0;
    *t_out = t1;
    return t0 <= t1;
  };
  double best = kInf;
  for (int j = 0; j < g.height(); ++j) {
    for (int i = 0; i < g.width(); ++i) {
      if (!f.isObstacle(i, j)) continue;
      const Eigen::Vector2d lo = g.origin_m() + g.resolution_m() * Eigen::Vector2d(i, j);
      double t0 = 0.0, t1 = 0.0;
      if (entry(lo, lo + Eigen::Vector2d::Constant(g.resolution_m()), &t0, &t1) && t1 >= 0.0) {
        best = std::min(best, std::max(t0, 0.0));
      }
    }
  }
  DistanceResult r;
  if (best <= max_range_m) {
    r.status = DistanceStatus::kOk;
    r.distance_m = best;
    r.obstacle = p + d * best;
    return r;
  }
  double t0 = 0.0, t1 = 0.0;
  entry(g.origin_m(), g.max_m(), &t0, &t1);
  r.status = DistanceStatus::kNotFound;
  r.distance_m = std::min(t1, max_range_m);
  return r;
}

class GridDistanceFieldRandomTest : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(GridDistanceFieldRandomTest, EdtEqualsBruteForceExactly) {
  for (const UnknownPolicy policy : {UnknownPolicy::kObstacle, UnknownPolicy::kFree}) {
    // Given a random map with sparse obstacles (long distances) and one with dense ones
    for (const double p_occ : {0.002, 0.05, 0.3}) {
      const OccupancyGrid2 grid = randomGrid(GetParam(), 61, 47, p_occ, 0.01);
      // When the field is built
      const GridDistanceField dut(grid, policy);
      // Then every cell's squared distance is the brute-force one and the stored obstacle is at it
      for (int j = 0; j < grid.height(); ++j) {
        for (int i = 0; i < grid.width(); ++i) {
          const std::int64_t expected = bruteSquaredDistance(grid, i, j, policy);
          ASSERT_EQ(dut.squaredCellDistance(i, j), expected) << i << "," << j;
          if (expected < 0) continue;
          const CellIndex o = dut.nearestObstacleCell(i, j);
          ASSERT_TRUE(dut.isObstacle(o.x(), o.y()));
          ASSERT_EQ(std::int64_t(o.x() - i) * (o.x() - i) + std::int64_t(o.y() - j) * (o.y() - j),
                    expected);
        }
      }
    }
  }
}

TEST_P(GridDistanceFieldRandomTest, NearestSideRayEqualBruteForce) {
  const OccupancyGrid2 grid = randomGrid(GetParam(), 80, 60, 0.02, 0.01);
  const GridDistanceField dut(grid);
  std::mt19937 rng(GetParam() + 1000);
  const Eigen::Vector2d lo = grid.origin_m();
  const Eigen::Vector2d hi = grid.max_m();
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  std::uniform_real_distribution<double> ua(-M_PI, M_PI), ur(0.05, 3.0);
  int checked = 0;
  while (checked < 400) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const auto c = grid.cellOf(p);
    if (!c || grid.at(c->x(), c->y()) != CellState::kFree) continue;
    ++checked;
    // NEAREST: exact grid distance, obstacle point at distance_m from the cell centre
    const DistanceResult near = dut.nearest(p);
    ASSERT_EQ(near.status, DistanceStatus::kOk);
    const std::int64_t sq = bruteSquaredDistance(grid, c->x(), c->y(), UnknownPolicy::kObstacle);
    EXPECT_EQ(near.distance_m, dut.cellDistanceToMetres(sq));
    EXPECT_NEAR((near.obstacle - grid.cellCenter_m(c->x(), c->y())).norm(), near.distance_m, 1e-9);
    // (on the closed square of an obstacle cell: a 4-neighbour's point is on its face)
    const CellIndex o = dut.nearestObstacleCell(c->x(), c->y());
    EXPECT_LE((near.obstacle - grid.cellCenter_m(o.x(), o.y())).cwiseAbs().maxCoeff(),
              0.5 * grid.resolution_m() + 1e-12);

    // SIDE: random normal, random range (also unbounded)
    const double a = ua(rng);
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    for (const double range : {ur(rng), kInf}) {
      const DistanceResult side = dut.nearestInHalfPlane(p, 2.5 * n, range);
      const DistanceResult ref = bruteSide(dut, p, n, range);
      ASSERT_EQ(side.status, ref.status) << p.transpose() << " n " << n.transpose();
      EXPECT_EQ(side.distance_m, ref.distance_m) << p.transpose() << " n " << n.transpose();
      if (side.status == DistanceStatus::kOk) {
        EXPECT_GE(side.distance_m, near.distance_m);
      }
    }

    // RAY: random direction, random range
    const double range = ur(rng);
    const DistanceResult ray = dut.ray(p, 0.3 * n, range);
    const DistanceResult ref = bruteRay(dut, p, n, range);
    ASSERT_EQ(ray.status, ref.status) << p.transpose() << " d " << n.transpose();
    EXPECT_NEAR(ray.distance_m, ref.distance_m, 1e-9);
    if (ray.status == DistanceStatus::kOk) {
      EXPECT_NEAR((ray.obstacle - ref.obstacle).norm(), 0.0, 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, GridDistanceFieldRandomTest, ::testing::Values(1u, 7u, 42u, 2024u));

TEST(GridDistanceFieldTest, DistanceConventionOnASingleObstacle) {
  // Given one obstacle cell at (5, 5) in a free 11x11 grid with origin 0 and res 0.1
  OccupancyGrid2 grid(11, 11, 0.1, Eigen::Vector2d::Zero(), CellState::kFree);
  grid.set(5, 5, CellState::kOccupied);
  const GridDistanceField dut(grid);
  // Then a 4-neighbour is half a cell away and a cell 3 columns away 2.5 cells
  EXPECT_DOUBLE_EQ(dut.nearest({0.65, 0.55}).distance_m, 0.05);
  EXPECT_DOUBLE_EQ(dut.nearest({0.85, 0.51}).distance_m, 0.25);
  EXPECT_NEAR(dut.nearest({0.85, 0.51}).obstacle.x(), 0.6, 1e-12);
  // And RAY is not snapped: from x = 0.12 to the face at x = 0.5
  const DistanceResult r = dut.ray({0.12, 0.55}, {1.0, 0.0}, 5.0);
  EXPECT_EQ(r.status, DistanceStatus::kOk);
  EXPECT_NEAR(r.distance_m, 0.38, 1e-12);
  // And SIDE looking away from the obstacle finds nothing, towards it finds it
  EXPECT_EQ(dut.nearestInHalfPlane({0.85, 0.55}, {1.0, 0.0}, 10.0).status,
            DistanceStatus::kNotFound);
  EXPECT_DOUBLE_EQ(dut.nearestInHalfPlane({0.85, 0.55}, {-1.0, 0.0}, 10.0).distance_m, 0.25);
  // And the range bounds the distance
  EXPECT_EQ(dut.nearestInHalfPlane({0.85, 0.55}, {-1.0, 0.0}, 0.2501).status, DistanceStatus::kOk);
  EXPECT_EQ(dut.nearestInHalfPlane({0.85, 0.55}, {-1.0, 0.0}, 0.2499).status,
            DistanceStatus::kNotFound);
}

TEST(GridDistanceFieldTest, StatusCodes) {
  OccupancyGrid2 grid(10, 10, 0.1, Eigen::Vector2d(1.0, 2.0), CellState::kFree);
  grid.set(2, 2, CellState::kOccupied);
  grid.set(7, 7, CellState::kUnknown);
  const GridDistanceField dut(grid);
  const Eigen::Vector2d free_p(1.55, 2.55), occ_p(1.25, 2.25), unk_p(1.75, 2.75);
  const Eigen::Vector2d out_p(0.9, 2.5), e(1.0, 0.0);
  for (const auto& [p, expected] : std::vector<std::pair<Eigen::Vector2d, DistanceStatus>>{
           {free_p, DistanceStatus::kOk},
           {occ_p, DistanceStatus::kInObstacle},
           {unk_p, DistanceStatus::kUnknownSpace},
           {out_p, DistanceStatus::kOutsideMap},
           {Eigen::Vector2d(1.0, 3.0), DistanceStatus::kOutsideMap},  // upper edge is outside
           {Eigen::Vector2d(kNan, 2.5), DistanceStatus::kInvalidQuery},
           {Eigen::Vector2d(1.5, kInf), DistanceStatus::kInvalidQuery}}) {
    EXPECT_EQ(dut.nearest(p).status, expected) << p.transpose();
    EXPECT_EQ(dut.nearestInHalfPlane(p, -e, 5.0).status, expected) << p.transpose();
    // (the free point's ray leaves the map along row 5)
    EXPECT_EQ(dut.ray(p, -e, 5.0).status,
              expected == DistanceStatus::kOk ? DistanceStatus::kNotFound : expected)
        << p.transpose();
  }
  EXPECT_EQ(dut.nearest(occ_p).distance_m, 0.0);
  // Zero / non-finite normal or direction, non-positive or NaN range
  for (const Eigen::Vector2d& v :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(kNan, 1.0), Eigen::Vector2d(kInf, 0.0)}) {
    EXPECT_EQ(dut.nearestInHalfPlane(free_p, v, 5.0).status, DistanceStatus::kInvalidQuery);
    EXPECT_EQ(dut.ray(free_p, v, 5.0).status, DistanceStatus::kInvalidQuery);
  }
  for (const double range : {0.0, -1.0, kNan}) {
    EXPECT_EQ(dut.nearestInHalfPlane(free_p, e, range).status, DistanceStatus::kInvalidQuery);
    EXPECT_EQ(dut.ray(free_p, e, range).status, DistanceStatus::kInvalidQuery);
  }
  // Unknown as free: the unknown cell no longer counts as an obstacle, but a query in it does
  const GridDistanceField lenient(grid, UnknownPolicy::kFree);
  EXPECT_EQ(lenient.nearest(unk_p).status, DistanceStatus::kUnknownSpace);
  EXPECT_DOUBLE_EQ(lenient.nearest({1.75, 2.65}).distance_m, dut.cellDistanceToMetres(25 + 16));
  EXPECT_DOUBLE_EQ(dut.nearest({1.75, 2.65}).distance_m, 0.05);
  // RAY leaving the map reports the free length to the edge; within range, the range
  EXPECT_EQ(dut.ray(free_p, {0.0, -1.0}, 5.0).status, DistanceStatus::kNotFound);
  EXPECT_NEAR(dut.ray(free_p, {0.0, -1.0}, 5.0).distance_m, 0.55, 1e-12);
  EXPECT_DOUBLE_EQ(dut.ray(free_p, {0.0, -1.0}, 0.3).distance_m, 0.3);
  // No obstacle at all
  const GridDistanceField none(
      OccupancyGrid2(5, 5, 0.1, Eigen::Vector2d::Zero(), CellState::kFree));
  EXPECT_EQ(none.nearest({0.25, 0.25}).status, DistanceStatus::kNotFound);
  EXPECT_EQ(none.nearestInHalfPlane({0.25, 0.25}, e, 1.0).status, DistanceStatus::kNotFound);
  // Empty grid: everything is outside
  const GridDistanceField empty{OccupancyGrid2()};
  EXPECT_EQ(empty.nearest({0.0, 0.0}).status, DistanceStatus::kOutsideMap);
  EXPECT_STREQ(toString(DistanceStatus::kUnknownSpace), "UNKNOWN_SPACE");
}

TEST(GridDistanceFieldTest, SideToleranceAdmitsCellsTouchingTheHalfPlane) {
  // Given an obstacle whose centre is 0.6 res behind q along n (its square still reaches past q)
  OccupancyGrid2 grid(20, 20, 0.1, Eigen::Vector2d::Zero(), CellState::kFree);
  grid.set(10, 15, CellState::kOccupied);
  const GridDistanceField dut(grid);
  const Eigen::Vector2d q(1.0 + 0.06 + 0.05, 0.55);  // centre of (10,15) is x = 1.05
  // Then it is found with n = +x, and not once it is more than res/sqrt(2) behind
  EXPECT_EQ(dut.nearestInHalfPlane(q, {1.0, 0.0}, 5.0).status, DistanceStatus::kOk);
  const Eigen::Vector2d q_far(1.05 + 0.0708, 0.55);
  EXPECT_EQ(dut.nearestInHalfPlane(q_far, {1.0, 0.0}, 5.0).status, DistanceStatus::kNotFound);
}

}  // namespace
}  // namespace coopnav
