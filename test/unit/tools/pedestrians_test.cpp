// coopnav_ctl's pedestrian evaluation (tools/ctl/pedestrians.hpp): a hand-built head-on pair whose
// truth is known, the window choices (avoidance onset, lead), rejection of bad files, and the
// calibration on the real UCY pairs in test/data/pedestrians.
#include "pedestrians.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "json.hpp"
#include "test_paths.hpp"

namespace coopnav::ctl {
namespace {

namespace fs = std::filesystem;
using assessment::SideRule;

constexpr double kDtS = 0.4;  // the file's annotation period
constexpr int kSamples = 21;  // t = 0 .. 8 s

// a walks +x from (0, 0) at 1 m/s and steps 0.5 m to its right (away from b) between 2.4 s and
// 4.8 s; b walks -x from (12, 0.2) at 1 m/s, straight. They meet at x = 6 at t = 6 s.
Json syntheticPairJson() {
  Json ta = {{"id", 1}, {"t", Json::array()}, {"x", Json::array()}, {"y", Json::array()}};
  Json tb = {{"id", 2}, {"t", Json::array()}, {"x", Json::array()}, {"y", Json::array()}};
  for (int k = 0; k < kSamples; ++k) {
    const double t = kDtS * k;
    const double step = std::clamp((t - 2.4) / 2.4, 0.0, 1.0);
    ta["t"].push_back(t);
    ta["x"].push_back(t);
    ta["y"].push_back(-0.5 * step);
    tb["t"].push_back(t);
    tb["x"].push_back(12.0 - t);
    tb["y"].push_back(0.2);
  }
  Json pair = {{"ds", "synthetic"},
               {"a", 1},
               {"b", 2},
               {"t0_s", 0.0},
               {"t_cross_s", 6.0},
               {"heading_a", {1.0, 0.0}},
               {"heading_b", {-1.0, 0.0}},
               {"traj_a", ta},
               {"traj_b", tb}};
  return Json{{"schema", kPedestrianPairsSchema}, {"dt", kDtS}, {"pairs", Json::array({pair})}};
}

class PedestriansTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("coopnav_pedestrians_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    auto p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }

  fs::path dir_;
};

TEST_F(PedestriansTest, SteppingWalkerRanksAboveStraightOne) {
  const auto pairs = loadPedestrianPairs(write("pair.json", dumpJson(syntheticPairJson())));
  ASSERT_EQ(pairs.size(), 1u);
  for (const SideRule rule : {SideRule::kPathSide, SideRule::kHumanSide}) {
    SCOPED_TRACE(assessment::toString(rule));
    assessment::PathAssessorConfig config;  // paper profile: γ 0.98, τ 0.4 m
    config.side_rule = rule;
    const auto e = evaluateWalkers(pairs, config);
    ASSERT_EQ(e.walkers.size(), 2u);
    const auto& a = e.walkers[0];
    const auto& b = e.walkers[1];
    EXPECT_EQ(a.id, 1);
    EXPECT_EQ(a.other_id, 2);
    // a: d = -0.5 (to its right), b on its left (+0.7) -> 0.5 m away from b.
    EXPECT_NEAR(a.lateral_m, -0.5, 1e-9);
    EXPECT_NEAR(a.other_offset_m, 0.7, 1e-9);
    EXPECT_NEAR(a.dev_away_m, 0.5, 1e-9);
    // b never left its line.
    EXPECT_NEAR(b.lateral_m, 0.0, 1e-9);
    EXPECT_NEAR(b.dev_away_m, 0.0, 1e-9);
    ASSERT_TRUE(a.cm_m && b.cm_m);
    EXPECT_EQ(a.samples, 61u);  // 0 .. 6 s every 0.1 s
    EXPECT_GT(*a.cm_m, *b.cm_m);
    EXPECT_GT(*a.cm_m, 0.0);
    EXPECT_EQ(e.pairs_judged, 1u);
    EXPECT_EQ(e.pairs_ranked_right, 1u);
    EXPECT_DOUBLE_EQ(e.ranking, 1.0);
    EXPECT_DOUBLE_EQ(e.auc, 1.0);
    EXPECT_EQ(e.true_positive + e.false_negative, 1u);  // only a stepped >= 0.3 m away
    EXPECT_EQ(e.true_negative, 1u);
  }
}

// Given a walker's lateral deviations d(t) from its initial heading line (heading +x, origin 0).
std::optional<AvoidanceOnset> onsetOf(const std::vector<double>& d_m, double dt_s = kDtS) {
  std::vector<double> t;
  std::vector<Eigen::Vector2d> p;
  for (std::size_t i = 0; i < d_m.size(); ++i) {
    t.push_back(dt_s * static_cast<double>(i));
    p.emplace_back(1.3 * t.back(), d_m[i]);
  }
  return detectAvoidanceOnset(t, p, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX());
}

TEST(AvoidanceOnset, StraightWalkerHasNone) {
  EXPECT_FALSE(onsetOf({0.0, 0.0, 0.01, -0.02, 0.03, 0.0, 0.05, 0.09}));
  EXPECT_FALSE(onsetOf({}));
}

TEST(AvoidanceOnset, StartsWhereTheGrowthThatCrossedTheThresholdBegan) {
  // Wobble, a dip, then a steady step to the right (negative d) from sample 4 on.
  const auto o = onsetOf({0.0, 0.03, 0.04, 0.02, 0.03, -0.02, -0.06, -0.11, -0.2, -0.3});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->detected_index, 7u);  // first |d| >= 0.1 m
  EXPECT_DOUBLE_EQ(o->detected_t_s, 7 * kDtS);
  EXPECT_DOUBLE_EQ(o->onset_t_s, 4 * kDtS);  // -d grew from sample 4 to 7
  // Nothing after the detection is looked at: the same prefix gives the same onset.
  const auto prefix = onsetOf({0.0, 0.03, 0.04, 0.02, 0.03, -0.02, -0.06, -0.11});
  ASSERT_TRUE(prefix);
  EXPECT_DOUBLE_EQ(prefix->onset_t_s, o->onset_t_s);
}

TEST(AvoidanceOnset, SlowDriftIsNotTheAvoidance) {
  // 0.025 m/s of drift off the heading line, then a step at 0.1 m/s and more.
  const auto o = onsetOf({0.0, 0.01, 0.02, 0.03, 0.04, 0.08, 0.13});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->detected_index, 6u);
  EXPECT_DOUBLE_EQ(o->onset_t_s, 4 * kDtS);
}

TEST(AvoidanceOnset, LeftStepAndAPauseInTheGrowth) {
  // A step to the left that pauses (equal samples end the growth run).
  const auto o = onsetOf({0.0, 0.02, 0.05, 0.05, 0.08, 0.12, 0.2});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->detected_index, 5u);
  EXPECT_DOUBLE_EQ(o->onset_t_s, 3 * kDtS);
  // A deviation present from the first sample on is detected there, with the onset at it.
  const auto at_once = onsetOf({0.15, 0.2});
  ASSERT_TRUE(at_once);
  EXPECT_EQ(at_once->detected_index, 0u);
  EXPECT_DOUBLE_EQ(at_once->onset_t_s, 0.0);
}

TEST_F(PedestriansTest, WindowsStartAtOnsetAndLead) {
  const auto pairs = loadPedestrianPairs(write("pair.json", dumpJson(syntheticPairJson())));
  assessment::PathAssessorConfig config;  // paper profile: γ 0.98, τ 0.4 m, path side

  // a's step begins at 2.4 s (d = -0.083 at 2.8 s, -0.167 at 3.2 s: detected there).
  const auto onset = evaluateWalkers(pairs, config, {WindowKind::kOnset, 0.0});
  ASSERT_EQ(onset.walkers.size(), 2u);
  const auto& a = onset.walkers[0];
  ASSERT_TRUE(a.onset_t_s);
  EXPECT_NEAR(*a.onset_t_s, 2.4, 1e-9);
  EXPECT_NEAR(a.window_start_s, 2.4, 1e-9);
  EXPECT_EQ(a.samples, 37u);  // 2.4 .. 6.0 s every 0.1 s (START stamped 0.8 s in the past)
  // b never deviates: no onset, the round-1 window.
  const auto& b = onset.walkers[1];
  EXPECT_FALSE(b.onset_t_s);
  EXPECT_DOUBLE_EQ(b.window_start_s, 0.0);
  EXPECT_EQ(b.samples, 61u);

  const auto round1 = evaluateWalkers(pairs, config);
  ASSERT_TRUE(round1.walkers[0].cm_m && a.cm_m);
  // The window without the straight approach weighs the step more.
  EXPECT_GT(*a.cm_m, *round1.walkers[0].cm_m);

  const auto lead = evaluateWalkers(pairs, config, {WindowKind::kLead, 2.0});
  EXPECT_DOUBLE_EQ(lead.walkers[0].window_start_s, 4.0);
  EXPECT_EQ(lead.walkers[0].samples, 21u);  // 4.0 .. 6.0 s
  EXPECT_EQ(lead.walkers[1].samples, 21u);
  // A lead longer than the encounter starts at t0_s.
  const auto long_lead = evaluateWalkers(pairs, config, {WindowKind::kLead, 10.0});
  EXPECT_DOUBLE_EQ(long_lead.walkers[0].window_start_s, 0.0);
  EXPECT_EQ(long_lead.walkers[0].samples, 61u);

  // The plan both the in-process replay and the daemon runner follow: START after the
  // observation the onset was detected at (3.2 s), stamped at the onset.
  const auto runs = planWalkerRuns(pairs, {WindowKind::kOnset, 0.0});
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_NEAR(runs[0].observations[runs[0].start_after].t_s, 3.2, 1e-9);
  EXPECT_EQ(runs[1].start_after, 0u);
  EXPECT_EQ(runs[0].observations.size(), 16u);  // 0 .. 6 s every 0.4 s
  EXPECT_DOUBLE_EQ(runs[0].stop_t_s, 6.0);
}

TEST(PedestrianWindows, NamesReadBack) {
  for (const auto k : {WindowKind::kRound1, WindowKind::kOnset, WindowKind::kLead})
    EXPECT_EQ(windowKindFromString(toString(k)), k);
  EXPECT_FALSE(windowKindFromString("t0"));
  EXPECT_EQ(toString(WindowSetting{WindowKind::kLead, 2.0}), "lead 2 s");
  const auto windows = calibrationWindows();
  ASSERT_FALSE(windows.empty());
  EXPECT_EQ(windows.front().kind, WindowKind::kRound1);  // the paper's first: it wins ties
}

TEST_F(PedestriansTest, BadFilesAreRejectedWithFileAndReason) {
  const auto expectError = [&](const std::string& name, const Json& doc, const std::string& why) {
    const auto path = write(name, dumpJson(doc));
    try {
      loadPedestrianPairs(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(why), std::string::npos) << msg;
    }
  };
  Json doc = syntheticPairJson();
  doc["schema"] = "headon_pairs/1";
  expectError("schema.json", doc, "schema");

  doc = syntheticPairJson();
  doc["pairs"][0]["traj_b"]["x"].erase(0);
  expectError("unequal.json", doc, "unequal length");

  doc = syntheticPairJson();
  doc["pairs"][0]["traj_a"]["y"][3] = "0.1";
  expectError("string.json", doc, "not a number");

  doc = syntheticPairJson();
  doc["pairs"][0]["t_cross_s"] = 20.0;  // past both tracks
  expectError("cover.json", doc, "does not cover");

  // JSON has no NaN or infinity; a number too large for a double reads as one.
  auto text = dumpJson(syntheticPairJson());
  text.replace(text.find("\"t0_s\": 0"), 9, "\"t0_s\": 1e999");
  const auto path = write("inf.json", text);
  EXPECT_THROW(loadPedestrianPairs(path), std::runtime_error);
  EXPECT_THROW(loadPedestrianPairs(write("garbage.json", "{pairs: []}")), std::runtime_error);
  EXPECT_THROW(loadPedestrianPairs((dir_ / "missing.json").string()), std::runtime_error);
}

// The measured fact behind the calibration: on real walkers the paper profile ranks and
// classifies poorly, the calibrated settings (fit without the held-out sequence) well.
TEST(PedestriansRealData, CalibrationBeatsPaperProfileOnHeldOutSequences) {
  const auto pairs =
      loadPedestrianPairs(::coopnav::test::testDataDir() + "/pedestrians/headon_pairs.json");
  ASSERT_EQ(pairs.size(), 172u);
  const auto r = calibrate(pairs);
  ASSERT_EQ(r.folds.size(), 2u);
  for (const auto& f : r.folds) {
    SCOPED_TRACE(f.held_out_ds);
    EXPECT_GE(f.held_out.ranking, 0.85);
    EXPECT_GE(f.held_out.agreement, 0.85);
    EXPECT_LT(f.paper_held_out.ranking, f.held_out.ranking);
    EXPECT_LT(f.paper_held_out.agreement, f.held_out.agreement);
  }
  EXPECT_LT(r.paper_score.ranking, 0.8);
  EXPECT_LT(r.paper_score.agreement, 0.8);
  EXPECT_GT(r.final_score.objective, r.paper_score.objective);
  // Deterministic: the same data give the same settings.
  const auto again = calibrate(pairs);
  EXPECT_EQ(again.final_setting.gamma_per_s, r.final_setting.gamma_per_s);
  EXPECT_EQ(again.final_setting.side_rule, r.final_setting.side_rule);
  EXPECT_EQ(again.final_setting.tau_m, r.final_setting.tau_m);
  EXPECT_EQ(again.final_setting.window.kind, r.final_setting.window.kind);
  EXPECT_EQ(again.final_setting.window.lead_s, r.final_setting.window.lead_s);

  // The window search: one result per window, round 1 first; the paper profile with the round-1
  // window is the paper score; any window's best is at most the overall best, and the shipped
  // profile is the round-1 window's best.
  ASSERT_EQ(r.windows.size(), calibrationWindows().size());
  EXPECT_EQ(r.windows.front().window.kind, WindowKind::kRound1);
  EXPECT_DOUBLE_EQ(r.windows.front().paper.objective, r.paper_score.objective);
  for (const auto& w : r.windows) EXPECT_LE(w.fit_score.objective, r.final_score.objective);
  EXPECT_EQ(r.profile_setting.window.kind, WindowKind::kRound1);
  EXPECT_DOUBLE_EQ(r.profile_score.objective, r.windows.front().fit_score.objective);
  for (const auto& f : r.folds) EXPECT_EQ(f.window_held_out.size(), r.windows.size());

  // The shipped `calibrated` profile is the round-1 fit (the dialogue manager STARTs at round 1;
  // `calibrate` prints the unrestricted winner beside it).
  const YAML::Node profile =
      YAML::LoadFile(::coopnav::test::sourceDir() + "/config/path_assessor_calibrated.yaml");
  const double period_s = profile["sample_period_s"].as<double>();
  EXPECT_NEAR(profile["gamma"].as<double>(),
              gammaPerSample(r.profile_setting.gamma_per_s, period_s), 1e-12);
  EXPECT_DOUBLE_EQ(profile["tau_m"].as<double>(), r.profile_setting.tau_m);
  EXPECT_EQ(profile["side_rule"].as<std::string>(),
            assessment::toString(r.profile_setting.side_rule));
}

}  // namespace
}  // namespace coopnav::ctl
