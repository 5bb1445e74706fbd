// coopnav_ctl's run analysis (command.hpp): what a recorded run (an LCM log) says, as text and
// structured files for the experiment layer (tools/exp).
//   transcript LOG [--scenario NAME] [--no-sim-status] [--no-unknown] [--no-final-cm]
//              [--with-status]
//   summarize LOG --out FILE [--scenario NAME] [--merge]
//   merge-summaries OUT INPUT...
//   cm-table SUMMARY
//   trace LOG --json FILE [--map FILE] [--scenario NAME]
//   metrics LOG... [--json F] [--csv F] [--map FILE] [--scenario NAME]
#include <filesystem>
#include <iostream>
#include <memory>

#include "command.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "logfile/log_reader.hpp"
#include "maps/map_loader.hpp"
#include "run_analysis.hpp"
#include "run_metrics_export.hpp"
#include "summary.hpp"
#include "trace.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

// Reads the log; reports what was skipped on stderr (never on stdout, which must be the same
// for the same message contents). Returns false when the log has no coopnav message at all.
bool loadRun(const std::string& path, RunLog& run) {
  run = readRunLog(path);
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

/// The scenario's name: the one given, else the log's sim status, else the log file's stem.
std::string runName(const RunAnalysis& a, const std::string& log) {
  if (!a.scenario.empty()) return a.scenario;
  return std::filesystem::path(log).stem().string();
}

class TranscriptCommand final : public Command {
 public:
  explicit TranscriptCommand(CLI::App& sub) {
    sub.add_option("log", log_, "LCM log of one run (lcm-logger)")->required();
    sub.add_option("--scenario", scenario_, "name in the header (default: from the log)");
    sub.add_flag("--no-sim-status", no_sim_status_,
                 "leave out the final simulator status (replays have none)");
    sub.add_flag("--no-unknown", no_unknown_, "leave out situation-unknown notes");
    sub.add_flag("--no-final-cm", no_final_cm_, "leave out the final CM lines");
    sub.add_flag("--with-status", with_status_,
                 "add daemons' DEGRADED reports (wall-clock: not deterministic)");
  }

  int run(const std::string&) override {
    RunLog run;
    if (!loadRun(log_, run)) return 1;
    const auto analysis = analyseRun(run, scenario_);
    if (!scenario_.empty() && analysis.final_status &&
        run.sim_status[*analysis.final_status].scenario != scenario_)
      std::cerr << "coopnav_ctl: note: the log's sim status names scenario '"
                << printable(run.sim_status[*analysis.final_status].scenario) << "', not '"
                << printable(scenario_) << "'\n";
    TranscriptOptions topt;
    topt.include_sim_status = !no_sim_status_;
    topt.include_unknown = !no_unknown_;
    topt.include_final_cm = !no_final_cm_;
    topt.include_daemon_status = with_status_;
    std::cout << formatTranscript(runName(analysis, log_), buildTranscript(run, analysis, topt));
    return 0;
  }

 private:
  std::string log_;
  std::string scenario_;
  bool no_sim_status_{false};
  bool no_unknown_{false};
  bool no_final_cm_{false};
  bool with_status_{false};
};

class SummarizeCommand final : public Command {
 public:
  explicit SummarizeCommand(CLI::App& sub) {
    sub.add_option("log", log_, "LCM log of one run")->required();
    sub.add_option("--scenario", scenario_, "scenario name (default: from the log)");
    sub.add_option("--out", out_, "summary file to write")->required();
    sub.add_flag("--merge", merge_into_out_,
                 "merge into --out if it exists (replacing this scenario's entry)");
  }

  int run(const std::string&) override {
    RunLog run;
    if (!loadRun(log_, run)) return 1;
    auto analysis = analyseRun(run, scenario_);
    analysis.scenario = runName(analysis, log_);
    const auto entry = summarizeRun(run, analysis, std::filesystem::path(log_).filename().string());
    Json doc = summaryDocument({entry});
    if (merge_into_out_ && std::filesystem::exists(out_))
      doc = mergeSummaries({readSummaryFile(out_), doc});
    writeTextFile(out_, dumpJson(doc));
    return 0;
  }

 private:
  std::string log_;
  std::string scenario_;
  std::string out_;
  bool merge_into_out_{false};
};

class MergeSummariesCommand final : public Command {
 public:
  explicit MergeSummariesCommand(CLI::App& sub) {
    sub.add_option("out", out_, "summary file to write")->required();
    sub.add_option("inputs", inputs_, "summary files, later ones win per scenario")->required();
  }

  int run(const std::string&) override {
    std::vector<Json> docs;
    for (const auto& in : inputs_) docs.push_back(readSummaryFile(in));
    writeTextFile(out_, dumpJson(mergeSummaries(docs)));
    return 0;
  }

 private:
  std::string out_;
  std::vector<std::string> inputs_;
};

class CmTableCommand final : public Command {
 public:
  explicit CmTableCommand(CLI::App& sub) {
    sub.add_option("summary", summary_, "summary.json")->required();
  }

  int run(const std::string&) override {
    std::cout << formatCmTable(readSummaryFile(summary_));
    return 0;
  }

 private:
  std::string summary_;
};

class TraceCommand final : public Command {
 public:
  explicit TraceCommand(CLI::App& sub) {
    sub.add_option("log", log_, "LCM log of one run")->required()->check(CLI::ExistingFile);
    sub.add_option("--json", json_, "trace file to write")->required();
    sub.add_option("--map", map_,
                   "the run's scenario file (its map section) or a map file; the run directory's "
                   "scenario.path names it")
        ->check(CLI::ExistingFile);
    sub.add_option("--scenario", scenario_, "scenario name (default: from the log)");
  }

  int run(const std::string&) override {
    RunLog run;
    if (!loadRun(log_, run)) return 1;
    auto analysis = analyseRun(run, scenario_);
    analysis.scenario = runName(analysis, log_);
    writeTextFile(json_, dumpJson(traceDocument(run, analysis, log_, map_)));
    return 0;
  }

 private:
  std::string log_;
  std::string json_;
  std::string map_;
  std::string scenario_;
};

/// The field's metrics of recorded runs (run_metrics_export.hpp, docs/metrics.md). Exit status
/// 1 when a log cannot be read or holds no agent states (the other logs' rows are written).
class MetricsCommand final : public Command {
 public:
  explicit MetricsCommand(CLI::App& sub) {
    sub.add_option("logs", logs_, "LCM logs, one run each")->required();
    sub.add_option("--json", json_out_, "JSON file to write (default: JSON on stdout)");
    sub.add_option("--csv", csv_out_, "CSV file to write (one row per run)");
    sub.add_option("--map", map_,
                   "the runs' map (ROS map YAML, walls YAML or scenario): clearance to walls and "
                   "the map's shortest path for SPL; without it, no wall metrics and the straight "
                   "line")
        ->check(CLI::ExistingFile);
    sub.add_option("--scenario", scenario_, "scenario name (default: from each log)");
  }

  int run(const std::string&) override {
    std::unique_ptr<GridDistanceField> field;
    if (!map_.empty()) {
      MapLoadOptions mo;
      mo.build_tree = false;
      field = std::make_unique<GridDistanceField>(loadMap(map_, mo).grid);
    }
    std::vector<Json> entries;
    int status = 0;
    for (const auto& path : logs_) {
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
      auto analysis = analyseRun(run, scenario_);
      analysis.scenario = runName(analysis, path);
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
    if (json_out_.empty())
      std::cout << json;
    else
      writeTextFile(json_out_, json);
    if (!csv_out_.empty()) writeTextFile(csv_out_, metricsCsv(entries));
    return status;
  }

 private:
  std::vector<std::string> logs_;
  std::string json_out_;
  std::string csv_out_;
  std::string map_;
  std::string scenario_;
};

}  // namespace

void addRunCommands(CLI::App& app, CommandTable& table) {
  addCommand<TranscriptCommand>(
      app, table, "transcript",
      "print what the robot said and did in a recorded run (deterministic text)");
  addCommand<SummarizeCommand>(app, table, "summarize", "write summary.json of a recorded run");
  addCommand<MergeSummariesCommand>(app, table, "merge-summaries", "merge summary files into one");
  addCommand<CmTableCommand>(app, table, "cm-table",
                             "print the CM table beside the paper's Table I");
  addCommand<TraceCommand>(app, table, "trace",
                           "write a recorded run as JSON for plots: states, assessments, CA, "
                           "utterances, actions, modes, the map");
  addCommand<MetricsCommand>(app, table, "metrics",
                             "the field's social-navigation metrics of recorded runs "
                             "(docs/metrics.md): JSON and CSV, one row per run");
}

}  // namespace coopnav::ctl
