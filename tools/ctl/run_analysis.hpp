#pragma once
/// @file What the log tools derive from one recorded run, shared by the transcript, the summary
/// and the trace: per-human interaction CA, round-1 crossing points, docking, and the wire
/// codes spelled as words.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "logfile/log_reader.hpp"

namespace coopnav::ctl {

/// γ values reported in summary.json ("cm_by_gamma"), around the paper's 0.98 (§III).
inline constexpr double kSummaryGammas[] = {0.80, 0.85, 0.90, 0.95, 0.98, 0.99, 1.0};
/// Round-1 threshold used to place CP_h / CP_r when no round-1 utterance was logged [s].
inline constexpr double kRound1TCross_s = 7.0;

// Wire codes as words (the lcmtypes' constant names).
std::string speechActName(std::int8_t act);       ///< utterance_t.ACT_*, e.g. "INFORM_DIRECTION"
std::string robotActionName(std::int8_t action);  ///< robot_action_t.ACTION_*: "DOCK", "RESUME"
std::string recorderCommandName(std::int8_t command);  ///< "START", "STOP", "RESET"
std::string simStateName(std::int8_t state);           ///< sim_status_t.STATE_*
std::string crossingName(std::int8_t status);          ///< situation_t.CROSSING_*
std::string predicateName(std::int8_t pred);           ///< "TRUE", "FALSE", "UNKNOWN"
std::string directionName(std::int8_t dir);            ///< "left", "right", "undefined"
/// utterance_t.DELIVERY_*: "said", "muted", "too_late" ("delivery_<n>" for any other code).
std::string deliveryName(std::int8_t delivery);
/// True unless the utterance was decided but not said (muted, too late); an unknown code counts
/// as said, as the transcript prints it.
bool wasSaid(std::int8_t delivery);

double utimeToS(std::int64_t utime);

/// One human's path-assessment history, rebuilt from the published messages.
struct HumanAnalysis {
  std::int32_t id{0};
  /// Index of this human's last path_assessment_t in RunLog::assessments.
  std::optional<std::size_t> last_assessment;
  /// CA since the start of the last interaction (no reset), rebuilt as "the first
  /// (interaction_samples - window_samples) samples of the previous rebuild, then this window";
  /// complete only when every window message carried all its samples and no message was missed
  /// (checked against interaction_samples of the last message).
  std::vector<double> interaction_ca_m;
  bool interaction_ca_complete{false};
  /// Sample indices in interaction_ca_m where a decision window began (0 and each reset).
  std::vector<std::size_t> window_starts;
  /// [s] Time of the START command of the last interaction; nullopt when none was logged.
  std::optional<double> recorder_start_s;
  bool docked{false};  ///< a DOCK action was addressed to this human
  /// Index into RunLog::situations of the situation at the first round (the first utterance's
  /// step, else the first with t_CROSS <= kRound1TCross_s); nullopt when neither exists.
  std::optional<std::size_t> first_round_situation;
};

struct RunAnalysis {
  std::string scenario;               ///< --scenario, else the sim status' scenario, else ""
  std::vector<HumanAnalysis> humans;  ///< every human id seen, ascending
  /// Index of the last sim_status_t; nullopt when the log has none.
  std::optional<std::size_t> final_status;
  /// (human id, utime) -> index of the situation of that human at that time.
  std::map<std::pair<std::int32_t, std::int64_t>, std::size_t> situation_at;

  const HumanAnalysis* human(std::int32_t id) const;
  /// t_CROSS of the human's situation at utime; NaN when none was logged.
  double tCrossAt(const RunLog& run, std::int32_t human_id, std::int64_t utime) const;
};

/// scenario_override "" = take the name from the log.
RunAnalysis analyseRun(const RunLog& run, const std::string& scenario_override = "");

}  // namespace coopnav::ctl
