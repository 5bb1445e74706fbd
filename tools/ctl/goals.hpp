#pragma once
/// @file Goal inference (lib/planning/goal_inference.hpp, issue 31) evaluated on the real head-on
/// pedestrian pairs (test/data/pedestrians): does GoalBelief::mostLikely() name where a walker
/// leaves the scene, 3 s before the closest approach?
///
/// Truth: a walker's goal is the last point of its full track (where it leaves the scene).
/// Candidates: the exits of all OTHER walkers of the same sequence (ds), without the evaluated
/// pair's two walkers (leave-pair-out: the truth is not handed in), clustered in a fixed order.
/// A walker whose exit joins no cluster has "no candidate" and counts as wrong in the accuracy
/// over all walkers. Open space: Euclidean distances (no map).

#include <cstddef>
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

/// Leave-one-sequence-out: β fit (max mean_log_p_true, ties to the smaller β) on the other
/// sequences, evaluated on the held-out one.
struct GoalFold {
  std::string held_out_ds;
  double beta_per_m{0.0};
  GoalEvaluation held_out;
};

/// One configuration (clustering × prior) with its cross-validated β.
struct GoalConfigResult {
  GoalEvalOptions options;      ///< beta_per_m: the fit on all pairs (or the one given)
  std::vector<GoalFold> folds;  ///< in order of first appearance of the sequences
  std::size_t walkers{0};       ///< pooled over the folds
  std::size_t with_candidate{0};
  std::size_t correct{0};
  double accuracy_all{0.0};  ///< pooled held-out accuracy
  double accuracy_with_candidate{0.0};
  std::vector<GoalEvaluation> sweep;  ///< all pairs, one per goalBetasPerM()
};

struct GoalReport {
  std::vector<GoalConfigResult>
      configs;  ///< greedy/uniform, greedy/freq, chained/uniform, chained/freq
  bool beta_given{false};
};

/// Runs the four configurations. beta_per_m: use it everywhere instead of fitting.
GoalReport evaluateGoalReport(const std::vector<PedestrianPair>& pairs,
                              std::optional<double> beta_per_m = std::nullopt,
                              const GoalEvalOptions& base = {});

/// Text report of `coopnav_ctl goals` (deterministic; ends with `goal accuracy at t_cross-3s:`
/// lines and RESULT lines).
std::string formatGoalReport(const GoalReport& r);

}  // namespace coopnav::ctl
