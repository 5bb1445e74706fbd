#pragma once
/// @file The population's plan (what was generated) and its result (population.json and the
/// plain-text table) from each run's summary.json entry (tools/ctl/README.md "summary.json").
/// Header-only (see generator.hpp); JSON values are nlohmann::ordered_json as in coopnav_ctl.
///
/// Fields of summary.json this reads beyond the long-standing ones (`final_state`, `detail`,
/// `min_clearance_m`, `robot_time_to_goal_s`, `sim_time_s`, `humans[].cm_interaction_m` ...):
/// `contact` (null or {human_id, t_s, robot_at_fault, robot_speed_m_s}), `min_clearance_t_s`,
/// `docks`, `retreats`, `guard_steps`, `dialogue_checks` (said, addressed and the lists of
/// words said to someone not being crossed, contradictions, groups told twice). A missing field
/// is unknown (null in the output), so the tool reads summaries written before and after those
/// fields exist.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "generator.hpp"
#include "stats.hpp"

namespace coopnav::population {

using Json = nlohmann::ordered_json;

inline constexpr const char* kPlanFormat = "coopnav-population-plan/1";
inline constexpr const char* kPopulationFormat = "coopnav-population/1";

/// Options of a generated population that its plan records (only when set: a plain
/// population's plan.json is what it was before they existed).
struct PlanOptions {
  std::string head_on_behaviour;  ///< generate --behaviour: every head-on human's behaviour
  bool muted_twins{false};        ///< generate --cue-effect: every encounter also runs muted
  bool crowd{false};              ///< generate --crowd: crowd encounters (generateCrowdPopulation)
  /// generate --slower-ahead / --pause: every encounter's widened variant is a slower person
  /// ahead / one of its people pauses (a study of them; the other draws stay the seed's).
  bool slower_ahead{false};
  bool pause{false};
  /// generate --max-width-m: only the layouts no wider than this [m] (0: all).
  double max_width_m{0.0};
};

/// The generator's ranges with the options' forced draws.
inline Ranges rangesOf(const PlanOptions& options) {
  Ranges r;
  if (options.slower_ahead) {
    r.abreast_p = 0.0;
    r.slower_ahead_p = 1.0;
  }
  if (options.pause) r.pause_p = 1.0;
  if (options.max_width_m > 0.0) r.max_width_m = options.max_width_m;
  return r;
}

/// The run of an encounter with the dialogue manager muted (same scenario file and seed).
inline std::string mutedTwinName(const std::string& name) { return name + "_muted"; }

/// What the generator wrote, for the aggregation and for a reader of the run directory.
inline Json planJson(const std::vector<Encounter>& encounters, std::uint64_t seed,
                     const PlanOptions& options = {}) {
  Json plan;
  plan["format"] = kPlanFormat;
  plan["seed"] = seed;
  plan["n"] = encounters.size();
  if (!options.head_on_behaviour.empty()) plan["head_on_behaviour"] = options.head_on_behaviour;
  if (options.muted_twins) plan["cue_effect"] = true;
  if (options.crowd) plan["crowd"] = true;
  if (options.slower_ahead) plan["slower_ahead"] = true;
  if (options.pause) plan["pause"] = true;
  if (options.max_width_m > 0.0) plan["max_width_m"] = options.max_width_m;
  Json list = Json::array();
  std::set<std::string> baselines;
  Json base_list = Json::array();
  for (const auto& e : encounters) {
    Json j;
    j["name"] = e.name;
    j["scenario"] = "scenarios/" + e.name + ".yaml";
    j["baseline"] = baselineName(e);
    j["layout"] = e.layout.key;
    j["width_m"] = e.layout.width_m;
    if (!e.kind.empty()) j["kind"] = e.kind;
    if (e.kind.empty()) {
      j["robot_kinematics"] = e.differential ? "differential" : "holonomic";
      j["tracker_noise"] = e.tracker_noise;
      j["variant"] = e.variant;
      int paused = 0;
      for (const auto& h : e.humans)
        if (h.pause_duration_s > 0.0) paused = h.id;
      j["paused_human"] = paused == 0 ? Json() : Json(paused);
    }
    if (options.muted_twins) j["muted_twin"] = mutedTwinName(e.name);
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
      if (h.pause_duration_s > 0.0)
        hj["pause"] = {{"after_m", h.pause_after_m}, {"duration_s", h.pause_duration_s}};
      if (!e.kind.empty()) hj["group"] = h.group;
      humans.push_back(std::move(hj));
    }
    j["humans"] = std::move(humans);
    list.push_back(std::move(j));
    if (baselines.insert(baselineName(e)).second) {
      Json b;
      b["name"] = baselineName(e);
      b["scenario"] = "scenarios/" + baselineName(e) + ".yaml";
      b["layout"] = e.layout.key;
      base_list.push_back(std::move(b));
    }
  }
  plan["encounters"] = std::move(list);
  plan["baselines"] = std::move(base_list);
  return plan;
}

namespace detail {

/// The summary entry of run `name`; nullptr for a run that produced none.
inline const Json* findRun(const std::map<std::string, Json>& summaries, const std::string& name) {
  auto it = summaries.find(name);
  return it == summaries.end() ? nullptr : &it->second;
}

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

/// A run is a stalemate when it ends in a standstill or the time limit, or when robot and person
/// wait for each other longer than this [s] (summary.json max_mutual_wait_s).
inline constexpr double kStalemateMutualWait_s = 10.0;

/// Roles of the assessed encounters: people coming towards the robot. Not one walking its way
/// (same_way), across its path at a junction (crossing) or standing (standing).
inline bool isOncomingRole(const std::string& role) {
  return role == "head_on" || role == "follower";
}

/// The dialogue checks of one run (summary.json `dialogue_checks`, read from the log alone):
/// {said, addressed, unaddressed_with_several (said - addressed when the scenario has several
/// people, else null: alone the paper's words are said unaddressed), said_to_not_crossing,
/// contradictions, told_twice, action_contradicts_words (the summary's lists), fails}; null when
/// the run has no summary or its summary no checks (older summaries: unknown, not failing).
inline Json dialogueChecksOf(const Json* run, std::size_t humans) {
  const Json* c = detail::field(run, "dialogue_checks");
  if (c == nullptr || !c->is_object()) return Json();
  Json d;
  const Json said = detail::numberOrNull(detail::field(c, "said"));
  const Json addressed = detail::numberOrNull(detail::field(c, "addressed"));
  d["said"] = said;
  d["addressed"] = addressed;
  d["unaddressed_with_several"] =
      humans > 1 && said.is_number() && addressed.is_number()
          ? Json(said.get<std::int64_t>() - addressed.get<std::int64_t>())
          : Json();
  bool fails = d["unaddressed_with_several"].is_number() &&
               d["unaddressed_with_several"].get<std::int64_t>() > 0;
  for (const char* key :
       {"said_to_not_crossing", "contradictions", "told_twice", "action_contradicts_words"}) {
    const Json* list = detail::field(c, key);
    d[key] = list != nullptr && list->is_array() ? *list : Json::array();
    fails = fails || !d[key].empty();
  }
  d["fails"] = fails;
  return d;
}

/// The verdict expected of a behaviour (docs/population.md): facilitating and late_facilitating
/// contribute, minimal and oblivious do not; social_force and responsive: no expectation (null).
inline Json expectedContributing(const std::string& behaviour) {
  if (behaviour == "facilitating" || behaviour == "late_facilitating") return true;
  if (behaviour == "minimal" || behaviour == "oblivious") return false;
  return Json();
}

/// Who touched whom in one run: cause is "none", "robot_at_fault", "human_walked_in",
/// "robot_hit_wall" (a COLLISION without a robot-human contact: summary.json's `contact` is null,
/// so the robot hit a wall), "unattributed" (a COLLISION in a summary written before `contact`
/// existed: whom or what it hit is not known) or "no_run" (no summary). Read from the summary's
/// fields only, never from its `detail` sentence.
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
  if (text(field(run, "final_state")) != "COLLISION") return c;
  c["cause"] = contact != nullptr ? "robot_hit_wall" : "unattributed";
  return c;
}

/// Causes that fail the population: the robot may have driven into someone (or something).
inline bool isSafetyFailure(const std::string& cause) {
  return cause == "robot_at_fault" || cause == "robot_hit_wall" || cause == "unattributed";
}

// ---- The spoken cue's effect: each encounter spoken to and with the dialogue manager muted.

/// What each human heard, from world_sim's cue outcomes (its `cue_outcomes_file`, one JSON
/// object a line: daemons/world_sim/README.md "Cue outcomes"), for the cue-effect section:
/// [{"id", "cues", "heard", "complied", "not_heard", "not_complied"}] in id order. Cues to a
/// human whose behaviour does not react to words, and thanks (nothing to comply with), are left
/// out. coopnav_population adds it to a run's summary entry as "hearing"; summary.json itself
/// does not have it. A last line without its newline (a run stopped while writing) is left out;
/// any other line that is not a cue outcome throws std::runtime_error naming it.
inline Json hearingFromCueOutcomes(const std::string& jsonl) {
  struct Counts {
    int complied = 0, not_complied = 0, not_heard = 0;
  };
  std::map<std::int64_t, Counts> counts;
  std::size_t at = 0;
  for (int line = 1; at < jsonl.size(); ++line) {
    const std::size_t end = jsonl.find('\n', at);
    if (end == std::string::npos) break;
    const std::string text = jsonl.substr(at, end - at);
    at = end + 1;
    if (text.empty()) continue;
    const Json o = Json::parse(text, nullptr, false);
    const auto flag = [&](const char* key) {
      const auto it = o.is_object() ? o.find(key) : o.end();
      if (it == o.end() || !it->is_boolean())
        throw std::runtime_error("cue outcomes line " + std::to_string(line) + ": no boolean '" +
                                 key + "'");
      return it->get<bool>();
    };
    if (!o.is_object() || !o.contains("human_id") || !o.at("human_id").is_number_integer() ||
        !o.contains("cue") || !o.at("cue").is_string())
      throw std::runtime_error("cue outcomes line " + std::to_string(line) +
                               ": not a cue outcome (human_id, cue)");
    if (!flag("responds") || o.at("cue") == "thank") continue;
    Counts& c = counts[o.at("human_id").get<std::int64_t>()];
    if (!flag("heard"))
      ++c.not_heard;
    else if (flag("complies"))
      ++c.complied;
    else
      ++c.not_complied;
  }
  Json out = Json::array();
  for (const auto& [id, c] : counts)
    out.push_back(Json{{"id", id},
                       {"cues", c.complied + c.not_complied + c.not_heard},
                       {"heard", c.complied + c.not_complied},
                       {"complied", c.complied},
                       {"not_heard", c.not_heard},
                       {"not_complied", c.not_complied}});
  return out;
}

namespace detail {

/// The entry of human `id` in a summary entry's humans; nullptr when absent.
inline const Json* humanOf(const Json* run, double id) {
  const Json* list = field(run, "humans");
  if (list == nullptr || !list->is_array()) return nullptr;
  for (const auto& h : *list)
    if (number(field(&h, "id")) == id) return &h;
  return nullptr;
}

inline Json medianOrNull(const std::vector<double>& v) {
  const double m = median(v);
  return std::isfinite(m) ? Json(m) : Json();
}
inline Json meanOrNull(const std::vector<double>& v) {
  const double m = mean(v);
  return std::isfinite(m) ? Json(m) : Json();
}
inline Json minOrNull(const std::vector<double>& v) {
  return v.empty() ? Json() : Json(*std::min_element(v.begin(), v.end()));
}

}  // namespace detail

/// One half of a pair (speaking or muted) for the head-on human `head_id`: outcome, its
/// interaction CM and verdict, whether the robot docked, time to goal, min clearance, the
/// contact's cause, the cues decided for it (THANK aside: no cue to act on) by delivery, the said
/// cues' lead before t_CROSS (summary `lead_s`), and what it heard (null without cue outcomes).
inline Json cueSide(const Json* run, double head_id) {
  using namespace detail;
  Json s;
  const std::string outcome = run ? text(field(run, "final_state")) : "NO_SUMMARY";
  s["outcome"] = outcome.empty() ? "UNKNOWN" : outcome;
  const Json* h = humanOf(run, head_id);
  s["cm_interaction_m"] = numberOrNull(field(h, "cm_interaction_m"));
  s["is_contributing_interaction"] = boolOrNull(field(h, "is_contributing_interaction"));
  Json docked = boolOrNull(field(run, "docked"));
  if (docked.is_null() && numberOrNull(field(run, "docks")).is_number())
    docked = number(field(run, "docks")) > 0;
  s["docked"] = docked;
  s["robot_time_to_goal_s"] = numberOrNull(field(run, "robot_time_to_goal_s"));
  s["min_clearance_m"] = numberOrNull(field(run, "min_clearance_m"));
  s["contact"] = contactOf(run)["cause"];
  int said = 0, too_late = 0, muted = 0;
  Json leads = Json::array();
  const Json* transcript = field(h, "transcript");
  if (transcript != nullptr && transcript->is_array()) {
    for (const auto& e : *transcript) {
      if (text(field(&e, "kind")) != "say" || text(field(&e, "act")) == "THANK") continue;
      // A summary from before deliveries has none: everything it lists was said.
      const std::string delivery = text(field(&e, "delivery"));
      if (delivery == "muted") {
        ++muted;
      } else if (delivery == "too_late") {
        ++too_late;
      } else {
        ++said;
        const Json lead = numberOrNull(field(&e, "lead_s"));
        if (lead.is_number()) leads.push_back(lead);
      }
    }
  }
  s["cues_said"] = said;
  s["cues_too_late"] = too_late;
  s["cues_muted"] = muted;
  s["lead_s"] = std::move(leads);
  const Json* hearing = field(run, "hearing");
  Json heard, complied;
  if (hearing != nullptr && hearing->is_array()) {
    heard = 0;
    complied = 0;
    for (const auto& x : *hearing)
      if (number(field(&x, "id")) == head_id) {
        heard = numberOrNull(field(&x, "heard"));
        complied = numberOrNull(field(&x, "complied"));
      }
  }
  s["heard"] = std::move(heard);
  s["complied"] = std::move(complied);
  return s;
}

/// The overall figures of a set of pairs (cueEffect's records), over the pairs whose two runs
/// both left a summary. CM: paired over the pairs where both have one; the difference is
/// speaking − muted, with a percentile bootstrap 95 % interval of its mean (2000 resamples, a
/// fixed seed) and an exact sign test. Docks avoided: muted docked and speaking did not; added:
/// the reverse.
inline Json cueEffectGroup(const std::vector<const Json*>& pairs) {
  using namespace detail;
  int both = 0, cm_pairs = 0, greater = 0, smaller = 0, ties = 0;
  std::vector<double> cm_s, cm_m, cm_d, ttg_s, ttg_m, ttg_d, clr_s, clr_m, leads;
  int dock_s = 0, dock_m = 0, avoided = 0, added = 0, docks_known = 0;
  int not_reached_s = 0, not_reached_m = 0, contacts_s = 0, contacts_m = 0, fault_s = 0,
      fault_m = 0, contrib_s = 0, contrib_m = 0, judged_s = 0, judged_m = 0;
  int said = 0, too_late = 0, with_hearing = 0, heard = 0, complied = 0;
  for (const Json* p : pairs) {
    const Json& sp = p->at("speaking");
    const Json& mu = p->at("muted");
    if (sp.at("outcome") == "NO_SUMMARY" || mu.at("outcome") == "NO_SUMMARY") continue;
    ++both;
    if (sp.at("cm_interaction_m").is_number() && mu.at("cm_interaction_m").is_number()) {
      ++cm_pairs;
      const double a = sp.at("cm_interaction_m").get<double>();
      const double b = mu.at("cm_interaction_m").get<double>();
      cm_s.push_back(a);
      cm_m.push_back(b);
      cm_d.push_back(a - b);
      (a > b ? greater : (a < b ? smaller : ties)) += 1;
    }
    if (sp.at("docked").is_boolean() && mu.at("docked").is_boolean()) {
      ++docks_known;
      const bool ds = sp.at("docked").get<bool>(), dm = mu.at("docked").get<bool>();
      dock_s += ds ? 1 : 0;
      dock_m += dm ? 1 : 0;
      avoided += dm && !ds ? 1 : 0;
      added += ds && !dm ? 1 : 0;
    }
    const Json& ts = sp.at("robot_time_to_goal_s");
    const Json& tm = mu.at("robot_time_to_goal_s");
    if (ts.is_number())
      ttg_s.push_back(ts.get<double>());
    else
      ++not_reached_s;
    if (tm.is_number())
      ttg_m.push_back(tm.get<double>());
    else
      ++not_reached_m;
    if (ts.is_number() && tm.is_number()) ttg_d.push_back(ts.get<double>() - tm.get<double>());
    if (sp.at("min_clearance_m").is_number())
      clr_s.push_back(sp.at("min_clearance_m").get<double>());
    if (mu.at("min_clearance_m").is_number())
      clr_m.push_back(mu.at("min_clearance_m").get<double>());
    const std::string cs = sp.at("contact").get<std::string>();
    const std::string cm = mu.at("contact").get<std::string>();
    contacts_s += cs != "none" && cs != "no_run" ? 1 : 0;
    contacts_m += cm != "none" && cm != "no_run" ? 1 : 0;
    fault_s += isSafetyFailure(cs) ? 1 : 0;
    fault_m += isSafetyFailure(cm) ? 1 : 0;
    if (sp.at("is_contributing_interaction").is_boolean()) {
      ++judged_s;
      contrib_s += sp.at("is_contributing_interaction").get<bool>() ? 1 : 0;
    }
    if (mu.at("is_contributing_interaction").is_boolean()) {
      ++judged_m;
      contrib_m += mu.at("is_contributing_interaction").get<bool>() ? 1 : 0;
    }
    said += sp.at("cues_said").get<int>();
    too_late += sp.at("cues_too_late").get<int>();
    for (const auto& l : sp.at("lead_s")) leads.push_back(l.get<double>());
    if (sp.at("heard").is_number()) {
      ++with_hearing;
      heard += sp.at("heard").get<int>();
      complied += sp.at("complied").get<int>();
    }
  }
  Json g;
  g["pairs"] = pairs.size();
  g["pairs_run"] = both;
  Rng rng(0xC0E0EFFEC7ULL);
  const auto ci = bootstrapMeanInterval(cm_d, 0.95, 2000, rng);
  g["cm"] = Json{
      {"pairs", cm_pairs},
      {"mean_speaking_m", meanOrNull(cm_s)},
      {"mean_muted_m", meanOrNull(cm_m)},
      {"median_speaking_m", medianOrNull(cm_s)},
      {"median_muted_m", medianOrNull(cm_m)},
      {"mean_difference_m", meanOrNull(cm_d)},
      {"difference_ci95_m", std::isfinite(ci.first) ? Json::array({ci.first, ci.second}) : Json()},
      {"speaking_higher", greater},
      {"muted_higher", smaller},
      {"ties", ties},
      {"sign_test_p", cm_pairs ? Json(signTestP(greater, smaller)) : Json()},
      {"contributing_speaking", contrib_s},
      {"judged_speaking", judged_s},
      {"contributing_muted", contrib_m},
      {"judged_muted", judged_m}};
  g["docked"] = Json{{"pairs", docks_known},
                     {"speaking", dock_s},
                     {"muted", dock_m},
                     {"avoided", avoided},
                     {"added", added}};
  g["time_to_goal"] = Json{{"median_speaking_s", medianOrNull(ttg_s)},
                           {"median_muted_s", medianOrNull(ttg_m)},
                           {"median_difference_s", medianOrNull(ttg_d)},
                           {"not_reached_speaking", not_reached_s},
                           {"not_reached_muted", not_reached_m}};
  g["min_clearance"] = Json{{"min_speaking_m", minOrNull(clr_s)},
                            {"median_speaking_m", medianOrNull(clr_s)},
                            {"min_muted_m", minOrNull(clr_m)},
                            {"median_muted_m", medianOrNull(clr_m)}};
  g["contacts"] = Json{{"speaking", contacts_s},
                       {"muted", contacts_m},
                       {"robot_at_fault_or_unattributed_speaking", fault_s},
                       {"robot_at_fault_or_unattributed_muted", fault_m}};
  g["cues"] = Json{{"said", said},
                   {"too_late", too_late},
                   {"lead_median_s", medianOrNull(leads)},
                   {"lead_min_s", minOrNull(leads)}};
  g["hearing"] = with_hearing
                     ? Json{{"runs", with_hearing}, {"heard", heard}, {"complied", complied}}
                     : Json();
  return g;
}

/// The cue-effect section of population.json (null when the plan has no muted twins): one record
/// per encounter (its head-on human, speaking against muted), the muted half's failures (they
/// count towards the exit code as the speaking half's do), the figures over all pairs and per
/// layout (corridor width).
inline Json cueEffect(const Json& plan, const std::map<std::string, Json>& summaries) {
  using namespace detail;
  auto summaryOf = [&](const std::string& name) { return findRun(summaries, name); };
  Json records = Json::array();
  int muted_failed = 0;
  std::map<std::string, int> muted_causes;
  for (const auto& e : plan.at("encounters")) {
    if (!e.contains("muted_twin")) continue;
    const std::string name = e.at("name").get<std::string>();
    const std::string twin = e.at("muted_twin").get<std::string>();
    double head_id = std::nan("");
    for (const auto& h : e.at("humans"))
      if (h.at("role") == "head_on") head_id = h.at("id").get<double>();
    const Json* sp_run = summaryOf(name);
    const Json* mu_run = summaryOf(twin);
    if (mu_run == nullptr) ++muted_failed;
    Json r;
    r["name"] = name;
    r["muted_run"] = twin;
    r["layout"] = e.at("layout");
    r["width_m"] = e.at("width_m");
    r["head_on_id"] = std::isfinite(head_id) ? Json(head_id) : Json();
    r["speaking"] = cueSide(sp_run, head_id);
    r["muted"] = cueSide(mu_run, head_id);
    const Json& a = r["speaking"]["cm_interaction_m"];
    const Json& b = r["muted"]["cm_interaction_m"];
    r["cm_difference_m"] =
        a.is_number() && b.is_number() ? Json(a.get<double>() - b.get<double>()) : Json();
    const Json& ds = r["speaking"]["docked"];
    const Json& dm = r["muted"]["docked"];
    r["dock"] = !ds.is_boolean() || !dm.is_boolean() ? Json()
                : ds == dm                           ? Json("same")
                : dm.get<bool>()                     ? Json("avoided")
                                                     : Json("added");
    const std::string cause = r["muted"]["contact"].get<std::string>();
    if (cause != "none" && cause != "no_run") ++muted_causes[cause];
    records.push_back(std::move(r));
  }
  if (records.empty()) return Json();
  std::vector<const Json*> all;
  std::map<std::string, std::vector<const Json*>> by_layout;
  for (const auto& r : records) {
    all.push_back(&r);
    by_layout[r.at("layout").get<std::string>()].push_back(&r);
  }
  int safety = 0;
  Json causes = Json::object();
  for (const auto& [k, v] : muted_causes) {
    causes[k] = v;
    if (isSafetyFailure(k)) safety += v;
  }
  Json c;
  c["pairs"] = records.size();
  c["muted_failed_runs"] = muted_failed;
  c["muted_contacts_by_cause"] = std::move(causes);
  c["muted_robot_at_fault_or_unattributed"] = safety;
  c["overall"] = cueEffectGroup(all);
  Json layouts = Json::object();
  for (const auto& [key, list] : by_layout) {
    Json g = cueEffectGroup(list);
    g["width_m"] = list.front()->at("width_m");
    layouts[key] = std::move(g);
  }
  c["by_layout"] = std::move(layouts);
  c["encounters"] = std::move(records);
  return c;
}

/// population.json from the plan and the summary entries by run name (encounters and
/// baselines; a missing entry is a run that produced no summary).
inline Json aggregatePopulation(const Json& plan, const std::map<std::string, Json>& summaries) {
  using namespace detail;
  auto summaryOf = [&](const std::string& name) { return findRun(summaries, name); };
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
  int failed_runs = 0, standstills = 0, goal_not_reached = 0, stalemates = 0;
  std::vector<double> mutual_waits, stalled;
  int goal_humans = 0, goal_judged = 0, goal_correct = 0;  // goal inference at round 1
  std::map<std::string, std::optional<double>> sums{
      {"docks", 0.0}, {"retreats", 0.0}, {"guard_steps", 0.0}};
  struct DialogueTally {
    int checked = 0, without = 0, not_crossing = 0, contradictions = 0, told_twice = 0,
        unaddressed_runs = 0, failing = 0, action_words = 0;
    std::int64_t said = 0, addressed = 0, unaddressed = 0;
  } dlg;
  // Crowds: the safety figures and the checks per kind of encounter.
  struct KindTally {
    int runs = 0, without_summary = 0, goal_reached = 0, contacts = 0, safety = 0,
        dialogue_failing = 0;
    std::vector<double> clearances;
  };
  std::map<std::string, KindTally> by_kind;

  for (const auto& e : plan.at("encounters")) {
    const std::string name = e.at("name").get<std::string>();
    const Json* run = summaryOf(name);
    const Json* base = summaryOf(e.at("baseline").get<std::string>());
    Json r;
    r["name"] = name;
    r["scenario"] = e.at("scenario");
    r["layout"] = e.at("layout");
    r["width_m"] = e.at("width_m");
    if (e.contains("kind")) r["kind"] = e.at("kind");
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
    for (const char* k : {"robot_kinematics", "tracker_noise", "variant", "paused_human"})
      if (e.contains(k)) r[k] = e.at(k);
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
    // Progress (summary.json from coopnav_ctl summarize: tools/ctl/progress_metrics.hpp).
    r["stalled_s"] = numberOrNull(field(run, "stalled_s"));
    r["max_mutual_wait_s"] = numberOrNull(field(run, "max_mutual_wait_s"));
    const double wait_s = number(field(run, "max_mutual_wait_s"));
    if (std::isfinite(wait_s)) mutual_waits.push_back(wait_s);
    if (const double st = number(field(run, "stalled_s")); std::isfinite(st)) stalled.push_back(st);
    const bool stalemate = outcome == "STANDSTILL" || outcome == "TIME_LIMIT" ||
                           (std::isfinite(wait_s) && wait_s > kStalemateMutualWait_s);
    r["stalemate"] = stalemate;
    stalemates += stalemate ? 1 : 0;
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
      if (run != nullptr && isOncomingRole(h.at("role").get<std::string>()) && gi != nullptr &&
          gi->is_object()) {
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
      if (run != nullptr && isOncomingRole(h.at("role").get<std::string>())) {
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

    Json checks = dialogueChecksOf(run, e.at("humans").size());
    if (run != nullptr && checks.is_null()) ++dlg.without;
    if (checks.is_object()) {
      ++dlg.checked;
      dlg.said += checks["said"].is_number() ? checks["said"].get<std::int64_t>() : 0;
      dlg.addressed +=
          checks["addressed"].is_number() ? checks["addressed"].get<std::int64_t>() : 0;
      dlg.not_crossing += checks["said_to_not_crossing"].empty() ? 0 : 1;
      dlg.contradictions += checks["contradictions"].empty() ? 0 : 1;
      dlg.told_twice += checks["told_twice"].empty() ? 0 : 1;
      dlg.action_words += checks["action_contradicts_words"].empty() ? 0 : 1;
      const Json& u = checks["unaddressed_with_several"];
      if (u.is_number() && u.get<std::int64_t>() > 0) {
        ++dlg.unaddressed_runs;
        dlg.unaddressed += u.get<std::int64_t>();
      }
      dlg.failing += checks["fails"].get<bool>() ? 1 : 0;
    }
    if (e.contains("kind")) {
      KindTally& k = by_kind[e.at("kind").get<std::string>()];
      ++k.runs;
      k.without_summary += run == nullptr ? 1 : 0;
      k.goal_reached += outcome == "GOAL_REACHED" ? 1 : 0;
      k.contacts += cause != "none" && cause != "no_run" ? 1 : 0;
      k.safety += isSafetyFailure(cause) ? 1 : 0;
      k.dialogue_failing += checks.is_object() && checks["fails"].get<bool>() ? 1 : 0;
      if (r["min_clearance_m"].is_number())
        k.clearances.push_back(r["min_clearance_m"].get<double>());
    }
    r["dialogue_checks"] = std::move(checks);
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
  const double p95 = quantile(ratios, 0.95);
  // A run that never reached its goal (a stalemate, a contact that ended it) took unboundedly
  // long: counted so, the p95 of every run is unbounded (null) once such runs exceed 5 %.
  std::vector<double> all_runs = ratios;
  all_runs.insert(all_runs.end(), static_cast<std::size_t>(goal_not_reached),
                  std::numeric_limits<double>::infinity());
  std::sort(all_runs.begin(), all_runs.end());
  const double p95_all =
      all_runs.empty() ? std::nan("")
                       : all_runs[std::min(all_runs.size(),
                                           std::max<std::size_t>(
                                               static_cast<std::size_t>(std::ceil(
                                                   0.95 * static_cast<double>(all_runs.size()))),
                                               1)) -
                                  1];
  totals["time_to_goal_ratio"] =
      Json{{"runs", ratios.size()},
           {"median", std::isfinite(med) ? Json(med) : Json()},
           {"p95", std::isfinite(p95) ? Json(p95) : Json()},
           {"max", std::isfinite(max) ? Json(max) : Json()},
           {"runs_goal_not_reached", goal_not_reached},
           {"p95_all_runs", std::isfinite(p95_all) ? Json(p95_all) : Json()}};
  auto maxOf = [](const std::vector<double>& v) {
    return v.empty() ? Json() : Json(*std::max_element(v.begin(), v.end()));
  };
  totals["stalemates"] = stalemates;
  totals["max_mutual_wait_s"] = maxOf(mutual_waits);
  totals["mutual_waits_over_limit"] =
      std::count_if(mutual_waits.begin(), mutual_waits.end(),
                    [](double w) { return w > kStalemateMutualWait_s; });
  const double stalled_median = median(stalled);
  totals["stalled_s"] =
      Json{{"median", std::isfinite(stalled_median) ? Json(stalled_median) : Json()},
           {"max", maxOf(stalled)}};
  totals["dialogue_checks"] = Json{{"runs_checked", dlg.checked},
                                   {"runs_without_checks", dlg.without},
                                   {"said", dlg.said},
                                   {"addressed", dlg.addressed},
                                   {"runs_said_to_not_crossing", dlg.not_crossing},
                                   {"runs_contradictions", dlg.contradictions},
                                   {"runs_told_twice", dlg.told_twice},
                                   {"runs_action_contradicts_words", dlg.action_words},
                                   {"runs_unaddressed_with_several", dlg.unaddressed_runs},
                                   {"sentences_unaddressed_with_several", dlg.unaddressed},
                                   {"failing_runs", dlg.failing}};
  if (plan.value("crowd", false)) {
    Json kinds = Json::object();
    for (const auto& [kind, k] : by_kind)
      kinds[kind] = Json{{"runs", k.runs},
                         {"without_summary", k.without_summary},
                         {"goal_reached", k.goal_reached},
                         {"contacts", k.contacts},
                         {"robot_at_fault_or_unattributed", k.safety},
                         {"min_clearance_min_m", minOrNull(k.clearances)},
                         {"min_clearance_median_m", medianOrNull(k.clearances)},
                         {"dialogue_failing_runs", k.dialogue_failing}};
    totals["by_kind"] = std::move(kinds);
  }

  Json doc;
  doc["format"] = kPopulationFormat;
  doc["seed"] = plan.at("seed");
  doc["totals"] = std::move(totals);
  doc["runs"] = std::move(runs);
  // Only with muted twins (population.sh --cue-effect).
  if (Json cue = cueEffect(plan, summaries); !cue.is_null()) doc["cue_effect"] = std::move(cue);
  return doc;
}

/// True when the population fails: a contact with the robot at fault (or one it cannot clear),
/// in an encounter or in its muted twin.
inline bool populationFails(const Json& population) {
  const Json* cue = detail::field(&population, "cue_effect");
  const int muted = cue ? cue->at("muted_robot_at_fault_or_unattributed").get<int>() : 0;
  return population.at("totals").at("robot_at_fault_or_unattributed").get<int>() + muted > 0;
}

/// Runs whose dialogue checks failed (words to someone not being crossed, a contradiction, a
/// group told twice, or a sentence not addressed while several people were there).
inline int dialogueFailingRuns(const Json& population) {
  const Json* c = detail::field(&population.at("totals"), "dialogue_checks");
  return c ? c->at("failing_runs").get<int>() : 0;
}

/// Encounters that ran to their end without progress or safety: a standstill, the time limit, a
/// mutual wait over kStalemateMutualWait_s or any contact (a human walking into the robot too: the
/// population fails on it, though with exit code 1 only when the robot was at fault). One line per
/// run: its name and why.
inline std::vector<std::string> runsEndedBadly(const Json& population) {
  std::vector<std::string> out;
  for (const auto& r : population.at("runs")) {
    const std::string outcome = r.at("outcome").get<std::string>();
    const std::string cause = r.at("contact").at("cause").get<std::string>();
    std::string why;
    if (cause != "none" && cause != "no_run") why = "contact (" + cause + ")";
    if (outcome == "STANDSTILL" || outcome == "TIME_LIMIT")
      why += (why.empty() ? "" : ", ") + outcome;
    else if (const Json& w = r.at("max_mutual_wait_s");
             w.is_number() && w.get<double>() > kStalemateMutualWait_s)
      why += (why.empty() ? "" : ", ") + std::string("mutual wait of ") +
             fmt("%.1f", w.get<double>()) + " s";
    if (!why.empty()) out.push_back(r.at("name").get<std::string>() + ": " + why);
  }
  return out;
}

/// Runs that left no summary: encounters and their muted twins.
inline int runsWithoutSummary(const Json& population) {
  const Json* cue = detail::field(&population, "cue_effect");
  return population.at("totals").at("failed_runs").get<int>() +
         (cue ? cue->at("muted_failed_runs").get<int>() : 0);
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

namespace detail {
/// num() without the sign of a value that rounds to zero ("-0.00" reads as a direction).
inline std::string numz(const Json& v, const char* format) {
  std::string t = num(v, format);
  if (t[0] == '-' && t.size() > 1 && t.find_first_not_of("-0.") == std::string::npos) t.erase(0, 1);
  return t;
}
/// numz() with a "+" before a positive value: a difference.
inline std::string signedNum(const Json& v, const char* format) {
  std::string t = numz(v, format);
  if (t == "-" || t[0] == '-' || t.find_first_not_of("0.") == std::string::npos) return t;
  return "+" + t;
}
inline std::string shortCause(const std::string& cause) {
  if (cause == "none") return "-";
  if (cause == "robot_at_fault") return "FAULT";
  if (cause == "human_walked_in") return "walked_in";
  if (cause == "robot_hit_wall") return "WALL";
  if (cause == "unattributed") return "UNATTR";
  return cause;
}
inline std::string yesNo(const Json& v) {
  return v.is_boolean() ? (v.get<bool>() ? "y" : "n") : std::string("?");
}
}  // namespace detail

/// The cue-effect section of population.txt: one line per encounter, the figures over all pairs,
/// then per layout.
inline std::string formatCueEffect(const Json& cue) {
  using namespace detail;
  std::string s;
  s += "\n# cue effect: each encounter spoken to (S) and with the dialogue manager muted (M), same "
       "scenario and seed; CM etc. of the head-on human\n";
  s +=
      "# dock: y/n; contact: - none, walked_in, FAULT (robot at fault), WALL, UNATTR; cues: said / "
      "not said (too late); lead: said cues' end before t_CROSS [s]; heard/complied: world_sim\n";
  s += pad("run", 10) + pad("layout", 16) + pad("CM S/M", 12) + pad("dCM", 7) + pad("dock", 6) +
       pad("ttg_s S/M", 13) + pad("min_clr S/M", 13) + pad("contact S/M", 21) + pad("cues", 6) +
       pad("heard", 7) + "lead_s\n";
  for (const auto& r : cue.at("encounters")) {
    const Json& a = r.at("speaking");
    const Json& b = r.at("muted");
    std::string leads;
    for (const auto& l : a.at("lead_s")) leads += (leads.empty() ? "" : ",") + numz(l, "%.1f");
    s += pad(r.at("name").get<std::string>(), 10) + pad(r.at("layout").get<std::string>(), 16) +
         pad(numz(a.at("cm_interaction_m"), "%.2f") + "/" + numz(b.at("cm_interaction_m"), "%.2f"),
             12) +
         pad(signedNum(r.at("cm_difference_m"), "%.2f"), 7) +
         pad(yesNo(a.at("docked")) + "/" + yesNo(b.at("docked")), 6) +
         pad(numz(a.at("robot_time_to_goal_s"), "%.1f") + "/" +
                 numz(b.at("robot_time_to_goal_s"), "%.1f"),
             13) +
         pad(numz(a.at("min_clearance_m"), "%.2f") + "/" + numz(b.at("min_clearance_m"), "%.2f"),
             13) +
         pad(shortCause(a.at("contact").get<std::string>()) + "/" +
                 shortCause(b.at("contact").get<std::string>()),
             21) +
         pad(a.at("cues_said").dump() + "/" + a.at("cues_too_late").dump(), 6) +
         pad(numz(a.at("heard"), "%.0f") + "/" + numz(a.at("complied"), "%.0f"), 7) +
         (leads.empty() ? "-" : leads) + "\n";
  }
  const Json& o = cue.at("overall");
  const Json& cm = o.at("cm");
  const Json& d = o.at("docked");
  const Json& t = o.at("time_to_goal");
  const Json& c = o.at("min_clearance");
  const Json& k = o.at("contacts");
  const Json& q = o.at("cues");
  s += "cue effect over " + cue.at("pairs").dump() +
       " encounters (both halves with a summary: " + o.at("pairs_run").dump() +
       "; muted runs without a summary " + cue.at("muted_failed_runs").dump() + "):\n";
  std::string interval = "-";
  if (cm.at("difference_ci95_m").is_array())
    interval = signedNum(cm.at("difference_ci95_m").at(0), "%.3f") + " .. " +
               signedNum(cm.at("difference_ci95_m").at(1), "%.3f");
  s += "  CM of the head-on human, " + cm.at("pairs").dump() + " pairs: mean speaking " +
       numz(cm.at("mean_speaking_m"), "%.3f") + " m, muted " + numz(cm.at("mean_muted_m"), "%.3f") +
       " m (medians " + numz(cm.at("median_speaking_m"), "%.3f") + " / " +
       numz(cm.at("median_muted_m"), "%.3f") + ")\n";
  s += "  paired difference speaking - muted: mean " +
       signedNum(cm.at("mean_difference_m"), "%.3f") + " m, 95 % bootstrap interval " + interval +
       " m; speaking higher " + cm.at("speaking_higher").dump() + ", muted higher " +
       cm.at("muted_higher").dump() + ", ties " + cm.at("ties").dump() + ", sign test p " +
       numz(cm.at("sign_test_p"), "%.3g") + "\n";
  s += "  IsContributing (interaction): speaking " + cm.at("contributing_speaking").dump() + "/" +
       cm.at("judged_speaking").dump() + ", muted " + cm.at("contributing_muted").dump() + "/" +
       cm.at("judged_muted").dump() + "\n";
  s += "  docked: speaking " + d.at("speaking").dump() + ", muted " + d.at("muted").dump() +
       " of " + d.at("pairs").dump() + " pairs; docks avoided by speaking " +
       d.at("avoided").dump() + ", added " + d.at("added").dump() + "\n";
  s += "  time to goal: median speaking " + numz(t.at("median_speaking_s"), "%.2f") + " s, muted " +
       numz(t.at("median_muted_s"), "%.2f") + " s, paired median difference " +
       signedNum(t.at("median_difference_s"), "%.2f") + " s; not reached " +
       t.at("not_reached_speaking").dump() + " / " + t.at("not_reached_muted").dump() + "\n";
  s += "  min clearance: speaking min " + numz(c.at("min_speaking_m"), "%.3f") + " m, median " +
       numz(c.at("median_speaking_m"), "%.3f") + " m; muted min " +
       numz(c.at("min_muted_m"), "%.3f") + " m, median " + numz(c.at("median_muted_m"), "%.3f") +
       " m\n";
  s += "  contacts: speaking " + k.at("speaking").dump() + ", muted " + k.at("muted").dump() +
       " (robot at fault or unattributed " +
       k.at("robot_at_fault_or_unattributed_speaking").dump() + " / " +
       k.at("robot_at_fault_or_unattributed_muted").dump() + ")\n";
  s += "  cues said " + q.at("said").dump() + ", not said (too late) " + q.at("too_late").dump() +
       "; lead of the said ones before t_CROSS: median " + numz(q.at("lead_median_s"), "%.2f") +
       " s, min " + numz(q.at("lead_min_s"), "%.2f") + " s\n";
  if (o.at("hearing").is_object())
    s += "  heard (world_sim): " + o.at("hearing").at("heard").dump() + " cues heard, " +
         o.at("hearing").at("complied").dump() + " complied with\n";
  s += "by layout: pairs, CM mean S/M (difference), docked S/M (avoided/added), ttg median S/M "
       "[s], min clearance S/M [m], contacts S/M, lead median/min [s], too late\n";
  for (const auto& [key, g] : cue.at("by_layout").items()) {
    const Json& gc = g.at("cm");
    const Json& gd = g.at("docked");
    const Json& gt = g.at("time_to_goal");
    const Json& gl = g.at("min_clearance");
    const Json& gk = g.at("contacts");
    const Json& gq = g.at("cues");
    s += "  " + pad(key, 16) + pad(g.at("pairs_run").dump(), 4) +
         pad(numz(gc.at("mean_speaking_m"), "%.2f") + "/" + numz(gc.at("mean_muted_m"), "%.2f") +
                 " (" + signedNum(gc.at("mean_difference_m"), "%.2f") + ")",
             20) +
         pad(gd.at("speaking").dump() + "/" + gd.at("muted").dump() + " (" +
                 gd.at("avoided").dump() + "/" + gd.at("added").dump() + ")",
             12) +
         pad(numz(gt.at("median_speaking_s"), "%.1f") + "/" + numz(gt.at("median_muted_s"), "%.1f"),
             12) +
         pad(numz(gl.at("min_speaking_m"), "%.2f") + "/" + numz(gl.at("min_muted_m"), "%.2f"), 11) +
         pad(gk.at("speaking").dump() + "/" + gk.at("muted").dump(), 6) +
         pad(numz(gq.at("lead_median_s"), "%.1f") + "/" + numz(gq.at("lead_min_s"), "%.1f"), 10) +
         gq.at("too_late").dump() + "\n";
  }
  return s;
}

/// The dialogue checks' lines of population.txt (and, for crowds, the figures per kind).
inline std::string formatDialogueChecks(const Json& population) {
  using namespace detail;
  const Json& t = population.at("totals");
  std::string s;
  const Json& d = t.at("dialogue_checks");
  s += "dialogue checks (summary.json dialogue_checks) of " + d.at("runs_checked").dump() +
       " runs (without checks " + d.at("runs_without_checks").dump() + "): said " +
       d.at("said").dump() + " sentences, " + d.at("addressed").dump() + " addressed\n";
  s += "  runs with words to someone not being crossed " +
       d.at("runs_said_to_not_crossing").dump() + ", with contradictions " +
       d.at("runs_contradictions").dump() + ", with a group told twice " +
       d.at("runs_told_twice").dump() + ", with an action contradicting the words " +
       d.value("runs_action_contradicts_words", Json(0)).dump() +
       ", with sentences not addressed among several people " +
       d.at("runs_unaddressed_with_several").dump() + " (" +
       d.at("sentences_unaddressed_with_several").dump() + " sentences)\n";
  s += "  runs failing a dialogue check: " + d.at("failing_runs").dump() + "\n";
  if (t.contains("by_kind")) {
    s += "# crowd kinds: runs, goal reached, contacts (robot at fault or unattributed), min "
         "clearance min/median [m], runs failing a dialogue check\n";
    for (const auto& [kind, k] : t.at("by_kind").items())
      s += "  " + pad(kind, 15) + pad(k.at("runs").dump(), 5) +
           pad("goal " + k.at("goal_reached").dump(), 9) +
           pad("contacts " + k.at("contacts").dump() + " (" +
                   k.at("robot_at_fault_or_unattributed").dump() + ")",
               16) +
           pad("min_clr " + num(k.at("min_clearance_min_m"), "%.3f") + "/" +
                   num(k.at("min_clearance_median_m"), "%.3f"),
               22) +
           "dialogue failing " + k.at("dialogue_failing_runs").dump() + "\n";
  }
  return s;
}

/// The plain-text table: one line per run, then the totals (and the cue effect, with muted
/// twins).
inline std::string formatTable(const Json& population) {
  using namespace detail;
  std::string s;
  s += "# coopnav population, seed " + population.at("seed").dump() + "\n";
  s += "# humans: id:behaviour(role) CM_interaction/IsContributing (T/F/? = unknown); roles h = "
       "head-on, f = follower, s = same way, c = crossing (junction), t = standing (talking)\n";
  const bool crowd = population.at("totals").contains("by_kind");
  s += "# words: sentences said/addressed, then the dialogue checks that failed: n said to someone "
       "not being crossed, c contradiction, t group told twice, u not addressed among several\n";
  s += pad("run", 9) + pad("layout", 16) + (crowd ? pad("kind", 15) : std::string()) +
       pad("outcome", 20) + pad("contact", 22) + pad("min_clr_m", 10) + pad("dock", 5) +
       pad("retr", 5) + pad("guard", 6) + pad("ttg_ratio", 10) + pad("words", 10) + "humans\n";
  for (const auto& r : population.at("runs")) {
    const Json& c = r.at("contact");
    std::string contact = c.at("cause").get<std::string>();
    if (c.at("human_id").is_number()) contact += " h" + num(c.at("human_id"), "%.0f");
    std::string humans;
    for (const auto& h : r.at("humans")) {
      const std::string role_name = h.at("role").get<std::string>();
      const std::string role = role_name == "standing" ? "t" : role_name.substr(0, 1);
      humans += num(h.at("id"), "%.0f") + ":" + shortBehaviour(h.at("behaviour")) + "(" + role +
                ") " + num(h.at("cm_interaction_m"), "%.2f") + "/" +
                tri(h.at("is_contributing_interaction")) + "  ";
    }
    while (!humans.empty() && humans.back() == ' ') humans.pop_back();
    std::string words = "-";
    if (const Json& d = r.at("dialogue_checks"); d.is_object()) {
      words = num(d.at("said"), "%.0f") + "/" + num(d.at("addressed"), "%.0f");
      std::string flags;
      if (!d.at("said_to_not_crossing").empty()) flags += "n";
      if (!d.at("contradictions").empty()) flags += "c";
      if (!d.at("told_twice").empty()) flags += "t";
      if (!d.at("action_contradicts_words").empty()) flags += "a";
      if (d.at("unaddressed_with_several").is_number() &&
          d.at("unaddressed_with_several").get<std::int64_t>() > 0)
        flags += "u";
      if (!flags.empty()) words += "!" + flags;
    }
    s += pad(r.at("name").get<std::string>(), 9) + pad(r.at("layout").get<std::string>(), 16) +
         (crowd ? pad(r.value("kind", std::string("-")), 15) : std::string()) +
         pad(r.at("outcome").get<std::string>(), 20) + pad(contact, 22) +
         pad(num(r.at("min_clearance_m"), "%.3f"), 10) + pad(num(r.at("docks"), "%.0f"), 5) +
         pad(num(r.at("retreats"), "%.0f"), 5) + pad(num(r.at("guard_steps"), "%.0f"), 6) +
         pad(num(r.at("time_to_goal_ratio"), "%.2f"), 10) + pad(words, 10) + humans + "\n";
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
       ", p95 " + num(ttg.value("p95", Json()), "%.2f") + ", max " + num(ttg.at("max"), "%.2f") +
       " over " + ttg.at("runs").dump() + " runs that reached it";
  if (ttg.contains("p95_all_runs"))
    s += "; p95 of all runs, the " + ttg.at("runs_goal_not_reached").dump() +
         " that did not reach it counted as unbounded: " +
         (ttg.at("p95_all_runs").is_null() ? std::string("unbounded")
                                           : num(ttg.at("p95_all_runs"), "%.2f"));
  s += "\n";
  if (t.contains("stalemates"))
    s += "progress: stalemates (STANDSTILL, TIME_LIMIT or a mutual wait over " +
         fmt("%.0f", kStalemateMutualWait_s) + " s) " + t.at("stalemates").dump() +
         ", runs with a mutual wait over " + fmt("%.0f", kStalemateMutualWait_s) + " s " +
         t.value("mutual_waits_over_limit", Json()).dump() + ", longest mutual wait " +
         num(t.at("max_mutual_wait_s"), "%.1f") + " s, stalled time median " +
         num(t.at("stalled_s").at("median"), "%.1f") + " s, max " +
         num(t.at("stalled_s").at("max"), "%.1f") + " s\n";
  if (t.contains("goal_inference") && t.at("goal_inference").at("humans").get<int>() > 0) {
    const Json& gi = t.at("goal_inference");
    s += "goal inference (goals withheld): region planned with at round 1 = the one walked to, " +
         gi.at("correct").dump() + "/" + gi.at("judged").dump() + " = " +
         num(gi.at("accuracy_at_round1"), "%.3f") +
         " (oncoming humans with an estimate: " + gi.at("humans").dump() + ")\n";
  }
  s += formatDialogueChecks(population);
  if (population.contains("cue_effect")) s += formatCueEffect(population.at("cue_effect"));
  return s;
}

}  // namespace coopnav::population
