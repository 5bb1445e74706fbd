// The population generator (tools/population/generator.hpp): determinism, coverage of the
// behaviours and layouts, and every drawn value inside the ranges docs/population.md states.
#include "../../../tools/population/generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
    ASSERT_LE(e.humans.size(), 4u);
    EXPECT_LE(e.seed, 1ULL << 53);
    const pop::HumanSpec& h = e.humans.at(0);
    EXPECT_EQ(h.role, "head_on");
    // A pair abreast may be centred where the head-on person alone would not fit beside it.
    if (e.variant != "abreast") {
      EXPECT_LE(std::abs(h.start_y_m - e.layout.centre_y_m), 0.3 + 1e-9);
    }
    EXPECT_GT(h.start_x_m, e.layout.robot_goal_x_m);
    EXPECT_LT(h.goal_x_m, e.layout.robot_start_x_m);
    for (const auto& x : e.humans) {
      const bool slower = e.variant == "slower_ahead" && &x == &e.humans.back();
      EXPECT_GE(x.speed_m_s, slower ? 0.4 : 0.8);
      EXPECT_LE(x.speed_m_s, slower ? 0.6 : 1.3);
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

// The widened encounters (issue 44): a differential robot, a tracker's noise, a pair abreast or
// a slower person ahead, each at about its share, drawn from the encounter's own stream so that
// the rest of every encounter is what the seed drew without them.
TEST(PopulationGenerator, WidenedEncountersKeepTheOtherDraws) {
  pop::Ranges none;
  none.differential_p = none.tracker_noise_p = none.abreast_p = none.slower_ahead_p = 0.0;
  none.pause_p = 0.0;
  const auto plain = pop::generatePopulation(600, 13, none);
  const auto wide = pop::generatePopulation(600, 13);
  ASSERT_EQ(plain.size(), wide.size());
  int differential = 0, tracker = 0, abreast = 0, slower = 0;
  for (std::size_t i = 0; i < wide.size(); ++i) {
    const pop::Encounter& p = plain[i];
    const pop::Encounter& w = wide[i];
    EXPECT_FALSE(p.differential || p.tracker_noise || !p.variant.empty());
    EXPECT_EQ(p.seed, w.seed);
    EXPECT_EQ(p.layout.key, w.layout.key);
    differential += w.differential;
    tracker += w.tracker_noise;
    const std::string y = pop::scenarioYaml(w);
    EXPECT_EQ(y.find("kinematics: differential") != std::string::npos, w.differential);
    EXPECT_EQ(y.find("tracker: {position_sigma_m: 0.05") != std::string::npos, w.tracker_noise);
    EXPECT_EQ(pop::scenarioYaml(w, false, "b").find("tracker:"), std::string::npos);
    EXPECT_EQ(pop::baselineName(w),
              pop::baselineName(w.layout) + (w.differential ? "_differential" : ""));
    const std::size_t base_n = p.humans.size();
    if (w.variant.empty()) {
      EXPECT_EQ(w.humans.size(), base_n);
    } else {
      ASSERT_EQ(w.humans.size(), base_n + 1) << w.name;
      const pop::HumanSpec& x = w.humans.back();
      EXPECT_EQ(x.id, static_cast<int>(base_n) + 1);
      if (w.layout.extra_lanes_y_m.empty()) {  // else in the lanes round open_wide's pillar
        EXPECT_GE(x.start_y_m, w.layout.lateral_min_y_m - 1e-9) << w.name;
        EXPECT_LE(x.start_y_m, w.layout.lateral_max_y_m + 1e-9) << w.name;
      }
      if (w.variant == "abreast") {
        ++abreast;
        const pop::HumanSpec& h = w.humans.front();
        EXPECT_EQ(x.role, "head_on");
        EXPECT_EQ(x.behaviour, h.behaviour);
        EXPECT_EQ(x.speed_m_s, h.speed_m_s);
        EXPECT_EQ(h.group, 1);
        EXPECT_EQ(x.group, 1);
        const double spacing = std::abs(x.start_y_m - h.start_y_m);
        EXPECT_GE(spacing, 0.7 - 1e-9);
        EXPECT_LE(spacing, 0.9 + 1e-9);
        EXPECT_GE(h.start_y_m, w.layout.lateral_min_y_m - 1e-9) << w.name;
        EXPECT_LE(h.start_y_m, w.layout.lateral_max_y_m + 1e-9) << w.name;
      } else {
        ++slower;
        EXPECT_EQ(w.variant, "slower_ahead");
        EXPECT_EQ(x.role, "same_way");
        EXPECT_LT(x.speed_m_s, 0.7);  // slower than the robot
        EXPECT_GE(x.start_x_m, w.layout.robot_start_x_m + 3.0 - 1e-9);
        EXPECT_LE(x.start_x_m, w.layout.robot_start_x_m + 6.0 + 1e-9);
        EXPECT_GT(x.goal_x_m, w.layout.robot_goal_x_m);
      }
    }
    // Everyone the seed drew without the widening is unchanged but for a pair's centring.
    for (std::size_t k = 0; k < base_n; ++k) {
      EXPECT_EQ(p.humans[k].behaviour, w.humans[k].behaviour);
      EXPECT_EQ(p.humans[k].start_x_m, w.humans[k].start_x_m);
      EXPECT_EQ(p.humans[k].speed_m_s, w.humans[k].speed_m_s);
      if (k > 0 || w.variant != "abreast") {
        EXPECT_EQ(p.humans[k].start_y_m, w.humans[k].start_y_m);
      }
    }
  }
  // 600 draws each: p 0.25, 0.25, 0.15 (pairs need 0.7 m of lanes: not in open_wide), 0.15.
  EXPECT_GT(differential, 110);
  EXPECT_LT(differential, 190);
  EXPECT_GT(tracker, 110);
  EXPECT_LT(tracker, 190);
  EXPECT_GT(abreast, 50);
  EXPECT_LT(abreast, 110);
  EXPECT_GT(slower, 60);
  EXPECT_LT(slower, 120);
}

// A person who pauses (issue 44): drawn after every other widened draw, so that the
// encounters are what they were without pauses but for the pause itself.
TEST(PopulationGenerator, PausesAddNothingButThePause) {
  pop::Ranges no_pause;
  no_pause.pause_p = 0.0;
  const auto plain = pop::generatePopulation(600, 17, no_pause);
  const auto paused = pop::generatePopulation(600, 17);
  ASSERT_EQ(plain.size(), paused.size());
  int pauses = 0;
  for (std::size_t i = 0; i < paused.size(); ++i) {
    const pop::Encounter& p = plain[i];
    const pop::Encounter& w = paused[i];
    EXPECT_EQ(p.differential, w.differential);
    EXPECT_EQ(p.tracker_noise, w.tracker_noise);
    EXPECT_EQ(p.variant, w.variant);
    ASSERT_EQ(p.humans.size(), w.humans.size());
    int here = 0;
    for (std::size_t k = 0; k < w.humans.size(); ++k) {
      const pop::HumanSpec& a = p.humans[k];
      const pop::HumanSpec& b = w.humans[k];
      EXPECT_EQ(a.pause_duration_s, 0.0);
      EXPECT_EQ(a.start_x_m, b.start_x_m);
      EXPECT_EQ(a.start_y_m, b.start_y_m);
      EXPECT_EQ(a.speed_m_s, b.speed_m_s);
      EXPECT_EQ(a.params, b.params);
      if (b.pause_duration_s == 0.0) continue;
      ++here;
      EXPECT_GE(b.pause_duration_s, 3.0 - 1e-9);
      EXPECT_LE(b.pause_duration_s, 10.0 + 1e-9);
      EXPECT_GT(b.pause_after_m, 0.0);
      EXPECT_LE(b.pause_after_m, 8.0 + 1e-9);
      const double path_m = std::hypot(b.goal_x_m - b.start_x_m, b.goal_y_m - b.start_y_m);
      EXPECT_LE(b.pause_after_m, 0.5 * path_m + 0.05);
    }
    EXPECT_LE(here, 1);
    pauses += here;
    EXPECT_EQ(pop::scenarioYaml(w).find("    pause: {after_m: ") != std::string::npos, here == 1);
    if (here == 0) {
      EXPECT_EQ(pop::scenarioYaml(p), pop::scenarioYaml(w));
    }
  }
  EXPECT_GT(pauses, 35);  // p 0.1 of 600
  EXPECT_LT(pauses, 90);
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
      if (x.role == "head_on") {
        // The head-on person, and the one abreast of them (its pair: same behaviour and params).
        EXPECT_EQ(y.behaviour, "responsive");
        EXPECT_EQ(y.params, b.humans.at(0).params);
      } else {
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

// ---- Crowds (generate --crowd): generateCrowdPopulation.

namespace {

bool isCrowdKind(const std::string& k) {
  const auto& kinds = pop::crowdKindNames();
  return std::find(kinds.begin(), kinds.end(), k) != kinds.end();
}

std::string allCrowdYaml(const std::vector<pop::Encounter>& es) {
  std::string s;
  for (const auto& e : es) s += pop::scenarioYaml(e) + pop::scenarioYaml(e, false, "b");
  return s;
}

}  // namespace

TEST(PopulationCrowd, SameSeedSameBytesOtherSeedOtherPopulation) {
  const auto a = pop::generateCrowdPopulation(40, 3);
  const auto b = pop::generateCrowdPopulation(40, 3);
  const auto c = pop::generateCrowdPopulation(40, 4);
  EXPECT_EQ(allCrowdYaml(a), allCrowdYaml(b));
  EXPECT_NE(allCrowdYaml(a), allCrowdYaml(c));
  const auto d = pop::generateCrowdPopulation(48, 3);
  EXPECT_EQ(allCrowdYaml(a), allCrowdYaml({d.begin(), d.begin() + 40}));
  // The crowd option leaves the head-on populations alone.
  EXPECT_NE(allCrowdYaml(a), allYaml(pop::generatePopulation(40, 3)));
  EXPECT_EQ(pop::scenarioYaml(pop::generatePopulation(1, 3).at(0)).find("crowd"),
            std::string::npos);
}

TEST(PopulationCrowd, EveryKindOncePerBlockOfFour) {
  const auto es = pop::generateCrowdPopulation(24, 9);
  for (std::size_t block = 0; block < 6; ++block) {
    std::set<std::string> seen;
    for (std::size_t i = 0; i < 4; ++i) {
      const std::string& k = es[block * 4 + i].kind;
      EXPECT_TRUE(isCrowdKind(k)) << k;
      seen.insert(k);
    }
    EXPECT_EQ(seen.size(), 4u) << "block " << block;
  }
}

// Given many crowd encounters, every count lies in its kind's range, people do not start
// overlapping each other (nor closer than 0.8 m unless they walk or stand together), nor in or
// near a wall, nor near the robot; at the junction everyone starts in a branch of the crossing
// corridor; a group shares behaviour, speed and params.
TEST(PopulationCrowd, CountsPlacesAndGroupsStayInTheirRanges) {
  const auto es = pop::generateCrowdPopulation(400, 17);
  const pop::CrowdRanges c;
  const pop::JunctionGeometry jg;
  std::map<std::string, std::set<std::size_t>> sizes;
  std::set<std::string> roles, behaviours;
  for (const auto& e : es) {
    SCOPED_TRACE(e.name + " " + e.kind);
    const std::size_t n = e.humans.size();
    sizes[e.kind].insert(n);
    EXPECT_LE(e.seed, 1ULL << 53);
    int group_size = 0, oncoming = 0, same_way = 0, crossing = 0, standing = 0;
    for (const auto& h : e.humans) {
      roles.insert(h.role);
      behaviours.insert(h.behaviour);
      group_size += h.group != 0 ? 1 : 0;
      oncoming += h.role == "head_on" ? 1 : 0;
      same_way += h.role == "same_way" ? 1 : 0;
      crossing += h.role == "crossing" ? 1 : 0;
      standing += h.role == "standing" ? 1 : 0;
    }
    for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(e.humans[k].id, static_cast<int>(k) + 1);
    if (e.kind == "flows") {
      EXPECT_GE(n, 2u);
      EXPECT_LE(n, 10u);
      EXPECT_GE(oncoming, 1);  // both ways
      EXPECT_GE(same_way, 1);
      EXPECT_EQ(group_size, 0);
    } else if (e.kind == "group_abreast") {
      EXPECT_GE(group_size, 2);
      EXPECT_LE(group_size, 3);
      EXPECT_LE(n, static_cast<std::size_t>(group_size) + 2);
    } else if (e.kind == "standing_talk") {
      EXPECT_GE(standing, 2);
      EXPECT_LE(standing, 3);
      EXPECT_LE(n, static_cast<std::size_t>(standing) + 1);
      for (const auto& h : e.humans)
        if (h.role == "standing") {
          EXPECT_EQ(h.speed_m_s, 0.0);
          EXPECT_EQ(h.velocity_noise_m_s, 0.0);
          EXPECT_EQ(h.start_x_m, h.goal_x_m);
          EXPECT_EQ(h.start_y_m, h.goal_y_m);
          // By a wall: the body within 0.15-0.4 m of it (the third one faces them).
          const double wall_gap =
              std::min(h.start_y_m, e.layout.width_m - h.start_y_m) - pop::kHumanRadiusM;
          if (h.start_theta == "0.0" || h.start_theta == "3.14159") {
            EXPECT_GE(wall_gap, 0.15 - 0.003);
            EXPECT_LE(wall_gap, 0.4 + 0.003);
          }
        }
    } else {
      ASSERT_EQ(e.kind, "junction");
      EXPECT_GE(n, 4u);
      EXPECT_LE(n, 6u);
      EXPECT_EQ(group_size, 2);  // one pair
      EXPECT_GE(crossing, 1);
      EXPECT_GE(same_way, 1);
      EXPECT_EQ(e.layout.map_file, "junctions.yaml");
      for (const auto& h : e.humans) {
        // In a branch of the crossing corridor, clear of its walls, north or south of the
        // robot's corridor.
        EXPECT_GE(h.start_x_m, jg.branch_x0_m + pop::kHumanRadiusM + 0.1 - 1e-9);
        EXPECT_LE(h.start_x_m, jg.branch_x1_m - pop::kHumanRadiusM - 0.1 + 1e-9);
        const bool north = h.start_y_m >= jg.north_y0_m + pop::kHumanRadiusM;
        const bool south = h.start_y_m <= jg.south_y1_m - pop::kHumanRadiusM;
        EXPECT_TRUE(north || south) << h.start_y_m;
        EXPECT_LE(h.start_y_m, jg.north_y1_m - pop::kHumanRadiusM - 0.1);
        EXPECT_GE(h.start_y_m, jg.south_y0_m + 2.0 - 1e-9);  // south of the 1.5 m corridor
        EXPECT_EQ(h.start_theta, north ? "-1.5708" : "1.5708");
        if (h.role == "crossing") {
          EXPECT_EQ(h.goal_x_m, (jg.branch_x0_m + jg.branch_x1_m) / 2);  // on its centre line
          EXPECT_TRUE(north ? h.goal_y_m <= jg.south_goal_y_m : h.goal_y_m > jg.north_y0_m + 5.0);
          EXPECT_TRUE(h.via.empty());
        } else {
          // Turning at the junction into the robot's corridor: towards it (west) or its way.
          ASSERT_EQ(h.via.size(), 1u);
          EXPECT_EQ(h.via[0][0], h.start_x_m);
          EXPECT_GE(h.via[0][1], e.layout.lateral_min_y_m - 1e-9);
          EXPECT_LE(h.via[0][1], e.layout.lateral_max_y_m + 1e-9);
          // In the open areas west and east of the blocks (x 0.3-6.85, 37.5-39.7), or moved
          // along the corridor (goals kept apart), never onto the robot's way.
          if (h.role == "head_on") {
            EXPECT_GE(h.goal_x_m, 1.2 - 1e-9);
            EXPECT_LE(h.goal_x_m, e.layout.robot_start_x_m - 0.5 + 1e-9);
          } else {
            EXPECT_LE(h.goal_x_m, 38.8 + 1e-9);
            EXPECT_GE(h.goal_x_m, e.layout.robot_goal_x_m + 1.5 - 1e-9);
          }
          if (h.goal_x_m > 6.0 && h.goal_x_m < 38.3) {  // in the corridor: off its walls
            EXPECT_GE(h.goal_y_m, e.layout.lateral_min_y_m + 0.2 - 1e-9);
            EXPECT_LE(h.goal_y_m, e.layout.lateral_max_y_m - 0.2 + 1e-9);
          }
          // Walking the robot's way only when well ahead of it.
          if (h.role == "same_way") {
            EXPECT_LE(std::abs(h.start_y_m - 26.0), h.speed_m_s * c.junction_away_before_s + 1e-6);
          }
        }
      }
    }
    if (e.kind != "junction") {
      EXPECT_EQ(e.layout.map_file, "");
      EXPECT_TRUE(std::find(pop::crowdWidthsM().begin(), pop::crowdWidthsM().end(),
                            e.layout.width_m) != pop::crowdWidthsM().end());
      for (const auto& h : e.humans) {
        EXPECT_GE(h.start_y_m, e.layout.lateral_min_y_m - 1e-9);
        EXPECT_LE(h.start_y_m, e.layout.lateral_max_y_m + 1e-9);
        // Goals off the walls by c.goal_wall_clearance_m (standing people: where they stand).
        if (h.role != "standing") {
          EXPECT_GE(h.goal_y_m, c.goal_wall_clearance_m - 1e-9);
          EXPECT_LE(h.goal_y_m, e.layout.width_m - c.goal_wall_clearance_m + 1e-9);
        }
        EXPECT_GT(h.start_x_m, e.layout.wall_x0_m + 0.5);
        EXPECT_LT(h.start_x_m, e.layout.wall_x1_m - 0.5);
        if (h.role == "head_on" || h.role == "follower") {
          EXPECT_LT(h.goal_x_m, e.layout.robot_start_x_m);
        }
        if (h.role == "same_way") {
          EXPECT_GT(h.goal_x_m, e.layout.robot_goal_x_m);
        }
      }
    }
    for (std::size_t a = 0; a < n; ++a) {
      const pop::HumanSpec& x = e.humans[a];
      if (x.role != "standing") {
        EXPECT_GE(x.speed_m_s, 0.8);
        EXPECT_LE(x.speed_m_s, 1.3);
      }
      EXPECT_GE(
          std::hypot(x.start_x_m - e.layout.robot_start_x_m, x.start_y_m - e.layout.centre_y_m),
          c.robot_keep_out_m - 1e-9);
      for (std::size_t b = a + 1; b < n; ++b) {
        const pop::HumanSpec& y = e.humans[b];
        const double d = std::hypot(x.start_x_m - y.start_x_m, x.start_y_m - y.start_y_m);
        const bool together = x.group != 0 && x.group == y.group;
        // Walkers do not end on each other's goal (one could not reach it).
        if (x.speed_m_s > 0.0 && y.speed_m_s > 0.0) {
          EXPECT_GE(std::hypot(x.goal_x_m - y.goal_x_m, x.goal_y_m - y.goal_y_m),
                    c.goal_gap_m - 1e-9)
              << "goals of " << x.id << " and " << y.id;
        }
        EXPECT_GE(d, together ? 2 * pop::kHumanRadiusM + 0.1 - 1e-9 : c.min_start_gap_m - 1e-9)
            << x.id << " and " << y.id;
        if (together && x.role != "standing") {
          EXPECT_EQ(x.behaviour, y.behaviour);
          EXPECT_EQ(x.speed_m_s, y.speed_m_s);
          EXPECT_EQ(x.params, y.params);
          EXPECT_EQ(x.start_y_m == y.start_y_m, e.kind == "junction");  // abreast
        }
      }
    }
  }
  // Every count of each range is drawn.
  EXPECT_EQ(sizes["flows"].size(), 9u);
  EXPECT_EQ(*sizes["junction"].begin(), 4u);
  EXPECT_EQ(*sizes["junction"].rbegin(), 6u);
  EXPECT_EQ(roles,
            (std::set<std::string>{"head_on", "follower", "same_way", "crossing", "standing"}));
  EXPECT_EQ(behaviours.size(), 6u);
}

TEST(PopulationCrowd, ScenarioYamlWritesViaHeadingAndKind) {
  const auto es = pop::generateCrowdPopulation(8, 2);
  bool via = false, standing = false;
  for (const auto& e : es) {
    const std::string y = pop::scenarioYaml(e);
    EXPECT_NE(y.find(", crowd " + e.kind + ".\n"), std::string::npos);
    if (e.kind == "junction") {
      EXPECT_NE(y.find("  file: ../maps/junctions.yaml\n"), std::string::npos);
      EXPECT_NE(y.find("start: {x_m: 13.000, y_m: 26.000, theta_rad: 0.0}"), std::string::npos);
      via = via || y.find("    via: [{x_m: ") != std::string::npos;
    }
    if (e.kind == "standing_talk") {
      standing = y.find("    speed_m_s: 0.00\n") != std::string::npos;
      EXPECT_NE(y.find("theta_rad: 3.14159}\n    goal:"), std::string::npos);
    }
    const std::string base = pop::scenarioYaml(e, false, pop::baselineName(e.layout));
    EXPECT_NE(base.find("humans: []\n"), std::string::npos);
    EXPECT_EQ(base.find("crowd"), std::string::npos);
  }
  EXPECT_TRUE(via);
  EXPECT_TRUE(standing);
  EXPECT_EQ(pop::baselineName(pop::junctionCrossLayout()), "base_junction_cross");
}
