// coopnav_ctl goals (tools/ctl/goals.hpp): goal inference scored on pedestrian pairs. A hand-built
// scene whose truth is known, and the figures on the real UCY pairs in test/data/pedestrians.
#include "goals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_paths.hpp"

namespace coopnav::ctl {
namespace {

double ratio(std::size_t num, std::size_t den) {
  return static_cast<double>(num) / static_cast<double>(den);
}

constexpr double kDtS = 0.4;

/// A straight walk from (x0, y0) at velocity (vx, vy) m/s for 20 s, then optionally a turn
/// (velocity (tx, ty) from t = 12 s).
PedestrianTrack walk(long id, double x0, double y0, double vx, double vy, double tx = 0.0,
                     double ty = 0.0, bool turn = false) {
  PedestrianTrack t;
  t.id = id;
  double x = x0, y = y0;
  for (int k = 0; k <= 50; ++k) {
    const double time = kDtS * k;
    t.t_s.push_back(time);
    t.x_m.push_back(x);
    t.y_m.push_back(y);
    const bool turned = turn && time >= 12.0;
    x += kDtS * (turned ? tx : vx);
    y += kDtS * (turned ? ty : vy);
  }
  return t;
}

PedestrianPair pair(const std::string& ds, PedestrianTrack a, PedestrianTrack b) {
  PedestrianPair p;
  p.ds = ds;
  p.t0_s = 0.0;
  p.t_cross_s = 10.0;
  p.a = std::move(a);
  p.b = std::move(b);
  return p;
}

// Three pairs of an east walker (exit (10, 0)) and a west walker (exit (-10, 0.3)), and a pair
// whose east walker turns north at 12 s (exit (2, 8), nobody else's).
std::vector<PedestrianPair> scene() {
  std::vector<PedestrianPair> pairs;
  for (long k = 0; k < 3; ++k) {
    pairs.push_back(pair("s", walk(10 * k + 1, -10.0, 0.1 * k, 1.0, 0.0),
                         walk(10 * k + 2, 10.0, 0.3, -1.0, 0.0)));
  }
  pairs.push_back(
      pair("s", walk(41, -10.0, 0.0, 1.0, 0.0, 0.0, 1.0, true), walk(42, 10.0, 0.3, -1.0, 0.0)));
  return pairs;
}

TEST(GoalsTest, WalkersHeadingForAnExitGetItAndAnUnsharedExitHasNoCandidate) {
  GoalEvalOptions o;
  for (const ExitClustering how : {ExitClustering::kGreedyRadius, ExitClustering::kChained}) {
    SCOPED_TRACE(toString(how));
    o.clustering = how;
    const GoalEvaluation e = evaluateGoalInference(scene(), o);
    ASSERT_EQ(e.walkers, 8u);
    // Leave-pair-out: the north exit is only walker 41's own, so it has no candidate.
    EXPECT_EQ(e.with_candidate, 7u);
    EXPECT_FALSE(e.cases[6].has_candidate);
    EXPECT_EQ(e.cases[6].id, 41);
    EXPECT_EQ(e.correct, 7u);
    EXPECT_DOUBLE_EQ(e.accuracy_with_candidate, 1.0);
    EXPECT_DOUBLE_EQ(e.accuracy_all, 7.0 / 8.0);
    // Observed up to t_cross - 3 s = 7 s: 18 samples at 0.4 s.
    EXPECT_EQ(e.cases[0].observations, 18u);
    // East, west and walker 41's north exit (another pair's walker: a candidate here).
    EXPECT_EQ(e.cases[0].candidates, 3u);
    EXPECT_GT(e.cases[0].p_true, 0.9);
  }
}

TEST(GoalsTest, ObservingNothingLeavesThePrior) {
  GoalEvalOptions o;
  o.lead_s = 20.0;  // t_cross - 20 s is before every track
  o.frequency_prior = false;
  const GoalEvaluation e = evaluateGoalInference(scene(), o);
  for (const auto& c : e.cases) EXPECT_EQ(c.observations, 0u);
  // Three candidates, uniform prior: the tie goes to the first, east (walker 11's exit, the
  // first of another pair), so walker 1 is right and walker 2 (going west) wrong.
  EXPECT_NEAR(e.cases[0].p_true, 1.0 / 3.0, 1e-12);
  EXPECT_TRUE(e.cases[0].correct);
  EXPECT_FALSE(e.cases[1].correct);
}

TEST(GoalsTest, TheTrackAfterTMeasuresTheTurnToTheExit) {
  const GoalEvaluation e = evaluateGoalInference(scene(), GoalEvalOptions{});
  // Walker 1 at its last sample by t = 7 s (6.8 s): at (-3.2, 0) heading east to its exit
  // (10, 0): straight on.
  EXPECT_TRUE(e.cases[0].has_heading);
  EXPECT_NEAR(e.cases[0].exit_off_heading_deg, 0.0, 1e-6);
  EXPECT_NEAR(e.cases[0].remaining_path_ratio, 1.0, 1e-9);
  EXPECT_EQ(e.cases[0].heading_pick, 0);  // the east cluster
  EXPECT_TRUE(e.cases[0].heading_correct);
  // Walker 41 at (-3.2, 0) heading east, turns north at (2, 0) to its exit (2, 8): 5.2 m + 8 m
  // walked for a straight hypot(5.2, 8) m, the exit atan(8 / 5.2) off its heading.
  EXPECT_NEAR(e.cases[6].exit_off_heading_deg, std::atan2(8.0, 5.2) * 180.0 / M_PI, 1e-6);
  EXPECT_NEAR(e.cases[6].remaining_path_ratio, 13.2 / std::hypot(5.2, 8.0), 1e-9);
  EXPECT_FALSE(e.cases[6].heading_correct);  // no candidate
}

TEST(GoalsTest, HeadingLikelihoodIsAVonMisesMixtureOverTheClustersExits) {
  const Eigen::Vector2d east(1.0, 0.0);
  const Eigen::Vector2d at(0.0, 0.0);
  const double kappa = 2.0;
  EXPECT_DOUBLE_EQ(headingLikelihood(east, at, {{10.0, 0.0}}, kappa), 1.0);
  EXPECT_NEAR(headingLikelihood(east, at, {{0.0, 10.0}}, kappa), std::exp(-kappa), 1e-12);
  EXPECT_NEAR(headingLikelihood(east, at, {{-5.0, 0.0}}, kappa), std::exp(-2.0 * kappa), 1e-12);
  EXPECT_NEAR(headingLikelihood(east, at, {{10.0, 0.0}, {0.0, 10.0}}, kappa),
              0.5 * (1.0 + std::exp(-kappa)), 1e-12);
  EXPECT_DOUBLE_EQ(headingLikelihood(east, at, {{0.0, 10.0}}, 0.0), 1.0);  // κ = 0: flat
  EXPECT_DOUBLE_EQ(headingLikelihood(east, at, {at}, kappa), 1.0);         // no direction
}

TEST(GoalsTest, HeadingTermSharpensTheBeliefAndIsNeutralAtKappaZero) {
  GoalEvalOptions o;
  o.beta_per_m = 0.1;
  const GoalEvaluation without_term = evaluateGoalInference(scene(), o);
  o.heading_term = true;
  o.heading_kappa = 0.0;
  const GoalEvaluation flat = evaluateGoalInference(scene(), o);
  o.heading_kappa = 5.0;
  const GoalEvaluation sharp = evaluateGoalInference(scene(), o);
  ASSERT_EQ(sharp.cases.size(), without_term.cases.size());
  EXPECT_EQ(sharp.correct, 7u);
  for (std::size_t i = 0; i < sharp.cases.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(flat.cases[i].p_true, without_term.cases[i].p_true, 1e-12);
    if (!sharp.cases[i].has_candidate) continue;
    EXPECT_GT(sharp.cases[i].p_true, without_term.cases[i].p_true);
  }
}

// The measured figures on the real pairs, as regression bounds (tools/ctl/README.md, "Goal
// inference"): the issue's 85 % is not reached; what is reached must not get worse, and the
// measurement of why stays what it is.
TEST(GoalsRealData, AccuracyAtTCrossMinus3s) {
  const auto pairs =
      loadPedestrianPairs(::coopnav::test::testDataDir() + "/pedestrians/headon_pairs.json");
  const GoalReport r = evaluateGoalReport(pairs);
  ASSERT_EQ(r.configs.size(), 5u);
  const GoalConfigResult& baseline = r.configs[0];  // greedy radius, uniform prior
  const GoalConfigResult& best = r.configs[3];      // chained, exit-frequency prior
  EXPECT_EQ(best.options.clustering, ExitClustering::kChained);
  EXPECT_TRUE(best.options.frequency_prior);
  EXPECT_FALSE(best.options.heading_term);
  EXPECT_EQ(best.walkers, 344u);
  EXPECT_LE(best.walkers - best.with_candidate, 2u);
  EXPECT_GE(best.accuracy_all, 0.75);
  EXPECT_GT(best.accuracy_all, baseline.accuracy_all + 0.3);
  ASSERT_EQ(best.folds.size(), 2u);
  EXPECT_EQ(best.folds[0].held_out_ds, "UCY_zara01");
  EXPECT_GE(best.folds[0].held_out.accuracy_all, 0.9);
  EXPECT_GE(best.folds[1].held_out.accuracy_all, 0.7);
  // The heading term (κ fit leave-one-sequence-out) adds nothing held out: 0.765 as without it.
  const GoalConfigResult& heading = r.configs[4];
  EXPECT_TRUE(heading.options.heading_term);
  EXPECT_EQ(heading.walkers, 344u);
  EXPECT_GE(heading.accuracy_all, 0.75);
  EXPECT_LT(heading.accuracy_all, 0.85);
  ASSERT_EQ(heading.kappa_sweep.size(), goalHeadingKappas().size());

  // What the track can tell: about 19 % of the walkers leave more than 30° off their heading at
  // t, and even all the others right leaves the 85 % out of reach.
  ASSERT_EQ(r.ceiling.size(), 7u);
  const GoalCeilingRow& all = r.ceiling[0];
  EXPECT_EQ(all.walkers, 344u);
  EXPECT_GE(all.off_30deg, 55u);
  EXPECT_LE(all.off_30deg, 75u);
  EXPECT_GE(all.off_45deg, 28u);
  EXPECT_LE(all.off_45deg, 38u);
  EXPECT_EQ(all.path_correct, best.correct);
  EXPECT_EQ(all.combined_correct, heading.correct);
  EXPECT_GE(all.heading_correct, 235u);  // heading predictor 0.709
  EXPECT_LE(all.either_correct, 280u);   // 0.788: switching predictors gains little
  EXPECT_GE(all.either_correct, all.path_correct);
  const GoalCeilingRow& straight = r.ceiling[3];
  const GoalCeilingRow& turns = r.ceiling[4];
  EXPECT_EQ(straight.off_30deg, 0u);
  EXPECT_EQ(turns.off_30deg, turns.walkers);
  EXPECT_GE(ratio(straight.path_correct, straight.walkers), 0.87);
  EXPECT_LE(ratio(turns.path_correct, turns.walkers), 0.45);
  EXPECT_GT(r.straight_on_perfect_bound, 0.83);
  EXPECT_LT(r.straight_on_perfect_bound, 0.85);
  // Deterministic.
  const GoalReport again = evaluateGoalReport(pairs);
  EXPECT_EQ(again.configs[3].correct, best.correct);
  EXPECT_EQ(again.configs[3].options.beta_per_m, best.options.beta_per_m);
  EXPECT_EQ(again.configs[4].correct, heading.correct);
  EXPECT_EQ(formatGoalReport(again), formatGoalReport(r));
}

}  // namespace
}  // namespace coopnav::ctl
