// Obstacles of the moment over a static map: the nearer of the two wins, the map's own verdicts
// (outside, inside an obstacle) stand, and without points every answer is the map's, bit for bit.
#include "coopnav/distance/point_obstacle_map.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "coopnav/distance/grid_distance_field.hpp"

namespace coopnav {
namespace {

// 4 m x 2 m free, one wall row along y = 0 (cells j = 0): a corridor's lower wall.
GridDistanceField wallMap() {
  OccupancyGrid2 g(80, 40, 0.05, Eigen::Vector2d(0.0, 0.0), CellState::kFree);
  for (int i = 0; i < 80; ++i) g.set(i, 0, CellState::kOccupied);
  return GridDistanceField(std::move(g), UnknownPolicy::kFree);
}

TEST(PointObstacleMap, WithoutPointsEveryAnswerIsTheMaps) {
  const GridDistanceField base = wallMap();
  const PointObstacleMap m(base, {});
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(3.3, 0.4),
                                   Eigen::Vector2d(-1.0, 1.0), Eigen::Vector2d(2.0, 0.01)}) {
    const DistanceResult a = base.nearest(p), b = m.nearest(p);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.distance_m, b.distance_m);
    EXPECT_EQ(a.obstacle, b.obstacle);
  }
  const DistanceResult a = base.nearestInHalfPlane({1.0, 1.0}, {0.0, -1.0}, 3.0);
  const DistanceResult b = m.nearestInHalfPlane({1.0, 1.0}, {0.0, -1.0}, 3.0);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.distance_m, b.distance_m);
}

TEST(PointObstacleMap, TheNearerOfWallAndPointWins) {
  const GridDistanceField base = wallMap();
  const PointObstacleMap m(base, {{2.0, 1.5}, {3.0, 1.8}});
  // At (2, 1.2): the point 0.3 m above beats the wall ~1.2 m below.
  DistanceResult r = m.nearest({2.0, 1.2});
  ASSERT_EQ(r.status, DistanceStatus::kOk);
  EXPECT_NEAR(r.distance_m, 0.3, 1e-12);
  EXPECT_NEAR(r.obstacle.x(), 2.0, 1e-12);
  EXPECT_NEAR(r.obstacle.y(), 1.5, 1e-12);
  // At (0.5, 0.3): the wall is nearer than either point.
  r = m.nearest({0.5, 0.3});
  ASSERT_EQ(r.status, DistanceStatus::kOk);
  EXPECT_EQ(r.distance_m, base.nearest({0.5, 0.3}).distance_m);
  EXPECT_LT(r.obstacle.y(), 0.1);
}

TEST(PointObstacleMap, TheMapsVerdictsStand) {
  const GridDistanceField base = wallMap();
  const PointObstacleMap m(base, {{2.0, 1.5}, {-0.5, 1.0}});
  EXPECT_EQ(m.nearest({-0.5, 1.1}).status, base.nearest({-0.5, 1.1}).status);  // outside
  EXPECT_EQ(m.nearest({2.0, 0.01}).status, DistanceStatus::kInObstacle);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(m.nearest({nan, 1.0}).status, base.nearest({nan, 1.0}).status);
}

TEST(PointObstacleMap, NonFinitePointsAreDropped) {
  const GridDistanceField base = wallMap();
  const double inf = std::numeric_limits<double>::infinity();
  const PointObstacleMap m(base, {{inf, 1.0}, {2.0, 1.5}});
  ASSERT_EQ(m.points().size(), 1U);
  EXPECT_NEAR(m.nearest({2.0, 1.2}).distance_m, 0.3, 1e-12);
}

TEST(PointObstacleMap, HalfPlaneSeesOnlyPointsOnItsSideAndInRange) {
  const GridDistanceField base = wallMap();
  const PointObstacleMap m(base, {{2.0, 1.5}});
  // Looking up from (2, 1.0): the point 0.5 m up.
  DistanceResult r = m.nearestInHalfPlane({2.0, 1.0}, {0.0, 1.0}, 3.0);
  ASSERT_EQ(r.status, DistanceStatus::kOk);
  EXPECT_NEAR(r.distance_m, 0.5, 1e-12);
  // Looking down: the wall, not the point behind.
  r = m.nearestInHalfPlane({2.0, 1.0}, {0.0, -1.0}, 3.0);
  ASSERT_EQ(r.status, DistanceStatus::kOk);
  EXPECT_GT(r.distance_m, 0.8);
  // Up, with a range shorter than the point: the map's answer (nothing up there).
  r = m.nearestInHalfPlane({2.0, 1.0}, {0.0, 1.0}, 0.4);
  EXPECT_EQ(r.status, base.nearestInHalfPlane({2.0, 1.0}, {0.0, 1.0}, 0.4).status);
}

}  // namespace
}  // namespace coopnav
