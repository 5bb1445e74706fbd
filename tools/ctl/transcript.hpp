#pragma once
/// @file The transcript of a recorded run: what the robot said (and decided but did not say: muted,
/// or too late to end before the crossing) and did, when (simulated time) and at which t_CROSS, why
/// a situation was unknown (first occurrence of each reason), the final CM per human and the final
/// simulator status. Deterministic: the same message contents give the same bytes (no wall-clock
/// values, fixed float formats, a fixed order within a time stamp).

#include <cstdint>
#include <string>
#include <vector>

#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"

namespace coopnav::ctl {

struct TranscriptEntry {
  enum class Kind : std::uint8_t {
    kSay,
    kAction,
    kRecorder,
    kUnknown,
    kDaemonDegraded,
    kFinalCm,
    kSimStatus,
    kRestart  ///< a daemon restarted mid-run: state recovered, or lost (degraded)
  };
  Kind kind{Kind::kSay};
  std::int64_t utime{0};
  std::int32_t human_id{-1};  ///< -1: not about one human (sim status)
  double t_cross_s{0.0};      ///< NaN when unknown / not applicable
  std::string what;           ///< act, action, command, crossing status or sim state name
  std::string text;           ///< utterance text or reason
  int round{0};               ///< utterances only
  std::string direction;      ///< utterances only: "left", "right", "undefined"
  /// Utterances only: "said", "muted", "too_late" (deliveryName); a SAY line unless muted or too
  /// late (NOT SAID).
  std::string delivery;
  double speech_start_s{0.0};     ///< utterances only: [s] after utime when speaking starts
  double speech_duration_s{0.0};  ///< utterances only: [s] how long saying the text takes
  std::string line;               ///< the formatted transcript line (no newline)
};

struct TranscriptOptions {
  bool include_unknown{true};     ///< situation-unknown notes
  bool include_final_cm{true};    ///< per-human final CM lines
  bool include_sim_status{true};  ///< the final simulator status line (absent in replays)
  /// At most this many distinct unknown reasons per human (reasons may carry numbers).
  int max_unknown_reasons{20};
  /// Daemons' DEGRADED status reports (first per daemon and detail). Off by default: they are
  /// wall-clock reports, placed at the last simulated step logged before them, so their lines
  /// may differ between identical runs.
  bool include_daemon_status{false};
};

std::vector<TranscriptEntry> buildTranscript(const RunLog& run, const RunAnalysis& analysis,
                                             const TranscriptOptions& options = {});

/// Header line "# scenario NAME", one line per entry, "\n"-terminated.
std::string formatTranscript(const std::string& scenario,
                             const std::vector<TranscriptEntry>& entries);

/// "12.30" style fixed formats used throughout the tools ("-" for NaN, "inf" / "-inf").
std::string fixed(double v, int decimals);

}  // namespace coopnav::ctl
