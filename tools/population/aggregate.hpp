#pragma once
/// @file The population's plan (what was generated) and its result (population.json and the
/// plain-text table) from each run's summary.json entry (tools/ctl/README.md "summary.json").
/// Header-only (see generator.hpp); JSON values are nlohmann::ordered_json as in coopnav_ctl.
///
/// Fields of summary.json this reads beyond the long-standing ones (`final_state`, `detail`,
/// `min_clearance_m`, `robot_time_to_goal_s`, `sim_time_s`, `humans[].cm_interaction_m` ...):
/// `contact` (null or {human_id, t_s, robot_at_fault, robot_speed_m_s}), `min_clearance_t_s`,
/// `docks`, `retreats`, `guard_steps`. A missing field is unknown (null in the output), so the
/// tool reads summaries written before and after those fields exist.

#include <cmath>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "generator.hpp"
#include "stats.hpp"

namespace coopnav::population {

using Json = nlohmann::ordered_json;

inline constexpr const char* kPlanFormat = "coopnav-population-plan/1";
inline constexpr const char* kPopulationFormat = "coopnav-population/1";

/// What the generator wrote, for the aggregation and for a reader of the run directory.
inline Json planJson(const std::vector<Encounter>& encounters, std::uint64_t seed) {
  Json plan;
  plan["format"] = kPlanFormat;
  plan["seed"] = seed;
  plan["n"] = encounters.size();
  Json list = Json::array();
  std::set<std::string> baselines;
  Json base_list = Json::array();
  for (const auto& e : encounters) {
    Json j;
    j["name"] = e.name;
    j["scenario"] = "scenarios/" + e.name + ".yaml";
    j["baseline"] = baselineName(e.layout);
    j["layout"] = e.layout.key;
    j["width_m"] = e.layout.width_m;
    Json humans = Json::array();
    for (const auto& h : e.humans) {
      Json hj;
      hj["id"] = h.id;
      hj["role"] = h.role;
      hj["behaviour"] = h.behaviour;
      hj["speed_m_s"] = h.speed_m_s;
      hj["lateral_offset_m"] = quantize(h.start_y_m - e.layout.centre_y_m, 0.005);
      Json params = Json::object();
      for (const auto& [k, v] : h.params) params[k] = v;
      hj["params"] = std::move(params);
      humans.push_back(std::move(hj));
    }
    j["humans"] = std::move(humans);
    list.push_back(std::move(j));
    if (baselines.insert(baselineName(e.layout)).second) {
      Json b;
      b["name"] = baselineName(e.layout);
      b["scenario"] = "scenarios/" + baselineName(e.layout) + ".yaml";
      b["layout"] = e.layout.key;
      base_list.push_back(std::move(b));
    }
  }
  plan["encounters"] = std::move(list);
  plan["baselines"] = std::move(base_list);
  return plan;
}

namespace detail {

inline const Json* field(const Json* v, const char* key) {
  if (v == nullptr || !v->is_object()) return nullptr;
  auto it = v->find(key);
  return it == v->end() ? nullptr : &*it;
}
inline Json numberOrNull(const Json* v) {
  return v != nullptr && v->is_number() && std::isfinite(v->get<double>()) ? *v : Json();
}
inline double number(const Json* v) {
  return v != nullptr && v->is_number() ? v->get<double>() : std::nan("");
}
inline std::string text(const Json* v) {
  return v != nullptr && v->is_string() ? v->get<std::string>() : std::string();
}
inline Json boolOrNull(const Json* v) { return v != nullptr && v->is_boolean() ? *v : Json(); }

}  // namespace detail

/// The verdict expected of a behaviour (docs/population.md): facilitating and late_facilitating
/// contribute, minimal and oblivious do not; social_force and responsive: no expectation (null).
inline Json expectedContributing(const std::string& behaviour) {
  if (behaviour == "facilitating" || behaviour == "late_facilitating") return true;
  if (behaviour == "minimal" || behaviour == "oblivious") return false;
  return Json();
}

/// Who touched whom in one run: cause is "none", "robot_at_fault", "human_walked_in",
/// "robot_hit_wall", "unattributed" (a contact with a human whose cause the summary does not
/// give) or "no_run" (no summary).
inline Json contactOf(const Json* run) {
  using namespace detail;
  Json c;
  c["cause"] = "none";
  c["human_id"] = nullptr;
  c["t_s"] = nullptr;
  c["robot_speed_m_s"] = nullptr;
  if (run == nullptr) {
    c["cause"] = "no_run";
    return c;
  }
  const bool collision = text(field(run, "final_state")) == "COLLISION";
  const std::string why = text(field(run, "detail"));
  const Json* contact = field(run, "contact");
  if (contact != nullptr && contact->is_object()) {
    c["human_id"] = numberOrNull(field(contact, "human_id"));
    c["t_s"] = numberOrNull(field(contact, "t_s"));
    c["robot_speed_m_s"] = numberOrNull(field(contact, "robot_speed_m_s"));
    const Json fault = boolOrNull(field(contact, "robot_at_fault"));
    c["cause"] = fault.is_null() ? "unattributed"
                                 : (fault.get<bool>() ? "robot_at_fault" : "human_walked_in");
    return c;
  }
  if (!collision) return c;
  // A COLLISION without a human contact, or a summary without `contact`: world_sim's final
  // detail says "robot collided with a wall ..." or "... with human N ...".
  if (why.find("with a wall") != std::string::npos) {
    c["cause"] = "robot_hit_wall";
    return c;
  }
  c["cause"] = "unattributed";
  std::smatch m;
  static const std::regex kHuman("human ([0-9]+)");
  if (std::regex_search(why, m, kHuman)) c["human_id"] = std::stoi(m[1].str());
  return c;
}

/// Causes that fail the population: the robot may have driven into someone (or something).
inline bool isSafetyFailure(const std::string& cause) {
  return cause == "robot_at_fault" || cause == "robot_hit_wall" || cause == "unattributed";
}

/// population.json from the plan and the summary entries by run name (encounters and
/// baselines; a missing entry is a run that produced no summary).
inline Json aggregatePopulation(const Json& plan, const std::map<std::string, Json>& summaries) {
  using namespace detail;
  auto summaryOf = [&](const std::string& name) -> const Json* {
    auto it = summaries.find(name);
    return it == summaries.end() ? nullptr : &it->second;
  };
  Json runs = Json::array();
  std::map<std::string, int> outcomes;
  std::map<std::string, int> causes{
      {"robot_at_fault", 0}, {"human_walked_in", 0}, {"robot_hit_wall", 0}, {"unattributed", 0}};
  std::map<std::string, std::map<std::string, int>> causes_by_behaviour;
  struct Tally {
    int judged = 0, correct = 0, no_verdict = 0, judged_w = 0, correct_w = 0;
    // The interaction CM against each threshold the path assessor reports, whichever was in
    // force: the paper's fixed τ and τ judged against the room the human had (tau_mode).
    int judged_fixed = 0, correct_fixed = 0, judged_room = 0, correct_room = 0;
  };
  std::map<std::string, Tally> accuracy;
  std::map<std::string, std::vector<double>> cm_by_behaviour;
  std::vector<double> ratios;
  int failed_runs = 0, standstills = 0, goal_not_reached = 0;
  int goal_humans = 0, goal_judged = 0, goal_correct = 0;  // goal inference at round 1
  std::map<std::string, std::optional<double>> sums{
      {"docks", 0.0}, {"retreats", 0.0}, {"guard_steps", 0.0}};

  for (const auto& e : plan.at("encounters")) {
    const std::string name = e.at("name").get<std::string>();
    const Json* run = summaryOf(name);
    const Json* base = summaryOf(e.at("baseline").get<std::string>());
    Json r;
    r["name"] = name;
    r["scenario"] = e.at("scenario");
    r["layout"] = e.at("layout");
    r["width_m"] = e.at("width_m");
    const std::string outcome = run ? text(field(run, "final_state")) : "NO_SUMMARY";
    r["outcome"] = outcome.empty() ? "UNKNOWN" : outcome;
    ++outcomes[r["outcome"].get<std::string>()];
    if (!run) ++failed_runs;
    if (outcome == "STANDSTILL" || outcome == "TIME_LIMIT") ++standstills;
    r["detail"] = run ? Json(text(field(run, "detail"))) : Json();
    r["sim_time_s"] = numberOrNull(field(run, "sim_time_s"));

    Json contact = contactOf(run);
    const std::string cause = contact["cause"].get<std::string>();
    std::string contact_behaviour;
    if (contact["human_id"].is_number()) {
      for (const auto& h : e.at("humans"))
        if (h.at("id").get<double>() == contact["human_id"].get<double>())
          contact_behaviour = h.at("behaviour").get<std::string>();
    }
    contact["behaviour"] = contact_behaviour.empty() ? Json() : Json(contact_behaviour);
    if (causes.count(cause)) {
      ++causes[cause];
      ++causes_by_behaviour[contact_behaviour.empty() ? "(none)" : contact_behaviour][cause];
    }
    r["contact"] = std::move(contact);
    r["min_clearance_m"] = numberOrNull(field(run, "min_clearance_m"));
    r["min_clearance_t_s"] = numberOrNull(field(run, "min_clearance_t_s"));
    for (auto& [key, sum] : sums) {
      const Json v = numberOrNull(field(run, key.c_str()));
      r[key] = v;
      if (v.is_null())
        sum.reset();
      else if (sum)
        *sum += v.get<double>();
    }
    const double t_run = number(field(run, "robot_time_to_goal_s"));
    const double t_base = number(field(base, "robot_time_to_goal_s"));
    if (!std::isfinite(t_run)) ++goal_not_reached;
    r["robot_time_to_goal_s"] = std::isfinite(t_run) ? Json(t_run) : Json();
    r["baseline_time_to_goal_s"] = std::isfinite(t_base) ? Json(t_base) : Json();
    const double ratio = t_run / t_base;
    r["time_to_goal_ratio"] = std::isfinite(ratio) ? Json(ratio) : Json();
    if (std::isfinite(ratio)) ratios.push_back(ratio);

    Json humans = Json::array();
    for (const auto& h : e.at("humans")) {
      Json hr;
      hr["id"] = h.at("id");
      hr["role"] = h.at("role");
      const std::string behaviour = h.at("behaviour").get<std::string>();
      hr["behaviour"] = behaviour;
      hr["speed_m_s"] = h.at("speed_m_s");
      const Json* found = nullptr;
      const Json* list = field(run, "humans");
      if (list != nullptr && list->is_array())
        for (const auto& s : *list)
          if (number(field(&s, "id")) == h.at("id").get<double>()) found = &s;
      hr["cm_interaction_m"] = numberOrNull(field(found, "cm_interaction_m"));
      hr["is_contributing_interaction"] = boolOrNull(field(found, "is_contributing_interaction"));
      hr["cm_window_m"] = numberOrNull(field(found, "cm_window_m"));
      hr["is_contributing"] = boolOrNull(field(found, "is_contributing"));
      hr["room_m"] = numberOrNull(field(found, "room_m"));
      hr["tau_fixed_m"] = numberOrNull(field(found, "tau_fixed_m"));
      hr["tau_room_m"] = numberOrNull(field(found, "tau_room_m"));
      // Goals withheld: was the region planned with at round 1 the one the human walked to?
      const Json* gi = field(found, "goal_inference");
      hr["goal_correct_at_round1"] = boolOrNull(field(gi, "correct"));
      if (run != nullptr && h.at("role") != "same_way" && gi != nullptr && gi->is_object()) {
        ++goal_humans;
        const Json& c = hr["goal_correct_at_round1"];
        if (!c.is_null()) {
          ++goal_judged;
          goal_correct += c.get<bool>() ? 1 : 0;
        }
      }
      const Json expected = expectedContributing(behaviour);
      hr["expected_contributing"] = expected;
      // The oncoming humans are the assessed encounters; one walking the robot's way is not.
      if (run != nullptr && h.at("role") != "same_way") {
        if (!expected.is_null()) {
          Tally& t = accuracy[behaviour];
          const Json& v = hr["is_contributing_interaction"];
          if (v.is_null()) {
            ++t.no_verdict;
          } else {
            ++t.judged;
            t.correct += v == expected ? 1 : 0;
          }
          const Json& w = hr["is_contributing"];
          if (!w.is_null()) {
            ++t.judged_w;
            t.correct_w += w == expected ? 1 : 0;
          }
          const Json& cm = hr["cm_interaction_m"];
          // Paper §II-C: IsContributing = CM > τ, for each τ.
          auto judge = [&](const char* tau_key, int& judged, int& correct) {
            const Json& tau = hr[tau_key];
            if (!cm.is_number() || !tau.is_number()) return;
            ++judged;
            correct += Json(cm.get<double>() > tau.get<double>()) == expected ? 1 : 0;
          };
          judge("tau_fixed_m", t.judged_fixed, t.correct_fixed);
          judge("tau_room_m", t.judged_room, t.correct_room);
        }
        if (hr["cm_interaction_m"].is_number())
          cm_by_behaviour[behaviour].push_back(hr["cm_interaction_m"].get<double>());
      }
      humans.push_back(std::move(hr));
    }
    r["humans"] = std::move(humans);
    runs.push_back(std::move(r));
  }

  Json totals;
  totals["runs"] = plan.at("encounters").size();
  totals["failed_runs"] = failed_runs;
  Json oc = Json::object();
  for (const auto& [k, v] : outcomes) oc[k] = v;
  totals["outcomes"] = std::move(oc);
  totals["standstills"] = standstills;
  totals["goal_not_reached"] = goal_not_reached;
  Json cc = Json::object();
  int contacts = 0;
  for (const auto& [k, v] : causes) {
    cc[k] = v;
    contacts += v;
  }
  totals["contacts"] = contacts;
  totals["contacts_by_cause"] = std::move(cc);
  Json cb = Json::object();
  for (const auto& [beh, m] : causes_by_behaviour) {
    Json x = Json::object();
    for (const auto& [k, v] : m) x[k] = v;
    cb[beh] = std::move(x);
  }
  totals["contacts_by_behaviour"] = std::move(cb);
  int safety = 0;
  for (const auto& [k, v] : causes)
    if (isSafetyFailure(k)) safety += v;
  totals["robot_at_fault_or_unattributed"] = safety;
  for (const auto& [key, sum] : sums) totals[key] = sum ? Json(*sum) : Json();

  Json acc = Json::object();
  auto share = [](int correct, int judged) {
    return judged ? Json(static_cast<double>(correct) / judged) : Json();
  };
  int all_judged = 0, all_correct = 0, all_fixed = 0, all_fixed_ok = 0, all_room = 0,
      all_room_ok = 0;
  for (const char* b : {"facilitating", "late_facilitating", "minimal", "oblivious"}) {
    const Tally t = accuracy.count(b) ? accuracy.at(b) : Tally{};
    Json a;
    a["expected"] = expectedContributing(b);
    a["judged"] = t.judged;
    a["correct"] = t.correct;
    a["no_verdict"] = t.no_verdict;
    a["accuracy"] = share(t.correct, t.judged);
    a["accuracy_window"] = share(t.correct_w, t.judged_w);
    a["accuracy_fixed_tau"] = share(t.correct_fixed, t.judged_fixed);
    a["accuracy_room_tau"] = share(t.correct_room, t.judged_room);
    acc[b] = std::move(a);
    all_judged += t.judged;
    all_correct += t.correct;
    all_fixed += t.judged_fixed;
    all_fixed_ok += t.correct_fixed;
    all_room += t.judged_room;
    all_room_ok += t.correct_room;
  }
  acc["all"] = Json{{"judged", all_judged},
                    {"correct", all_correct},
                    {"accuracy", share(all_correct, all_judged)},
                    {"accuracy_fixed_tau", share(all_fixed_ok, all_fixed)},
                    {"accuracy_room_tau", share(all_room_ok, all_room)}};
  totals["is_contributing_accuracy"] = std::move(acc);
  // Only with goals withheld (population.sh --goals-withheld); humans without a first round or
  // an estimate by then are not judged.
  totals["goal_inference"] = Json{{"humans", goal_humans},
                                  {"judged", goal_judged},
                                  {"correct", goal_correct},
                                  {"accuracy_at_round1", share(goal_correct, goal_judged)}};

  std::vector<double> negatives = cm_by_behaviour["minimal"];
  negatives.insert(negatives.end(), cm_by_behaviour["oblivious"].begin(),
                   cm_by_behaviour["oblivious"].end());
  const double auc = mannWhitneyAuc(cm_by_behaviour["facilitating"], negatives);
  totals["cm_auc_facilitating_vs_minimal_oblivious"] =
      Json{{"auc", std::isfinite(auc) ? Json(auc) : Json()},
           {"positives", cm_by_behaviour["facilitating"].size()},
           {"negatives", negatives.size()}};
  Json cm_median = Json::object();
  for (const auto& [b, v] : cm_by_behaviour) cm_median[b] = median(v);
  totals["cm_interaction_median_m"] = std::move(cm_median);
  const double med = median(ratios);
  const double max =
      ratios.empty() ? std::nan("") : *std::max_element(ratios.begin(), ratios.end());
  totals["time_to_goal_ratio"] = Json{{"runs", ratios.size()},
                                      {"median", std::isfinite(med) ? Json(med) : Json()},
                                      {"max", std::isfinite(max) ? Json(max) : Json()}};

  Json doc;
  doc["format"] = kPopulationFormat;
  doc["seed"] = plan.at("seed");
  doc["totals"] = std::move(totals);
  doc["runs"] = std::move(runs);
  return doc;
}

/// True when the population fails: a contact with the robot at fault (or one it cannot clear).
inline bool populationFails(const Json& population) {
  return population.at("totals").at("robot_at_fault_or_unattributed").get<int>() > 0;
}

namespace detail {
inline std::string num(const Json& v, const char* format) {
  return v.is_number() ? fmt(format, v.get<double>()) : std::string("-");
}
inline std::string pad(std::string s, std::size_t w) {
  if (s.size() < w) s.append(w - s.size(), ' ');
  return s;
}
inline std::string shortBehaviour(const std::string& b) {
  if (b == "facilitating") return "fac";
  if (b == "late_facilitating") return "late";
  if (b == "minimal") return "min";
  if (b == "oblivious") return "obl";
  if (b == "social_force") return "sfm";
  if (b == "responsive") return "resp";
  return b;
}
inline std::string tri(const Json& v) {
  return v.is_boolean() ? (v.get<bool>() ? "T" : "F") : std::string("?");
}
}  // namespace detail

/// The plain-text table: one line per run, then the totals.
inline std::string formatTable(const Json& population) {
  using namespace detail;
  std::string s;
  s += "# coopnav population, seed " + population.at("seed").dump() + "\n";
  s += "# humans: id:behaviour(role) CM_interaction/IsContributing (T/F/? = unknown); roles h = "
       "head-on, f = follower, s = same way\n";
  s += pad("run", 9) + pad("layout", 16) + pad("outcome", 20) + pad("contact", 22) +
       pad("min_clr_m", 10) + pad("dock", 5) + pad("retr", 5) + pad("guard", 6) +
       pad("ttg_ratio", 10) + "humans\n";
  for (const auto& r : population.at("runs")) {
    const Json& c = r.at("contact");
    std::string contact = c.at("cause").get<std::string>();
    if (c.at("human_id").is_number()) contact += " h" + num(c.at("human_id"), "%.0f");
    std::string humans;
    for (const auto& h : r.at("humans")) {
      const std::string role = h.at("role").get<std::string>().substr(0, 1);
      humans += num(h.at("id"), "%.0f") + ":" + shortBehaviour(h.at("behaviour")) + "(" + role +
                ") " + num(h.at("cm_interaction_m"), "%.2f") + "/" +
                tri(h.at("is_contributing_interaction")) + "  ";
    }
    while (!humans.empty() && humans.back() == ' ') humans.pop_back();
    s += pad(r.at("name").get<std::string>(), 9) + pad(r.at("layout").get<std::string>(), 16) +
         pad(r.at("outcome").get<std::string>(), 20) + pad(contact, 22) +
         pad(num(r.at("min_clearance_m"), "%.3f"), 10) + pad(num(r.at("docks"), "%.0f"), 5) +
         pad(num(r.at("retreats"), "%.0f"), 5) + pad(num(r.at("guard_steps"), "%.0f"), 6) +
         pad(num(r.at("time_to_goal_ratio"), "%.2f"), 10) + humans + "\n";
  }
  const Json& t = population.at("totals");
  s += "\n# totals\n";
  s += "runs " + t.at("runs").dump() + ", without a summary " + t.at("failed_runs").dump() +
       ", standstills (STANDSTILL or TIME_LIMIT) " + t.at("standstills").dump() +
       ", robot not at its goal " + t.at("goal_not_reached").dump() + "\n";
  s += "outcomes:";
  for (const auto& [k, v] : t.at("outcomes").items()) s += " " + k + " " + v.dump();
  s += "\ncontacts " + t.at("contacts").dump() + ":";
  for (const auto& [k, v] : t.at("contacts_by_cause").items()) s += " " + k + " " + v.dump();
  s += "\n";
  for (const auto& [b, m] : t.at("contacts_by_behaviour").items()) {
    s += "  contacts with " + b + ":";
    for (const auto& [k, v] : m.items()) s += " " + k + " " + v.dump();
    s += "\n";
  }
  s += "robot at fault or unattributed: " + t.at("robot_at_fault_or_unattributed").dump() + "\n";
  s += "docks " + num(t.at("docks"), "%.0f") + ", retreats " + num(t.at("retreats"), "%.0f") +
       ", guard steps " + num(t.at("guard_steps"), "%.0f") + " (- = not in the summaries)\n";
  s += "IsContributing (interaction CM, oncoming humans) accuracy by behaviour:\n";
  for (const auto& [b, a] : t.at("is_contributing_accuracy").items()) {
    if (b == "all") continue;
    s += "  " + pad(b, 18) + "expected " + tri(a.at("expected")) + "  correct " +
         a.at("correct").dump() + "/" + a.at("judged").dump() + " = " +
         num(a.at("accuracy"), "%.3f") + "  (window CM: " + num(a.at("accuracy_window"), "%.3f") +
         "), no verdict " + a.at("no_verdict").dump() + "; fixed tau " +
         num(a.at("accuracy_fixed_tau"), "%.3f") + ", room tau " +
         num(a.at("accuracy_room_tau"), "%.3f") + "\n";
  }
  const Json& all = t.at("is_contributing_accuracy").at("all");
  s += "  all               correct " + all.at("correct").dump() + "/" + all.at("judged").dump() +
       " = " + num(all.at("accuracy"), "%.3f") + "; fixed tau " +
       num(all.at("accuracy_fixed_tau"), "%.3f") + ", room tau " +
       num(all.at("accuracy_room_tau"), "%.3f") + "\n";
  const Json& auc = t.at("cm_auc_facilitating_vs_minimal_oblivious");
  s += "AUC of CM, facilitating (" + auc.at("positives").dump() + ") vs minimal/oblivious (" +
       auc.at("negatives").dump() + "): " + num(auc.at("auc"), "%.3f") + "\n";
  s += "median CM by behaviour:";
  for (const auto& [b, v] : t.at("cm_interaction_median_m").items())
    s += " " + b + " " + num(v, "%.3f");
  const Json& ttg = t.at("time_to_goal_ratio");
  s += "\ntime to goal against the run without humans: median " + num(ttg.at("median"), "%.2f") +
       ", max " + num(ttg.at("max"), "%.2f") + " over " + ttg.at("runs").dump() + " runs\n";
  if (t.contains("goal_inference") && t.at("goal_inference").at("humans").get<int>() > 0) {
    const Json& gi = t.at("goal_inference");
    s += "goal inference (goals withheld): region planned with at round 1 = the one walked to, " +
         gi.at("correct").dump() + "/" + gi.at("judged").dump() + " = " +
         num(gi.at("accuracy_at_round1"), "%.3f") +
         " (oncoming humans with an estimate: " + gi.at("humans").dump() + ")\n";
  }
  return s;
}

}  // namespace coopnav::population
