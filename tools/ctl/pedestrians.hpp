#pragma once
/// @file The paper's human path assessment (CA, CM, IsContributing; assessment::PathRecorder)
/// evaluated on real head-on pedestrian encounters (test/data/pedestrians, UCY zara01 and
/// students03), and a cross-validated calibration of γ, τ and the side rule on them.
///
/// Each encounter is replayed twice, each walker once as the "human" with the other as the
/// "robot". The truth a walker's CM is compared with is how far it stepped AWAY from the other by
/// the closest approach (dev_away_m, see WalkerResult). The CM window always ends at the closest
/// approach; where it starts is a choice (WindowSetting): the paper's round 1, the onset of the
/// walker's avoidance, or a fixed lead before the closest approach.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/assessment/path_assessment.hpp"

namespace coopnav::ctl {

inline constexpr const char* kPedestrianPairsSchema = "headon_pairs/2";

/// One annotated track (parallel arrays, times strictly increasing).
struct PedestrianTrack {
  long id{0};
  std::vector<double> t_s;
  std::vector<double> x_m;
  std::vector<double> y_m;
};

/// One head-on encounter of the file (only the members this evaluation uses).
struct PedestrianPair {
  std::string ds;                 ///< sequence name ("UCY_zara01", ...)
  double t0_s{0.0};               ///< [s] reference time k0 (the pair is still >= 8 m apart)
  double t_cross_s{0.0};          ///< [s] closest approach
  double heading_a[2]{1.0, 0.0};  ///< unit heading of a at t0_s
  double heading_b[2]{1.0, 0.0};  ///< unit heading of b at t0_s
  PedestrianTrack a;
  PedestrianTrack b;
};

/// Reads a "headon_pairs/2" file. Throws std::runtime_error("<path>: <reason>") on anything this
/// evaluation cannot trust: not JSON, wrong schema, a missing member, arrays of unequal length,
/// non-finite numbers, times not increasing, t0_s/t_cross_s outside a track or out of order, a
/// zero heading.
std::vector<PedestrianPair> loadPedestrianPairs(const std::string& path);

/// Where the CM window starts; it always ends at t_cross_s (STOP at the closest approach).
///  - kRound1 (the paper's): START at t0_s, the reference time (round 1).
///  - kOnset: START at the onset of the walker's own avoidance, as detectAvoidanceOnset() finds
///    it online from the track; a walker with no onset keeps the round-1 START.
///  - kLead: START lead_s before t_cross_s (not before t0_s).
enum class WindowKind : std::int8_t { kRound1 = 0, kOnset = 1, kLead = 2 };
const char* toString(WindowKind k);
/// The kind named by toString(); nullopt for any other name.
std::optional<WindowKind> windowKindFromString(const std::string& name);

struct WindowSetting {
  WindowKind kind{WindowKind::kRound1};
  double lead_s{0.0};  ///< [s] kLead: how long before t_cross_s the window starts, > 0
};
/// "round1", "onset", "lead 2 s".
std::string toString(const WindowSetting& w);

/// [m] lateral deviation from the initial heading line at which an avoidance is detected.
inline constexpr double kOnsetThresholdM = 0.1;
/// [m/s] slowest sideways motion that counts as avoiding: a walker drifts off a heading line
/// measured a few degrees off (2° at 1.3 m/s: 0.045 m/s) without avoiding anybody.
inline constexpr double kOnsetMinLateralSpeedMS = 0.05;

/// The onset of a walker's avoidance.
struct AvoidanceOnset {
  double onset_t_s{0.0};          ///< [s] the sample the growth that crossed the threshold began at
  double detected_t_s{0.0};       ///< [s] the sample the threshold was crossed at (>= onset_t_s)
  std::size_t detected_index{0};  ///< index of that sample in the samples given
};

/// Online onset of an avoidance, from the walker's samples in time order (its annotated
/// positions from t0_s on; nothing after the sample being looked at is used): d_i = u × (p_i −
/// origin_m) is the signed lateral deviation from the initial heading line (u unit). At the first
/// sample i with |d_i| >= threshold_m, with s = sign(d_i), the onset is the earliest sample j <= i
/// from which s·d grew at every sample up to i, each step faster than min_lateral_speed_m_s
/// ("the deviation keeps growing beyond a small threshold"): a robot knows it at sample i, and
/// stamps the recording's START at t_j (the path assessor keeps history_s of observations for a
/// START stamped in the past). nullopt when no sample reaches the threshold (the walker did not
/// avoid, or not by then).
std::optional<AvoidanceOnset> detectAvoidanceOnset(
    const std::vector<double>& t_s, const std::vector<Eigen::Vector2d>& p_m,
    const Eigen::Vector2d& origin_m, const Eigen::Vector2d& heading,
    double threshold_m = kOnsetThresholdM, double min_lateral_speed_m_s = kOnsetMinLateralSpeedMS);

/// One walker in the role of the human (the other walker is the "robot").
struct WalkerResult {
  std::size_t pair_index{0};
  std::string ds;
  long id{0};                  ///< this walker's track id
  long other_id{0};            ///< the other walker's
  std::optional<double> cm_m;  ///< [m] interaction CM from t0_s to t_cross_s; nullopt: no sample
  std::size_t samples{0};      ///< CA samples behind cm_m
  double lateral_m{0.0};  ///< [m] d = u × (p_h(t_cross) − p_h(t0)), u = heading at t0 (> 0 left)
  double other_offset_m{0.0};  ///< [m] u × (p_other(t_cross) − p_h(t_cross)), > 0: other on left
  /// [m] truth: lateral deviation away from the other at the closest approach,
  /// −sign(other_offset_m) · lateral_m (|lateral_m| when other_offset_m == 0).
  double dev_away_m{0.0};
  double t_cross_s{0.0};            ///< [s] the closest approach (the STOP stamp)
  double window_start_s{0.0};       ///< [s] the START stamp (the window's start)
  std::optional<double> onset_t_s;  ///< [s] detectAvoidanceOnset() before t_cross_s, if any
};

/// One walker-run as a sequence of recorder inputs: what the in-process replay feeds a
/// PathRecorder and what `--daemon` publishes to the real path assessor (pedestrians_daemon.hpp),
/// in the same order, so both must give the same CM.
struct WalkerRun {
  WalkerResult walker;  ///< truth and window filled in; cm_m and samples not yet
  /// The human's reference path: the straight line from its t0_s position along its t0_s heading.
  Path2 reference;
  struct Observation {
    double t_s{0.0};
    Eigen::Vector2d human_m{0.0, 0.0};
    Eigen::Vector2d robot_m{0.0, 0.0};  ///< the other walker, interpolated at t_s
  };
  /// At the human's annotated times in [t0_s, t_cross_s].
  std::vector<Observation> observations;
  /// START (stamped walker.window_start_s, against `reference`) is issued right after
  /// observations[start_after]: the first observation at or before the window start (round 1,
  /// lead; at least the first one, so the human is known), or the one the onset was detected at.
  std::size_t start_after{0};
  double stop_t_s{0.0};  ///< [s] STOP stamp (t_cross_s), issued after the last observation
};

/// The runs of every pair, a as the human then b, in pair order.
std::vector<WalkerRun> planWalkerRuns(const std::vector<PedestrianPair>& pairs,
                                      const WindowSetting& window = {});

/// CM of one run replayed through an assessment::PathRecorder (the interaction CM at the STOP)
/// and its sample count; cm nullopt when the run has no observation.
struct RunOutcome {
  std::optional<double> cm_m;
  std::size_t samples{0};
  std::vector<double> ca_m;  ///< the interaction CA (for γ sweeps without replaying)
};
RunOutcome replayRun(const WalkerRun& run, const assessment::PathAssessorConfig& config);

/// Thresholds of the truth (fixed, not calibrated).
inline constexpr double kRankingMinDifferenceM = 0.05;  ///< [m] |Δ dev_away| for a pair to count
inline constexpr double kStepAwayTruthM = 0.3;  ///< [m] dev_away from which a walker "contributed"

struct PedestrianEvaluation {
  assessment::PathAssessorConfig config;
  std::vector<WalkerResult> walkers;  ///< two per pair (a as human, then b as human)
  std::size_t pairs_judged{0};  ///< pairs with |dev_away_a − dev_away_b| >= 0.05 m and both CMs
  std::size_t pairs_ranked_right{0};  ///< of those: larger dev_away has the strictly larger CM
  double ranking{0.0};                ///< pairs_ranked_right / pairs_judged (NaN when none)
  std::size_t walkers_judged{0};      ///< walkers with a CM
  double agreement{0.0};  ///< share of them with (CM > τ) == (dev_away >= 0.3 m) (NaN when none)
  double auc{0.0};        ///< Mann-Whitney AUC of CM, dev_away >= 0.3 m vs the rest (ties ½)
  std::size_t true_positive{0};   ///< CM > τ and dev_away >= 0.3 m
  std::size_t false_positive{0};  ///< CM > τ and dev_away < 0.3 m
  std::size_t false_negative{0};  ///< CM <= τ and dev_away >= 0.3 m
  std::size_t true_negative{0};   ///< CM <= τ and dev_away < 0.3 m
};

/// Replays every pair with both role assignments through assessment::PathRecorder (reference path:
/// the human's straight line from its t0_s position along its t0_s heading; observations at the
/// human's annotated times in [t0_s, t_cross_s], the other's position interpolated at them; the
/// window as `window` says) and scores CM against dev_away_m. config.gamma is per sample
/// (config.sample_period_s).
PedestrianEvaluation evaluateWalkers(const std::vector<PedestrianPair>& pairs,
                                     const assessment::PathAssessorConfig& config,
                                     const WindowSetting& window = {});

/// Fills the scores of e from e.walkers (pairs as consecutive walkers a, b; their cm_m) and
/// e.config.tau_m.
void scoreEvaluation(PedestrianEvaluation& e);

/// γ per sample for a γ per second: γ_s^sample_period_s.
double gammaPerSample(double gamma_per_s, double sample_period_s);

/// One point of the calibration grid.
struct CalibrationSetting {
  double gamma_per_s{0.0};
  assessment::SideRule side_rule{assessment::SideRule::kPathSide};
  double tau_m{0.0};
  WindowSetting window;  ///< the paper's round 1 unless the grid chose another
};

/// Ranking and agreement of one setting on a set of pairs.
struct CalibrationScore {
  double ranking{0.0};
  double agreement{0.0};
  double objective{0.0};  ///< mean of the two (a NaN member counts as 0)
  double auc{0.0};        ///< AUC of CM (does not depend on τ; not in the objective)
};

struct CalibrationFold {
  std::string held_out_ds;   ///< the sequence left out
  std::size_t fit_pairs{0};  ///< pairs fitted on
  std::size_t held_out_pairs{0};
  CalibrationSetting setting;       ///< fit on the other sequences (any window)
  CalibrationScore fit;             ///< its score on them
  CalibrationScore held_out;        ///< its score on the left-out sequence
  CalibrationScore paper_held_out;  ///< the paper profile's score on the left-out sequence
  /// Per window of calibrationWindows(): the fit restricted to it and its held-out score.
  std::vector<CalibrationSetting> window_settings;
  std::vector<CalibrationScore> window_held_out;
};

/// All pairs under one window of calibrationWindows().
struct CalibrationWindowResult {
  WindowSetting window;
  CalibrationSetting fit;      ///< the grid's best with this window, on all pairs
  CalibrationScore fit_score;  ///< its score (in-sample)
  CalibrationScore paper;      ///< the paper's γ, τ and side rule with this window
};

struct CalibrationResult {
  std::vector<CalibrationFold> folds;  ///< one per sequence, in order of first appearance
  CalibrationSetting final_setting;    ///< fit on all pairs, any window
  CalibrationScore final_score;        ///< its score on all pairs (in-sample)
  /// The fit restricted to the round-1 window: the shipped `calibrated` profile
  /// (config/path_assessor_calibrated.yaml), since the dialogue manager STARTs at round 1.
  /// Equal to final_setting when the grid chose round 1.
  CalibrationSetting profile_setting;
  CalibrationScore profile_score;
  CalibrationSetting paper_setting;  ///< γ 0.98 per 0.1 s, τ 0.4 m, path side, round 1
  CalibrationScore paper_score;      ///< its score on all pairs
  std::vector<CalibrationWindowResult> windows;  ///< per window of calibrationWindows()
};

/// The grid (in search order: window outermost, then γ_s, then side rule, then τ ascending).
std::vector<WindowSetting> calibrationWindows();  ///< round1 first, onset, lead 1 2 3 4 s
std::vector<double> calibrationGammasPerS();
std::vector<double> calibrationTausM();

/// Grid search maximising the objective (mean of ranking and agreement); a tie within one
/// window, γ and side rule goes to the larger τ (the verdict claiming cooperation less often),
/// other ties keep the earliest grid point, so the paper's round-1 window wins any tie with
/// another window. Leave-one-sequence-out cross-validation, then a final fit on all pairs.
/// base: the other PathAssessorConfig members (sample period, deadband, ...). Deterministic.
CalibrationResult calibrate(const std::vector<PedestrianPair>& pairs,
                            const assessment::PathAssessorConfig& base = {});

/// The assessor configuration of a setting (γ converted to per sample).
assessment::PathAssessorConfig settingConfig(const CalibrationSetting& setting,
                                             const assessment::PathAssessorConfig& base = {});

/// Text reports of the two coopnav_ctl commands (deterministic; end with RESULT lines).
std::string formatPedestrianEvaluation(const PedestrianEvaluation& e, double gamma_per_s,
                                       const WindowSetting& window = {});
std::string formatCalibration(const CalibrationResult& r);

}  // namespace coopnav::ctl
