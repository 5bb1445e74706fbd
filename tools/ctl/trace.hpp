#pragma once
/// @file `coopnav_ctl trace`: one recorded run as structured data for plotting and analysis
/// (tools/exp/coopnav_exp/figures.py draws the paper's Figs. 5-8 from it): the robot's and every
/// human's states over time, each human's path assessments (CM, IsContributing, τ, γ, profile)
/// and interaction CA with the time of each sample, the utterances, the robot actions, the band
/// source's mode changes, the crossing points at the first round, the outcome, and the map the
/// run used (as its scenario gives it, with the loaded grid's obstacle cells). Deterministic: the
/// same log and map give the same bytes (times are message times, never the wall clock).

#include <string>

#include "json.hpp"
#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"

namespace coopnav::ctl {

/// Format tag and version of the trace document ("format": "coopnav-trace", "version": 1).
inline constexpr int kTraceVersion = 1;

/// The trace of a run. map_path "" = no map section ("map": null); else a scenario file (its
/// `map:` section) or a map file loadMap() reads. Throws MapLoadError when the map does not load.
Json traceDocument(const RunLog& run, const RunAnalysis& analysis, const std::string& log_path,
                   const std::string& map_path);

/// The map part of the trace (Json object), from a scenario or map file.
Json traceMap(const std::string& map_path);

}  // namespace coopnav::ctl
