#pragma once
/// @file Goal inference (lib/planning/goal_inference.hpp) evaluated on the real head-on
/// pedestrian pairs (test/data/pedestrians): does GoalBelief::mostLikely() name where a walker
/// leaves the scene, 3 s before the closest approach?
///
/// Truth: a walker's goal is the last point of its full track (where it leaves the scene).
/// Candidates: the exits of all OTHER walkers of the same sequence (ds), without the evaluated
/// pair's two walkers (leave-pair-out: the truth is not handed in), clustered in a fixed order.
/// A walker whose exit joins no cluster has "no candidate" and counts as wrong in the accuracy
/// over all walkers. Open space: Euclidean distances (no map).
///
/// Besides the posterior of GoalBelief (path length), the evaluation measures how much of a
/// walker's goal its track can tell at all: its heading at the evaluation time t (mean velocity
/// over the last heading_window_s) against the straight direction from its position at t to its
/// exit. A walker whose exit lies far off that heading turns after t, and nothing in the track up
/// to t says where to.

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pedestrians.hpp"

namespace coopnav::ctl {

/// How the other walkers' exits become candidate goals.
enum class ExitClustering {
  /// Greedy by radius, in order: an exit joins the first cluster whose first exit (its seed) is
  /// within the radius, else starts one.
  kGreedyRadius,
  /// Chained (single linkage): exits within the radius of each other share a cluster, so the
  /// exits along one side of the scene form one opening, as free border runs do on a map.
  kChained,
};

const char* toString(ExitClustering c);

struct GoalEvalOptions {
  double beta_per_m{1.0};        ///< GoalInferenceOptions::beta_per_m [1/m]
  double cluster_radius_m{1.5};  ///< [m] GoalCandidateOptions::min_separation_m's default
  double lead_s{3.0};            ///< observe up to t_cross_s − lead_s [s]
  ExitClustering clustering{ExitClustering::kChained};
  bool frequency_prior{true};  ///< prior ∝ number of exits in the cluster; false: uniform
  /// Multiplies the posterior by a von Mises likelihood of the heading at t given the goal:
  /// (1/M) Σ_m exp(κ (cos θ_m − 1)) over the cluster's M exits, θ_m the angle between the heading
  /// and the direction to exit m (a cluster is an opening; the walker heads for one of its points).
  bool heading_term{false};
  double heading_kappa{0.0};       ///< κ of the heading term [1] (0: flat, the term does nothing)
  double heading_window_s{1.0};    ///< [s] heading at t = displacement over this window / time
  double min_heading_step_m{0.2};  ///< [m] a shorter displacement over the window: no heading
};

/// One walker of one pair.
struct GoalCase {
  std::size_t pair_index{0};
  std::string ds;
  long id{0};
  std::size_t candidates{0};    ///< clusters offered
  std::size_t observations{0};  ///< track samples up to t_cross_s − lead_s
  bool has_candidate{false};    ///< its exit joins a cluster
  bool correct{false};          ///< mostLikely() is that cluster
  double p_true{0.0};           ///< posterior of that cluster (0 without one)
  /// The track after t (not seen by any predictor; it measures what can be predicted at all).
  bool has_heading{false};  ///< walked >= min_heading_step_m over the heading window
  double exit_off_heading_deg{std::numeric_limits<double>::quiet_NaN()};  ///< heading vs exit
  /// Length of the rest of the track from t to the exit / straight distance (NaN within 0.5 m).
  double remaining_path_ratio{std::numeric_limits<double>::quiet_NaN()};
  /// Heading predictor: the cluster with the exit best aligned with the heading (-1: no heading).
  int heading_pick{-1};
  bool heading_correct{false};  ///< heading_pick is the truth's cluster
};

struct GoalEvaluation {
  GoalEvalOptions options;
  std::vector<GoalCase> cases;  ///< pair order, a then b
  std::size_t walkers{0};
  std::size_t with_candidate{0};
  std::size_t correct{0};
  double accuracy_all{0.0};             ///< correct / walkers (NaN when none)
  double accuracy_with_candidate{0.0};  ///< correct / with_candidate (NaN when none)
  double mean_log_p_true{0.0};          ///< mean ln max(p_true, 1e-12) over those with a candidate
};

/// Evaluates every walker of every pair (of sequence only_ds when not empty). Deterministic.
GoalEvaluation evaluateGoalInference(const std::vector<PedestrianPair>& pairs,
                                     const GoalEvalOptions& options,
                                     const std::string& only_ds = "");

/// The β grid [1/m] of the sweep and of the fit.
std::vector<double> goalBetasPerM();
/// The κ grid of the heading term's fit (0 included: the fit may drop the term).
std::vector<double> goalHeadingKappas();

/// Heading-term factor of one cluster (see GoalEvalOptions::heading_term): heading and the
/// directions from the walker's position to each member exit; members at the position are skipped
/// (all skipped: 1).
double headingLikelihood(const Eigen::Vector2d& heading, const Eigen::Vector2d& position_m,
                         const std::vector<Eigen::Vector2d>& members_m, double kappa);

/// Leave-one-sequence-out: β (and κ with the heading term) fit (max mean_log_p_true, ties to the
/// smaller κ, then the smaller β) on the other sequences, evaluated on the held-out one.
struct GoalFold {
  std::string held_out_ds;
  double beta_per_m{0.0};
  double heading_kappa{0.0};
  GoalEvaluation held_out;
};

/// One configuration (clustering × prior × heading term) with its cross-validated β (and κ).
struct GoalConfigResult {
  GoalEvalOptions options;      ///< beta_per_m, heading_kappa: the fit on all pairs
  std::vector<GoalFold> folds;  ///< in order of first appearance of the sequences
  std::size_t walkers{0};       ///< pooled over the folds
  std::size_t with_candidate{0};
  std::size_t correct{0};
  double accuracy_all{0.0};  ///< pooled held-out accuracy
  double accuracy_with_candidate{0.0};
  std::vector<GoalEvaluation> sweep;        ///< all pairs, one per goalBetasPerM() (κ: the fit's)
  std::vector<GoalEvaluation> kappa_sweep;  ///< heading term: one per goalHeadingKappas()
};

/// What the track up to t can tell, over one set of walkers (all, a sequence, or a subset by
/// how far the exit lies off the heading at t). Correct counts are held-out (cross-validated).
struct GoalCeilingRow {
  std::string name;
  std::size_t walkers{0};
  std::size_t with_heading{0};  ///< has_heading
  std::size_t off_30deg{0};     ///< exit more than 30° off the heading at t
  std::size_t off_45deg{0};     ///< more than 45°
  double median_off_heading_deg{std::numeric_limits<double>::quiet_NaN()};
  double median_path_ratio{std::numeric_limits<double>::quiet_NaN()};  ///< remaining / straight
  std::size_t path_ratio_above_1_2{0};  ///< remaining path > 1.2 × straight distance
  std::size_t heading_correct{0};       ///< heading predictor
  std::size_t path_correct{0};          ///< chained + exit-frequency prior (path length)
  std::size_t combined_correct{0};      ///< chained + exit-frequency prior + heading term
  std::size_t either_correct{0};  ///< path or heading predictor right (an oracle picks): a bound
};

struct GoalReport {
  /// greedy/uniform, greedy/freq, chained/uniform, chained/freq, chained/freq + heading
  std::vector<GoalConfigResult> configs;
  /// all, per sequence, exit within 30° of the heading at t, more than 30° off, more than 45°
  /// off, no heading at t
  std::vector<GoalCeilingRow> ceiling;
  /// Accuracy if every walker whose exit lies within 30° of its heading at t were right and the
  /// others as the path-length posterior has them: what a better use of the track alone can reach.
  double straight_on_perfect_bound{std::numeric_limits<double>::quiet_NaN()};
  bool beta_given{false};
};

/// Runs the five configurations. beta_per_m: use it everywhere instead of fitting (κ still fit).
GoalReport evaluateGoalReport(const std::vector<PedestrianPair>& pairs,
                              std::optional<double> beta_per_m = std::nullopt,
                              const GoalEvalOptions& base = {});

/// Text report of `coopnav_ctl goals` (deterministic; ends with `goal accuracy at t_cross-3s:`
/// lines and RESULT lines).
std::string formatGoalReport(const GoalReport& r);

}  // namespace coopnav::ctl
