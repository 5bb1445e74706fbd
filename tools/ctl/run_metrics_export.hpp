#pragma once
/// @file `coopnav_ctl metrics`: the field's metrics of recorded runs (lib/metrics, docs/metrics.md)
/// from the log alone, written as JSON and CSV. The tracks are the lockstep agent states; the
/// robot's goal is the last COOPNAV_GOALS message of the log; the outcome and the time the robot
/// reached its goal are the simulator's last status; per person the path assessor's last CM sits
/// beside the Responsibility and Engagement shares. With a map, the robot's clearance to walls and
/// the map's shortest path (SPL, path length ratio) come from it; without one, no wall metrics and
/// the straight line.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/metrics/run_metrics.hpp"
#include "json.hpp"
#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"

namespace coopnav::ctl {

inline constexpr const char* kMetricsFormat = "coopnav-metrics/1";

/// The robot's goal in the log's last COOPNAV_GOALS message (the reader does not keep goals, so
/// this reads the file's goal events itself); nullopt when none names the robot.
std::optional<Eigen::Vector2d> robotGoalFromLog(const std::string& path);

/// The tracks, outcome and goal of one run. map: wall clearance and the geodesic shortest path
/// (nullptr: none).
metrics::RunInput metricsInput(const RunLog& run, const RunAnalysis& analysis,
                               const std::optional<Eigen::Vector2d>& robot_goal,
                               const DistanceMap* map);

/// One run's entry: {"scenario", "log", "outcome", "map", <run metrics>..., "persons": [...]}.
Json metricsEntry(const RunLog& run, const RunAnalysis& analysis, const metrics::RunMetrics& m,
                  const std::string& log_name, bool with_map);

/// {"format": kMetricsFormat, "runs": [entries...]}.
Json metricsDocument(const std::vector<Json>& entries);

/// One row per run: the run's scalar metrics, then per person `person<id>_<key>` (the union of
/// columns over the runs, in order of first appearance; empty where a run has none).
std::string metricsCsv(const std::vector<Json>& entries);

}  // namespace coopnav::ctl
