// The population generator (tools/population/generator.hpp): determinism, coverage of the
// behaviours and layouts, and every drawn value inside the ranges docs/population.md states.
#include "../../../tools/population/generator.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace pop = coopnav::population;

namespace {

std::string allYaml(const std::vector<pop::Encounter>& es) {
  std::string s;
  for (const auto& e : es) s += pop::scenarioYaml(e) + pop::scenarioYaml(e, false, "b");
  return s;
}

double param(const pop::HumanSpec& h, const std::string& key) {
  for (const auto& [k, v] : h.params)
    if (k == key) return v;
  return -1.0;
}

}  // namespace

TEST(PopulationGenerator, SameSeedSameBytesOtherSeedOtherPopulation) {
  const auto a = pop::generatePopulation(50, 7);
  const auto b = pop::generatePopulation(50, 7);
  const auto c = pop::generatePopulation(50, 8);
  EXPECT_EQ(allYaml(a), allYaml(b));
  EXPECT_NE(allYaml(a), allYaml(c));
  // A longer population starts with the shorter one: N only adds encounters.
  const auto d = pop::generatePopulation(60, 7);
  EXPECT_EQ(allYaml(a), allYaml({d.begin(), d.begin() + 50}));
}

TEST(PopulationGenerator, EveryBehaviourHeadOnOncePerBlockOfSix) {
  const auto es = pop::generatePopulation(24, 3);
  for (std::size_t block = 0; block < 4; ++block) {
    std::set<std::string> seen;
    for (std::size_t i = 0; i < 6; ++i) seen.insert(es[block * 6 + i].humans.at(0).behaviour);
    EXPECT_EQ(seen.size(), 6u) << "block " << block;
  }
}

TEST(PopulationGenerator, DrawsStayInTheirRanges) {
  const auto es = pop::generatePopulation(600, 11);
  std::set<std::string> layouts;
  std::map<std::size_t, int> counts;
  for (const auto& e : es) {
    layouts.insert(e.layout.key);
    ++counts[e.humans.size()];
    ASSERT_GE(e.humans.size(), 1u);
    ASSERT_LE(e.humans.size(), 3u);
    EXPECT_LE(e.seed, 1ULL << 53);
    const pop::HumanSpec& h = e.humans.at(0);
    EXPECT_EQ(h.role, "head_on");
    EXPECT_LE(std::abs(h.start_y_m - e.layout.centre_y_m), 0.3 + 1e-9);
    EXPECT_GT(h.start_x_m, e.layout.robot_goal_x_m);
    EXPECT_LT(h.goal_x_m, e.layout.robot_start_x_m);
    for (const auto& x : e.humans) {
      EXPECT_GE(x.speed_m_s, 0.8);
      EXPECT_LE(x.speed_m_s, 1.3);
      EXPECT_GE(x.velocity_noise_m_s, 0.0);
      EXPECT_LE(x.velocity_noise_m_s, 0.05);
      if (e.layout.extra_lanes_y_m.empty()) {
        EXPECT_GE(x.start_y_m, e.layout.lateral_min_y_m - 1e-9) << e.name;
        EXPECT_LE(x.start_y_m, e.layout.lateral_max_y_m + 1e-9) << e.name;
      }
      if (x.role == "follower") {
        EXPECT_GE(x.start_x_m, h.start_x_m + 2.0 - 1e-9);
      }
      if (x.role == "same_way") {
        EXPECT_GT(x.start_x_m, e.layout.robot_start_x_m + 2.5 - 1e-9);
        EXPECT_GT(x.goal_x_m, e.layout.robot_goal_x_m);
      }
      if (x.behaviour == "minimal") {
        EXPECT_GE(param(x, "max_deviation_m"), 0.15);
        EXPECT_LE(param(x, "max_deviation_m"), 0.35);
      }
      if (x.behaviour == "facilitating") {
        EXPECT_GE(param(x, "yield.offset_m"), 0.6);
        EXPECT_LE(param(x, "yield.offset_m"), 1.0);
      }
      if (x.behaviour == "late_facilitating") {
        EXPECT_GE(param(x, "trigger_ttc_s"), 2.0);
        EXPECT_LE(param(x, "trigger_ttc_s"), 3.5);
      }
    }
  }
  EXPECT_EQ(layouts.size(), pop::allLayouts().size());
  EXPECT_GT(counts[1], counts[2]);
  EXPECT_GT(counts[2], counts[3]);
  EXPECT_GT(counts[3], 60);
}

TEST(PopulationGenerator, NarrowestCorridorStillFitsARobotAndAHuman) {
  const double narrowest = pop::syntheticWidthsM().front();
  EXPECT_GT(narrowest, 2 * pop::kRobotRadiusM + 2 * pop::kHumanRadiusM + 0.1);
  EXPECT_LT(narrowest, 1.8);
  EXPECT_DOUBLE_EQ(pop::syntheticWidthsM().back(), 6.0);
}

TEST(PopulationGenerator, ScenarioYamlHasTheDocumentedShape) {
  pop::Encounter e;
  e.name = "pop_0001";
  e.seed = 42;
  e.layout = pop::syntheticCorridor(1.8);
  pop::HumanSpec h;
  h.role = "head_on";
  h.behaviour = "facilitating";
  h.start_x_m = 28.0;
  h.start_y_m = 1.0;
  h.goal_x_m = 2.5;
  h.goal_y_m = 1.0;
  h.speed_m_s = 1.1;
  h.params = {{"trigger_ttc_s", 4.5}, {"yield.offset_m", 0.8}, {"trigger_distance_m", 6.0}};
  e.humans.push_back(h);
  const std::string y = pop::scenarioYaml(e);
  EXPECT_NE(y.find("name: pop_0001\n"), std::string::npos);
  EXPECT_NE(y.find("seed: 42\n"), std::string::npos);
  EXPECT_NE(y.find("{x0_m: -1.00, y0_m: 1.90, x1_m: 34.00, y1_m: 1.90, thickness_m: 0.2}"),
            std::string::npos);
  EXPECT_NE(y.find("start: {x_m: 3.000, y_m: 0.900, theta_rad: 0.0}"), std::string::npos);
  EXPECT_NE(y.find("start: {x_m: 28.000, y_m: 1.000, theta_rad: 3.14159}"), std::string::npos);
  EXPECT_NE(y.find("params: {trigger_ttc_s: 4.50, yield: {offset_m: 0.80}, trigger_distance_m: "
                   "6.00}"),
            std::string::npos)
      << y;
  const std::string base = pop::scenarioYaml(e, false, "base_corridor_1_80");
  EXPECT_NE(base.find("name: base_corridor_1_80\n"), std::string::npos);
  EXPECT_NE(base.find("humans: []\n"), std::string::npos);
  EXPECT_EQ(base.find("behaviour"), std::string::npos);

  e.layout = pop::mapLayouts().at(0);
  EXPECT_NE(pop::scenarioYaml(e).find("  file: ../maps/open.yaml\n"), std::string::npos);
  EXPECT_EQ(pop::baselineName(pop::syntheticCorridor(2.25)), "base_corridor_2_25");
}

// Given a seed, when every head-on human is made responsive (generate --behaviour responsive),
// then only the head-on humans' behaviour and params change: layouts, positions, speeds, noise,
// the other humans and the scenario seeds are the seed's, the params lie in the responsive
// ranges, and the encounters whose head-on human was responsive anyway are the same bytes.
TEST(PopulationGenerator, HeadOnBehaviourOptionKeepsEveryOtherDraw) {
  const auto plain = pop::generatePopulation(60, 5);
  const auto resp = pop::generatePopulation(60, 5, {}, "responsive");
  ASSERT_EQ(plain.size(), resp.size());
  std::set<std::string> layouts;
  int unchanged = 0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    const pop::Encounter& a = plain[i];
    const pop::Encounter& b = resp[i];
    layouts.insert(b.layout.key);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.layout.key, b.layout.key);
    ASSERT_EQ(a.humans.size(), b.humans.size()) << a.name;
    for (std::size_t k = 0; k < a.humans.size(); ++k) {
      const pop::HumanSpec& x = a.humans[k];
      const pop::HumanSpec& y = b.humans[k];
      EXPECT_EQ(x.role, y.role);
      EXPECT_EQ(x.start_x_m, y.start_x_m);
      EXPECT_EQ(x.start_y_m, y.start_y_m);
      EXPECT_EQ(x.goal_x_m, y.goal_x_m);
      EXPECT_EQ(x.speed_m_s, y.speed_m_s);
      EXPECT_EQ(x.velocity_noise_m_s, y.velocity_noise_m_s);
      if (k > 0) {
        EXPECT_EQ(x.behaviour, y.behaviour);
        EXPECT_EQ(x.params, y.params);
      }
    }
    const pop::HumanSpec& h = b.humans.at(0);
    EXPECT_EQ(h.behaviour, "responsive");
    EXPECT_GE(param(h, "reaction_time_median_s"), 0.7);
    EXPECT_LE(param(h, "reaction_time_median_s"), 1.3);
    EXPECT_GE(param(h, "repeat_increment_m"), 0.1);
    EXPECT_LE(param(h, "repeat_increment_m"), 0.3);
    EXPECT_GE(param(h, "yield.offset_m"), 0.6);
    EXPECT_LE(param(h, "yield.offset_m"), 0.9);
    if (a.humans.at(0).behaviour == "responsive") {
      ++unchanged;
      EXPECT_EQ(pop::scenarioYaml(a), pop::scenarioYaml(b));
    }
  }
  EXPECT_EQ(unchanged, 10);  // one head-on behaviour in six
  EXPECT_GE(layouts.size(), 10u);
  EXPECT_EQ(allYaml(resp), allYaml(pop::generatePopulation(60, 5, {}, "responsive")));
  EXPECT_TRUE(pop::isBehaviourName("responsive"));
  EXPECT_FALSE(pop::isBehaviourName("recorded"));
  EXPECT_THROW(pop::generatePopulation(6, 5, {}, "recorded"), std::invalid_argument);
}
