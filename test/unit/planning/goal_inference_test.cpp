#include "coopnav/planning/goal_inference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "../band/analytic_map.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance/occupancy_grid.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

/// Free rectangle [x0, x1] x [y0, y1] carved into grid (world coordinates).
void carve(OccupancyGrid2& grid, double x0, double x1, double y0, double y1) {
  for (int j = 0; j < grid.height(); ++j) {
    for (int i = 0; i < grid.width(); ++i) {
      const Eigen::Vector2d c = grid.cellCenter_m(i, j);
      if (c.x() > x0 && c.x() < x1 && c.y() > y0 && c.y() < y1) grid.set(i, j, CellState::kFree);
    }
  }
}

/// A T: a 2 m bar along x (x 2..22, y 10..12, closed ends) and a 2 m stem (x 11..13) from the
/// bar down to the map's bottom border (y = 0), where it is open.
std::shared_ptr<GridDistanceField> tJunction() {
  OccupancyGrid2 grid(480, 280, 0.05, Eigen::Vector2d(0.0, 0.0), CellState::kOccupied);
  carve(grid, 2.0, 22.0, 10.0, 12.0);
  carve(grid, 11.0, 13.0, -1.0, 10.5);
  return std::make_shared<GridDistanceField>(std::move(grid));
}

/// The distance from p to the nearest candidate's centre.
double nearestCandidate(const std::vector<GoalRegion>& c, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& q : c) best = std::min(best, (q.centre() - p).norm());
  return best;
}

TEST(MapGoalCandidatesTest, StraightClosedCorridorGivesItsTwoEnds) {
  // Given a closed 20 x 2 m corridor.
  const auto map = BoxMap::corridor(0.0, 20.0, 0.0, 2.0);
  // When searching candidates.
  const auto c = mapGoalCandidates(*map);
  // Then there are exactly its two ends, on the centre line about w/2 from the end walls.
  ASSERT_EQ(c.size(), 2u);
  EXPECT_LT(nearestCandidate(c, {1.0, 1.0}), 0.5);
  EXPECT_LT(nearestCandidate(c, {19.0, 1.0}), 0.5);
}

TEST(GoalRegionTest, TargetKeepsTheWalkersPlaceAcrossTheRegion) {
  const GoalRegion r{{10.0, 0.0}, {10.0, 4.0}};
  EXPECT_EQ(r.centre(), Eigen::Vector2d(10.0, 2.0));
  // A walker at y 1.2 crosses at y 1.2; near an end it keeps inset_m from it.
  EXPECT_TRUE(r.target({0.0, 1.2}, 0.3).isApprox(Eigen::Vector2d(10.0, 1.2)));
  EXPECT_TRUE(r.target({0.0, 0.1}, 0.3).isApprox(Eigen::Vector2d(10.0, 0.3)));
  EXPECT_TRUE(r.target({0.0, 9.0}, 0.3).isApprox(Eigen::Vector2d(10.0, 3.7)));
  EXPECT_TRUE(r.closest({0.0, 9.0}).isApprox(Eigen::Vector2d(10.0, 4.0)));
  // A region shorter than twice the inset, and a point, give their centre.
  EXPECT_EQ(r.target({0.0, 1.2}, 2.5), r.centre());
  EXPECT_EQ(GoalRegion::point({1.0, 2.0}).target({5.0, 5.0}, 0.3), Eigen::Vector2d(1.0, 2.0));
  // Euclidean distance to a region is to its nearest point.
  const GoalDistances open(nullptr, std::vector<GoalRegion>{r});
  EXPECT_DOUBLE_EQ(open.distance(0, {7.0, 1.0}), 3.0);
  EXPECT_DOUBLE_EQ(open.distance(0, {10.0, 7.0}), 3.0);
}

TEST(MapGoalCandidatesTest, ACorridorEndIsItsCrossSection) {
  // Given a closed 20 x 2 m corridor: each end's region runs across the corridor's free width
  // (clearance >= 0.3 m: y 0.3..1.7), so a walker keeping its lane heads straight on.
  const auto map = BoxMap::corridor(0.0, 20.0, 0.0, 2.0);
  const auto c = mapGoalCandidates(*map);
  ASSERT_EQ(c.size(), 2u);
  for (const auto& r : c) {
    EXPECT_NEAR(std::abs(r.b.y() - r.a.y()), 1.4, 0.15);
    EXPECT_NEAR(r.a.x(), r.b.x(), 0.05);
    EXPECT_NEAR(r.target({10.0, 0.6}, 0.3).y(), 0.6, 0.05);
  }
  // The geodesic distance to an end is to its nearest point: from the same lane, straight on.
  const std::size_t right = c[0].centre().x() > 10.0 ? 0 : 1;
  const GoalDistances d(map, c);
  EXPECT_NEAR(d.distance(right, {10.0, 0.6}), c[right].centre().x() - 10.0, 0.15);
}

TEST(GoalBeliefTest, GoalsEquallyConsistentWithTheWalkTieAndTheNearestWins) {
  // Given a corridor and two goals beyond the walker, the farther listed first.
  const auto map = BoxMap::corridor(0.0, 20.0, 0.0, 2.0);
  const auto distances =
      std::make_shared<GoalDistances>(map, std::vector<Eigen::Vector2d>{{18.0, 1.0}, {14.0, 1.0}});
  GoalBelief dut(distances);
  double t = 0.0;
  for (double x = 2.0; x <= 9.0; x += 0.2) dut.observe(t += 0.2, {x, 1.0});
  // Then the walk fits both alike and the nearer one is named.
  EXPECT_NEAR(dut.probabilities()[0], dut.probabilities()[1], 0.05);
  EXPECT_EQ(dut.mostLikely(), 1);
  // In open space (no grid) there is no tolerance: the argmax.
  const auto open = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{18.0, 1.0}, {14.0, 3.0}});
  GoalBelief e(open);
  t = 0.0;
  for (double x = 2.0; x <= 9.0; x += 0.2) e.observe(t += 0.2, {x, 1.0});
  EXPECT_EQ(e.mostLikely(), 0);
}

TEST(GoalBeliefTest, ATieBeforeAJunctionGoesToTheGoalStraightOn) {
  // Given a long bar (x -20..22, y 10..12, closed ends) with a stem at x 11..13 down to an
  // opening at the map's bottom: the stem's opening is nearer than the bar's far end.
  OccupancyGrid2 grid(480, 140, 0.1, Eigen::Vector2d(-22.0, 0.0), CellState::kOccupied);
  carve(grid, -20.0, 22.0, 10.0, 12.0);
  carve(grid, 11.0, 13.0, -1.0, 10.5);
  const auto map = std::make_shared<GridDistanceField>(std::move(grid));
  const std::vector<Eigen::Vector2d> goals{{12.0, 0.3}, {-19.0, 11.0}};
  const auto distances = std::make_shared<GoalDistances>(map, goals);
  GoalBelief dut(distances);
  // When a walker comes along the bar from its right end towards the junction: both goals fit.
  double t = 0.0;
  for (double x = 21.0; x >= 16.0; x -= 0.2) dut.observe(t += 0.2, {x, 11.0});
  ASSERT_NEAR(dut.probabilities()[0], dut.probabilities()[1], 0.05);
  ASSERT_LT(distances->distance(0, {16.0, 11.0}), distances->distance(1, {16.0, 11.0}));
  // Then the one straight on is named, not the nearer one round the corner.
  EXPECT_EQ(dut.mostLikely(), 1);
}

TEST(GoalBeliefTest, APlannedGoalGivesWayOnlyToEvidenceBeyondTheMargin) {
  // Given two goals ahead, to the left and right of the walker's line (Euclidean, beta 1).
  GoalInferenceOptions o;
  o.beta_per_m = 1.0;
  const auto distances = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{20.0, 3.0}, {20.0, -3.0}}, o);
  GoalBelief dut(distances);
  dut.observe(0.0, {0.0, 0.0});
  dut.observe(1.0, {1.0, 0.0});
  // When it steps 0.5 m to the right: goal 1 is the most likely, by less than a 1 m margin.
  dut.observe(2.0, {2.0, -0.5});
  ASSERT_EQ(dut.mostLikely(), 1);
  const double log_odds = std::log(dut.probabilities()[1] / dut.probabilities()[0]);
  ASSERT_LT(log_odds, 1.0);
  EXPECT_EQ(dut.plannedGoal(0, 1.0), 0);             // kept
  EXPECT_EQ(dut.plannedGoal(0, 0.5 * log_odds), 1);  // a smaller margin gives way
  EXPECT_EQ(dut.plannedGoal(-1, 1.0), 1);            // nothing planned yet: the most likely
  EXPECT_EQ(dut.plannedGoal(7, 1.0), 1);             // out of range
  // Then it keeps walking right: the evidence passes the margin and the plan follows.
  dut.observe(3.0, {6.0, -4.0});
  EXPECT_EQ(dut.plannedGoal(0, 1.0), 1);
}

TEST(MapGoalCandidatesTest, TJunctionGivesItsOpeningAndTwoBranchEnds) {
  const auto map = tJunction();
  const auto c = mapGoalCandidates(*map);
  ASSERT_EQ(c.size(), 3u);
  // The opening first (at the border, moved opening_inset_m inward), then the two bar ends.
  EXPECT_LT((c[0].centre() - Eigen::Vector2d(12.0, 0.3)).norm(), 0.1);
  EXPECT_LT(nearestCandidate(c, {3.0, 11.0}), 0.5);
  EXPECT_LT(nearestCandidate(c, {21.0, 11.0}), 0.5);
}

TEST(MapGoalCandidatesTest, ShortStubsAndRoomCornersAreNotCandidates) {
  // Given a 10 x 6 m room (closed) with a 0.6 m deep, 1 m wide niche in its top wall.
  auto map = std::make_shared<BoxMap>(
      Eigen::AlignedBox2d(Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(10.5, 7.5)),
      std::vector<Eigen::AlignedBox2d>{{Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(10.5, 0.0)},
                                       {Eigen::Vector2d(-0.5, 0.0), Eigen::Vector2d(0.0, 7.5)},
                                       {Eigen::Vector2d(10.0, 0.0), Eigen::Vector2d(10.5, 7.5)},
                                       {Eigen::Vector2d(0.0, 6.0), Eigen::Vector2d(4.5, 7.5)},
                                       {Eigen::Vector2d(5.5, 6.0), Eigen::Vector2d(10.0, 7.5)},
                                       {Eigen::Vector2d(4.5, 6.6), Eigen::Vector2d(5.5, 7.5)}});
  const auto c = mapGoalCandidates(*map);
  // Then only the room's two ends along its long axis remain (no corner, no niche).
  ASSERT_EQ(c.size(), 2u);
  EXPECT_LT(nearestCandidate(c, {3.0, 3.0}), 0.6);
  EXPECT_LT(nearestCandidate(c, {7.0, 3.0}), 0.6);
}

TEST(MapGoalCandidatesTest, Deterministic) {
  const auto map = tJunction();
  const auto a = mapGoalCandidates(*map);
  const auto b = mapGoalCandidates(*map);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].a, b[i].a);
    EXPECT_EQ(a[i].b, b[i].b);
  }
}

TEST(GoalDistancesTest, GeodesicGoesAroundAWall) {
  // Given a 10 x 6 m room split by a wall at x 4.9..5.1 from the floor up to y = 4.
  auto map = BoxMap::corridor(0.0, 10.0, 0.0, 6.0);
  map->addBox({Eigen::Vector2d(4.9, 0.0), Eigen::Vector2d(5.1, 4.0)});
  const GoalDistances dut(map, {{8.0, 1.0}});
  // Then from (2, 1) the distance is the way over the wall's top (taut string ~9.0 m for r 0.3;
  // an 8-connected grid adds at most 8 %), not the 6 m straight line.
  const double d = dut.distance(0, {2.0, 1.0});
  EXPECT_GT(d, 8.9);
  EXPECT_LT(d, 9.9);
  EXPECT_NEAR(dut.distance(0, {8.0, 1.0}), 0.0, 0.1);
  EXPECT_NEAR(dut.distance(0, {8.0, 3.0}), 2.0, 0.15);
  // Outside the map, non-finite, or a goal that does not exist: +inf.
  EXPECT_TRUE(std::isinf(dut.distance(0, {50.0, 1.0})));
  EXPECT_TRUE(std::isinf(dut.distance(0, {NAN, 1.0})));
  EXPECT_TRUE(std::isinf(dut.distance(1, {2.0, 1.0})));
  // Near a wall (clearance 0.15 < r): still a finite distance.
  EXPECT_TRUE(std::isfinite(dut.distance(0, {2.0, 0.15})));
}

TEST(GoalBeliefTest, PosteriorFollowsTheBranchTheTrackTakes) {
  // Given the T with its three candidates (geodesic).
  const auto map = tJunction();
  const auto goals = mapGoalCandidates(*map);
  ASSERT_EQ(goals.size(), 3u);
  const auto distances = std::make_shared<GoalDistances>(map, goals);
  GoalBelief dut(distances);
  std::size_t left = 1, right = 2;
  if (goals[1].centre().x() > goals[2].centre().x()) std::swap(left, right);
  // When a human walks up the stem: the bar's two ends stay equally likely, the opening behind
  // it drops.
  double t = 0.0;
  for (double y = 2.0; y <= 9.0; y += 0.2) dut.observe(t += 0.2, {12.0, y});
  EXPECT_NEAR(dut.probabilities()[left], dut.probabilities()[right], 0.05);
  EXPECT_LT(dut.probabilities()[0], 1e-3);
  // Then it turns left: the left end becomes the most likely.
  for (double x = 12.0; x >= 7.0; x -= 0.2) dut.observe(t += 0.2, {x, 11.0});
  EXPECT_EQ(dut.mostLikely(), static_cast<int>(left));
  EXPECT_GT(dut.probabilities()[left], 0.99);
  double sum = 0.0;
  for (const double p : dut.probabilities()) sum += p;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_NEAR(dut.walkedLength_m(), 7.0 + 5.0 + 2.0, 0.3);
}

TEST(GoalBeliefTest, UnreachableGoalGetsZeroAndAllUnreachableGivesUniform) {
  // Given a corridor cut in two by a full-height wall at x = 10.
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 3.0);
  map->addBox({Eigen::Vector2d(9.8, 0.0), Eigen::Vector2d(10.2, 3.0)});
  const auto distances = std::make_shared<GoalDistances>(
      map, std::vector<Eigen::Vector2d>{{2.0, 1.5}, {18.0, 1.5}, {8.0, 1.5}});
  EXPECT_TRUE(std::isinf(distances->distance(1, {5.0, 1.5})));
  GoalBelief dut(distances);
  dut.observe(0.0, {5.0, 1.5});
  dut.observe(1.0, {5.5, 1.5});
  EXPECT_EQ(dut.probabilities()[1], 0.0);
  EXPECT_GT(dut.probabilities()[2], dut.probabilities()[0]);

  // Every goal on the other side: nothing to prefer, the prior (uniform) stays.
  const auto far =
      std::make_shared<GoalDistances>(map, std::vector<Eigen::Vector2d>{{15.0, 1.5}, {18.0, 1.5}});
  GoalBelief cut(far);
  cut.observe(0.0, {5.0, 1.5});
  cut.observe(1.0, {6.0, 1.5});
  EXPECT_EQ(cut.probabilities(), (std::vector<double>{0.5, 0.5}));
}

TEST(GoalBeliefTest, EuclideanModeMatchesTheFormula) {
  const std::vector<Eigen::Vector2d> goals{{10.0, 0.0}, {0.0, 10.0}, {-10.0, 0.0}};
  GoalInferenceOptions o;
  o.beta_per_m = 0.7;
  const auto distances = std::make_shared<GoalDistances>(nullptr, goals, o);
  EXPECT_FALSE(distances->geodesic());
  EXPECT_DOUBLE_EQ(distances->distance(0, {1.0, 0.0}), 9.0);
  GoalBelief dut(distances);
  // Before any observation: the prior.
  EXPECT_EQ(dut.probabilities(), std::vector<double>(3, 1.0 / 3.0));
  const Eigen::Vector2d s(0.0, 0.0), q(2.0, 1.0);
  dut.observe(0.0, s);
  dut.observe(1.0, {1.0, 0.5});
  dut.observe(2.0, q);
  std::vector<double> w;
  double z = 0.0;
  for (const auto& g : goals) {
    w.push_back(std::exp(-o.beta_per_m * ((q - g).norm() - (s - g).norm())));
    z += w.back();
  }
  for (std::size_t i = 0; i < goals.size(); ++i)
    EXPECT_NEAR(dut.probabilities()[i], w[i] / z, 1e-12) << i;
  EXPECT_EQ(dut.mostLikely(), 0);
  EXPECT_EQ(dut.observations(), 3u);
}

TEST(GoalBeliefTest, LogSpaceStaysFiniteForALargeBeta) {
  GoalInferenceOptions o;
  o.beta_per_m = 1e4;
  const auto distances = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{100.0, 0.0}, {-100.0, 0.0}}, o);
  GoalBelief dut(distances);
  dut.observe(0.0, {0.0, 0.0});
  dut.observe(10.0, {10.0, 0.0});  // exp(-1e5) underflows; log space must not
  EXPECT_EQ(dut.probabilities()[0], 1.0);
  EXPECT_EQ(dut.probabilities()[1], 0.0);
  EXPECT_EQ(dut.mostLikely(), 0);
}

TEST(GoalBeliefTest, BadInputIsIgnored) {
  const auto distances = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{10.0, 0.0}, {-10.0, 0.0}});
  GoalBelief dut(distances);
  EXPECT_TRUE(dut.observe(1.0, {0.0, 0.0}));
  EXPECT_TRUE(dut.observe(2.0, {1.0, 0.0}));
  const auto before = dut.probabilities();
  EXPECT_FALSE(dut.observe(3.0, {NAN, 0.0}));
  EXPECT_FALSE(dut.observe(NAN, {-5.0, 0.0}));
  EXPECT_FALSE(dut.observe(std::numeric_limits<double>::infinity(), {-5.0, 0.0}));
  EXPECT_FALSE(dut.observe(2.0, {-5.0, 0.0}));  // not after the last time
  EXPECT_FALSE(dut.observe(1.5, {-5.0, 0.0}));  // time going back
  EXPECT_EQ(dut.probabilities(), before);
  EXPECT_EQ(dut.observations(), 2u);
  EXPECT_DOUBLE_EQ(dut.walkedLength_m(), 1.0);
}

TEST(GoalBeliefTest, JitterDoesNotWalk) {
  const auto distances = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{10.0, 0.0}, {-10.0, 0.0}});
  GoalBelief dut(distances);
  dut.observe(0.0, {0.0, 0.0});
  for (int k = 1; k <= 20; ++k) dut.observe(0.1 * k, {(k % 2) * 0.02, 0.0});
  EXPECT_EQ(dut.walkedLength_m(), 0.0);
  EXPECT_NEAR(dut.probabilities()[0], 0.5, 1e-12);
}

TEST(GoalBeliefTest, ReachedGoalIsNotAheadUnlessItIsTheOnlyOne) {
  const auto two = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{1.0, 0.0}, {-10.0, 0.0}});
  GoalBelief dut(two);
  dut.observe(0.0, {0.0, 0.0});
  dut.observe(1.0, {0.8, 0.0});  // within 0.5 m of goal 0
  EXPECT_EQ(dut.probabilities()[0], 0.0);
  EXPECT_EQ(dut.mostLikely(), 1);

  const auto one =
      std::make_shared<GoalDistances>(nullptr, std::vector<Eigen::Vector2d>{{1.0, 0.0}});
  GoalBelief only(one);
  only.observe(0.0, {0.0, 0.0});
  only.observe(1.0, {0.8, 0.0});
  EXPECT_EQ(only.probabilities()[0], 1.0);
}

TEST(GoalBeliefTest, PriorIsUsedAndInvalidPriorIsUniform) {
  const auto distances = std::make_shared<GoalDistances>(
      nullptr, std::vector<Eigen::Vector2d>{{10.0, 0.0}, {-10.0, 0.0}});
  GoalBelief dut(distances, {3.0, 1.0});
  dut.observe(0.0, {0.0, 5.0});
  EXPECT_NEAR(dut.probabilities()[0], 0.75, 1e-12);
  for (const std::vector<double>& bad : std::vector<std::vector<double>>{
           {1.0}, {-1.0, 2.0}, {0.0, 0.0}, {NAN, 1.0}, {1.0, 1.0, 1.0}}) {
    GoalBelief u(distances, bad);
    EXPECT_EQ(u.probabilities(), (std::vector<double>{0.5, 0.5}));
  }
  GoalBelief none(nullptr);
  EXPECT_TRUE(none.observe(0.0, {0.0, 0.0}));
  EXPECT_EQ(none.mostLikely(), -1);
  EXPECT_TRUE(none.probabilities().empty());
}

TEST(GoalBeliefTest, DeterministicForTheSameTrack) {
  const auto map = tJunction();
  const auto distances = std::make_shared<GoalDistances>(map, mapGoalCandidates(*map));
  auto run = [&] {
    GoalBelief b(distances);
    double t = 0.0;
    for (double y = 1.0; y <= 10.0; y += 0.3) b.observe(t += 0.3, {12.0 + 0.1 * std::sin(y), y});
    for (double x = 12.0; x <= 18.0; x += 0.3) b.observe(t += 0.3, {x, 11.0});
    return b.probabilities();
  };
  EXPECT_EQ(run(), run());
}

}  // namespace
}  // namespace coopnav
