// coopnav_population: the generator and the aggregation of scripts/population.sh
// (docs/population.md).
//   coopnav_population generate --n N --seed S --out DIR --maps-dir config/maps
//                               [--behaviour B] [--cue-effect | --crowd]
//                               [--slower-ahead] [--pause] [--max-width-m W]
//     DIR/scenarios/*.yaml (encounters and one run without humans per layout), DIR/maps/ (the
//     maps they use), DIR/plan.json, DIR/jobs.txt (one "name<TAB>scenario" line per run, and
//     with --cue-effect after each encounter its muted twin "name_muted<TAB>scenario<TAB>muted").
//     --behaviour: every head-on human gets behaviour B, the other draws stay the seed's.
//     --crowd: crowd encounters instead (flows, a group abreast, people standing talking, a
//     junction: generator.hpp generateCrowdPopulation).
//     --slower-ahead, --pause: every encounter's widened variant is a slower person ahead, one
//     of its people pauses (the draws forced; the rest as the seed draws it). --max-width-m: only
//     the layouts no wider than W are drawn from.
//   coopnav_population aggregate --dir DIR
//     reads DIR/plan.json and DIR/runs/<name>/summary.json (and cue_outcomes.jsonl beside it,
//     world_sim's cue_outcomes_file: what the humans heard), writes DIR/population.json and
//     DIR/population.txt, prints the totals.
//   coopnav_population check --dir DIR
//     reads population.json back and checks it against plan.json and population.txt.
// Exit codes: 0 fine; 1 a contact with the robot at fault (or one the summaries cannot clear);
// 2 bad arguments or files; 3 runs without a summary (and no failure of exit 1 or 4); 4 a run
// failed a dialogue check (summary.json dialogue_checks; and no contact of exit 1); 5 a run ended
// in a contact, a standstill or the time limit (and nothing of exit 1 or 4).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "aggregate.hpp"
#include "json.hpp"
#include "summary.hpp"

namespace fs = std::filesystem;
namespace pop = coopnav::population;

namespace {

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + p.string());
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

int generate(std::size_t n, std::uint64_t seed, const fs::path& out, const fs::path& maps_dir,
             const pop::PlanOptions& options) {
  const auto encounters = options.crowd ? pop::generateCrowdPopulation(n, seed)
                                        : pop::generatePopulation(n, seed, pop::rangesOf(options),
                                                                  options.head_on_behaviour);
  fs::create_directories(out / "scenarios");
  fs::create_directories(out / "maps");
  // Stale files of an earlier, larger population in the same folder would be run again.
  for (const auto& f : fs::directory_iterator(out / "scenarios")) fs::remove(f.path());
  std::set<std::string> maps, baselines;
  std::string jobs;
  for (const auto& e : encounters) {
    if (!e.layout.map_file.empty()) maps.insert(e.layout.map_file);
    const std::string base = pop::baselineName(e);
    if (baselines.insert(base).second) {
      writeFile(out / "scenarios" / (base + ".yaml"), pop::scenarioYaml(e, false, base));
      jobs += base + "\tscenarios/" + base + ".yaml\n";
    }
  }
  for (const auto& e : encounters) {
    writeFile(out / "scenarios" / (e.name + ".yaml"), pop::scenarioYaml(e));
    jobs += e.name + "\tscenarios/" + e.name + ".yaml\n";
    // Beside its encounter, so that a population stopped half-way still has whole pairs.
    if (options.muted_twins)
      jobs += pop::mutedTwinName(e.name) + "\tscenarios/" + e.name + ".yaml\tmuted\n";
  }
  for (const auto& m : maps) {
    // The map YAML names its image; copy both so the run folder stands on its own.
    const std::string yaml = readFile(maps_dir / m);
    fs::copy_file(maps_dir / m, out / "maps" / m, fs::copy_options::overwrite_existing);
    const auto at = yaml.find("image:");
    if (at == std::string::npos) throw std::runtime_error(m + ": no image: key");
    std::string image = yaml.substr(at + 6, yaml.find('\n', at) - at - 6);
    image.erase(0, image.find_first_not_of(" \t\""));
    image.erase(image.find_last_not_of(" \t\r\"") + 1);
    fs::copy_file(maps_dir / image, out / "maps" / image, fs::copy_options::overwrite_existing);
  }
  writeFile(out / "jobs.txt", jobs);
  writeFile(out / "plan.json", coopnav::ctl::dumpJson(pop::planJson(encounters, seed, options)));
  std::cout << "coopnav_population: " << encounters.size()
            << (options.crowd ? " crowd encounters" : " encounters")
            << (options.muted_twins ? " (each also muted)" : "") << " and " << baselines.size()
            << " runs without humans in " << out.string() << "\n";
  return 0;
}

int aggregate(const fs::path& dir) {
  const pop::Json plan = coopnav::ctl::parseJson(readFile(dir / "plan.json"));
  if (plan.value("format", "") != pop::kPlanFormat)
    throw std::runtime_error((dir / "plan.json").string() + " is not a population plan");
  std::map<std::string, pop::Json> summaries;
  std::vector<std::string> names;
  for (const auto& e : plan.at("encounters")) {
    names.push_back(e.at("name").get<std::string>());
    if (e.contains("muted_twin")) names.push_back(e.at("muted_twin").get<std::string>());
  }
  for (const auto& b : plan.at("baselines")) names.push_back(b.at("name").get<std::string>());
  for (const auto& name : names) {
    const fs::path p = dir / "runs" / name / "summary.json";
    if (!fs::exists(p)) continue;
    try {
      const pop::Json doc = coopnav::ctl::readSummaryFile(p.string());
      const pop::Json& list = doc.at("scenarios");
      if (list.empty()) continue;
      summaries[name] = list.at(0);
      // What the simulated humans heard: world_sim's cue outcomes (its cue_outcomes_file).
      const fs::path cues = dir / "runs" / name / "cue_outcomes.jsonl";
      if (fs::exists(cues)) {
        try {
          summaries[name]["hearing"] = pop::hearingFromCueOutcomes(readFile(cues));
        } catch (const std::exception& ex) {
          std::cerr << "coopnav_population: " << cues.string() << ": " << ex.what()
                    << " (what its humans heard is unknown)\n";
        }
      }
    } catch (const std::exception& ex) {
      std::cerr << "coopnav_population: " << ex.what() << " (counted as a run without summary)\n";
    }
  }
  const pop::Json population = pop::aggregatePopulation(plan, summaries);
  const std::string table = pop::formatTable(population);
  writeFile(dir / "population.json", coopnav::ctl::dumpJson(population));
  writeFile(dir / "population.txt", table);
  std::cout << table.substr(table.find("# totals"));
  if (pop::populationFails(population)) {
    std::cerr << "coopnav_population: contacts with the robot at fault (or unattributed): see "
              << (dir / "population.txt").string() << "\n";
    return 1;
  }
  if (const int failing = pop::dialogueFailingRuns(population); failing > 0) {
    std::cerr << "coopnav_population: " << failing
              << " run(s) failed a dialogue check (words to someone not being crossed, a "
                 "contradiction, a group told twice, a sentence not addressed): see "
              << (dir / "population.txt").string() << "\n";
    return 4;
  }
  if (const auto bad = pop::runsEndedBadly(population); !bad.empty()) {
    std::cerr << "coopnav_population: " << bad.size()
              << " run(s) ended in a contact, a standstill or the time limit:\n";
    for (const auto& line : bad) std::cerr << "  " << line << "\n";
    return 5;
  }
  if (pop::runsWithoutSummary(population) > 0) return 3;
  return 0;
}

// Reads population.json back with the strict parser and checks it against plan.json and
// population.txt: one record per encounter in plan order, totals that add up, one table line per
// run. Prints each problem; returns 0 when there is none.
int check(const fs::path& dir) {
  const pop::Json plan = coopnav::ctl::parseJson(readFile(dir / "plan.json"));
  const pop::Json doc = coopnav::ctl::parseJson(readFile(dir / "population.json"));
  const std::string table = readFile(dir / "population.txt");
  std::vector<std::string> problems;
  auto want = [&](bool ok, const std::string& what) {
    if (!ok) problems.push_back(what);
  };
  want(doc.value("format", "") == pop::kPopulationFormat, "format is not coopnav-population/1");
  const pop::Json& runs = doc.at("runs");
  const pop::Json& encounters = plan.at("encounters");
  want(runs.size() == encounters.size(), "runs: " + std::to_string(runs.size()) + " records for " +
                                             std::to_string(encounters.size()) + " encounters");
  for (std::size_t i = 0; i < std::min(runs.size(), encounters.size()); ++i) {
    const std::string name = encounters[i].at("name").get<std::string>();
    want(runs[i].at("name") == name, "runs[" + std::to_string(i) + "] is not " + name);
    want(runs[i].at("humans").size() == encounters[i].at("humans").size(),
         name + ": humans differ from the plan");
    want(table.find("\n" + name + " ") != std::string::npos, name + ": no line in the table");
    for (const char* key : {"outcome", "contact", "min_clearance_m", "docks", "retreats",
                            "guard_steps", "time_to_goal_ratio", "dialogue_checks"})
      want(runs[i].contains(key), name + ": no '" + key + "'");
    if (encounters[i].contains("kind"))
      want(runs[i].value("kind", pop::Json()) == encounters[i].at("kind"),
           name + ": kind differs from the plan");
    // Each run's checks: null (no summary, or a summary without them) or whole.
    if (runs[i].contains("dialogue_checks") && !runs[i].at("dialogue_checks").is_null()) {
      const pop::Json& d = runs[i].at("dialogue_checks");
      bool whole = d.is_object();
      for (const char* key : {"said", "addressed", "unaddressed_with_several", "fails"})
        whole = whole && d.contains(key);
      for (const char* key : {"said_to_not_crossing", "contradictions", "told_twice"})
        whole = whole && d.contains(key) && d.at(key).is_array();
      want(whole, name + ": dialogue_checks is not whole");
      if (whole) {
        const bool several = encounters[i].at("humans").size() > 1;
        want(d.at("unaddressed_with_several").is_null() != several || !d.at("said").is_number() ||
                 !d.at("addressed").is_number(),
             name + ": unaddressed_with_several does not match the number of people");
        bool fails = d.at("unaddressed_with_several").is_number() &&
                     d.at("unaddressed_with_several").get<std::int64_t>() > 0;
        for (const char* key : {"said_to_not_crossing", "contradictions", "told_twice"})
          fails = fails || !d.at(key).empty();
        want(d.at("fails") == fails, name + ": dialogue_checks.fails does not match its lists");
      }
    }
  }
  const pop::Json& t = doc.at("totals");
  int outcomes = 0, contacts = 0, from_runs = 0;
  for (const auto& [k, v] : t.at("outcomes").items()) outcomes += v.get<int>();
  for (const auto& [k, v] : t.at("contacts_by_cause").items()) contacts += v.get<int>();
  for (const auto& r : runs) {
    const std::string cause = r.at("contact").at("cause").get<std::string>();
    from_runs += cause != "none" && cause != "no_run" ? 1 : 0;
  }
  want(outcomes == static_cast<int>(runs.size()), "outcomes do not add up to the runs");
  want(contacts == t.at("contacts").get<int>(), "contacts_by_cause do not add up to contacts");
  want(contacts == from_runs, "contacts do not match the runs' contact causes");
  // The dialogue checks' totals against the runs.
  const pop::Json* dt = t.contains("dialogue_checks") ? &t.at("dialogue_checks") : nullptr;
  want(dt != nullptr, "totals: no dialogue_checks");
  if (dt != nullptr) {
    int checked = 0, failing = 0, not_crossing = 0, contradictions = 0, twice = 0, unaddressed = 0;
    for (const auto& r : runs) {
      const pop::Json d = r.value("dialogue_checks", pop::Json());
      if (!d.is_object() || !d.contains("fails")) continue;
      ++checked;
      failing += d.at("fails").get<bool>() ? 1 : 0;
      not_crossing += d.value("said_to_not_crossing", pop::Json::array()).empty() ? 0 : 1;
      contradictions += d.value("contradictions", pop::Json::array()).empty() ? 0 : 1;
      twice += d.value("told_twice", pop::Json::array()).empty() ? 0 : 1;
      const pop::Json u = d.value("unaddressed_with_several", pop::Json());
      unaddressed += u.is_number() && u.get<std::int64_t>() > 0 ? 1 : 0;
    }
    want(dt->at("runs_checked") == checked, "dialogue_checks.runs_checked does not match the runs");
    want(dt->at("failing_runs") == failing, "dialogue_checks.failing_runs does not match the runs");
    want(dt->at("runs_said_to_not_crossing") == not_crossing &&
             dt->at("runs_contradictions") == contradictions &&
             dt->at("runs_told_twice") == twice &&
             dt->at("runs_unaddressed_with_several") == unaddressed,
         "dialogue_checks counts do not match the runs");
    want(dt->at("runs_checked").get<int>() + dt->at("runs_without_checks").get<int>() +
                 t.at("failed_runs").get<int>() ==
             static_cast<int>(runs.size()),
         "dialogue_checks: runs checked, without checks and without summary do not add up");
    want(table.find("runs failing a dialogue check: " + dt->at("failing_runs").dump()) !=
             std::string::npos,
         "the table does not give the runs failing a dialogue check");
  }
  // Crowds: the figures per kind add up to the runs.
  if (plan.value("crowd", false)) {
    const pop::Json* kinds = t.contains("by_kind") ? &t.at("by_kind") : nullptr;
    want(kinds != nullptr, "crowd plan but no totals.by_kind");
    if (kinds != nullptr) {
      int kind_runs = 0, kind_safety = 0, kind_failing = 0;
      for (const auto& [k, v] : kinds->items()) {
        kind_runs += v.at("runs").get<int>();
        kind_safety += v.at("robot_at_fault_or_unattributed").get<int>();
        kind_failing += v.at("dialogue_failing_runs").get<int>();
        want(table.find("  " + k + " ") != std::string::npos, k + ": no line in the table");
      }
      want(kind_runs == static_cast<int>(runs.size()), "by_kind runs do not add up to the runs");
      want(kind_safety == t.at("robot_at_fault_or_unattributed").get<int>(),
           "by_kind robot at fault do not add up");
      if (dt != nullptr)
        want(kind_failing == dt->at("failing_runs").get<int>(),
             "by_kind dialogue failing runs do not add up");
    }
  }
  // With muted twins: one pair per encounter, in plan order, and the section in the table.
  if (plan.value("cue_effect", false)) {
    const pop::Json* cue = doc.contains("cue_effect") ? &doc.at("cue_effect") : nullptr;
    want(cue != nullptr, "plan has muted twins but population.json no cue_effect");
    if (cue != nullptr) {
      const pop::Json& pairs = cue->at("encounters");
      want(pairs.size() == encounters.size(),
           "cue_effect: " + std::to_string(pairs.size()) + " pairs for " +
               std::to_string(encounters.size()) + " encounters");
      for (std::size_t i = 0; i < std::min(pairs.size(), encounters.size()); ++i)
        want(pairs[i].at("name") == encounters[i].at("name"),
             "cue_effect.encounters[" + std::to_string(i) + "] is not " +
                 encounters[i].at("name").get<std::string>());
      want(table.find("# cue effect") != std::string::npos, "no cue effect in the table");
    }
  }
  for (const auto& p : problems) std::cerr << "coopnav_population check: " << p << "\n";
  if (problems.empty())
    std::cout << "coopnav_population check: " << runs.size() << " runs, well formed\n";
  return problems.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"coopnav_population: generates a population of encounters and tabulates its runs"};
  app.require_subcommand(1);
  std::size_t n = 200;
  std::uint64_t seed = 1;
  std::string out, maps_dir, dir;
  auto* gen = app.add_subcommand("generate", "write the scenario files of a population");
  gen->add_option("--n", n, "number of encounters")->check(CLI::Range(1, 100000));
  gen->add_option("--seed", seed, "population seed");
  gen->add_option("--out", out, "output folder")->required();
  gen->add_option("--maps-dir", maps_dir, "folder of the maps (config/maps)")->required();
  pop::PlanOptions plan_options;
  const auto& behaviours = pop::behaviourNames();
  gen->add_option("--behaviour", plan_options.head_on_behaviour,
                  "every head-on human has this behaviour (the other draws stay the seed's)")
      ->check(CLI::IsMember(std::vector<std::string>(behaviours.begin(), behaviours.end())));
  auto* cue_flag = gen->add_flag(
      "--cue-effect", plan_options.muted_twins,
      "also run every encounter with the dialogue manager muted (jobs.txt, plan.json)");
  gen->add_flag("--crowd", plan_options.crowd,
                "crowd encounters: flows both ways, a group abreast, people standing talking by "
                "a wall, a junction (docs/population.md \"Crowds\")")
      ->excludes(cue_flag)
      ->excludes("--behaviour");
  gen->add_flag("--slower-ahead", plan_options.slower_ahead,
                "every encounter has a slower person ahead walking the robot's way (its widened "
                "variant forced; the other draws stay the seed's)")
      ->excludes("--crowd");
  gen->add_flag("--pause", plan_options.pause,
                "in every encounter one of the people pauses on the way (the pause draw forced)")
      ->excludes("--crowd");
  gen->add_option("--max-width-m", plan_options.max_width_m,
                  "only the corridors no wider than this [m] (a study of narrow ones)")
      ->check(CLI::Range(1.7, 100.0))
      ->excludes("--crowd");
  auto* agg = app.add_subcommand("aggregate", "write population.json and population.txt");
  agg->add_option("--dir", dir, "the population folder")->required();
  auto* chk = app.add_subcommand("check", "check population.json against the plan and the table");
  chk->add_option("--dir", dir, "the population folder")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    if (*gen) return generate(n, seed, out, maps_dir, plan_options);
    if (*chk) return check(dir);
    return aggregate(dir);
  } catch (const std::exception& ex) {
    std::cerr << "coopnav_population: " << ex.what() << "\n";
    return 2;
  }
}
