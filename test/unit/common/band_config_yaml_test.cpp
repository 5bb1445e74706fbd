// YAML views of the planner and dock configs: the lib structs' defaults stay the only defaults,
// nested keys override one field each, the planner's validate() reports under dotted YAML keys.
#include "config/band_config_yaml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "config/config.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

struct Holder {
  BandPlannerConfigYaml planner;
  ModeMachineOptionsYaml dock;
  template <class V>
  void visit(V& v) {
    v("planner", planner);
    v("dock", dock);
  }
};

std::string writeTemp(const std::string& text) {
  static int n = 0;
  const auto p = test::scratchDir() / ("bandcfg_" + std::to_string(n++) + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}

TEST(BandConfigYamlTest, NoFileGivesTheLibDefaults) {
  const auto h = loadConfig<Holder>("");
  const BandPlannerConfig lib;
  EXPECT_EQ(h.planner.config.dt_ref_s, lib.dt_ref_s);
  EXPECT_EQ(h.planner.config.robot.max_vel_x_m_s, lib.robot.max_vel_x_m_s);
  EXPECT_EQ(h.planner.config.human.max_vel_x_m_s, lib.human.max_vel_x_m_s);
  EXPECT_EQ(h.planner.config.other_weights.viapoint, lib.other_weights.viapoint);
  EXPECT_EQ(h.dock.options.hold_timeout_s, ModeMachineOptions{}.hold_timeout_s);
  // The printed defaults are the lib's, key for key.
  Holder fresh;
  EXPECT_EQ(configToYaml(h), configToYaml(fresh));
}

TEST(BandConfigYamlTest, NestedKeysOverrideOnlyTheirField) {
  const auto h =
      loadConfig<Holder>(writeTemp("planner:\n"
                                   "  dt_ref_s: 0.1\n"
                                   "  robot: {max_vel_x_m_s: 0.5, holonomic: false}\n"
                                   "  other_weights: {viapoint: 1.5}\n"
                                   "dock: {hold_timeout_s: 12, wall_margin_m: 0.2}\n"));
  const BandPlannerConfig lib;
  EXPECT_EQ(h.planner.config.dt_ref_s, 0.1);
  EXPECT_EQ(h.planner.config.robot.max_vel_x_m_s, 0.5);
  EXPECT_FALSE(h.planner.config.robot.holonomic);
  EXPECT_EQ(h.planner.config.robot.acc_lim_x_m_s2, lib.robot.acc_lim_x_m_s2);
  EXPECT_EQ(h.planner.config.other_weights.viapoint, 1.5);
  // The other band's non-default weights (defaultOtherWeights) survive a partial override.
  EXPECT_EQ(h.planner.config.other_weights.optimaltime, lib.other_weights.optimaltime);
  EXPECT_EQ(h.planner.config.other_weights.nominal_vel, lib.other_weights.nominal_vel);
  EXPECT_EQ(h.planner.config.human.radius_m, lib.human.radius_m);
  EXPECT_EQ(h.dock.options.hold_timeout_s, 12.0);
  EXPECT_EQ(h.dock.options.dock.margin_m, 0.2);
}

TEST(BandConfigYamlTest, PrintedConfigLoadsBackToTheSameValues) {
  Holder changed = loadConfig<Holder>(
      writeTemp("planner: {penalty_epsilon: 0.05, human: {max_vel_y_m_s: 0.3}}\n"));
  const auto again = loadConfig<Holder>(writeTemp(configToYaml(changed)));
  EXPECT_EQ(configToYaml(again), configToYaml(changed));
  EXPECT_EQ(again.planner.config.penalty_epsilon, 0.05);
  EXPECT_EQ(again.planner.config.human.max_vel_y_m_s, 0.3);
}

TEST(BandConfigYamlTest, PlannerRangeErrorsNameTheDottedKey) {
  try {
    loadConfig<Holder>(writeTemp(
        "planner: {dt_ref_s: -1, robot: {max_vel_x_m_s: 0}, planning_weights: {obstacle: -2}}\n"));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'planner.dt_ref_s' = -1"), std::string::npos) << what;
    EXPECT_NE(what.find("'planner.robot.max_vel_x_m_s' = 0"), std::string::npos) << what;
    EXPECT_NE(what.find("'planner.planning_weights.obstacle' = -2"), std::string::npos) << what;
  }
}

TEST(BandConfigYamlTest, UnknownAndMistypedNestedKeysAreErrors) {
  EXPECT_THROW(loadConfig<Holder>(writeTemp("planner: {robot: {max_speed: 1}}\n")), ConfigError);
  EXPECT_THROW(loadConfig<Holder>(writeTemp("planner: {warm_start: maybe}\n")), ConfigError);
  EXPECT_THROW(loadConfig<Holder>(writeTemp("dock: {human_far_m: 0}\n")), ConfigError);
  EXPECT_THROW(loadConfig<Holder>(writeTemp("dock: {goal_tolerance_m: 0.3}\n")), ConfigError);
}

TEST(BandConfigYamlTest, OverridesFromTheCommandLineReachNestedFields) {
  const auto h =
      loadConfig<Holder>("", {"planner.robot.radius_m=0.4", "planner.no_inner_iterations=5"});
  EXPECT_EQ(h.planner.config.robot.radius_m, 0.4);
  EXPECT_EQ(h.planner.config.no_inner_iterations, 5);
}

}  // namespace
}  // namespace coopnav
