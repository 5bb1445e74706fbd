#include "metrics_command.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "coopnav/distance/grid_distance_field.hpp"
#include "maps/map_loader.hpp"
#include "run_metrics_export.hpp"
#include "summary.hpp"

namespace coopnav::ctl {
namespace {

struct MetricsCommandOptions {
  CLI::App* app{nullptr};
  std::vector<std::string> logs;
  std::string json_out;
  std::string csv_out;
  std::string map;
  std::string scenario;
};

MetricsCommandOptions& opts() {
  static MetricsCommandOptions o;
  return o;
}

}  // namespace

void addMetricsCommand(CLI::App& app) {
  auto& o = opts();
  o.app = app.add_subcommand(
      "metrics",
      "the field's social-navigation metrics of recorded runs (docs/metrics.md): JSON and CSV, "
      "one row per run");
  o.app->add_option("logs", o.logs, "LCM logs, one run each")->required();
  o.app->add_option("--json", o.json_out, "JSON file to write (default: JSON on stdout)");
  o.app->add_option("--csv", o.csv_out, "CSV file to write (one row per run)");
  o.app
      ->add_option("--map", o.map,
                   "the runs' map (ROS map YAML, walls YAML or scenario): clearance to walls and "
                   "the map's shortest path for SPL; without it, no wall metrics and the straight "
                   "line")
      ->check(CLI::ExistingFile);
  o.app->add_option("--scenario", o.scenario, "scenario name (default: from each log)");
}

bool metricsCommandChosen() { return opts().app && *opts().app; }

int runMetricsCommand() {
  const auto& o = opts();
  std::unique_ptr<GridDistanceField> field;
  if (!o.map.empty()) {
    MapLoadOptions mo;
    mo.build_tree = false;
    field = std::make_unique<GridDistanceField>(loadMap(o.map, mo).grid);
  }
  std::vector<Json> entries;
  int status = 0;
  for (const auto& path : o.logs) {
    RunLog run;
    try {
      run = readRunLog(path);
    } catch (const std::exception& e) {
      std::cerr << "coopnav_ctl metrics: " << e.what() << "\n";
      status = 1;
      continue;
    }
    if (run.counts.anyCorruption())
      std::cerr << "coopnav_ctl metrics: " << path
                << ": skipped broken data: " << run.counts.describe() << "\n";
    if (run.agent_states.empty()) {
      std::cerr << "coopnav_ctl metrics: " << path << ": no agent states, no tracks\n";
      status = 1;
      continue;
    }
    auto analysis = analyseRun(run, o.scenario);
    if (analysis.scenario.empty()) analysis.scenario = std::filesystem::path(path).stem().string();
    const auto goal = robotGoalFromLog(path);
    if (!goal)
      std::cerr << "coopnav_ctl metrics: " << path
                << ": no robot goal in the log: no distance-to-goal metrics\n";
    const auto input = metricsInput(run, analysis, goal, field.get());
    const auto m = metrics::computeRunMetrics(input);
    entries.push_back(metricsEntry(
        run, analysis, m, std::filesystem::path(path).filename().string(), field != nullptr));
  }
  const std::string json = dumpJson(metricsDocument(entries));
  if (o.json_out.empty())
    std::cout << json;
  else
    writeTextFile(o.json_out, json);
  if (!o.csv_out.empty()) writeTextFile(o.csv_out, metricsCsv(entries));
  return status;
}

}  // namespace coopnav::ctl
