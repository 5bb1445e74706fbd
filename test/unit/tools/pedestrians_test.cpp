// coopnav_ctl's pedestrian evaluation (tools/ctl/pedestrians.hpp): a hand-built head-on pair whose
// truth is known, rejection of bad files, and the calibration on the real UCY pairs in
// test/data/pedestrians.
#include "pedestrians.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "json.hpp"

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
    const auto p = (dir_ / name).string();
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
      loadPedestrianPairs(std::string(COOPNAV_TEST_DATA_DIR) + "/pedestrians/headon_pairs.json");
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

  // The shipped `calibrated` profile is this fit.
  const YAML::Node profile =
      YAML::LoadFile(std::string(COOPNAV_SOURCE_DIR) + "/config/path_assessor_calibrated.yaml");
  const double period_s = profile["sample_period_s"].as<double>();
  EXPECT_NEAR(profile["gamma"].as<double>(), gammaPerSample(r.final_setting.gamma_per_s, period_s),
              1e-12);
  EXPECT_DOUBLE_EQ(profile["tau_m"].as<double>(), r.final_setting.tau_m);
  EXPECT_EQ(profile["side_rule"].as<std::string>(),
            assessment::toString(r.final_setting.side_rule));
}

}  // namespace
}  // namespace coopnav::ctl
