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

TEST(PopulationAggregate, StandstillsTimeLimitsAndEveryContactAreRunsEndedBadly) {
  const Json p = plan(Json::array({encounter("a", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("b", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("c", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("d", Json::array({human(1, "head_on", "minimal")})),
                                   encounter("e", Json::array({human(1, "head_on", "minimal")}))}));
  std::map<std::string, Json> s;
  s["base_x"] = run("GOAL_REACHED", nullptr, Json::array(), 30.0);
  s["a"] = run("GOAL_REACHED", nullptr, Json::array());
  s["a"]["max_mutual_wait_s"] = 9.5;
  s["a"]["stalled_s"] = 2.0;
  s["e"] = run("GOAL_REACHED", nullptr, Json::array(), 75.0);
  s["e"]["max_mutual_wait_s"] = 12.0;
  s["e"]["stalled_s"] = 4.0;
  s["b"] = run("STANDSTILL", nullptr, Json::array());
  s["c"] = run("TIME_LIMIT", nullptr, Json::array());
  s["d"] =
      run("COLLISION",
          Json{{"human_id", 1}, {"t_s", 9.0}, {"robot_at_fault", false}, {"robot_speed_m_s", 0.0}},
          Json::array());
  const Json out = pop::aggregatePopulation(p, s);
  EXPECT_FALSE(pop::populationFails(out));  // nobody the robot touched: not exit 1
  const std::vector<std::string> bad = pop::runsEndedBadly(out);
  ASSERT_EQ(bad.size(), 4U);
  EXPECT_EQ(bad[0], "b: STANDSTILL");
  EXPECT_EQ(bad[1], "c: TIME_LIMIT");
  EXPECT_EQ(bad[2], "d: contact (human_walked_in)");
  EXPECT_EQ(bad[3], "e: mutual wait of 12.0 s");
  EXPECT_EQ(out["totals"]["stalemates"], 3);  // b, c, e; a waited 9.5 s: not a stalemate
  EXPECT_EQ(out["runs"][4]["stalemate"], true);
  EXPECT_DOUBLE_EQ(out["totals"]["max_mutual_wait_s"].get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(out["totals"]["stalled_s"]["max"].get<double>(), 4.0);
  // Ratios 40/30 (a, b, c, d) and 75/30 (e): the 95th percentile by nearest rank is e's.
  EXPECT_DOUBLE_EQ(out["totals"]["time_to_goal_ratio"]["p95"].get<double>(), 2.5);
  EXPECT_EQ(out["totals"]["mutual_waits_over_limit"], 1);  // e
  EXPECT_EQ(out["totals"]["time_to_goal_ratio"]["runs_goal_not_reached"], 0);
  EXPECT_DOUBLE_EQ(out["totals"]["time_to_goal_ratio"]["p95_all_runs"].get<double>(), 2.5);

  // The standstill and the time limit never reached the goal: beside the p95 of the runs that
  // did (a, d, e), the p95 of every run counts them as unbounded.
  s["b"]["robot_time_to_goal_s"] = nullptr;
  s["c"]["robot_time_to_goal_s"] = nullptr;
  const Json failed = pop::aggregatePopulation(p, s);
  EXPECT_EQ(failed["totals"]["time_to_goal_ratio"]["runs"], 3);
  EXPECT_DOUBLE_EQ(failed["totals"]["time_to_goal_ratio"]["p95"].get<double>(), 2.5);
  EXPECT_EQ(failed["totals"]["time_to_goal_ratio"]["runs_goal_not_reached"], 2);
  EXPECT_TRUE(failed["totals"]["time_to_goal_ratio"]["p95_all_runs"].is_null());
  const std::string table = pop::formatTable(failed);
  EXPECT_NE(table.find("the 2 that did not reach it counted as unbounded: unbounded"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("runs with a mutual wait over 10 s 1"), std::string::npos) << table;

  s["b"] = s["c"] = s["d"] = s["e"] = s["a"];
  EXPECT_TRUE(pop::runsEndedBadly(pop::aggregatePopulation(p, s)).empty());
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
  // b: a summary with `contact`, null: the collision was not with a person, so with a wall.
  s["b"] = old("COLLISION", "robot collided with a wall at t = 3.0 s");
  s["b"]["contact"] = nullptr;
  s["c"] = old("TIME_LIMIT", "time limit of 90 s reached");
  // d: no summary at all (a run that did not start).
  const Json out = pop::aggregatePopulation(p, s);
  // Without `contact` nothing says whom the robot hit (the detail sentence is for people).
  EXPECT_EQ(out["runs"][0]["contact"]["cause"], "unattributed");
  EXPECT_TRUE(out["runs"][0]["contact"]["human_id"].is_null());
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
  EXPECT_DOUBLE_EQ(pop::quantile({5, 1, 4, 2, 3}, 0.95), 5.0);
  EXPECT_DOUBLE_EQ(pop::quantile({5, 1, 4, 2, 3}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(pop::quantile({1.0, 2.0}, 0.1), 1.0);
  EXPECT_TRUE(std::isnan(pop::quantile({}, 0.95)));
}

namespace {

Json sayEntry(const char* act, const char* delivery, Json lead_s) {
  return Json{{"kind", "say"}, {"act", act}, {"delivery", delivery}, {"lead_s", std::move(lead_s)}};
}

// A run of a cue-effect pair: the head-on human (id 1) with its CM and the transcript of what was
// decided for it.
Json cueRun(double cm, bool docked, double ttg, double clearance, Json transcript) {
  Json h = assessed(1, cm, cm > 0.4);
  h["transcript"] = std::move(transcript);
  Json r = run("GOAL_REACHED", nullptr, Json::array({std::move(h)}), ttg);
  r["docked"] = docked;
  r["min_clearance_m"] = clearance;
  return r;
}

Json twinned(const char* name, const char* layout, double width_m) {
  Json e = encounter(name, Json::array({human(1, "head_on", "responsive")}));
  e["layout"] = layout;
  e["width_m"] = width_m;
  e["muted_twin"] = pop::mutedTwinName(name);
  return e;
}

}  // namespace

// Given four encounters each run speaking and muted (a: the cue avoids a dock; b: speaking docks
// where muted did not; c: no difference; d: its muted twin left no summary), when aggregated,
// then each pair and the overall and per-layout figures are as counted by hand, and the muted
// half counts towards the failures.
TEST(PopulationCueEffect, PairsSpeakingAgainstMuted) {
  const Json p =
      plan(Json::array({twinned("a", "corridor_1.70", 1.7), twinned("b", "corridor_1.70", 1.7),
                        twinned("c", "corridor_3.00", 3.0), twinned("d", "corridor_3.00", 3.0)}));
  std::map<std::string, Json> s;
  s["a"] = cueRun(0.6, false, 40.0, 0.3,
                  Json::array({sayEntry("INFORM_DIRECTION", "said", 4.0),
                               sayEntry("INFORM_DOCKING", "too_late", -0.5),
                               sayEntry("THANK", "said", nullptr)}));
  s["a"]["hearing"] = Json::array({Json{{"id", 1}, {"heard", 1}, {"complied", 1}}});
  s["a_muted"] =
      cueRun(0.1, true, 48.0, 0.1, Json::array({sayEntry("INFORM_DIRECTION", "muted", 4.2)}));
  s["b"] = cueRun(0.5, true, 45.0, 0.2, Json::array({sayEntry("ASK_TO_MOVE", "said", 2.0)}));
  s["b_muted"] = cueRun(0.2, false, 41.0, 0.25, Json::array());
  s["c"] = cueRun(0.3, false, 38.0, 0.5, Json::array({sayEntry("INFORM_DIRECTION", "said", 5.0)}));
  s["c_muted"] = cueRun(0.3, false, 38.0, 0.5, Json::array());
  s["d"] = cueRun(0.7, false, 39.0, 0.4, Json::array());

  Json out = pop::aggregatePopulation(p, s);
  ASSERT_TRUE(out.contains("cue_effect"));
  const Json& cue = out["cue_effect"];
  EXPECT_EQ(cue["pairs"], 4);
  EXPECT_EQ(cue["muted_failed_runs"], 1);
  const Json& e = cue["encounters"];
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0]["muted_run"], "a_muted");
  EXPECT_EQ(e[0]["dock"], "avoided");
  EXPECT_EQ(e[1]["dock"], "added");
  EXPECT_EQ(e[2]["dock"], "same");
  EXPECT_TRUE(e[3]["dock"].is_null());
  EXPECT_EQ(e[3]["muted"]["outcome"], "NO_SUMMARY");
  EXPECT_NEAR(e[0]["cm_difference_m"].get<double>(), 0.5, 1e-12);
  EXPECT_EQ(e[0]["speaking"]["cues_said"], 1);  // the thanks is no cue
  EXPECT_EQ(e[0]["speaking"]["cues_too_late"], 1);
  EXPECT_EQ(e[0]["speaking"]["lead_s"], Json::array({4.0}));
  EXPECT_EQ(e[0]["speaking"]["heard"], 1);
  EXPECT_TRUE(e[1]["speaking"]["heard"].is_null());  // no cue outcomes read
  EXPECT_EQ(e[0]["muted"]["cues_muted"], 1);
  EXPECT_EQ(e[0]["muted"]["cues_said"], 0);

  const Json& o = cue["overall"];
  EXPECT_EQ(o["pairs"], 4);
  EXPECT_EQ(o["pairs_run"], 3);
  EXPECT_EQ(o["cm"]["pairs"], 3);
  EXPECT_NEAR(o["cm"]["mean_speaking_m"].get<double>(), 1.4 / 3.0, 1e-12);
  EXPECT_NEAR(o["cm"]["mean_muted_m"].get<double>(), 0.2, 1e-12);
  EXPECT_NEAR(o["cm"]["mean_difference_m"].get<double>(), 0.8 / 3.0, 1e-12);
  EXPECT_EQ(o["cm"]["speaking_higher"], 2);
  EXPECT_EQ(o["cm"]["muted_higher"], 0);
  EXPECT_EQ(o["cm"]["ties"], 1);
  EXPECT_DOUBLE_EQ(o["cm"]["sign_test_p"].get<double>(), 0.5);
  const Json& ci = o["cm"]["difference_ci95_m"];
  ASSERT_TRUE(ci.is_array());
  EXPECT_GE(ci[0].get<double>(), 0.0 - 1e-12);  // a resample mean lies within the values
  EXPECT_LE(ci[1].get<double>(), 0.5 + 1e-12);
  EXPECT_EQ(o["cm"]["contributing_speaking"], 2);
  EXPECT_EQ(o["cm"]["contributing_muted"], 0);
  EXPECT_EQ(o["docked"]["speaking"], 1);
  EXPECT_EQ(o["docked"]["muted"], 1);
  EXPECT_EQ(o["docked"]["avoided"], 1);
  EXPECT_EQ(o["docked"]["added"], 1);
  EXPECT_DOUBLE_EQ(o["time_to_goal"]["median_speaking_s"].get<double>(), 40.0);
  EXPECT_DOUBLE_EQ(o["time_to_goal"]["median_muted_s"].get<double>(), 41.0);
  EXPECT_DOUBLE_EQ(o["time_to_goal"]["median_difference_s"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(o["min_clearance"]["min_speaking_m"].get<double>(), 0.2);
  EXPECT_DOUBLE_EQ(o["min_clearance"]["median_speaking_m"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(o["min_clearance"]["min_muted_m"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(o["min_clearance"]["median_muted_m"].get<double>(), 0.25);
  EXPECT_EQ(o["cues"]["said"], 3);
  EXPECT_EQ(o["cues"]["too_late"], 1);
  EXPECT_DOUBLE_EQ(o["cues"]["lead_median_s"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(o["cues"]["lead_min_s"].get<double>(), 2.0);
  EXPECT_EQ(o["hearing"]["heard"], 1);
  EXPECT_EQ(o["contacts"]["muted"], 0);

  const Json& narrow = cue["by_layout"]["corridor_1.70"];
  EXPECT_EQ(narrow["pairs_run"], 2);
  EXPECT_DOUBLE_EQ(narrow["width_m"].get<double>(), 1.7);
  EXPECT_EQ(narrow["docked"]["avoided"], 1);
  EXPECT_EQ(cue["by_layout"]["corridor_3.00"]["pairs"], 2);
  EXPECT_EQ(cue["by_layout"]["corridor_3.00"]["pairs_run"], 1);

  EXPECT_FALSE(pop::populationFails(out));
  EXPECT_EQ(pop::runsWithoutSummary(out), 1);
  const std::string table = pop::formatTable(out);
  EXPECT_NE(table.find("# cue effect"), std::string::npos) << table;
  EXPECT_NE(table.find("docks avoided by speaking 1, added 1"), std::string::npos) << table;
  EXPECT_NE(table.find("\na         corridor_1.70   0.60/0.10   +0.50  n/y"), std::string::npos)
      << table;

  // The robot at fault in a muted twin fails the population as in an encounter.
  s["c_muted"]["contact"] =
      Json{{"human_id", 1}, {"t_s", 9.0}, {"robot_at_fault", true}, {"robot_speed_m_s", 0.3}};
  out = pop::aggregatePopulation(p, s);
  EXPECT_TRUE(pop::populationFails(out));
  EXPECT_EQ(out["cue_effect"]["muted_robot_at_fault_or_unattributed"], 1);
  EXPECT_EQ(out["cue_effect"]["overall"]["contacts"]["robot_at_fault_or_unattributed_muted"], 1);
  EXPECT_EQ(out["totals"]["robot_at_fault_or_unattributed"], 0);

  // Without muted twins there is no section.
  EXPECT_FALSE(pop::aggregatePopulation(plan(Json::array({encounter("a", Json::array())})), s)
                   .contains("cue_effect"));
}

TEST(PopulationCueEffect, PlanRecordsTheOptionsOnlyWhenSet) {
  const auto es = pop::generatePopulation(3, 5, {}, "responsive");
  const Json plain = pop::planJson(es, 5);
  EXPECT_FALSE(plain.contains("cue_effect"));
  EXPECT_FALSE(plain.contains("head_on_behaviour"));
  EXPECT_FALSE(plain["encounters"][0].contains("muted_twin"));
  const Json twins = pop::planJson(es, 5, {"responsive", true});
  EXPECT_EQ(twins["cue_effect"], true);
  EXPECT_EQ(twins["head_on_behaviour"], "responsive");
  EXPECT_EQ(twins["encounters"][2]["muted_twin"], "pop_0003_muted");
}

TEST(PopulationCueEffect, HearingIsReadFromCueOutcomes) {
  // world_sim's cue_outcomes_file: a heard and complied cue, a heard one not complied with, one
  // not heard, a thank (left out), a cue to someone who does not react to words (left out) and a
  // last line cut short by a stopped run (left out).
  const std::string jsonl =
      R"({"t_s":12.4,"human_id":1,"cue":"keep_side","side":"left","repeat":false,)"
      R"("distance_m":6.1,"responds":true,"heard":true,"complies":true,"act_s":13.3})"
      "\n"
      R"({"t_s":15.0,"human_id":1,"cue":"move_to_side","side":"right","repeat":true,)"
      R"("distance_m":3.0,"responds":true,"heard":true,"complies":false,"act_s":null})"
      "\n"
      R"({"t_s":16.0,"human_id":2,"cue":"keep_side","side":"left","repeat":false,)"
      R"("distance_m":12.3,"responds":true,"heard":false,"complies":false,"act_s":null})"
      "\n"
      R"({"t_s":20.0,"human_id":1,"cue":"thank","side":"undefined","repeat":false,)"
      R"("distance_m":1.0,"responds":true,"heard":true,"complies":true,"act_s":20.9})"
      "\n"
      R"({"t_s":21.0,"human_id":3,"cue":"keep_side","side":"left","repeat":false,)"
      R"("distance_m":4.0,"responds":false,"heard":false,"complies":false,"act_s":null})"
      "\n"
      R"({"t_s":22.0,"human_id":2,"cue":"keep_)";
  const Json h = pop::hearingFromCueOutcomes(jsonl);
  ASSERT_EQ(h.size(), 2u);
  EXPECT_EQ(h[0], (Json{{"id", 1},
                        {"cues", 2},
                        {"heard", 2},
                        {"complied", 1},
                        {"not_heard", 0},
                        {"not_complied", 1}}));
  EXPECT_EQ(h[1]["id"], 2);
  EXPECT_EQ(h[1]["not_heard"], 1);
  EXPECT_EQ(h[1]["heard"], 0);
  EXPECT_TRUE(pop::hearingFromCueOutcomes("").empty());
  // A whole line that is not a cue outcome is an error that names its line.
  try {
    pop::hearingFromCueOutcomes("\n{\"human_id\":1,\"cue\":\"keep_side\"}\n");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pop::hearingFromCueOutcomes("human 1 heard keep_side\n"), std::runtime_error);
}

TEST(PopulationStats, SignTestMeanAndBootstrap) {
  EXPECT_DOUBLE_EQ(pop::signTestP(5, 0), 2.0 / 32.0);
  EXPECT_DOUBLE_EQ(pop::signTestP(0, 5), 2.0 / 32.0);
  EXPECT_NEAR(pop::signTestP(1, 9), 2.0 * 11.0 / 1024.0, 1e-12);
  EXPECT_DOUBLE_EQ(pop::signTestP(3, 3), 1.0);
  EXPECT_DOUBLE_EQ(pop::signTestP(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(pop::mean({1.0, 2.0, std::nan(""), 6.0}), 3.0);
  EXPECT_TRUE(std::isnan(pop::mean({})));
  pop::Rng a(7), b(7);
  const auto ia = pop::bootstrapMeanInterval({1, 2, 3, 4, 5}, 0.95, 1000, a);
  const auto ib = pop::bootstrapMeanInterval({1, 2, 3, 4, 5}, 0.95, 1000, b);
  EXPECT_EQ(ia, ib);  // a seeded generator: the same interval
  EXPECT_LT(ia.first, 3.0);
  EXPECT_GT(ia.second, 3.0);
  EXPECT_GE(ia.first, 1.0);
  EXPECT_LE(ia.second, 5.0);
  EXPECT_TRUE(std::isnan(pop::bootstrapMeanInterval({1.0}, 0.95, 100, a).first));
}

// ---- Dialogue checks and crowds (summary.json dialogue_checks).

namespace {

Json checks(int said, int addressed, Json not_crossing = Json::array(),
            Json contradictions = Json::array(), Json told_twice = Json::array()) {
  return Json{{"said", said},
              {"addressed", addressed},
              {"said_to_not_crossing", std::move(not_crossing)},
              {"contradictions", std::move(contradictions)},
              {"told_twice", std::move(told_twice)}};
}

}  // namespace

// Given runs whose logs' dialogue checks are clean, list a failure, or lack, when the population
// is aggregated, then each run carries its checks (unaddressed sentences counted only where
// several people were), the totals count the runs per check, and a failing check is reported
// apart from the safety failures (populationFails stays false).
TEST(PopulationAggregate, DialogueChecksAreCountedPerRunAndFailApartFromSafety) {
  const Json p = plan(Json::array(
      {encounter("alone", Json::array({human(1, "head_on", "minimal")})),
       encounter("clean",
                 Json::array({human(1, "head_on", "minimal"), human(2, "same_way", "minimal")})),
       encounter("unaddr",
                 Json::array({human(1, "head_on", "minimal"), human(2, "follower", "minimal")})),
       encounter("contra",
                 Json::array({human(1, "head_on", "minimal"), human(2, "follower", "minimal")})),
       encounter("old", Json::array({human(1, "head_on", "minimal")})),
       encounter("none", Json::array({human(1, "head_on", "minimal")}))}));
  std::map<std::string, Json> s;
  s["base_x"] = run("GOAL_REACHED", nullptr, Json::array(), 30.0);
  s["alone"] = run("GOAL_REACHED", nullptr, Json::array());
  s["alone"]["dialogue_checks"] = checks(2, 0);  // alone: the paper's words, unaddressed
  s["clean"] = run("GOAL_REACHED", nullptr, Json::array());
  s["clean"]["dialogue_checks"] = checks(3, 3);
  s["unaddr"] = run("GOAL_REACHED", nullptr, Json::array());
  s["unaddr"]["dialogue_checks"] = checks(3, 1);
  s["contra"] = run("GOAL_REACHED", nullptr, Json::array());
  s["contra"]["dialogue_checks"] =
      checks(4, 4, Json::array({"12.30 s human 2 INFORM_DIRECTION round 1"}),
             Json::array({"14.00 s human 1 REPEAT_DIRECTION round 2: says the robot passes"}));
  s["old"] = run("GOAL_REACHED", nullptr, Json::array());  // a summary from before the checks
  const Json out = pop::aggregatePopulation(p, s);
  const Json& runs = out["runs"];
  EXPECT_TRUE(runs[0]["dialogue_checks"]["unaddressed_with_several"].is_null());
  EXPECT_FALSE(runs[0]["dialogue_checks"]["fails"].get<bool>());
  EXPECT_EQ(runs[1]["dialogue_checks"]["unaddressed_with_several"], 0);
  EXPECT_FALSE(runs[1]["dialogue_checks"]["fails"].get<bool>());
  EXPECT_EQ(runs[2]["dialogue_checks"]["unaddressed_with_several"], 2);
  EXPECT_TRUE(runs[2]["dialogue_checks"]["fails"].get<bool>());
  EXPECT_TRUE(runs[3]["dialogue_checks"]["fails"].get<bool>());
  EXPECT_EQ(runs[3]["dialogue_checks"]["contradictions"].size(), 1u);
  EXPECT_TRUE(runs[4]["dialogue_checks"].is_null());
  EXPECT_TRUE(runs[5]["dialogue_checks"].is_null());
  const Json& d = out["totals"]["dialogue_checks"];
  EXPECT_EQ(d["runs_checked"], 4);
  EXPECT_EQ(d["runs_without_checks"], 1);
  EXPECT_EQ(d["said"], 12);
  EXPECT_EQ(d["addressed"], 8);
  EXPECT_EQ(d["runs_said_to_not_crossing"], 1);
  EXPECT_EQ(d["runs_contradictions"], 1);
  EXPECT_EQ(d["runs_told_twice"], 0);
  EXPECT_EQ(d["runs_unaddressed_with_several"], 1);
  EXPECT_EQ(d["sentences_unaddressed_with_several"], 2);
  EXPECT_EQ(d["failing_runs"], 2);
  EXPECT_EQ(pop::dialogueFailingRuns(out), 2);
  EXPECT_FALSE(pop::populationFails(out));
  EXPECT_FALSE(out["totals"].contains("by_kind"));  // not a crowd plan
  const std::string table = pop::formatTable(out);
  EXPECT_NE(table.find("runs failing a dialogue check: 2\n"), std::string::npos) << table;
  EXPECT_NE(table.find(" 3/1!u "), std::string::npos) << table;
  EXPECT_NE(table.find(" 4/4!nc "), std::string::npos) << table;
  EXPECT_EQ(table.find("# crowd kinds"), std::string::npos);
}

// Given a crowd plan, the totals give per kind the runs, goals reached, contacts (those with the
// robot at fault), the min clearance and the runs failing a dialogue check; runs carry their
// kind; people crossing the robot's path or standing are not judged as oncoming encounters.
TEST(PopulationAggregate, CrowdKindsHaveTheirSafetyFiguresAndChecks) {
  auto crowdEncounter = [](const char* name, const char* kind, Json humans) {
    Json e = encounter(name, std::move(humans));
    e["kind"] = kind;
    return e;
  };
  Json p = plan(Json::array(
      {crowdEncounter("j1", "junction",
                      Json::array({human(1, "crossing", "minimal"), human(2, "head_on", "minimal"),
                                   human(3, "same_way", "facilitating")})),
       crowdEncounter(
           "t1", "standing_talk",
           Json::array({human(1, "standing", "minimal"), human(2, "standing", "minimal")})),
       crowdEncounter(
           "t2", "standing_talk",
           Json::array({human(1, "standing", "minimal"), human(2, "standing", "minimal")}))}));
  p["crowd"] = true;
  std::map<std::string, Json> s;
  s["j1"] =
      run("GOAL_REACHED", nullptr, Json::array({assessed(1, 0.5, true), assessed(2, 0.1, false)}));
  s["j1"]["dialogue_checks"] = checks(2, 2);
  s["j1"]["min_clearance_m"] = 0.31;
  s["t1"] =
      run("COLLISION",
          Json{{"human_id", 2}, {"t_s", 20.0}, {"robot_at_fault", true}, {"robot_speed_m_s", 0.3}},
          Json::array({assessed(1, 0.0, false)}));
  s["t1"]["dialogue_checks"] =
      checks(1, 1, Json::array({"3.00 s human 1 INFORM_DIRECTION round 1"}));
  s["t1"]["min_clearance_m"] = -0.01;
  s["t2"] = run("GOAL_REACHED", nullptr, Json::array());
  s["t2"]["dialogue_checks"] = checks(0, 0);
  s["t2"]["min_clearance_m"] = 0.8;
  const Json out = pop::aggregatePopulation(p, s);
  EXPECT_EQ(out["runs"][0]["kind"], "junction");
  const Json& k = out["totals"]["by_kind"];
  EXPECT_EQ(k["junction"]["runs"], 1);
  EXPECT_EQ(k["junction"]["goal_reached"], 1);
  EXPECT_EQ(k["junction"]["dialogue_failing_runs"], 0);
  EXPECT_EQ(k["standing_talk"]["runs"], 2);
  EXPECT_EQ(k["standing_talk"]["contacts"], 1);
  EXPECT_EQ(k["standing_talk"]["robot_at_fault_or_unattributed"], 1);
  EXPECT_DOUBLE_EQ(k["standing_talk"]["min_clearance_min_m"].get<double>(), -0.01);
  EXPECT_DOUBLE_EQ(k["standing_talk"]["min_clearance_median_m"].get<double>(), 0.395);
  EXPECT_EQ(k["standing_talk"]["dialogue_failing_runs"], 1);
  EXPECT_TRUE(pop::populationFails(out));
  // Only the head-on human of j1 is an assessed encounter (minimal, judged correctly).
  const Json& acc = out["totals"]["is_contributing_accuracy"];
  EXPECT_EQ(acc["all"]["judged"], 1);
  EXPECT_EQ(acc["minimal"]["correct"], 1);
  const std::string table = pop::formatTable(out);
  EXPECT_NE(table.find("# crowd kinds"), std::string::npos);
  EXPECT_NE(table.find("  standing_talk  2    goal 1"), std::string::npos) << table;
  EXPECT_NE(table.find("j1       corridor_2.00   junction       GOAL_REACHED"), std::string::npos)
      << table;
}
