// Crossing info of paper §II-B: i*, CP_h, CP_r, t_CROSS and Dir on hand-made bands.
#include "coopnav/assessment/crossing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace coopnav::assessment {
namespace {

// Band of a constant-velocity agent: p(t) = p0 + v t, poses every dt_s from 0 to duration_s.
Band straightBand(Eigen::Vector2d p0, Eigen::Vector2d v, double dt_s, double duration_s) {
  Band b;
  const double theta = std::atan2(v.y(), v.x());
  const int n = static_cast<int>(std::round(duration_s / dt_s));
  for (int i = 0; i <= n; ++i) {
    const double t = i * dt_s;
    const Eigen::Vector2d p = p0 + v * t;
    b.poses.push_back({t, {p.x(), p.y(), theta}});
  }
  return b;
}

TEST(Crossing, UnequalDtBandsArePairedByTimeNotIndex) {
  // Given robot R(t) = (t, 0) sampled every 0.1 s and human H(t) = (10 - t, 1) every 0.25 s.
  const Band robot = straightBand({0, 0}, {1, 0}, 0.1, 10.0);
  const Band human = straightBand({10, 1}, {-1, 0}, 0.25, 10.0);
  // When computing the crossing.
  const CrossingInfo c = computeCrossing(robot, human);
  // Then closest approach is at t = 5 s (|R - H| = 1), where index pairing would say
  // 0.1 i = 10 - 0.25 i -> i ≈ 28.6, i.e. t ≈ 2.9 s or 7.1 s.
  ASSERT_EQ(c.status, CrossingStatus::kOk) << c.reason;
  ASSERT_TRUE(c.t_cross_s.has_value());
  EXPECT_NEAR(*c.t_cross_s, 5.0, 1e-9);
  EXPECT_NEAR(c.cp_h.x(), 5.0, 1e-9);
  EXPECT_NEAR(c.cp_h.y(), 1.0, 1e-9);
  EXPECT_NEAR(c.cp_r.x(), 5.0, 1e-9);
  EXPECT_NEAR(c.cp_r.y(), 0.0, 1e-9);
  EXPECT_EQ(c.i_star, 100);  // 5 s / 0.05 s
  EXPECT_EQ(c.grid_size, 201);
}

TEST(Crossing, DirLeftWhenRobotIsOnTheHumansLeft) {
  // Human walks -x at y = 1; its left is -y, where the robot (y = 0) passes:
  // cross(h, CP_r - CP_h) = cross((-1, 0), (0, -1)) = +1 > 0.
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 10.0),
                                         straightBand({10, 1}, {-1, 0}, 0.25, 10.0));
  EXPECT_EQ(c.dir, Side::kLeft);
  EXPECT_FALSE(c.dir_from_fallback);
}

TEST(Crossing, DirRightWhenRobotIsOnTheHumansRight) {
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 10.0),
                                         straightBand({10, -1}, {-1, 0}, 0.25, 10.0));
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_EQ(c.dir, Side::kRight);
}

TEST(Crossing, DirUndefinedOnDeadOnCourseWithoutLateralMove) {
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 10.0),
                                         straightBand({10, 0}, {-1, 0}, 0.2, 10.0));
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_NEAR(*c.t_cross_s, 5.0, 1e-9);
  EXPECT_EQ(c.dir, Side::kUndefined);
  EXPECT_FALSE(c.reason.empty());
}

TEST(Crossing, DirFallsBackToTheSideTheRobotBandMovesTo) {
  // Dead-on at t = 5 s, then the robot band veers to +y = the right of a human walking -x.
  Band robot;
  for (int i = 0; i <= 100; ++i) {
    const double t = i * 0.1;
    robot.poses.push_back({t, {t, t > 5.0 ? 0.5 * (t - 5.0) : 0.0, 0.0}});
  }
  const CrossingInfo c = computeCrossing(robot, straightBand({10, 0}, {-1, 0}, 0.2, 10.0));
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_NEAR(*c.t_cross_s, 5.0, 1e-9);
  EXPECT_EQ(c.dir, Side::kRight);
  EXPECT_TRUE(c.dir_from_fallback);
}

TEST(Crossing, StillClosingAtHorizonIsBeyondHorizonWithUnknownTime) {
  // Bands of 3 s while the crossing would be at 5 s.
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 3.0),
                                         straightBand({10, 1}, {-1, 0}, 0.25, 3.0));
  EXPECT_EQ(c.status, CrossingStatus::kBeyondHorizon);
  EXPECT_FALSE(c.t_cross_s.has_value());
  EXPECT_TRUE(std::isnan(c.cp_h.x()));
  EXPECT_FALSE(c.reason.empty());
}

TEST(Crossing, DivergingAgentsCrossAtTheFirstCommonTime) {
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {-1, 0}, 0.1, 3.0),
                                         straightBand({2, 1}, {1, 0}, 0.25, 3.0));
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_NEAR(*c.t_cross_s, 0.0, 1e-12);
}

TEST(Crossing, ConstantDistanceIsNotBeyondHorizon) {
  // Parallel walkers: every grid point ties, the first one wins, nothing is closing.
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 3.0),
                                         straightBand({0, 2}, {1, 0}, 0.25, 3.0));
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_NEAR(*c.t_cross_s, 0.0, 1e-12);
}

TEST(Crossing, LaterStartingBandStartsTheCommonGrid) {
  // Human band poses from t = 1 s (its first pose is already 1 s in): grid from 1 s.
  Band human = straightBand({10, 1}, {-1, 0}, 0.25, 10.0);
  human.poses.erase(human.poses.begin(), human.poses.begin() + 4);
  const CrossingInfo c = computeCrossing(straightBand({0, 0}, {1, 0}, 0.1, 10.0), human);
  ASSERT_EQ(c.status, CrossingStatus::kOk);
  EXPECT_NEAR(*c.t_cross_s, 5.0, 1e-9);
  EXPECT_EQ(c.i_star, 80);
}

TEST(Crossing, BadBandsAreRejectedWithAReason) {
  const Band good = straightBand({0, 0}, {1, 0}, 0.1, 3.0);
  Band empty;
  Band one;
  one.poses.push_back({0.0, {0, 0, 0}});
  Band nan_pose = good;
  nan_pose.poses[3].pose.y_m = std::numeric_limits<double>::quiet_NaN();
  Band nan_time = good;
  nan_time.poses[2].t_s = std::numeric_limits<double>::quiet_NaN();
  Band not_increasing = good;
  not_increasing.poses[5].t_s = not_increasing.poses[4].t_s;
  Band later = good;
  for (auto& p : later.poses) p.t_s += 10.0;  // no common time span
  for (const Band* bad : {&empty, &one, &nan_pose, &nan_time, &not_increasing}) {
    const CrossingInfo a = computeCrossing(good, *bad);
    const CrossingInfo b = computeCrossing(*bad, good);
    EXPECT_EQ(a.status, CrossingStatus::kBadBands);
    EXPECT_EQ(b.status, CrossingStatus::kBadBands);
    EXPECT_FALSE(a.reason.empty());
    EXPECT_FALSE(a.t_cross_s.has_value());
    EXPECT_EQ(a.dir, Side::kUndefined);
  }
  EXPECT_EQ(computeCrossing(good, later).status, CrossingStatus::kBadBands);
  CrossingConfig bad_dt;
  bad_dt.grid_dt_s = 0.0;
  EXPECT_EQ(computeCrossing(good, good, bad_dt).status, CrossingStatus::kBadBands);
}

// Two 2-pose bands whose poses span `span_s`, crossing at mid-span.
std::pair<Band, Band> twoPoseBands(double span_s) {
  Band robot;
  robot.poses.push_back({0.0, {0, 0, 0}});
  robot.poses.push_back({span_s, {10, 0, 0}});
  Band human;
  human.poses.push_back({0.0, {10, 1, M_PI}});
  human.poses.push_back({span_s, {0, 1, M_PI}});
  return {robot, human};
}

void expectBadBandsNaming(const CrossingInfo& c, const std::string& cap) {
  EXPECT_EQ(c.status, CrossingStatus::kBadBands);
  EXPECT_EQ(c.grid_size, 0);
  EXPECT_EQ(c.i_star, -1);
  EXPECT_FALSE(c.t_cross_s.has_value());
  EXPECT_EQ(c.dir, Side::kUndefined);
  EXPECT_NE(c.reason.find(cap), std::string::npos) << c.reason;
}

TEST(Crossing, BandsSpanningTenMillionSecondsAreBadBandsWithoutBuildingTheGrid) {
  // Unchecked, the common grid of these bands had 2*10^8 points (> 1.9 GB in the daemon).
  const auto [robot, human] = twoPoseBands(1e7);
  expectBadBandsNaming(computeCrossing(robot, human), "max_band_span_s");
  expectBadBandsNaming(computeCrossing(human, robot), "max_band_span_s");
  // One long band is enough, whichever it is: the other may be a normal one.
  const Band normal = straightBand({0, 0}, {1, 0}, 0.1, 10.0);
  const CrossingInfo c = computeCrossing(normal, human);
  expectBadBandsNaming(c, "max_band_span_s");
  EXPECT_NE(c.reason.find("human band spans 10000000 s"), std::string::npos) << c.reason;
}

TEST(Crossing, AGridOverMaxGridPointsIsBadBandsWhateverTheSpanCap) {
  // The span cap lifted: the grid's own cap still holds, its size computed without an integer
  // overflow for spans up to 10^300 s, and with the grid cap at its most too.
  CrossingConfig no_span_cap;
  no_span_cap.max_band_span_s = std::numeric_limits<double>::max();
  for (const double span_s : {1e7, 1e12, 1e300}) {
    SCOPED_TRACE(span_s);
    const auto [robot, human] = twoPoseBands(span_s);
    expectBadBandsNaming(computeCrossing(robot, human, no_span_cap), "max_grid_points");
  }
  CrossingConfig no_cap = no_span_cap;
  no_cap.max_grid_points = std::numeric_limits<int>::max();
  for (const double span_s : {1e12, 1e300}) {  // 2*10^13 points and more: over INT_MAX
    SCOPED_TRACE(span_s);
    const auto [robot, human] = twoPoseBands(span_s);
    expectBadBandsNaming(computeCrossing(robot, human, no_cap), "max_grid_points");
  }
}

TEST(Crossing, BandsAtTheCapsAreAssessedAndJustOverThemAreNot) {
  // Default caps: a 600 s overlap at 0.05 s is 12001 points, assessed as any band.
  const CrossingConfig defaults;
  {
    const auto [robot, human] = twoPoseBands(defaults.max_band_span_s);
    const CrossingInfo c = computeCrossing(robot, human);
    ASSERT_EQ(c.status, CrossingStatus::kOk) << c.reason;
    EXPECT_EQ(c.grid_size, 12001);
    EXPECT_NEAR(*c.t_cross_s, 300.0, 1e-6);
    const auto [long_robot, long_human] = twoPoseBands(defaults.max_band_span_s + 0.01);
    expectBadBandsNaming(computeCrossing(long_robot, long_human), "max_band_span_s");
  }
  // max_grid_points exactly the grid's size: assessed; one less: bad bands.
  const Band robot = straightBand({0, 0}, {1, 0}, 0.1, 10.0);
  const Band human = straightBand({10, 1}, {-1, 0}, 0.25, 10.0);
  CrossingConfig exact;
  exact.max_grid_points = 201;  // 10 s / 0.05 s + 1
  EXPECT_EQ(computeCrossing(robot, human, exact).status, CrossingStatus::kOk);
  EXPECT_EQ(computeCrossing(robot, human, exact).grid_size, 201);
  CrossingConfig one_less = exact;
  one_less.max_grid_points = 200;
  expectBadBandsNaming(computeCrossing(robot, human, one_less), "max_grid_points");
}

TEST(Crossing, AnOverlapWithinTheMergingToleranceIsNoCommonSpan) {
  // Overlap 10^-12 s: its grid would be the end point alone, with no step to judge closing on.
  Band robot;
  robot.poses.push_back({0.0, {0, 0, 0}});
  robot.poses.push_back({1.0, {1, 0, 0}});
  Band human;
  human.poses.push_back({1.0 - 1e-12, {3, 1, M_PI}});
  human.poses.push_back({5.0, {0, 1, M_PI}});
  expectBadBandsNaming(computeCrossing(robot, human), "no time span");
}

TEST(Crossing, InterpolationOfHeadingTakesTheShorterArc) {
  Band b;
  b.poses.push_back({0.0, {0, 0, 3.0}});
  b.poses.push_back({1.0, {2, 0, -3.0}});
  const Pose2 p = interpolateBand(b, 0.5);
  EXPECT_NEAR(p.x_m, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(p.theta_rad), M_PI, 1e-12);        // not 0
  EXPECT_NEAR(interpolateBand(b, -1.0).x_m, 0.0, 1e-12);  // clamped
  EXPECT_NEAR(interpolateBand(b, 5.0).x_m, 2.0, 1e-12);
}

}  // namespace
}  // namespace coopnav::assessment
