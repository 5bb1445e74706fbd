#include "coopnav/planning/global_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "../band/analytic_map.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

TEST(GridPathPlannerTest, ShortestPathAroundABox) {
  // Given a 10 x 6 m room with a 1 x 2 m box in the middle (y 2..4) and a point agent.
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 6.0);
  map->addBox({Eigen::Vector2d(4.5, 2.0), Eigen::Vector2d(5.5, 4.0)});
  GridPathPlanner::Options o;
  o.clearance_weight = 0.0;  // pure shortest path
  GridPathPlanner dut(map, o);
  // When planning from (2, 3) to (8, 3) with radius 0.3.
  const PathResult r = dut.plan({2.0, 3.0}, {8.0, 3.0}, 0.3);
  ASSERT_EQ(r.status, PathStatus::kOk);
  // Then the path is about the taut string around the inflated box corners.
  const double r_m = 0.3;
  const Eigen::Vector2d c1(4.5 - 0.0, 4.0 + r_m), c2(5.5, 4.0 + r_m);
  const double taut = (c1 - Eigen::Vector2d(2.0, 3.0)).norm() + (c2 - c1).norm() +
                      (Eigen::Vector2d(8.0, 3.0) - c2).norm();
  EXPECT_NEAR(r.length_m, taut, 0.1 * taut);
  EXPECT_GT(r.length_m, taut - 0.05);
  EXPECT_EQ(r.path.front(), Eigen::Vector2d(2.0, 3.0));
  EXPECT_EQ(r.path.back(), Eigen::Vector2d(8.0, 3.0));
  for (const auto& p : r.path) EXPECT_GE(map->nearest(p).distance_m, r_m - 0.06);
}

TEST(GridPathPlannerTest, ClearanceCostKeepsAwayFromWalls) {
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 3.0);
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  const PathResult r = dut.plan({1.0, 0.6}, {9.0, 0.6}, 0.3);
  ASSERT_EQ(r.status, PathStatus::kOk);
  double max_clear = 0.0;
  for (const auto& p : r.path) max_clear = std::max(max_clear, map->nearest(p).distance_m);
  EXPECT_GT(max_clear, 0.7);  // moved towards radius + preferred clearance
}

TEST(GridPathPlannerTest, BlockedCorridorFailsCleanly) {
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 3.0);
  map->addBox({Eigen::Vector2d(5.0, 0.0), Eigen::Vector2d(5.2, 3.0)});
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  const PathResult r = dut.plan({1.0, 1.5}, {9.0, 1.5}, 0.3);
  EXPECT_EQ(r.status, PathStatus::kNoPath);
  EXPECT_TRUE(r.path.empty());
}

TEST(GridPathPlannerTest, GapNarrowerThanTheAgentIsBlocked) {
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 3.0);
  map->addBox({Eigen::Vector2d(5.0, 0.0), Eigen::Vector2d(5.2, 2.6)});  // 0.4 m gap
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  EXPECT_EQ(dut.plan({1.0, 1.5}, {9.0, 1.5}, 0.3).status, PathStatus::kNoPath);
  EXPECT_EQ(dut.plan({1.0, 1.5}, {9.0, 1.5}, 0.15).status, PathStatus::kOk);
}

/// The outline of a box as laser returns every 0.05 m (the faces a scan would see and more).
std::vector<Eigen::Vector2d> boxReturns(double x0, double y0, double x1, double y1) {
  std::vector<Eigen::Vector2d> pts;
  for (double x = x0; x <= x1 + 1e-9; x += 0.05) {
    pts.emplace_back(x, y0);
    pts.emplace_back(x, y1);
  }
  for (double y = y0; y <= y1 + 1e-9; y += 0.05) {
    pts.emplace_back(x0, y);
    pts.emplace_back(x1, y);
  }
  return pts;
}

double nearestReturn(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& pts) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& q : pts) d = std::min(d, (q - p).norm());
  return d;
}

TEST(GridPathPlannerTest, ObstaclesOfTheMomentAreGoneRound) {
  // Given open.pgm's 2.25 m corridor and a box against its lower wall that the map does not
  // hold, 1.4 m free above it (unmapped_box_corridor), and the PR2's radius.
  auto map = BoxMap::corridor(0.0, 30.0, 0.45, 2.70);
  const auto box = boxReturns(15.0, 0.45, 15.6, 1.3);
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  const double r_m = 0.47;
  // Then the static map's path runs through it, the path with its returns round it, above.
  const PathResult blind = dut.plan({11.0, 1.575}, {21.0, 1.575}, r_m);
  ASSERT_EQ(blind.status, PathStatus::kOk);
  double blind_min = std::numeric_limits<double>::infinity();
  for (const auto& p : blind.path) blind_min = std::min(blind_min, nearestReturn(p, box));
  EXPECT_LT(blind_min, 0.3);
  const PathResult r = dut.plan({11.0, 1.575}, {21.0, 1.575}, r_m, box);
  ASSERT_EQ(r.status, PathStatus::kOk);
  for (const auto& p : r.path) {
    EXPECT_GE(nearestReturn(p, box), r_m - 0.071) << p.transpose();
    EXPECT_GE(map->nearest(p).distance_m, r_m - 0.071) << p.transpose();
  }
  EXPECT_EQ(r.path.front(), Eigen::Vector2d(11.0, 1.575));
  EXPECT_EQ(r.path.back(), Eigen::Vector2d(21.0, 1.575));
  // And the query leaves the planner as it was: the next plan without returns is the blind one.
  EXPECT_EQ(dut.plan({11.0, 1.575}, {21.0, 1.575}, r_m).path, blind.path);
}

TEST(GridPathPlannerTest, ReturnsThatCloseTheCorridorLeaveNoPath) {
  // A box leaving 0.7 m of a 2.25 m corridor: a 0.94 m robot cannot pass, a 0.6 m one can.
  auto map = BoxMap::corridor(0.0, 30.0, 0.45, 2.70);
  const auto box = boxReturns(15.0, 0.45, 15.6, 2.0);
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  EXPECT_EQ(dut.plan({11.0, 1.575}, {21.0, 1.575}, 0.47, box).status, PathStatus::kNoPath);
  EXPECT_EQ(dut.plan({11.0, 1.575}, {21.0, 1.575}, 0.25, box).status, PathStatus::kOk);
  // Non-finite returns are ignored, not trusted.
  EXPECT_EQ(dut.plan({11.0, 1.575}, {21.0, 1.575}, 0.47,
                     {Eigen::Vector2d(std::nan(""), 1.0), Eigen::Vector2d(1e300, 1e300)})
                .status,
            PathStatus::kOk);
}

TEST(GridPathPlannerTest, StatusesForBadEndpoints) {
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 3.0);
  map->addBox({Eigen::Vector2d(5.0, 1.0), Eigen::Vector2d(6.0, 2.0)});
  GridPathPlanner dut(map, GridPathPlanner::Options{});
  EXPECT_EQ(dut.plan({5.5, 1.5}, {9.0, 1.5}, 0.3).status, PathStatus::kStartInObstacle);
  EXPECT_EQ(dut.plan({1.0, 1.5}, {5.5, 1.5}, 0.3).status, PathStatus::kGoalInObstacle);
  EXPECT_EQ(dut.plan({-50.0, 1.5}, {9.0, 1.5}, 0.3).status, PathStatus::kStartOutsideMap);
  EXPECT_EQ(dut.plan({1.0, 1.5}, {90.0, 1.5}, 0.3).status, PathStatus::kGoalOutsideMap);
  EXPECT_EQ(dut.plan({NAN, 1.5}, {9.0, 1.5}, 0.3).status, PathStatus::kInvalidInput);
}

TEST(PathUtilsTest, SubPathAndResample) {
  const Path2 p{{0.0, 0.0}, {4.0, 0.0}, {4.0, 3.0}};
  EXPECT_DOUBLE_EQ(pathLength(p), 7.0);
  const Path2 s = subPath(p, 3.0, 2.0);
  EXPECT_NEAR(pathLength(s), 2.0, 1e-9);
  EXPECT_TRUE(s.front().isApprox(Eigen::Vector2d(3.0, 0.0)));
  EXPECT_TRUE(s.back().isApprox(Eigen::Vector2d(4.0, 1.0)));
  const Path2 r = resamplePath(p, 0.5);
  EXPECT_EQ(r.size(), 15u);
  EXPECT_NEAR(pathLength(r), 7.0, 1e-9);
}

}  // namespace
}  // namespace coopnav
