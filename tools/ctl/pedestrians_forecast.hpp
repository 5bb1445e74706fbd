#pragma once
/// @file Judgement in time on the real head-on pedestrian pairs (pedestrians.hpp): how well the
/// published CM / IsContributing, and the forecast p_contributing (assessment/forecast.hpp), tell
/// at t_cross − {4, 3, 2, 1, 0} s whether a walker WILL have stepped >= 0.3 m away by the
/// crossing; leave-one-sequence-out, with bootstrap confidence intervals.

#include <cstdint>
#include <string>
#include <vector>

#include "coopnav/assessment/forecast.hpp"
#include "pedestrians.hpp"
#include "profiles/forecast_profile.hpp"

namespace coopnav::ctl {

/// [s] how long before the closest approach the judgement is read.
const std::vector<double>& decisionLeadsS();

/// Bootstrap settings: resamples of the PAIRS of a sequence (both walkers of a pair go together:
/// they see each other), percentile interval.
inline constexpr int kBootstrapResamples = 1000;
inline constexpr std::uint64_t kBootstrapSeed = 46;
inline constexpr double kBootstrapLevel = 0.95;
/// λ of the forecast's L2 penalty on standardised features: fixed, not fitted (two sequences
/// cannot select it leave-one-out without scoring on the held-out one).
inline constexpr double kForecastL2 = 1.0;
/// [s] the forecast is fitted on every annotated time of a walker at most this long before its
/// crossing (the decisions it serves: the paper's round 2 is at t_CROSS ≈ 4 s).
inline constexpr double kForecastFitHorizonS = 6.0;
/// p_contributing above which the forecast says "contributing" (accuracy).
inline constexpr double kForecastThreshold = 0.5;

/// One walker's judgement at one lead: a score (higher = more cooperative) and a verdict. Unknown
/// (no START yet, no features): score at the bottom, verdict "not contributing" (the robot cannot
/// count on it).
struct Judgement {
  bool known{false};
  double score{0.0};
  bool said{false};
};

/// AUC and accuracy of one judge on one sequence (or all) at one lead.
struct DecisionScore {
  std::string ds;  ///< sequence, or "all"
  double lead_s{0.0};
  std::size_t walkers{0};
  std::size_t known{0};      ///< walkers with a judgement by then
  std::size_t positives{0};  ///< walkers with dev_away >= 0.3 m
  double auc{0.0};
  double auc_lo{0.0};
  double auc_hi{0.0};
  double accuracy{0.0};
  double accuracy_lo{0.0};
  double accuracy_hi{0.0};
};

/// One judge's rows: per lead, per sequence then "all".
struct DecisionTable {
  std::string judge;  ///< "paper CM", "calibrated CM (LOSO)", "forecast (LOSO)", ...
  std::string note;   ///< its settings
  std::vector<DecisionScore> rows;
};

/// Judgements of CM at each lead: per walker run of planWalkerRuns(pairs) (round-1 window), the
/// recorder fed the observations up to t_cross − lead, read running (cm_window_m,
/// is_contributing_window). [lead][walker].
std::vector<std::vector<Judgement>> cmJudgements(const std::vector<PedestrianPair>& pairs,
                                                 const assessment::PathAssessorConfig& config);

/// Forecast features of a run's observations up to t_s (nullopt: none yet).
std::optional<assessment::ForecastFeatures> runFeaturesAt(const WalkerRun& run, double t_s);

/// The forecast's training set from the runs of `pairs`: every annotated time within
/// kForecastFitHorizonS of the crossing with features; label dev_away >= kStepAwayTruthM.
assessment::ForecastModel fitForecast(const std::vector<PedestrianPair>& pairs);

/// Scores judgements ([lead][walker], walkers as planWalkerRuns(pairs) orders them) per sequence
/// and pooled, with bootstrap intervals.
DecisionTable scoreJudgements(const std::string& judge, const std::string& note,
                              const std::vector<PedestrianPair>& pairs,
                              const std::vector<std::vector<Judgement>>& judgements);

/// The end-of-interaction judgement on one held-out sequence (ForecastStudy::end_of_interaction).
struct EndOfInteractionFold {
  std::string ds;
  std::size_t pairs{0};
  std::size_t pairs_in_line{0};  ///< the other within kForecastInLineM of the walker's line at t0
  std::size_t ranked{0}, ranked_right{0};                  ///< all pairs judged
  std::size_t ranked_in_line{0}, ranked_right_in_line{0};  ///< ... of them in line
  std::size_t judged{0}, agreeing{0};                      ///< all walkers with a CM
  std::size_t judged_in_line{0}, agreeing_in_line{0};      ///< ... of pairs in line
  double ranking{0.0}, agreement{0.0};                     ///< NaN when none
  std::vector<std::string> misses;  ///< one line per pair ranked wrong or walker judged wrong
};

/// The end-of-interaction judgement of `setting` on the pairs of one sequence `ds`.
EndOfInteractionFold endOfInteraction(const std::vector<PedestrianPair>& pairs,
                                      const std::string& ds, const CalibrationSetting& setting);

struct ForecastStudy {
  std::vector<DecisionTable> tables;  ///< paper, calibrated (LOSO), calibrated (shipped), forecast
  assessment::ForecastModel model;    ///< fit on all pairs (the profile)
  std::vector<std::pair<std::string, assessment::ForecastModel>> fold_models;  ///< per held out
  /// Per sequence: walkers the forecast (LOSO) ranks wrong at 2 s, as the misses table.
  std::string misses;
  /// Per held-out sequence, the end-of-interaction judgement (the calibrated CM's round-1 fit on
  /// the other sequence, read at the crossing): ranking and agreement, split by whether the two
  /// walkers started nearly in line (the sign of CA ambiguous), and every pair it ranks wrong and
  /// walker it judges wrong.
  std::vector<EndOfInteractionFold> end_of_interaction;
};

/// The whole study (deterministic). cal: calibrate(pairs): its folds' round-1 fits are the
/// calibrated CM held out, its profile_setting the shipped calibrated profile.
ForecastStudy runForecastStudy(const std::vector<PedestrianPair>& pairs,
                               const CalibrationResult& cal);

std::string formatDecisionTables(const std::vector<DecisionTable>& tables);
std::string formatForecastStudy(const ForecastStudy& s);
/// The profile file (config/path_assessor_forecast.yaml) and its reader live in
/// daemons/common/profiles, which the path assessor shares.
using coopnav::forecastProfileYaml;
using coopnav::loadForecastProfile;

}  // namespace coopnav::ctl
