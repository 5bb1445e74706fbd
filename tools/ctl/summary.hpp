#pragma once
/// @file summary.json of a set of runs and the CM table beside the paper's Table I.
///
/// Layout: {"format": "coopnav-summary/1", "scenarios": [<scenario>, ...]}, one entry per
/// scenario name. Per human it reports both CMs the path assessor publishes: the window CM (since
/// the last reset, what round 2 decides on) and the interaction CM (since round 1, no reset,
/// what Table I reports; design-readings "CM windows"), and the CM recomputed for several γ with
/// coopnav::assessment::discountedMean from the logged CA.

#include <string>
#include <vector>

#include "json.hpp"
#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"

namespace coopnav::ctl {

inline constexpr const char* kSummaryFormat = "coopnav-summary/1";

/// What the robot did, from its velocity commands in the log (in log order).
struct RobotBehaviourCounts {
  std::int64_t docks{0};        ///< entries into MODE_DOCKING (from any other mode)
  std::int64_t retreats{0};     ///< entries into MODE_RETREATING
  std::int64_t guard_steps{0};  ///< commands with guard != GUARD_NONE
  std::int64_t commands{0};     ///< commands read
};
RobotBehaviourCounts countRobotBehaviour(const RunLog& run);

/// The summary entry of one run. log_name: shown as "log" (a file name, not a path).
Json summarizeRun(const RunLog& run, const RunAnalysis& analysis, const std::string& log_name);

/// {"format": ..., "scenarios": [entries...]}.
Json summaryDocument(const std::vector<Json>& scenario_entries);

/// Merges summary documents: scenarios in order of first appearance, a later entry with the same
/// name replacing the earlier one. Throws std::runtime_error when an input is not a summary.
Json mergeSummaries(const std::vector<Json>& documents);

/// Reads a summary file (throws std::runtime_error naming the file on any problem).
Json readSummaryFile(const std::string& path);
/// Writes text to path (throws std::runtime_error on failure).
void writeTextFile(const std::string& path, const std::string& text);

/// Paper Table I (§III) CM for a scenario name starting with open_/narrow_ + facilitating/minimal;
/// NaN for any other scenario.
double paperTableCm(const std::string& scenario);

/// The CM table: one row per scenario and human, paper rows first in Table I order.
std::string formatCmTable(const Json& summary);

}  // namespace coopnav::ctl
