// The population's aggregation (tools/population/aggregate.hpp, stats.hpp): who touched whom,
// unknown fields, time-to-goal ratio, IsContributing accuracy and the AUC of CM.
#include "../../../tools/population/aggregate.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pop = coopnav::population;
using pop::Json;

namespace {

Json human(int id, const char* role, const char* behaviour) {
  return Json{{"id", id}, {"role", role}, {"behaviour", behaviour}, {"speed_m_s", 1.0}};
}

Json encounter(const char* name, Json humans) {
  return Json{{"name", name},         {"scenario", std::string("scenarios/") + name + ".yaml"},
              {"baseline", "base_x"}, {"layout", "corridor_2.00"},
              {"width_m", 2.0},       {"humans", std::move(humans)}};
}

Json plan(Json encounters) {
  return Json{{"format", pop::kPlanFormat},
              {"seed", 5},
              {"encounters", std::move(encounters)},
              {"baselines", Json::array({Json{{"name", "base_x"}}})}};
}

Json assessed(int id, double cm, bool contributing) {
  return Json{{"id", id},
              {"cm_interaction_m", cm},
              {"is_contributing_interaction", contributing},
              {"cm_window_m", cm},
              {"is_contributing", contributing}};
}

Json run(const char* state, Json contact, Json humans, double ttg = 40.0) {
  Json r{{"final_state", state},
         {"detail", ""},
         {"min_clearance_m", 0.2},
         {"robot_time_to_goal_s", ttg},
         {"humans", std::move(humans)},
         {"contact", std::move(contact)},
         {"min_clearance_t_s", 12.5},
         {"docks", 1},
         {"retreats", 0},
         {"guard_steps", 3}};
  return r;
}

}  // namespace

TEST(PopulationAggregate, RobotAtFaultContactFailsThePopulation) {
  const Json p =
      plan(Json::array({encounter("a", Json::array({human(1, "head_on", "minimal")})),
                        encounter("b", Json::array({human(1, "head_on", "oblivious"),
                                                    human(2, "follower", "minimal")}))}));
  std::map<std::string, Json> s;
  s["base_x"] = run("GOAL_REACHED", nullptr, Json::array(), 30.0);
  s["a"] = run("GOAL_REACHED", nullptr, Json::array({assessed(1, 0.1, false)}));
  s["b"] =
      run("COLLISION",
          Json{{"human_id", 1}, {"t_s", 9.0}, {"robot_at_fault", false}, {"robot_speed_m_s", -0.1}},
          Json::array());
  Json out = pop::aggregatePopulation(p, s);
  EXPECT_FALSE(pop::populationFails(out));
  EXPECT_EQ(out["totals"]["contacts_by_cause"]["human_walked_in"], 1);
  EXPECT_EQ(out["totals"]["contacts_by_behaviour"]["oblivious"]["human_walked_in"], 1);
  EXPECT_EQ(out["runs"][1]["contact"]["behaviour"], "oblivious");
  EXPECT_DOUBLE_EQ(out["runs"][0]["time_to_goal_ratio"].get<double>(), 40.0 / 30.0);

  s["b"]["contact"]["robot_at_fault"] = true;
  s["b"]["contact"]["human_id"] = 2;
  out = pop::aggregatePopulation(p, s);
  EXPECT_TRUE(pop::populationFails(out));
  EXPECT_EQ(out["totals"]["contacts_by_behaviour"]["minimal"]["robot_at_fault"], 1);
  EXPECT_NE(pop::formatTable(out).find("robot_at_fault h2"), std::string::npos);
}

TEST(PopulationAggregate, SummariesWithoutTheNewFieldsAreReadAsUnknown) {
  const Json p = plan(Json::array({encounter("a", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("b", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("c", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("d", Json::array({human(1, "head_on", "minimal")}))}));
  auto old = [](const char* state, const char* detail) {
    return Json{{"final_state", state}, {"detail", detail}, {"robot_time_to_goal_s", nullptr}};
  };
  std::map<std::string, Json> s;
  s["a"] = old("COLLISION", "robot collided with human 1 at t = 20.3 s");
  s["b"] = old("COLLISION", "robot collided with a wall at t = 3.0 s");
  s["c"] = old("TIME_LIMIT", "time limit of 90 s reached");
  // d: no summary at all (a run that did not start).
  const Json out = pop::aggregatePopulation(p, s);
  EXPECT_EQ(out["runs"][0]["contact"]["cause"], "unattributed");
  EXPECT_EQ(out["runs"][0]["contact"]["human_id"], 1);
  EXPECT_EQ(out["runs"][1]["contact"]["cause"], "robot_hit_wall");
  EXPECT_EQ(out["runs"][2]["contact"]["cause"], "none");
  EXPECT_EQ(out["runs"][3]["outcome"], "NO_SUMMARY");
  EXPECT_TRUE(out["runs"][2]["docks"].is_null());
  EXPECT_TRUE(out["totals"]["docks"].is_null());
  EXPECT_TRUE(out["runs"][2]["time_to_goal_ratio"].is_null());
  EXPECT_EQ(out["totals"]["failed_runs"], 1);
  EXPECT_EQ(out["totals"]["standstills"], 1);
  EXPECT_EQ(out["totals"]["robot_at_fault_or_unattributed"], 2);
  EXPECT_TRUE(pop::populationFails(out));
}

TEST(PopulationAggregate, AccuracyAndAucFollowTheStatedExpectations) {
  Json encounters = Json::array();
  std::map<std::string, Json> s;
  const std::vector<std::tuple<const char*, double, bool>> cases{
      {"facilitating", 0.9, true}, {"facilitating", 0.35, false}, {"late_facilitating", 0.5, true},
      {"minimal", 0.1, false},     {"minimal", 0.45, true},       {"oblivious", 0.0, false},
      {"social_force", 0.2, false}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string name = "r" + std::to_string(i);
    const auto& [b, cm, contributing] = cases[i];
    encounters.push_back(encounter(name.c_str(), Json::array({human(1, "head_on", b)})));
    s[name] = run("GOAL_REACHED", nullptr, Json::array({assessed(1, cm, contributing)}));
  }
  // A same-way human is not an encounter: its verdict is left out.
  encounters.push_back(encounter("sw", Json::array({human(1, "same_way", "facilitating")})));
  s["sw"] = run("GOAL_REACHED", nullptr, Json::array({assessed(1, 0.0, false)}));
  const Json out = pop::aggregatePopulation(plan(encounters), s);
  const Json& acc = out["totals"]["is_contributing_accuracy"];
  EXPECT_EQ(acc["facilitating"]["judged"], 2);
  EXPECT_EQ(acc["facilitating"]["correct"], 1);
  EXPECT_EQ(acc["late_facilitating"]["correct"], 1);
  EXPECT_EQ(acc["minimal"]["correct"], 1);
  EXPECT_EQ(acc["oblivious"]["correct"], 1);
  EXPECT_EQ(acc["all"]["judged"], 6);
  EXPECT_EQ(acc["all"]["correct"], 4);
  EXPECT_FALSE(acc.contains("social_force"));
  // Facilitating {0.9, 0.35} against {0.1, 0.45, 0.0}: 5 of 6 pairs ordered.
  const Json& auc = out["totals"]["cm_auc_facilitating_vs_minimal_oblivious"];
  EXPECT_NEAR(auc["auc"].get<double>(), 5.0 / 6.0, 1e-12);
  EXPECT_EQ(auc["positives"], 2);
  EXPECT_EQ(auc["negatives"], 3);
}

TEST(PopulationAggregate, AccuracyIsReportedAgainstTheFixedAndTheRoomTau) {
  // Interaction CM 0.3 in a narrow corridor (τ against the room 0.25) and 0.3 in a wide one
  // (τ 0.4 both ways), both facilitating; a minimal human at 0.2 with τ against the room 0.15.
  const std::vector<std::tuple<const char*, double, double>> cases{
      {"facilitating", 0.3, 0.25}, {"facilitating", 0.3, 0.4}, {"minimal", 0.2, 0.15}};
  Json encounters = Json::array();
  std::map<std::string, Json> s;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string name = "r" + std::to_string(i);
    const auto& [b, cm, tau_room] = cases[i];
    encounters.push_back(encounter(name.c_str(), Json::array({human(1, "head_on", b)})));
    Json h = assessed(1, cm, false);
    h["tau_fixed_m"] = 0.4;
    h["tau_room_m"] = tau_room;
    h["room_m"] = 2.0 * tau_room;
    s[name] = run("GOAL_REACHED", nullptr, Json::array({h}));
  }
  // A summary without the thresholds (older builds) is judged by neither.
  encounters.push_back(encounter("old", Json::array({human(1, "head_on", "minimal")})));
  s["old"] = run("GOAL_REACHED", nullptr, Json::array({assessed(1, 0.1, false)}));
  const Json out = pop::aggregatePopulation(plan(encounters), s);
  const Json& acc = out["totals"]["is_contributing_accuracy"];
  EXPECT_DOUBLE_EQ(acc["facilitating"]["accuracy_fixed_tau"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(acc["facilitating"]["accuracy_room_tau"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(acc["minimal"]["accuracy_fixed_tau"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(acc["minimal"]["accuracy_room_tau"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(acc["all"]["accuracy_fixed_tau"].get<double>(), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(acc["all"]["accuracy_room_tau"].get<double>(), 1.0 / 3.0);
  EXPECT_EQ(acc["minimal"]["judged"], 2);  // the in-force verdict counts the old summary too
  EXPECT_NEAR(out["runs"][0]["humans"][0]["room_m"].get<double>(), 0.5, 1e-15);
}

TEST(PopulationStats, MannWhitneyAuc) {
  EXPECT_DOUBLE_EQ(pop::mannWhitneyAuc({2, 3}, {0, 1}), 1.0);
  EXPECT_DOUBLE_EQ(pop::mannWhitneyAuc({0, 1}, {2, 3}), 0.0);
  EXPECT_DOUBLE_EQ(pop::mannWhitneyAuc({1, 1}, {1}), 0.5);
  EXPECT_DOUBLE_EQ(pop::mannWhitneyAuc({1, 3, std::nan("")}, {2}), 0.5);
  EXPECT_TRUE(std::isnan(pop::mannWhitneyAuc({}, {1})));
  EXPECT_DOUBLE_EQ(pop::median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(pop::median({4, 1, 2, 3}), 2.5);
}
