#pragma once
/// @file Joint optimisation of several timed elastic bands (the planning agent's and one per
/// anticipated agent) as ONE sparse nonlinear least-squares problem (own sparse LM, or Ceres), as
/// CoHAN puts the robot and human bands in one g2o graph (Singamaneni et al. 2021). Outer loop as
/// TEB (Rösmann et al. 2015) — autoResize, build, a few Levenberg–Marquardt iterations, obstacle
/// and safety weights × weight_adapt_factor — except that the bands are resized and the problem is
/// built once per call: between outer iterations only the via-point projections, the pairing
/// fractions and the weight multiplier change (rebuilding every outer iteration, as TEB does,
/// costs 1.3-2.7 ms of a ~10 ms cycle).

#include <ceres/types.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "coopnav/band/band_config.hpp"
#include "coopnav/band/costs/segment_velocity.hpp"
#include "coopnav/band/timed_elastic_band.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// One band in the joint problem. The optimiser changes *band in place.
struct BandAgent {
  std::int32_t id{0};
  bool is_robot{false};  ///< the robot in the relative-velocity formula
  TimedElasticBand* band{nullptr};
  band_costs::MotionLimits limits;  ///< limits with √weights filled in (makeMotionLimits)
  BandWeights weights;
  double radius_m{0.3};
  Velocity2 start_velocity_body;    ///< measured velocity at the first pose, body frame
  bool end_is_goal{false};          ///< standstill at the last pose (goal-acceleration term)
  const Path2* reference{nullptr};  ///< via-point path (nullptr: none)
};

/// How the Ceres backend (config solver "ceres") solves: the options that matter for this problem,
/// so that bench_band can compare Ceres' configurations on the same residual blocks. The defaults
/// are the tuned set-up every caller gets (LM, SuiteSparse normal Cholesky, plain λI damping).
/// Whatever the choice, Ceres runs on one thread: the terms of a band share its heading cache.
struct CeresBackendOptions {
  /// Which parameter blocks Ceres eliminates first (Solver::Options::linear_solver_ordering).
  enum class Ordering : std::int8_t {
    kAutomatic,  ///< Ceres' own (for Schur solvers: its maximal independent set)
    /// Schur: an independent set of the bands' time differences ΔT first, everything else after.
    kTimeDiffsFirst,
    /// Schur: an independent set of the bands' interior poses first, everything else after.
    kPosesFirst,
    /// One group per anticipated agent's band, the planning agent's band last: each band is
    /// eliminated against the planning band it couples to (SuiteSparse: constrained AMD).
    kBandsPlanningLast,
  };
  ceres::TrustRegionStrategyType strategy{ceres::LEVENBERG_MARQUARDT};
  ceres::DoglegType dogleg{ceres::TRADITIONAL_DOGLEG};
  ceres::LinearSolverType linear_solver{ceres::SPARSE_NORMAL_CHOLESKY};
  ceres::SparseLinearAlgebraLibraryType sparse_library{ceres::SUITE_SPARSE};
  ceres::PreconditionerType preconditioner{ceres::JACOBI};  ///< ITERATIVE_SCHUR, CGNR
  Ordering ordering{Ordering::kAutomatic};
  bool use_explicit_schur_complement{false};  ///< ITERATIVE_SCHUR with SCHUR_JACOBI only
  bool dynamic_sparsity{false};               ///< SPARSE_NORMAL_CHOLESKY only
  bool use_postordering{false};               ///< sparse Cholesky (SuiteSparse) only
  /// Off in the tuned set-up: Jacobi-scaled damping barely damps a band's flat θ / y directions.
  bool jacobi_scaling{false};
  bool use_inner_iterations{false};
  /// Trust region radius of the first step of each solve: LM's first damping is its inverse
  /// (tuned 1: λ₀ = 1 as our LM); dogleg's first step length (Ceres' default 1e4).
  double initial_trust_region_radius{1.0};
  /// ITERATIVE_SCHUR / CGNR: relative residual at which the linear solve stops (Ceres' default
  /// 0.1: inexact steps); smaller makes the steps LM's exact ones.
  double eta{0.1};

  /// Short human-readable name, e.g. "LM SPARSE_SCHUR/EIGEN_SPARSE order=dt-first".
  std::string name() const;
  /// Whether Ceres takes our LM's steps up to rounding (LM, λI damping from λ₀ = 1, exact linear
  /// solves), and so reaches our final cost. The others step differently: dogleg, Jacobi-scaled
  /// damping, inexact iterative solves (eta ≥ 1e-6).
  bool takesOurSteps() const;
  /// Whether this Ceres build has the library and accepts the combination (Solver::Options::
  /// IsValid); why not in *why. An ordering's validity shows only at solve time.
  bool usable(std::string* why = nullptr) const;
};

/// The configurations bench_band compares (and the unit tests solve with): Ceres' sparse
/// libraries, orderings, Schur-based and iterative solvers, dogleg, and the options that change
/// the work per iteration; all keep the tuned damping (λI, radius 1). The first is the default.
/// Some may not be usable() in a given Ceres build.
std::vector<CeresBackendOptions> ceresBackendConfigurations();

/// Sets the Ceres backend's options for optimizeBands calls on this thread while it lives (the
/// planner's config only names the solver; bench_band and tests pick Ceres configurations with
/// it). Nested scopes restore the previous options.
class ScopedCeresBackendOptions {
 public:
  explicit ScopedCeresBackendOptions(const CeresBackendOptions& options);
  ~ScopedCeresBackendOptions();
  ScopedCeresBackendOptions(const ScopedCeresBackendOptions&) = delete;
  ScopedCeresBackendOptions& operator=(const ScopedCeresBackendOptions&) = delete;

 private:
  const CeresBackendOptions* previous_;
  CeresBackendOptions options_;
};

/// Builds MotionLimits (√weights) from kinematics and weights; nominal_vel_m_s <= 0 disables it.
band_costs::MotionLimits makeMotionLimits(const AgentKinematics& kin, const BandWeights& w,
                                          double epsilon, double nominal_vel_m_s);

/// Cost of one term family after the last iteration (Ceres cost = ½ Σ r²).
struct TermCost {
  std::string name;
  double cost{0.0};
};

struct OptimizeStats {
  int iterations{0};  ///< LM iterations over all outer loops
  int accepted{0};    ///< of them, steps taken
  int outer_iterations{0};
  int rebuilds{0};  ///< problems rebuilt after the first (a band resized, or the pair guard)
  /// Of the rebuilds, those only because a pose pair left out of the safety terms came close.
  int guard_rebuilds{0};
  double initial_cost{0.0};  ///< at the first outer iteration
  double final_cost{0.0};
  double solver_time_s{0.0};  ///< by the caller's clock (0 without one)
  bool budget_exhausted{false};
  std::vector<TermCost> terms;
};

/// Optimises agents[0..] jointly; agents[0] is the planning agent (coupled to every other), the
/// others are coupled pairwise when their bands come close. Respects max_iterations (total LM
/// iterations, <= 0: config inner × outer) and time_budget_s (<= 0: none), measured with the
/// caller's monotonic clock_s (lib/ reads no clock; empty: no budget and no solver_time_s).
/// Bands with < 2 poses are left untouched.
OptimizeStats optimizeBands(std::vector<BandAgent>& agents, const DistanceMap& map,
                            const BandPlannerConfig& cfg, int max_iterations, double time_budget_s,
                            const std::function<double()>& clock_s = {});

/// Time pairing helper: for each pose time of band a, the segment and fraction of band b at the
/// same time (nullopt past b's end). Exposed for tests and the crossing read-out.
std::vector<std::optional<TimedElasticBand::Locator>> pairByTime(const TimedElasticBand& a,
                                                                 const TimedElasticBand& b);

}  // namespace coopnav
