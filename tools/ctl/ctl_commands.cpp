#include "ctl_commands.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "goals.hpp"
#include "logfile/log_reader.hpp"
#include "maps/map_loader.hpp"
#include "metrics_command.hpp"
#include "pedestrians.hpp"
#include "pedestrians_daemon.hpp"
#include "pedestrians_forecast.hpp"
#include "run_analysis.hpp"
#include "summary.hpp"
#include "transcript.hpp"

namespace coopnav {
namespace {

// CLI11 binds options to variables that must live until the command runs.
struct LogCommandOptions {
  CLI::App* transcript{nullptr};
  CLI::App* summarize{nullptr};
  CLI::App* merge{nullptr};
  CLI::App* cm_table{nullptr};
  CLI::App* pedestrians{nullptr};
  CLI::App* calibrate{nullptr};
  CLI::App* forecast{nullptr};
  std::string forecast_profile_out;  // forecast: --write-profile
  bool decision_time{false};         // pedestrians: --decision-time
  CLI::App* goals{nullptr};
  CLI::App* goal_candidates{nullptr};
  std::optional<double> goals_beta_per_m;  // goals: fit leave-one-sequence-out unless given
  std::string log;
  std::string scenario;
  std::string out;
  bool merge_into_out{false};
  bool no_sim_status{false};
  bool no_unknown{false};
  bool no_final_cm{false};
  bool with_status{false};
  std::vector<std::string> inputs;
  // pedestrians: the paper profile unless given (γ 0.98 per 0.1 s sample, τ 0.4 m, path side).
  std::optional<double> gamma_per_s;
  std::optional<double> tau_m;
  std::optional<std::string> side_rule;
  std::string window{"round1"};
  double lead_s{2.0};
  bool daemon{false};
  ctl::DaemonRunOptions daemon_options;
};

LogCommandOptions& opts() {
  static LogCommandOptions o;
  return o;
}

// Reads the log; reports what was skipped on stderr (never on stdout, which must be the same
// for the same message contents). Returns false when the log has no coopnav message at all.
bool loadRun(const std::string& path, ctl::RunLog& run) {
  run = ctl::readRunLog(path);
  if (run.counts.anyCorruption())
    std::cerr << "coopnav_ctl: " << path << ": skipped broken data: " << run.counts.describe()
              << "\n";
  if (run.counts.decoded == 0) {
    std::cerr << "coopnav_ctl: " << path << ": no coopnav message decoded ("
              << run.counts.describe() << ")\n";
    return false;
  }
  return true;
}

std::string runName(const ctl::RunAnalysis& a, const std::string& log) {
  if (!a.scenario.empty()) return a.scenario;
  return std::filesystem::path(log).stem().string();
}

int transcriptCommand() {
  const auto& o = opts();
  ctl::RunLog run;
  if (!loadRun(o.log, run)) return 1;
  const auto analysis = ctl::analyseRun(run, o.scenario);
  if (!o.scenario.empty() && analysis.final_status &&
      run.sim_status[*analysis.final_status].scenario != o.scenario)
    std::cerr << "coopnav_ctl: note: the log's sim status names scenario '"
              << ctl::printable(run.sim_status[*analysis.final_status].scenario) << "', not '"
              << ctl::printable(o.scenario) << "'\n";
  ctl::TranscriptOptions topt;
  topt.include_sim_status = !o.no_sim_status;
  topt.include_unknown = !o.no_unknown;
  topt.include_final_cm = !o.no_final_cm;
  topt.include_daemon_status = o.with_status;
  std::cout << ctl::formatTranscript(runName(analysis, o.log),
                                     ctl::buildTranscript(run, analysis, topt));
  return 0;
}

int summarizeCommand() {
  const auto& o = opts();
  ctl::RunLog run;
  if (!loadRun(o.log, run)) return 1;
  auto analysis = ctl::analyseRun(run, o.scenario);
  analysis.scenario = runName(analysis, o.log);
  const auto entry =
      ctl::summarizeRun(run, analysis, std::filesystem::path(o.log).filename().string());
  ctl::Json doc = ctl::summaryDocument({entry});
  if (o.merge_into_out && std::filesystem::exists(o.out))
    doc = ctl::mergeSummaries({ctl::readSummaryFile(o.out), doc});
  ctl::writeTextFile(o.out, ctl::dumpJson(doc));
  return 0;
}

int mergeCommand() {
  const auto& o = opts();
  std::vector<ctl::Json> docs;
  for (const auto& in : o.inputs) docs.push_back(ctl::readSummaryFile(in));
  ctl::writeTextFile(o.out, ctl::dumpJson(ctl::mergeSummaries(docs)));
  return 0;
}

int cmTableCommand() {
  std::cout << ctl::formatCmTable(ctl::readSummaryFile(opts().out));
  return 0;
}

int pedestriansCommand() {
  const auto& o = opts();
  ctl::WindowSetting window;
  window.kind = ctl::windowKindFromString(o.window).value_or(window.kind);
  window.lead_s = o.lead_s;
  const auto pairs = ctl::loadPedestrianPairs(o.log);
  if (o.daemon) {
    // The daemon runs with its config file; the settings given here become its --set overrides.
    ctl::DaemonRunOptions d = o.daemon_options;
    std::vector<std::string> sets;
    char buf[64];
    if (o.gamma_per_s) {
      std::snprintf(
          buf, sizeof buf, "gamma=%.17g",
          ctl::gammaPerSample(*o.gamma_per_s, assessment::PathAssessorConfig{}.sample_period_s));
      sets.emplace_back(buf);
    }
    if (o.tau_m) {
      std::snprintf(buf, sizeof buf, "tau_m=%.17g", *o.tau_m);
      sets.emplace_back(buf);
    }
    if (o.side_rule) sets.push_back("side_rule=" + *o.side_rule);
    d.overrides.insert(d.overrides.begin(), sets.begin(), sets.end());
    const auto r = ctl::runPedestriansThroughDaemon(pairs, window, d);
    std::cout << ctl::formatDaemonRun(r, window);
    return r.sample_mismatches == 0 && r.max_abs_dcm_m <= ctl::kDaemonAgreementM ? 0 : 1;
  }
  assessment::PathAssessorConfig config;  // γ 0.98 per sample exactly when no --gamma-per-s
  if (o.gamma_per_s) config.gamma = ctl::gammaPerSample(*o.gamma_per_s, config.sample_period_s);
  config.tau_m = o.tau_m.value_or(config.tau_m);
  if (o.side_rule)
    config.side_rule = assessment::sideRuleFromString(*o.side_rule).value_or(config.side_rule);
  if (o.decision_time) {
    // The settings given (no fit here): the judgement read at t_cross - {4 .. 0} s.
    std::cout << ctl::formatDecisionTables({ctl::scoreJudgements(
        "CM", "the settings above, round-1 window", pairs, ctl::cmJudgements(pairs, config))});
  }
  const auto e = ctl::evaluateWalkers(pairs, config, window);
  std::cout << ctl::formatPedestrianEvaluation(
      e, o.gamma_per_s.value_or(std::pow(config.gamma, 1.0 / config.sample_period_s)), window);
  return 0;
}

int calibrateCommand() {
  std::cout << ctl::formatCalibration(ctl::calibrate(ctl::loadPedestrianPairs(opts().log)));
  return 0;
}

int forecastCommand() {
  const auto& o = opts();
  const auto pairs = ctl::loadPedestrianPairs(o.log);
  const auto study = ctl::runForecastStudy(pairs, ctl::calibrate(pairs));
  std::cout << ctl::formatForecastStudy(study);
  if (!o.forecast_profile_out.empty()) {
    std::ofstream out(o.forecast_profile_out);
    out << ctl::forecastProfileYaml(study.model);
    if (!out) {
      std::cerr << o.forecast_profile_out << ": cannot write\n";
      return 1;
    }
    std::cout << "wrote " << o.forecast_profile_out << "\n";
  }
  return 0;
}

int goalsCommand() {
  const auto& o = opts();
  std::cout << ctl::formatGoalReport(
      ctl::evaluateGoalReport(ctl::loadPedestrianPairs(o.log), o.goals_beta_per_m));
  return 0;
}

/// The candidate goals the band source's goal inference would start from on a map (default
/// options): from the map's shape, then annotated on it (goal_regions).
int goalCandidatesCommand() {
  LoadedMap loaded = loadMap(opts().log);
  const GridDistanceField field(std::move(loaded.grid));
  const auto print = [](const char* from, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d c = 0.5 * (a + b);
    std::printf("%-9s centre (%.2f, %.2f)  from (%.2f, %.2f) to (%.2f, %.2f)  %.2f m\n", from,
                c.x(), c.y(), a.x(), a.y(), b.x(), b.y(), (b - a).norm());
  };
  for (const GoalRegion& r : mapGoalCandidates(field)) print("shape", r.a, r.b);
  for (const MapGoalRegion& r : loaded.goal_regions) print("annotated", r.a, r.b);
  return 0;
}

}  // namespace

void addCtlCommands(CLI::App& app) {
  auto& o = opts();
  o.transcript = app.add_subcommand(
      "transcript", "print what the robot said and did in a recorded run (deterministic text)");
  o.transcript->add_option("log", o.log, "LCM log of one run (lcm-logger)")->required();
  o.transcript->add_option("--scenario", o.scenario, "name in the header (default: from the log)");
  o.transcript->add_flag("--no-sim-status", o.no_sim_status,
                         "leave out the final simulator status (replays have none)");
  o.transcript->add_flag("--no-unknown", o.no_unknown, "leave out situation-unknown notes");
  o.transcript->add_flag("--no-final-cm", o.no_final_cm, "leave out the final CM lines");
  o.transcript->add_flag("--with-status", o.with_status,
                         "add daemons' DEGRADED reports (wall-clock: not deterministic)");

  o.summarize = app.add_subcommand("summarize", "write summary.json of a recorded run");
  o.summarize->add_option("log", o.log, "LCM log of one run")->required();
  o.summarize->add_option("--scenario", o.scenario, "scenario name (default: from the log)");
  o.summarize->add_option("--out", o.out, "summary file to write")->required();
  o.summarize->add_flag("--merge", o.merge_into_out,
                        "merge into --out if it exists (replacing this scenario's entry)");

  o.merge = app.add_subcommand("merge-summaries", "merge summary files into one");
  o.merge->add_option("out", o.out, "summary file to write")->required();
  o.merge->add_option("inputs", o.inputs, "summary files, later ones win per scenario")->required();

  o.cm_table = app.add_subcommand("cm-table", "print the CM table beside the paper's Table I");
  o.cm_table->add_option("summary", o.out, "summary.json")->required();

  o.pedestrians = app.add_subcommand("pedestrians",
                                     "score CM / IsContributing on real head-on pedestrian pairs");
  o.pedestrians->add_option("pairs", o.log, "headon_pairs.json")->required();
  o.pedestrians->add_option("--gamma-per-s", o.gamma_per_s, "gamma per second (default 0.98^10)")
      ->check(CLI::PositiveNumber);
  o.pedestrians->add_option("--tau", o.tau_m, "tau [m] (default 0.4)");
  o.pedestrians->add_option("--side-rule", o.side_rule, "CA sign rule (default path_side)")
      ->check(CLI::IsMember({"path_side", "human_side"}));
  o.pedestrians
      ->add_option("--window", o.window,
                   "where the CM window starts: round1 (t0, the paper's), onset (the walker's "
                   "avoidance onset), lead (--lead-s before the closest approach)")
      ->check(CLI::IsMember({"round1", "onset", "lead"}));
  o.pedestrians->add_option("--lead-s", o.lead_s, "lead window length [s] (default 2)")
      ->check(CLI::PositiveNumber);
  o.pedestrians->add_flag("--daemon", o.daemon,
                          "run the walkers through a spawned coopnav_path_assessor over LCM and "
                          "compare with the in-process replay (exit 1 when they differ)");
  auto& d = o.daemon_options;
  o.pedestrians->add_option("--path-assessor", d.path_assessor,
                            "--daemon: the daemon binary (default: the build tree's)");
  o.pedestrians
      ->add_option("--profile", d.profile,
                   "--daemon: config/path_assessor.yaml (paper) or "
                   "config/path_assessor_calibrated.yaml (calibrated)")
      ->check(CLI::IsMember({"paper", "calibrated"}));
  o.pedestrians->add_option("--config", d.config_path, "--daemon: the daemon's config file");
  o.pedestrians->add_option("--set", d.overrides, "--daemon: key=value for the daemon (repeatable)")
      ->allow_extra_args(false);
  o.pedestrians->add_option(
      "--lcm-url", d.lcm_url,
      std::string("--daemon: a private LCM URL (default ") + ctl::kPedestrianDaemonUrl + ")");

  o.calibrate = app.add_subcommand(
      "calibrate",
      "fit gamma, tau, the side rule and the window on pedestrian pairs (leave one sequence out)");
  o.calibrate->add_option("pairs", o.log, "headon_pairs.json")->required();

  o.pedestrians->add_flag("--decision-time", o.decision_time,
                          "also the judgement's AUC and accuracy at t_cross - {4, 3, 2, 1, 0} s, "
                          "per sequence, with bootstrap intervals");

  o.forecast = app.add_subcommand(
      "forecast",
      "judgement in time on pedestrian pairs: paper / calibrated CM and the p_contributing "
      "forecast at t_cross - {4 .. 0} s, leave one sequence out; fit the forecast profile");
  o.forecast->add_option("pairs", o.log, "headon_pairs.json")->required();
  o.forecast->add_option(
      "--write-profile", o.forecast_profile_out,
      "write the forecast fitted on all pairs (config/path_assessor_forecast.yaml)");

  o.goals = app.add_subcommand(
      "goals", "score goal inference (most likely exit at t_cross - 3 s) on pedestrian pairs");
  o.goals->add_option("pairs", o.log, "headon_pairs.json")->required();
  o.goals->add_option("--beta-per-m", o.goals_beta_per_m, "beta [1/m] (default: fit by sequence)")
      ->check(CLI::PositiveNumber);

  o.goal_candidates = app.add_subcommand(
      "goal-candidates",
      "print the candidate goals of a map (its shape's openings and corridor ends, then its "
      "goal_regions), as the band source's goal inference finds them with default options");
  o.goal_candidates->add_option("map", o.log, "map file (ROS map YAML, walls YAML, scenario)")
      ->required()
      ->check(CLI::ExistingFile);

  ctl::addMetricsCommand(app);
}

int runCtlCommands(CLI::App&, const std::string&) {
  auto& o = opts();
  if (*o.transcript) return transcriptCommand();
  if (*o.summarize) return summarizeCommand();
  if (*o.merge) return mergeCommand();
  if (*o.cm_table) return cmTableCommand();
  if (*o.pedestrians) return pedestriansCommand();
  if (*o.calibrate) return calibrateCommand();
  if (*o.forecast) return forecastCommand();
  if (*o.goals) return goalsCommand();
  if (*o.goal_candidates) return goalCandidatesCommand();
  if (ctl::metricsCommandChosen()) return ctl::runMetricsCommand();
  return 2;
}

}  // namespace coopnav
