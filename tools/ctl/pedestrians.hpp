#pragma once
/// @file The paper's human path assessment (CA, CM, IsContributing; assessment::PathRecorder)
/// evaluated on real head-on pedestrian encounters (test/data/pedestrians, UCY zara01 and
/// students03), and a cross-validated calibration of γ, τ and the side rule on them.
///
/// Each encounter is replayed twice, each walker once as the "human" with the other as the
/// "robot". The truth a walker's CM is compared with is how far it stepped AWAY from the other by
/// the closest approach (dev_away_m, see WalkerResult).

#include <cstddef>
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
};

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
/// human's annotated times in [t0_s, t_cross_s], the other's position interpolated at them) and
/// scores CM against dev_away_m. config.gamma is per sample (config.sample_period_s).
PedestrianEvaluation evaluateWalkers(const std::vector<PedestrianPair>& pairs,
                                     const assessment::PathAssessorConfig& config);

/// γ per sample for a γ per second: γ_s^sample_period_s.
double gammaPerSample(double gamma_per_s, double sample_period_s);

/// One point of the calibration grid.
struct CalibrationSetting {
  double gamma_per_s{0.0};
  assessment::SideRule side_rule{assessment::SideRule::kPathSide};
  double tau_m{0.0};
};

/// Ranking and agreement of one setting on a set of pairs.
struct CalibrationScore {
  double ranking{0.0};
  double agreement{0.0};
  double objective{0.0};  ///< mean of the two (a NaN member counts as 0)
};

struct CalibrationFold {
  std::string held_out_ds;   ///< the sequence left out
  std::size_t fit_pairs{0};  ///< pairs fitted on
  std::size_t held_out_pairs{0};
  CalibrationSetting setting;       ///< fit on the other sequences
  CalibrationScore fit;             ///< its score on them
  CalibrationScore held_out;        ///< its score on the left-out sequence
  CalibrationScore paper_held_out;  ///< the paper profile's score on the left-out sequence
};

struct CalibrationResult {
  std::vector<CalibrationFold> folds;  ///< one per sequence, in order of first appearance
  CalibrationSetting final_setting;    ///< fit on all pairs
  CalibrationScore final_score;        ///< its score on all pairs (in-sample)
  CalibrationSetting paper_setting;    ///< γ 0.98 per 0.1 s, τ 0.4 m, path side
  CalibrationScore paper_score;        ///< its score on all pairs
};

/// The grid (in search order: γ_s outermost, then side rule, then τ ascending).
std::vector<double> calibrationGammasPerS();
std::vector<double> calibrationTausM();

/// Grid search maximising the objective (mean of ranking and agreement); a tie within one γ and
/// side rule goes to the larger τ (the verdict claiming cooperation less often), other ties keep
/// the earliest grid point. Leave-one-sequence-out cross-validation, then a final fit on all pairs.
/// base: the other PathAssessorConfig members (sample period, deadband, ...). Deterministic.
CalibrationResult calibrate(const std::vector<PedestrianPair>& pairs,
                            const assessment::PathAssessorConfig& base = {});

/// The assessor configuration of a setting (γ converted to per sample).
assessment::PathAssessorConfig settingConfig(const CalibrationSetting& setting,
                                             const assessment::PathAssessorConfig& base = {});

/// Text reports of the two coopnav_ctl commands (deterministic; end with RESULT lines).
std::string formatPedestrianEvaluation(const PedestrianEvaluation& e, double gamma_per_s);
std::string formatCalibration(const CalibrationResult& r);

}  // namespace coopnav::ctl
