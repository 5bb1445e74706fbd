// The forecast of cooperation (assessment/forecast.hpp): features, probability and the IRLS fit on
// hand-computed cases.
#include "coopnav/assessment/forecast.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace coopnav::assessment {
namespace {

// Human walks +x at 1 m/s from the origin and steps to y = -0.2 at t = 1.2 s; the robot comes
// down the line y = 0.5 at 1 m/s from x = 8.
std::vector<ForecastObservation> stepAside() {
  std::vector<ForecastObservation> obs;
  for (const double t : {0.0, 0.4, 0.8, 1.2}) {
    const Eigen::Vector2d h(t, t > 1.0 ? -0.2 : 0.0);
    obs.push_back({t, h, Eigen::Vector2d(8.0 - t, 0.5)});
  }
  return obs;
}

TEST(Forecast, FeaturesOfAStepAwayFromTheRobot) {
  const auto f = forecastFeatures(stepAside(), {0.0, 0.0}, {2.0, 0.0});  // heading normalised
  ASSERT_TRUE(f.has_value());
  EXPECT_FALSE(f->side_ambiguous);
  // Robot on the left (gap u × (r − h) = 0.7 > 0): away is right, s = −1; d = −0.2.
  EXPECT_NEAR(f->x[0], 0.2, 1e-12);
  // Over the last 0.8 s (from t = 0.4, d = 0): −(−0.2) / 0.8.
  EXPECT_NEAR(f->x[1], 0.25, 1e-12);
  // |(1, −0.25)| − |(1, 0)| (first span 0 .. 0.8 s).
  EXPECT_NEAR(f->x[2], std::sqrt(1.0625) - 1.0, 1e-12);
  EXPECT_NEAR(f->x[3], std::atan2(0.25, 1.0), 1e-12);
  // along 5.6 m; closing: −(5.6, 0.7)·(−2, 0.25) / |(5.6, 0.7)| = 11.025 / 5.64358 m/s.
  EXPECT_NEAR(f->x[4], 5.6 * std::sqrt(31.85) / 11.025, 1e-12);
  EXPECT_NEAR(f->x[5], 0.7, 1e-12);
}

TEST(Forecast, InLineRobotTakesTheSideTheHumanMovedTo) {
  auto obs = stepAside();
  for (auto& o : obs) o.robot_m.y() = o.human_m.y() + 0.05;  // within kForecastInLineM
  const auto f = forecastFeatures(obs, {0.0, 0.0}, {1.0, 0.0});
  ASSERT_TRUE(f.has_value());
  EXPECT_TRUE(f->side_ambiguous);
  // The robot "on the left" would make a step right positive too; here s = sign(d) = −1 too,
  // so the same numbers; mirror the step to the left and they stay positive.
  EXPECT_NEAR(f->x[0], 0.2, 1e-12);
  for (auto& o : obs) {
    o.human_m.y() = -o.human_m.y();
    o.robot_m.y() = o.human_m.y() - 0.05;
  }
  const auto g = forecastFeatures(obs, {0.0, 0.0}, {1.0, 0.0});
  ASSERT_TRUE(g.has_value());
  EXPECT_TRUE(g->side_ambiguous);
  EXPECT_NEAR(g->x[0], 0.2, 1e-12);
  EXPECT_NEAR(g->x[1], 0.25, 1e-12);
}

TEST(Forecast, NoFeaturesBeforeAVelocity) {
  auto obs = stepAside();
  EXPECT_FALSE(forecastFeatures({obs[0]}, {0.0, 0.0}, {1.0, 0.0}).has_value());
  obs[1].t_s = 0.1;  // spans 0.1 s < half the velocity span
  EXPECT_FALSE(forecastFeatures({obs[0], obs[1]}, {0.0, 0.0}, {1.0, 0.0}).has_value());
  EXPECT_FALSE(forecastFeatures(stepAside(), {0.0, 0.0}, {0.0, 0.0}).has_value());
}

TEST(Forecast, ProbabilityIsTheLogisticOfTheStandardisedScore) {
  ForecastModel m;
  m.bias = -1.0;
  m.mean[0] = 0.1;
  m.scale[0] = 0.2;
  m.weight[0] = 2.0;
  m.weight[5] = -0.5;
  ForecastFeatures f;
  f.x[0] = 0.3;                                        // (0.3 − 0.1) / 0.2 = 1 → +2
  f.x[5] = 2.0;                                        // −0.5 · 2 = −1
  EXPECT_NEAR(forecastProbability(m, f), 0.5, 1e-15);  // z = −1 + 2 − 1 = 0
  f.x[0] = 0.5;                                        // z = 2
  EXPECT_NEAR(forecastProbability(m, f), 1.0 / (1.0 + std::exp(-2.0)), 1e-15);
}

// One binary feature, 4 samples each: y = {1,0,0,0} at x = 0, {1,1,1,0} at x = 1.
void binaryData(Eigen::MatrixXd& X, Eigen::VectorXd& y) {
  X.resize(8, 1);
  y.resize(8);
  const double ys[8] = {1, 0, 0, 0, 1, 1, 1, 0};
  for (int i = 0; i < 8; ++i) {
    X(i, 0) = i < 4 ? 0.0 : 1.0;
    y[i] = ys[i];
  }
}

TEST(Forecast, UnpenalisedFitIsTheLogOddsOfEachGroup) {
  Eigen::MatrixXd X;
  Eigen::VectorXd y;
  binaryData(X, y);
  const LogisticFit fit = fitLogisticL2(X, y, 0.0);
  ASSERT_TRUE(fit.converged);
  EXPECT_NEAR(fit.beta[0], std::log(1.0 / 3.0), 1e-9);  // logit 0.25
  EXPECT_NEAR(fit.beta[1], 2.0 * std::log(3.0), 1e-9);  // logit 0.75 − logit 0.25
}

TEST(Forecast, PenalisedFitMeetsItsStationarityCondition) {
  Eigen::MatrixXd X;
  Eigen::VectorXd y;
  binaryData(X, y);
  const LogisticFit fit = fitLogisticL2(X, y, 1.0);
  ASSERT_TRUE(fit.converged);
  const double w = fit.beta[1];
  // By symmetry b = −w/2; the weight's gradient 4 (σ(w/2) − 0.75) + λ w vanishes; shrunk below
  // the unpenalised 2 ln 3.
  EXPECT_NEAR(fit.beta[0], -0.5 * w, 1e-9);
  EXPECT_NEAR(4.0 * (1.0 / (1.0 + std::exp(-0.5 * w)) - 0.75) + w, 0.0, 1e-9);
  EXPECT_GT(w, 0.0);
  EXPECT_LT(w, 2.0 * std::log(3.0));
}

TEST(Forecast, SeparableDataStaysFiniteUnderThePenalty) {
  Eigen::MatrixXd X(4, 1);
  X << -1, -0.5, 0.5, 1;
  Eigen::VectorXd y(4);
  y << 0, 0, 1, 1;
  const LogisticFit fit = fitLogisticL2(X, y, 0.1);
  ASSERT_TRUE(fit.converged);
  EXPECT_TRUE(std::isfinite(fit.beta[1]));
  EXPECT_GT(fit.beta[1], 0.0);
}

TEST(Forecast, BadFitInputsAreRefused) {
  Eigen::MatrixXd X(2, 1);
  X << 0, 1;
  Eigen::VectorXd y(2);
  y << 0, 2;
  EXPECT_THROW(fitLogisticL2(X, y, 1.0), std::invalid_argument);
  y << 0, 1;
  EXPECT_THROW(fitLogisticL2(X, y, -1.0), std::invalid_argument);
  EXPECT_THROW(fitLogisticL2(Eigen::MatrixXd(0, 1), Eigen::VectorXd(0), 1.0),
               std::invalid_argument);
  EXPECT_THROW(fitForecastModel({}, {}, 1.0), std::invalid_argument);
}

TEST(Forecast, ModelStandardisesAndKeepsConstantFeaturesAtScaleOne) {
  std::vector<ForecastFeatures> fs(4);
  std::vector<int> ys{0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    fs[static_cast<std::size_t>(i)].x[0] = i;    // mean 1.5, sd sqrt(1.25)
    fs[static_cast<std::size_t>(i)].x[1] = 3.0;  // constant
  }
  const ForecastModel m = fitForecastModel(fs, ys, 1.0);
  EXPECT_NEAR(m.mean[0], 1.5, 1e-12);
  EXPECT_NEAR(m.scale[0], std::sqrt(1.25), 1e-12);
  EXPECT_NEAR(m.mean[1], 3.0, 1e-12);
  EXPECT_EQ(m.scale[1], 1.0);
  EXPECT_NEAR(m.weight[1], 0.0, 1e-9);  // a centred constant column carries nothing
  EXPECT_GT(m.weight[0], 0.0);
  EXPECT_NEAR(m.bias, 0.0, 1e-9);  // balanced, symmetric
  EXPECT_GT(forecastProbability(m, fs[3]), 0.5);
  EXPECT_LT(forecastProbability(m, fs[0]), 0.5);
}

}  // namespace
}  // namespace coopnav::assessment

namespace coopnav::assessment {
namespace {

TEST(CooperationForecaster, MatchesTheFeaturesOfTheWholeTrackWithBoundedMemory) {
  ForecastModel m;
  m.bias = -0.3;
  m.weight = {1.0, 0.5, 0.2, -0.1, 0.05, -0.4};
  CooperationForecaster fc(m);
  EXPECT_TRUE(std::isnan(fc.pContributing()));
  fc.observe(0.0, {0, 0}, {8, 0.5});  // before start: ignored
  const Eigen::Vector2d origin(0.0, 0.0);
  const Eigen::Vector2d heading(1.0, 0.1);
  fc.start(origin, heading);
  std::vector<ForecastObservation> all;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.4 * k;
    // Weaving human, robot coming head-on with a slow drift.
    const Eigen::Vector2d h(1.1 * t, 0.3 * std::sin(0.7 * t) - 0.02 * t * t);
    const Eigen::Vector2d r(20.0 - 0.9 * t, 0.4 + 0.05 * t);
    all.push_back({t, h, r});
    fc.observe(t, h, r);
    const auto f = forecastFeatures(all, origin, heading);
    if (!f) {
      EXPECT_TRUE(std::isnan(fc.pContributing())) << t;
      continue;
    }
    ASSERT_TRUE(fc.features().has_value()) << t;
    for (std::size_t i = 0; i < kForecastFeatureCount; ++i)
      EXPECT_NEAR(fc.features()->x[i], f->x[i], 1e-12) << t << " " << i;
    EXPECT_NEAR(fc.pContributing(), forecastProbability(m, *f), 1e-15) << t;
  }
  const double last = fc.pContributing();
  fc.observe(15.0, {0, 0}, {1, 1});  // not later than the last (15.6 s): ignored
  EXPECT_EQ(fc.pContributing(), last);
  fc.stop();
  fc.observe(20.0, {0, 0}, {1, 1});  // after stop: ignored, the last value stays
  EXPECT_EQ(fc.pContributing(), last);
  fc.start(origin, heading);
  EXPECT_TRUE(std::isnan(fc.pContributing()));
}

}  // namespace
}  // namespace coopnav::assessment
