#pragma once
/// @file `coopnav_ctl pedestrians --daemon`: the pedestrian walker-runs (pedestrians.hpp) through
/// the real coopnav_path_assessor process over LCM, compared with the in-process replay.
///
/// The tool spawns the daemon on a private udpm URL and plays the dialogue manager and the
/// tracker for it, free-running (step -1): per walker-run, under a fresh human id, the human's
/// reference path (reference_paths_t), then every observation (agent_states_t: robot = the other
/// walker, human = this walker, utime from the track time), START and STOP
/// (path_assessor_control_t) where WalkerRun puts them, and one last agent-states message at the
/// last observation's time (ignored as an observation) so that the assessment after STOP is
/// published. After each agent-states message it waits for that message's path_assessment_t, so
/// nothing is sent faster than the daemon handles it.

#include <string>
#include <vector>

#include "pedestrians.hpp"

namespace coopnav::ctl {

/// ttl=0: host only; a port of its own, apart from a running stack's (7667) and the tests'.
inline constexpr const char* kPedestrianDaemonUrl = "udpm://239.255.76.67:7980?ttl=0";

/// [m] |CM_daemon − CM_in_process| within which the two count as the same computation.
inline constexpr double kDaemonAgreementM = 1e-9;

struct DaemonRunOptions {
  /// The coopnav_path_assessor binary; "" = the build tree's, beside this coopnav_ctl.
  std::string path_assessor;
  /// Its config; "" = config/path_assessor.yaml (`paper`) or config/path_assessor_calibrated.yaml
  /// (`calibrated`), found from the working directory, else from the build tree's parent.
  std::string config_path;
  std::string profile{"paper"};        ///< which default config ("paper" | "calibrated")
  std::vector<std::string> overrides;  ///< --set key=value, passed to the daemon
  std::string lcm_url{kPedestrianDaemonUrl};
  double ready_timeout_s{15.0};  ///< [s] for the daemon's first status message
  double reply_timeout_s{5.0};   ///< [s] for each assessment
};

struct DaemonRunResult {
  std::string path_assessor;  ///< the binary run
  std::string config_path;    ///< the config it ran with
  /// The daemon's recorder settings (its --print-config) and profile name; the in-process replay
  /// used the same.
  assessment::PathAssessorConfig config;
  std::string profile;
  PedestrianEvaluation daemon;       ///< CMs from the daemon's last assessment of each run
  PedestrianEvaluation in_process;   ///< CMs from replayRun() with config
  double max_abs_dcm_m{0.0};         ///< max |CM_daemon − CM_in_process| over the walkers
  std::size_t sample_mismatches{0};  ///< walkers whose sample counts (or CM presence) differ
  std::size_t messages_sent{0};      ///< agent states, reference paths and controls
};

/// The coopnav_path_assessor beside this executable in the build tree (COOPNAV_BUILD_DIR wins).
std::string defaultPathAssessorBinary();

/// Runs every pair's walker-runs through the daemon. Throws std::runtime_error with a clear
/// reason when the daemon cannot start, rejects its config, dies, or an assessment does not come
/// within reply_timeout_s (or does not show the recording STARTed / STOPped). The child is
/// stopped (SIGTERM, then SIGKILL after 3 s) and waited for on every path.
DaemonRunResult runPedestriansThroughDaemon(const std::vector<PedestrianPair>& pairs,
                                            const WindowSetting& window,
                                            const DaemonRunOptions& options);

/// Text report: the daemon's scores (formatPedestrianEvaluation) and the agreement with the
/// in-process replay (ends with RESULT lines).
std::string formatDaemonRun(const DaemonRunResult& r, const WindowSetting& window);

}  // namespace coopnav::ctl
