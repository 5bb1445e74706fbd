#include "coopnav/band/band_config.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

namespace coopnav {
namespace {

TEST(BandPlannerConfigTest, DefaultsAreCohanSimValuesAndValid) {
  const BandPlannerConfig c;
  EXPECT_TRUE(c.validate().empty());
  EXPECT_DOUBLE_EQ(c.dt_ref_s, 0.125);
  EXPECT_DOUBLE_EQ(c.dt_hysteresis_s, 0.0125);
  EXPECT_DOUBLE_EQ(c.robot.max_vel_x_m_s, 0.7);
  EXPECT_DOUBLE_EQ(c.human.max_vel_x_m_s, 1.3);
  EXPECT_DOUBLE_EQ(c.min_agent_robot_dist_m, 0.6);
  // Minimal human contribution: the anticipated band is held to its path 10x harder.
  EXPECT_DOUBLE_EQ(c.other_weights.viapoint, 10.0 * c.planning_weights.viapoint);
  EXPECT_DOUBLE_EQ(c.other_weights.optimaltime, 3.0);
}

TEST(BandPlannerConfigTest, ValidateListsEveryErrorWithKeyValueAndRange) {
  BandPlannerConfig c;
  c.dt_ref_s = 0.0;
  c.human.acc_lim_x_m_s2 = -1.0;
  c.other_weights.viapoint = std::nan("");
  const auto errors = c.validate();
  ASSERT_GE(errors.size(), 3u);
  EXPECT_EQ(errors[0].key, "dt_ref_s");
  EXPECT_EQ(errors[0].value, 0.0);
  EXPECT_EQ(errors[0].allowed, "(0, 2]");
  bool acc = false, via = false;
  for (const auto& e : errors) {
    acc |= e.key == "human.acc_lim_x_m_s2";
    via |= e.key == "other_weights.viapoint";
  }
  EXPECT_TRUE(acc);
  EXPECT_TRUE(via);
}

TEST(BandPlannerConfigTest, SolverIsOneOfTwo) {
  BandPlannerConfig c;
  EXPECT_EQ(c.solver, "sparse_lm");
  c.solver = "ceres";
  EXPECT_TRUE(c.validate().empty());
  c.solver = "g2o";
  const auto errors = c.validate();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].key, "solver");
  EXPECT_EQ(errors[0].allowed, "sparse_lm | ceres");
}

TEST(BandPlannerConfigTest, DampingStartScaleIsOffByDefaultAndNotNegative) {
  BandPlannerConfig c;
  EXPECT_EQ(c.initial_damping_scale, 0.0);  // λ₀ = 1, Ceres' start
  c.initial_damping_scale = 0.01;
  EXPECT_TRUE(c.validate().empty());
  c.initial_damping_scale = -0.01;
  const auto errors = c.validate();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].key, "initial_damping_scale");
}

/// Breaks every numeric key (NaN; out of range for an integer) and records its dotted name.
struct BreakEveryKey {
  std::vector<std::string>& names;
  std::string prefix;
  void operator()(const char* key, double& v, const KeyRange&) const {
    v = std::numeric_limits<double>::quiet_NaN();
    names.push_back(prefix + key);
  }
  void operator()(const char* key, int& v, const KeyRange&) const {
    v = -1000000;
    names.push_back(prefix + key);
  }
  void operator()(const char*, std::string&, const KeyChoices&) const {}
  void operator()(const char*, bool&) const {}
  void operator()(const char* key, AgentKinematics& k) const {
    AgentKinematics::forEachKey(k, BreakEveryKey{names, prefix + key + "."});
  }
  void operator()(const char* key, BandWeights& w) const {
    BandWeights::forEachKey(w, BreakEveryKey{names, prefix + key + "."});
  }
};

TEST(BandPlannerConfigTest, EveryNumericKeyIsDeclaredOnceAndValidateChecksExactlyThose) {
  BandPlannerConfig c;
  std::vector<std::string> names;
  BandPlannerConfig::forEachKey(c, BreakEveryKey{names, ""});
  EXPECT_EQ(names.size(), 30U + 2 * 9 + 2 * 13);  // top level, robot/human, the two weight sets
  std::vector<std::string> sorted = names;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a key twice";
  std::vector<std::string> rejected;
  for (const auto& e : c.validate()) rejected.push_back(e.key);
  EXPECT_EQ(rejected, names);
}

}  // namespace
}  // namespace coopnav
