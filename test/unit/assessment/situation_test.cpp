// Geometric assessment of paper §II-B: d_h, half-plane queries, d_HR and the three predicates.
#include "coopnav/assessment/situation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace coopnav::assessment {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr Tristate T = Tristate::kTrue;
constexpr Tristate F = Tristate::kFalse;
constexpr Tristate U = Tristate::kUnknown;

CrossingInfo okCrossing(Eigen::Vector2d cp_h, Eigen::Vector2d cp_r, double heading_rad, Side dir) {
  CrossingInfo c;
  c.status = CrossingStatus::kOk;
  c.i_star = 10;
  c.t_cross_s = 5.0;
  c.cp_h = cp_h;
  c.cp_r = cp_r;
  c.human_heading_rad = heading_rad;
  c.dir = dir;
  return c;
}

TEST(HalfPlaneQueries, NormalsPointAwayFromTheOtherAgent) {
  const auto q = halfPlaneQueries(okCrossing({5, 1}, {5, 0}, M_PI, Side::kLeft));
  ASSERT_TRUE(q.has_value());
  EXPECT_FALSE(q->from_heading_fallback);
  EXPECT_TRUE(q->human.point.isApprox(Eigen::Vector2d(5, 1)));
  EXPECT_TRUE(q->human.normal.isApprox(Eigen::Vector2d(0, 1)));  // from CP_r to CP_h
  EXPECT_TRUE(q->robot.point.isApprox(Eigen::Vector2d(5, 0)));
  EXPECT_TRUE(q->robot.normal.isApprox(Eigen::Vector2d(0, -1)));  // from CP_h to CP_r
}

TEST(HalfPlaneQueries, CoincidentPointsUseTheHeadingNormalAwayFromDir) {
  // Human heading -x; Dir = RIGHT (+y side), so the human moves to its left (-y).
  const auto q = halfPlaneQueries(okCrossing({5, 0}, {5, 0.01}, M_PI, Side::kRight));
  ASSERT_TRUE(q.has_value());
  EXPECT_TRUE(q->from_heading_fallback);
  EXPECT_NEAR(q->human.normal.x(), 0.0, 1e-12);
  EXPECT_NEAR(q->human.normal.y(), -1.0, 1e-12);
  EXPECT_NEAR(q->robot.normal.y(), 1.0, 1e-12);
  // Dir LEFT mirrors it.
  const auto q2 = halfPlaneQueries(okCrossing({5, 0}, {5, 0}, M_PI, Side::kLeft));
  ASSERT_TRUE(q2.has_value());
  EXPECT_NEAR(q2->human.normal.y(), 1.0, 1e-12);
}

TEST(HalfPlaneQueries, NoQueryWithoutAUsableSide) {
  EXPECT_FALSE(halfPlaneQueries(okCrossing({5, 0}, {5, 0}, M_PI, Side::kUndefined)).has_value());
  CrossingInfo beyond;
  beyond.status = CrossingStatus::kBeyondHorizon;
  EXPECT_FALSE(halfPlaneQueries(beyond).has_value());
}

TEST(ObstacleDistance, ServerStatusesMapToKnownOrUnknown) {
  DistanceResult r;
  r.status = DistanceStatus::kOk;
  r.distance_m = 0.7;
  EXPECT_EQ(obstacleDistanceFrom(r), 0.7);
  // As a body's clearance: centre distance minus the radius, never negative.
  EXPECT_DOUBLE_EQ(*obstacleDistanceFrom(r, 0.47), 0.7 - 0.47);
  EXPECT_EQ(*obstacleDistanceFrom(r, 0.9), 0.0);
  r.status = DistanceStatus::kInObstacle;
  EXPECT_EQ(obstacleDistanceFrom(r), 0.0);
  r.status = DistanceStatus::kNotFound;
  EXPECT_EQ(obstacleDistanceFrom(r), kInf);
  for (auto s : {DistanceStatus::kOutsideMap, DistanceStatus::kUnknownSpace,
                 DistanceStatus::kInvalidQuery}) {
    r.status = s;
    EXPECT_FALSE(obstacleDistanceFrom(r).has_value());
  }
}

TEST(DistanceToReferencePath, IsTheUnsignedDistanceOfCpH) {
  const Path2 path{{0, 0}, {10, 0}};
  EXPECT_NEAR(*distanceToReferencePath({5, 1}, path), 1.0, 1e-12);
  EXPECT_NEAR(*distanceToReferencePath({5, -0.4}, path), 0.4, 1e-12);
  EXPECT_NEAR(*distanceToReferencePath({13, 4}, path), 5.0, 1e-12);  // past the end: to the end
  EXPECT_FALSE(distanceToReferencePath({5, 1}, Path2{}).has_value());
  EXPECT_FALSE(distanceToReferencePath({kNaN, 1}, path).has_value());
}

TEST(Predicates, HumanNeedsToContributeAroundTauH) {
  const double tau = 0.3;
  EXPECT_EQ(humanNeedsToContribute(0.2999, tau), F);
  EXPECT_EQ(humanNeedsToContribute(0.3, tau), F);  // strict: d_h > τ_h
  EXPECT_EQ(humanNeedsToContribute(0.3001, tau), T);
  EXPECT_EQ(humanNeedsToContribute(std::nullopt, tau), U);
  EXPECT_EQ(humanNeedsToContribute(kNaN, tau), U);
}

TEST(Predicates, HumanIsConstrainedAroundTauOH) {
  const double tau = 1.0;
  EXPECT_EQ(humanIsConstrained(0.999, tau), T);
  EXPECT_EQ(humanIsConstrained(1.0, tau), F);  // strict: d_OH < τ_OH
  EXPECT_EQ(humanIsConstrained(1.001, tau), F);
  EXPECT_EQ(humanIsConstrained(0.0, tau), T);
  EXPECT_EQ(humanIsConstrained(kInf, tau), F);  // nothing within range is known, not unknown
  EXPECT_EQ(humanIsConstrained(std::nullopt, tau), U);
  EXPECT_EQ(humanIsConstrained(kNaN, tau), U);
}

TEST(Predicates, RobotIsConstrainedIsAKleeneConjunction) {
  struct Row {
    std::optional<double> d_hr, d_or;
    Tristate expected;
  };
  const Row rows[] = {
      {1.19, 0.29, T},         {1.2, 0.29, F},          {1.21, 0.29, F},
      {1.19, 0.3, F},          {1.19, 0.31, F},         {1.19, kInf, F},
      {std::nullopt, 0.29, U}, {1.19, std::nullopt, U}, {1.19, kNaN, U},
      {1.3, std::nullopt, F},  {std::nullopt, 0.5, F},  {std::nullopt, std::nullopt, U},
  };
  for (const Row& r : rows) {
    EXPECT_EQ(robotIsConstrained(r.d_hr, r.d_or, 1.2, 0.3), r.expected)
        << "d_hr " << r.d_hr.value_or(-1) << " d_or " << r.d_or.value_or(-1);
  }
}

TEST(AssessSituation, ComputesAllDistancesAndPredicates) {
  // CP_h 1 m off its path (y = 0), robot 1 m away, d_OH 0.8 m, d_OR 0.2 m.
  const Path2 path{{0, 1}, {10, 1}};
  const CrossingInfo c = okCrossing({5, 0}, {5, -1}, M_PI, Side::kLeft);
  const SituationAssessment a = assessSituation(c, path, 0.8, 0.2);
  EXPECT_NEAR(*a.d_h_m, 1.0, 1e-12);
  EXPECT_NEAR(*a.d_hr_m, 1.0, 1e-12);
  EXPECT_EQ(*a.d_oh_m, 0.8);
  EXPECT_EQ(*a.d_or_m, 0.2);
  EXPECT_EQ(a.human_needs_to_contribute, T);
  EXPECT_EQ(a.human_is_constrained, T);
  EXPECT_EQ(a.robot_is_constrained, T);
  EXPECT_TRUE(a.reason.empty()) << a.reason;
}

TEST(AssessSituation, MissingInputsGiveUnknownWithReason) {
  const CrossingInfo c = okCrossing({5, 0}, {5, -1}, M_PI, Side::kLeft);
  const SituationAssessment a = assessSituation(c, Path2{}, std::nullopt, kNaN);
  EXPECT_EQ(a.human_needs_to_contribute, U);
  EXPECT_EQ(a.human_is_constrained, U);
  EXPECT_EQ(a.robot_is_constrained, U);  // d_HR 1 < 1.2 but d_OR unknown
  EXPECT_NE(a.reason.find("reference path"), std::string::npos);
  EXPECT_NE(a.reason.find("d_OH"), std::string::npos);
  EXPECT_NE(a.reason.find("d_OR"), std::string::npos);
}

TEST(AssessSituation, BadCrossingMakesEverythingUnknown) {
  CrossingInfo c;
  c.status = CrossingStatus::kBadBands;
  c.reason = "human band has 1 poses";
  c.cp_h = {5, 0};  // garbage that must not be used
  c.cp_r = {5, 0};
  const SituationAssessment a = assessSituation(c, Path2{{0, 1}, {10, 1}}, 0.1, 0.1);
  EXPECT_FALSE(a.d_h_m.has_value());
  EXPECT_FALSE(a.d_hr_m.has_value());
  EXPECT_FALSE(a.d_oh_m.has_value());
  EXPECT_EQ(a.human_needs_to_contribute, U);
  EXPECT_EQ(a.human_is_constrained, U);
  EXPECT_EQ(a.robot_is_constrained, U);
  EXPECT_NE(a.reason.find("bad_bands"), std::string::npos);
}

}  // namespace
}  // namespace coopnav::assessment
