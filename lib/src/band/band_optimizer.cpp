#include "coopnav/band/band_optimizer.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "coopnav/band/costs/acceleration_cost.hpp"
#include "coopnav/band/costs/agent_safety_cost.hpp"
#include "coopnav/band/costs/hinge_autodiff.hpp"
#include "coopnav/band/costs/holonomic_motion_costs.hpp"
#include "coopnav/band/costs/kinematics_cost.hpp"
#include "coopnav/band/costs/obstacle_cost.hpp"
#include "coopnav/band/costs/relative_velocity_cost.hpp"
#include "coopnav/band/costs/time_optimal_cost.hpp"
#include "coopnav/band/costs/velocity_cost.hpp"
#include "coopnav/band/costs/via_point_cost.hpp"
#include "coopnav/band/sparse_lm.hpp"
#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

using namespace band_costs;  // NOLINT: the cost functors only

enum Term : int {
  kVelocity = 0,
  kAcceleration,
  kTimeOptimal,
  kViaPoint,
  kObstacle,
  kKinematics,
  kAgentRobotSafety,
  kRelativeVelocity,
  kAgentAgentSafety,
  kNumTerms
};
constexpr const char* kTermNames[kNumTerms] = {
    "velocity",   "acceleration",       "time_optimal",      "via_point",         "obstacle",
    "kinematics", "agent_robot_safety", "relative_velocity", "agent_agent_safety"};

/// Pose pairs whose time-paired clearance is above the safety distance by more than this margin
/// when the problem is built get no safety term (its hinge residual is zero there), and agent
/// pairs with no pose pair within it get no terms at all: a term over the whole horizon couples
/// every time slice of two bands and fills the factorisation (bench_band's five humans walk
/// 1.7-2.1 m apart: a 2 m margin took 27 % more instructions a cycle than 0.5 m, for the same
/// bands to 13 digits). The guard below re-admits a left-out pair that comes close.
constexpr double kPairPrefilterMargin_m = 0.5;
/// The guard: a pose pair left out that comes within this much of its safety distance during
/// the cycle makes the outer loop rebuild the problem with it before the next solve, so that a
/// left-out pair is never more than one solve's movement inside the safety distance.
constexpr double kPairGuard_m = 0.5 * kPairPrefilterMargin_m;

/// A residual block differentiated automatically; penalty terms skip the dual numbers while
/// inactive (hinge_autodiff.hpp). One allocation per block.
template <typename Functor, int kN, int... kBlocks>
ceres::CostFunction* autodiff(Functor f) {
  return new HingeAutoDiffCostFunction<Functor, kN, kBlocks...>(std::move(f));
}

double sq(double w) { return std::sqrt(std::max(w, 0.0)); }

/// Clearance (centre distance − radii) between pose i of a and b at the same time.
double pairedClearance(const TimedElasticBand& a, std::size_t i, const TimedElasticBand& b,
                       const TimedElasticBand::Locator& at, double radii_m) {
  const double s = at.fraction;
  const Eigen::Vector2d pb =
      (1.0 - s) * b.pose(at.segment).position() + s * b.pose(at.segment + 1).position();
  return (a.pose(i).position() - pb).norm() - radii_m;
}

double minPairedDistance(const TimedElasticBand& a, const TimedElasticBand& b) {
  const auto pairs = pairByTime(a, b);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (pairs[i]) best = std::min(best, pairedClearance(a, i, b, *pairs[i], 0.0));
  }
  return best;
}

/// The joint problem of one planning cycle, built ONCE (rebuilding it every outer iteration
/// costs 1.3-2.7 ms of a ~10 ms cycle). What TEB re-derives per outer iteration without changing
/// the structure lives in storage the cost terms read through pointers: the weight multiplier,
/// the via-point projections and the time-pairing fractions (refresh()). The structure itself
/// (which poses pair with which segments, which pairs are coupled) is fixed for the cycle; the
/// warm start keeps it close from one cycle to the next.
class ProblemBuilder {
 public:
  ProblemBuilder(std::vector<BandAgent>& agents, const DistanceMap& map,
                 const BandPlannerConfig& cfg)
      : agents_(agents), map_(map), cfg_(cfg) {}

  struct ParamSpec {
    double* values;
    int size;
    bool constant;
    int agent;  ///< index into the agents: whose band (Ceres' band orderings)
  };
  /// Most parameter blocks of one term (relative velocity: two segments of two bands).
  static constexpr int kMaxTermParams = 6;
  struct ResidualSpec {
    std::unique_ptr<ceres::CostFunction> cost;
    // Fixed-size: ~1000 blocks per build, ~2.5 builds per cycle, no allocation for the list.
    std::array<double*, kMaxTermParams> params{};
    int num_params{0};
    std::vector<double*> paramVector() const {
      return {params.begin(), params.begin() + num_params};
    }
  };
  const std::vector<ParamSpec>& params() const { return params_; }
  const std::vector<ResidualSpec>& residuals() const { return residuals_; }
  /// Indices into residuals() of one term family.
  const std::vector<std::size_t>& blocks(int term) const { return blocks_[term]; }

  void build() {
    for (std::size_t k = 0; k < agents_.size(); ++k) addBand(agents_[k], static_cast<int>(k));
    for (std::size_t i = 0; i < agents_.size(); ++i) {
      for (std::size_t j = i + 1; j < agents_.size(); ++j) addCoupling(i, j);
    }
  }

  /// Weight multiplier of the obstacle and safety terms (TEB weight adaptation).
  void setMultiplier(double m) { sqrt_mult_ = std::sqrt(std::max(m, 0.0)); }

  /// Whether a pose pair left without a safety term by the prefilter has come within
  /// kPairGuard_m of its safety distance (then the problem must be rebuilt to include it).
  bool leftOutPairCameClose() const {
    for (const Coupling& c : couplings_) {
      const TimedElasticBand& a = *agents_[c.ia].band;
      const TimedElasticBand& b = *agents_[c.ib].band;
      const auto pairs = pairByTime(a, b);
      for (std::size_t i = 1; i + 1 < pairs.size() && i < c.has_safety.size(); ++i) {
        if (!pairs[i] || c.has_safety[i]) continue;
        if (pairedClearance(a, i, b, *pairs[i], c.radii_m) < c.min_dist_m + kPairGuard_m)
          return true;
      }
    }
    return false;
  }

  /// Re-projects the via-point poses and re-times the pairings after the bands moved.
  void refresh() {
    for (std::size_t k = 0; k < vias_.size(); ++k) project(vias_[k], &anchors_[k]);
    const TimedElasticBand* last_a = nullptr;
    const TimedElasticBand* last_b = nullptr;
    std::vector<double> ta, tb;
    for (std::size_t k = 0; k < pairings_.size(); ++k) {
      const Pairing& q = pairings_[k];
      if (q.a != last_a) ta = q.a->times_s(), last_a = q.a;
      if (q.b != last_b) tb = q.b->times_s(), last_b = q.b;
      const double dt = tb[q.j + 1] - tb[q.j];
      fractions_[k] = dt > 0.0 ? std::clamp((ta[q.i] - tb[q.j]) / dt, 0.0, 1.0) : 0.0;
    }
  }

 private:
  struct Via {
    const PathProjector* path;
    const TimedElasticBand* band;
    std::size_t i;
    std::size_t segment{0};  ///< last projection's: the next one's search hint
  };
  /// An agent pair whose safety terms the prefilter thinned: which poses of a got one.
  struct Coupling {
    std::size_t ia, ib;
    double min_dist_m, radii_m;
    std::vector<char> has_safety;  ///< per pose of a's band
  };
  struct Pairing {
    const TimedElasticBand* a;
    std::size_t i;
    const TimedElasticBand* b;
    std::size_t j;
  };

  static void project(Via& v, ViaAnchor* out) {
    *out = ViaAnchor{};
    const auto proj = v.path->project(v.band->pose(v.i).position(), v.segment);
    if (!proj) return;
    v.segment = proj->segment;
    const Path2& path = v.path->path();
    const Eigen::Vector2d d = path[proj->segment + 1] - path[proj->segment];
    const double n = d.norm();
    if (n < 1e-9) return;
    *out = ViaAnchor{proj->closest.x(), proj->closest.y(), -d.y() / n, d.x() / n};
  }

  void add(int term, ceres::CostFunction* f, std::initializer_list<double*> params) {
    if (params.size() > static_cast<std::size_t>(kMaxTermParams))
      throw std::logic_error("band term with more than kMaxTermParams parameter blocks");
    blocks_[term].push_back(residuals_.size());
    ResidualSpec& r = residuals_.emplace_back();
    r.cost.reset(f);
    std::copy(params.begin(), params.end(), r.params.begin());
    r.num_params = static_cast<int>(params.size());
  }

  void addBand(BandAgent& a, int agent) {
    TimedElasticBand& b = *a.band;
    const std::size_t n = b.size();
    if (n < 2) return;
    // Interleaved pose, ΔT, pose, …: the unknowns of one band in time order, which keeps the
    // normal equations banded before any fill-reducing ordering. First and last pose are fixed.
    for (std::size_t i = 0; i < n; ++i) {
      params_.push_back({b.poseData(i), 3, i == 0 || i + 1 == n, agent});
      if (i + 1 < n) params_.push_back({b.dtData(i), 1, false, agent});
    }

    const MotionLimits& lim = a.limits;
    const BandWeights& w = a.weights;
    const double eps = cfg_.penalty_epsilon;
    const bool diff = !lim.holonomic;
    const double sw_nh = sq(diff ? w.kinematics_nh_diff_drive : w.kinematics_nh);
    const double sw_fwd = diff ? sq(w.kinematics_forward_drive) : 0.0;
    // One heading-trigonometry cache per band, shared by its velocity, acceleration and
    // kinematics terms (holonomic_motion_costs.hpp: BandTrig).
    const BandTrig* trig = &trigs_.emplace_back(n);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      add(kVelocity,
          lim.holonomic ? new HolonomicVelocityCostFunction(lim, {trig, i})
                        : autodiff<VelocityCost, 4, 3, 3, 1>(VelocityCost(lim)),
          {b.poseData(i), b.poseData(i + 1), b.dtData(i)});
      add(kTimeOptimal,
          autodiff<TimeOptimalCost, 2, 1>(TimeOptimalCost(sq(w.optimaltime), cfg_.dt_min_s)),
          {b.dtData(i)});
      if (sw_nh > 0.0 || sw_fwd > 0.0) {
        add(kKinematics, new KinematicsCostFunction(sw_nh, sw_fwd, {trig, i}),
            {b.poseData(i), b.poseData(i + 1)});
      }
    }
    for (std::size_t i = 0; i + 2 < n; ++i) {
      add(kAcceleration,
          lim.holonomic ? new HolonomicAccelerationCostFunction(lim, {trig, i})
                        : autodiff<AccelerationCost, 3, 3, 3, 3, 1, 1>(AccelerationCost(lim)),
          {b.poseData(i), b.poseData(i + 1), b.poseData(i + 2), b.dtData(i), b.dtData(i + 1)});
    }
    const Velocity2& v0 = a.start_velocity_body;
    // Hand-derived Jacobians where the band is holonomic (holonomic_motion_costs.hpp).
    auto boundary = [&](double vx, double vy, double om, bool at_start) -> ceres::CostFunction* {
      if (lim.holonomic) {
        return new HolonomicBoundaryAccelerationCostFunction(lim, vx, vy, om, at_start,
                                                             {trig, at_start ? 0 : n - 2});
      }
      return autodiff<BoundaryAccelerationCost, 3, 3, 3, 1>(
          BoundaryAccelerationCost(lim, vx, vy, om, at_start));
    };
    add(kAcceleration, boundary(v0.vx_m_s, v0.vy_m_s, v0.omega_rad_s, true),
        {b.poseData(0), b.poseData(1), b.dtData(0)});
    if (a.end_is_goal) {
      add(kAcceleration, boundary(0.0, 0.0, 0.0, false),
          {b.poseData(n - 2), b.poseData(n - 1), b.dtData(n - 2)});
    }
    const double sw_obst = sq(w.obstacle);
    const bool via = a.reference != nullptr && a.reference->size() >= 2 && w.viapoint > 0.0;
    if (via) projectors_.emplace_back(*a.reference);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      add(kObstacle,
          new ObstacleCost(&map_, sw_obst, &sqrt_mult_, cfg_.min_obstacle_dist_m, a.radius_m, eps),
          {b.poseData(i)});
      if (via) {
        // The previous pose's segment: the band follows its path.
        vias_.push_back({&projectors_.back(), &b, i, vias_.empty() ? 0 : vias_.back().segment});
        anchors_.emplace_back();
        project(vias_.back(), &anchors_.back());
        add(kViaPoint, autodiff<ViaPointCost, 1, 3>(ViaPointCost(sq(w.viapoint), &anchors_.back())),
            {b.poseData(i)});
      }
    }
  }

  const double* pairing(const TimedElasticBand& a, std::size_t i, const TimedElasticBand& b,
                        const TimedElasticBand::Locator& loc) {
    pairings_.push_back({&a, i, &b, loc.segment});
    fractions_.push_back(loc.fraction);
    return &fractions_.back();
  }

  void addCoupling(std::size_t ia, std::size_t ib) {
    BandAgent& A = agents_[ia];
    BandAgent& B = agents_[ib];
    TimedElasticBand& a = *A.band;
    TimedElasticBand& b = *B.band;
    if (a.size() < 2 || b.size() < 2) return;
    const bool robot_pair = A.is_robot != B.is_robot;
    const double min_dist = robot_pair ? cfg_.min_agent_robot_dist_m : cfg_.min_agent_agent_dist_m;
    const double radii = A.radius_m + B.radius_m;
    bool safety_on = true;
    if (cfg_.safety_activation_dist_m > 0.0) {
      safety_on = (a.pose(0).position() - b.pose(0).position()).norm() - radii <
                  cfg_.safety_activation_dist_m;
    }
    Coupling* guard = nullptr;
    if (safety_on) {
      guard = &couplings_.emplace_back(Coupling{ia, ib, min_dist, radii, {}});
      guard->has_safety.assign(a.size(), 0);
    }
    if (ia != 0 && minPairedDistance(a, b) > radii + min_dist + kPairPrefilterMargin_m) return;
    // The safety distance is an obstacle that moves: like TEB's dynamic obstacles it gets the
    // outer-loop weight multiplier, so that the penalty's residual violation shrinks.
    const double sw_safety =
        sq(robot_pair ? cfg_.weight_agent_robot_safety : cfg_.weight_agent_agent_safety);
    const double sw_rel = sq(cfg_.weight_agent_robot_rel_vel);
    const auto pairs = pairByTime(a, b);
    const double eps = cfg_.penalty_epsilon;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (!pairs[i]) continue;
      const std::size_t j = pairs[i]->segment;
      const double clearance_m = pairedClearance(a, i, b, *pairs[i], radii);
      // Pose 0 is fixed: no safety term; its segment's relative velocity (the command) counts.
      const bool safety =
          safety_on && i > 0 && i + 1 < a.size() && clearance_m < min_dist + kPairPrefilterMargin_m;
      if (safety) guard->has_safety[i] = 1;
      bool rel_on = robot_pair && sw_rel > 0.0 && i + 1 < a.size();
      if (rel_on && cfg_.rel_vel_activation_dist_m > 0.0) {
        rel_on = clearance_m < cfg_.rel_vel_activation_dist_m;
      }
      if (!safety && !rel_on) continue;
      const double* frac = pairing(a, i, b, *pairs[i]);
      if (safety) {
        add(robot_pair ? kAgentRobotSafety : kAgentAgentSafety,
            autodiff<AgentSafetyCost, 1, 3, 3, 3>(
                AgentSafetyCost(sw_safety, &sqrt_mult_, min_dist, radii, frac, eps)),
            {a.poseData(i), b.poseData(j), b.poseData(j + 1)});
      }
      if (rel_on) {
        add(kRelativeVelocity,
            autodiff<RelativeVelocityCost, 1, 3, 3, 1, 3, 3, 1>(
                RelativeVelocityCost(sw_rel, cfg_.rel_vel_cost_threshold, frac, A.is_robot, eps)),
            {a.poseData(i), a.poseData(i + 1), a.dtData(i), b.poseData(j), b.poseData(j + 1),
             b.dtData(j)});
      }
    }
  }

  std::vector<BandAgent>& agents_;
  const DistanceMap& map_;
  const BandPlannerConfig& cfg_;
  double sqrt_mult_{1.0};
  std::vector<ParamSpec> params_;
  std::vector<ResidualSpec> residuals_;
  std::vector<std::size_t> blocks_[kNumTerms];
  // Deques: stable addresses for the pointers the cost terms hold.
  std::deque<BandTrig> trigs_;            ///< one per band
  std::deque<PathProjector> projectors_;  ///< one per band with a reference path
  std::deque<Via> vias_;
  std::deque<ViaAnchor> anchors_;
  std::deque<Pairing> pairings_;
  std::deque<double> fractions_;
  std::vector<Coupling> couplings_;
};

/// What one solve of the built problem reports back to the outer loop.
struct SolveOutcome {
  double initial_cost{0.0};
  int iterations{0};  ///< linear solves (accepted or rejected steps)
  int accepted{0};    ///< of them, steps taken
  bool out_of_time{false};
};

/// One least-squares solver over the residual blocks a ProblemBuilder made. Two exist so that
/// bench_band can compare them on the same problem; config `solver` picks one.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual SolveOutcome solve(int max_iterations, const std::function<bool()>& out_of_time) = 0;
  /// ½ Σ r² of residual block i at the current parameters.
  virtual double blockCost(std::size_t i) = 0;
};

class SparseLmBackend final : public Backend {
 public:
  SparseLmBackend(const ProblemBuilder& pb, double initial_damping_scale)
      : initial_damping_scale_(initial_damping_scale) {
    for (const auto& p : pb.params()) lm_.addParameterBlock(p.values, p.size, p.constant);
    for (const auto& r : pb.residuals())
      lm_.addResidualBlock(r.cost.get(), r.params.data(), r.num_params);
  }
  SolveOutcome solve(int max_iterations, const std::function<bool()>& out_of_time) override {
    SparseLm::Options o;
    o.max_iterations = max_iterations;
    o.should_stop = out_of_time;
    o.initial_lambda_scale = initial_damping_scale_;
    const SparseLm::Summary s = lm_.solve(o);
    return {s.initial_cost, s.iterations, s.accepted, s.stopped};
  }
  double blockCost(std::size_t i) override { return lm_.blockCost(i); }

 private:
  double initial_damping_scale_;
  SparseLm lm_;
};

/// The options of a thread's ScopedCeresBackendOptions (nullptr: the defaults).
thread_local const CeresBackendOptions* t_ceres_options = nullptr;

ceres::Solver::Options toCeres(const CeresBackendOptions& c) {
  ceres::Solver::Options o;
  // Tuned: plain λI damping as g2o (min = max LM diagonal), initial trust radius 1, no line
  // search, one thread (the terms of a band share its BandTrig). With Ceres' defaults a cycle
  // takes 3x as long, and Jacobi-scaled damping stalls in the flat θ/y directions.
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = c.strategy;
  o.dogleg_type = c.dogleg;
  o.linear_solver_type = c.linear_solver;
  o.sparse_linear_algebra_library_type = c.sparse_library;
  o.preconditioner_type = c.preconditioner;
  o.use_explicit_schur_complement = c.use_explicit_schur_complement;
  o.dynamic_sparsity = c.dynamic_sparsity;
  o.use_postordering = c.use_postordering;
  o.jacobi_scaling = c.jacobi_scaling;
  o.use_inner_iterations = c.use_inner_iterations;
  o.min_lm_diagonal = 1.0;
  o.max_lm_diagonal = 1.0;
  o.initial_trust_region_radius = c.initial_trust_region_radius;
  o.eta = c.eta;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  return o;
}

/// The elimination ordering `kind` asks for; nullptr: Ceres' own.
std::shared_ptr<ceres::ParameterBlockOrdering> makeOrdering(const ProblemBuilder& pb,
                                                            CeresBackendOptions::Ordering kind) {
  using Ordering = CeresBackendOptions::Ordering;
  if (kind == Ordering::kAutomatic) return nullptr;
  const auto& params = pb.params();
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  if (kind == Ordering::kBandsPlanningLast) {
    int last = 0;
    for (const auto& p : params) last = std::max(last, p.agent);
    // Agent k > 0 in group k − 1, the planning agent (0) after all of them.
    for (const auto& p : params)
      ordering->AddElementToGroup(p.values, p.agent == 0 ? last : p.agent - 1);
    return ordering;
  }
  // Schur solvers need group 0 to be an independent set (no residual block over two of its
  // blocks): greedily in band order, each block taken excludes every block it shares a term with.
  std::unordered_map<const double*, std::size_t> index;
  for (std::size_t k = 0; k < params.size(); ++k) index.emplace(params[k].values, k);
  std::vector<std::vector<std::size_t>> terms_of(params.size());
  const auto& residuals = pb.residuals();
  for (std::size_t r = 0; r < residuals.size(); ++r) {
    for (int q = 0; q < residuals[r].num_params; ++q)
      terms_of[index.at(residuals[r].params[q])].push_back(r);
  }
  const bool poses = kind == Ordering::kPosesFirst;
  std::vector<char> excluded(params.size(), 0);
  for (std::size_t k = 0; k < params.size(); ++k) {
    const bool candidate = !params[k].constant && (params[k].size == 3) == poses;
    if (!candidate || excluded[k]) {
      ordering->AddElementToGroup(params[k].values, 1);
      continue;
    }
    ordering->AddElementToGroup(params[k].values, 0);
    for (const std::size_t r : terms_of[k]) {
      for (int q = 0; q < residuals[r].num_params; ++q)
        excluded[index.at(residuals[r].params[q])] = 1;
    }
  }
  return ordering;
}

class CeresBackend final : public Backend {
 public:
  CeresBackend(const ProblemBuilder& pb, const CeresBackendOptions& options)
      : opt_(toCeres(options)) {
    ceres::Problem::Options po;
    po.enable_fast_removal = false;
    // The builder owns the cost functions; parameter blocks are the bands' own storage,
    // registered exactly once.
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.disable_all_safety_checks = true;
    problem_ = std::make_unique<ceres::Problem>(po);
    for (const auto& p : pb.params()) {
      problem_->AddParameterBlock(p.values, p.size);
      if (p.constant) problem_->SetParameterBlockConstant(p.values);
    }
    for (const auto& r : pb.residuals())
      ids_.push_back(problem_->AddResidualBlock(r.cost.get(), nullptr, r.paramVector()));
    opt_.linear_solver_ordering = makeOrdering(pb, options.ordering);
  }
  SolveOutcome solve(int max_iterations, const std::function<bool()>& out_of_time) override {
    struct Stop : ceres::IterationCallback {
      const std::function<bool()>* f;
      bool hit{false};
      ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
        if (*f && (*f)()) {
          hit = true;
          return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
        }
        return ceres::SOLVER_CONTINUE;
      }
    } stop;
    stop.f = &out_of_time;
    opt_.callbacks = {&stop};
    opt_.max_num_iterations = max_iterations;
    ceres::Solver::Summary sum;
    ceres::Solve(opt_, problem_.get(), &sum);
    // summary.iterations holds iteration 0 (the initial evaluation) plus every LM step.
    return {sum.initial_cost, std::max(0, static_cast<int>(sum.iterations.size()) - 1),
            sum.num_successful_steps, stop.hit};
  }
  double blockCost(std::size_t i) override {
    double c = 0.0;
    problem_->EvaluateResidualBlock(ids_[i], false, &c, nullptr, nullptr);
    return c;
  }

 private:
  std::unique_ptr<ceres::Problem> problem_;
  std::vector<ceres::ResidualBlockId> ids_;
  ceres::Solver::Options opt_;
};

std::unique_ptr<Backend> makeBackend(const ProblemBuilder& pb, const BandPlannerConfig& cfg) {
  if (cfg.solver == "ceres") {
    return std::make_unique<CeresBackend>(
        pb, t_ceres_options != nullptr ? *t_ceres_options : CeresBackendOptions{});
  }
  return std::make_unique<SparseLmBackend>(pb, cfg.initial_damping_scale);
}

double evaluateTerms(const ProblemBuilder& pb, Backend& backend, std::vector<TermCost>* terms) {
  double total = 0.0;
  terms->clear();
  for (int t = 0; t < kNumTerms; ++t) {
    double c = 0.0;
    for (const auto i : pb.blocks(t)) c += backend.blockCost(i);
    terms->push_back({kTermNames[t], c});
    total += c;
  }
  return total;
}

}  // namespace

std::string CeresBackendOptions::name() const {
  std::string n = strategy == ceres::LEVENBERG_MARQUARDT ? "LM"
                  : dogleg == ceres::TRADITIONAL_DOGLEG  ? "DOGLEG"
                                                         : "SUBSPACE_DOGLEG";
  n += std::string(" ") + ceres::LinearSolverTypeToString(linear_solver);
  const bool sparse = linear_solver == ceres::SPARSE_NORMAL_CHOLESKY ||
                      linear_solver == ceres::SPARSE_SCHUR ||
                      (linear_solver == ceres::ITERATIVE_SCHUR && use_explicit_schur_complement);
  if (sparse) n += std::string("/") + ceres::SparseLinearAlgebraLibraryTypeToString(sparse_library);
  if (linear_solver == ceres::ITERATIVE_SCHUR || linear_solver == ceres::CGNR)
    n += std::string("/") + ceres::PreconditionerTypeToString(preconditioner);
  switch (ordering) {
    case Ordering::kAutomatic:
      break;
    case Ordering::kTimeDiffsFirst:
      n += " order=dt-first";
      break;
    case Ordering::kPosesFirst:
      n += " order=poses-first";
      break;
    case Ordering::kBandsPlanningLast:
      n += " order=bands,planning-last";
      break;
  }
  if (use_explicit_schur_complement) n += " explicit-schur";
  if (dynamic_sparsity) n += " dynamic-sparsity";
  if (use_postordering) n += " postordering";
  if (jacobi_scaling) n += " jacobi-scaling";
  if (use_inner_iterations) n += " inner-iterations";
  if (initial_trust_region_radius != CeresBackendOptions{}.initial_trust_region_radius) {
    char buf[48];
    std::snprintf(buf, sizeof buf, " radius=%g", initial_trust_region_radius);
    n += buf;
  }
  if ((linear_solver == ceres::ITERATIVE_SCHUR || linear_solver == ceres::CGNR) &&
      eta != CeresBackendOptions{}.eta) {
    char buf[48];
    std::snprintf(buf, sizeof buf, " eta=%g", eta);
    n += buf;
  }
  return n;
}

bool CeresBackendOptions::takesOurSteps() const {
  // Iterative solves never count, whatever eta: they follow our steps only up to rounding, and
  // over 32 accept/reject decisions that can branch (2 % off our cost under -O1, the ASan build).
  const bool exact_solve = linear_solver != ceres::ITERATIVE_SCHUR && linear_solver != ceres::CGNR;
  return strategy == ceres::LEVENBERG_MARQUARDT && !jacobi_scaling && exact_solve &&
         initial_trust_region_radius == 1.0 && !use_inner_iterations;
}

bool CeresBackendOptions::usable(std::string* why) const {
  const bool needs_sparse =
      linear_solver == ceres::SPARSE_NORMAL_CHOLESKY || linear_solver == ceres::SPARSE_SCHUR ||
      (linear_solver == ceres::ITERATIVE_SCHUR &&
       (use_explicit_schur_complement || preconditioner == ceres::CLUSTER_JACOBI ||
        preconditioner == ceres::CLUSTER_TRIDIAGONAL));
  if (needs_sparse && !ceres::IsSparseLinearAlgebraLibraryTypeAvailable(sparse_library)) {
    if (why != nullptr) {
      *why = std::string(ceres::SparseLinearAlgebraLibraryTypeToString(sparse_library)) +
             " not compiled into this Ceres";
    }
    return false;
  }
  std::string message;
  const bool ok = toCeres(*this).IsValid(&message);
  if (why != nullptr) *why = message;
  return ok;
}

std::vector<CeresBackendOptions> ceresBackendConfigurations() {
  using Ordering = CeresBackendOptions::Ordering;
  std::vector<CeresBackendOptions> out;
  // No EIGEN_SPARSE: Debian's Ceres 2.1 runs Eigen's sparse templates, instantiated in our
  // translation units and in libceres with different allocation settings, so one frees what the
  // other allocated (AddressSanitizer: bad-free in DynamicSparseNormalCholeskySolver). It was
  // never faster than the other two libraries (within noise).
  const ceres::SparseLinearAlgebraLibraryType libs[] = {ceres::SUITE_SPARSE, ceres::CX_SPARSE};
  for (const auto lib : libs) {
    CeresBackendOptions o;  // the defaults: SPARSE_NORMAL_CHOLESKY
    o.sparse_library = lib;
    out.push_back(o);
    o.ordering = Ordering::kBandsPlanningLast;
    out.push_back(o);
    o.ordering = Ordering::kAutomatic;
    o.dynamic_sparsity = true;
    out.push_back(o);
  }
  {
    CeresBackendOptions o;
    o.use_postordering = true;
    out.push_back(o);
  }
  for (const auto lib : libs) {
    for (const auto ord :
         {Ordering::kAutomatic, Ordering::kTimeDiffsFirst, Ordering::kPosesFirst}) {
      CeresBackendOptions o;
      o.linear_solver = ceres::SPARSE_SCHUR;
      o.sparse_library = lib;
      o.ordering = ord;
      out.push_back(o);
    }
  }
  for (const auto ord : {Ordering::kAutomatic, Ordering::kTimeDiffsFirst}) {
    CeresBackendOptions o;
    o.linear_solver = ceres::DENSE_SCHUR;
    o.ordering = ord;
    out.push_back(o);
  }
  // Inexact steps (Ceres' default tolerance) and, as tight as a direct solve, exact ones.
  for (const double eta : {0.1, 1e-8}) {
    CeresBackendOptions o;
    o.eta = eta;
    o.linear_solver = ceres::ITERATIVE_SCHUR;
    o.preconditioner = ceres::JACOBI;
    out.push_back(o);
    o.preconditioner = ceres::SCHUR_JACOBI;
    out.push_back(o);
    o.ordering = Ordering::kTimeDiffsFirst;
    out.push_back(o);
    o.ordering = Ordering::kAutomatic;
    o.use_explicit_schur_complement = true;
    out.push_back(o);
    o.use_explicit_schur_complement = false;
    o.linear_solver = ceres::CGNR;
    o.preconditioner = ceres::JACOBI;
    out.push_back(o);
  }
  // Dogleg from the tuned radius (from Ceres' default 1e4 it ends ~35x higher in the unit test).
  for (const auto lib : {ceres::SUITE_SPARSE, ceres::CX_SPARSE}) {
    for (const auto dogleg : {ceres::TRADITIONAL_DOGLEG, ceres::SUBSPACE_DOGLEG}) {
      CeresBackendOptions o;
      o.strategy = ceres::DOGLEG;
      o.dogleg = dogleg;
      o.sparse_library = lib;
      out.push_back(o);
    }
  }
  {
    CeresBackendOptions o;
    o.jacobi_scaling = true;
    out.push_back(o);
  }
  return out;
}

ScopedCeresBackendOptions::ScopedCeresBackendOptions(const CeresBackendOptions& options)
    : previous_(t_ceres_options), options_(options) {
  t_ceres_options = &options_;
}

ScopedCeresBackendOptions::~ScopedCeresBackendOptions() { t_ceres_options = previous_; }

band_costs::MotionLimits makeMotionLimits(const AgentKinematics& kin, const BandWeights& w,
                                          double epsilon, double nominal_vel_m_s) {
  MotionLimits m;
  m.holonomic = kin.holonomic;
  m.max_vel_x_m_s = kin.max_vel_x_m_s;
  m.max_vel_x_backwards_m_s = kin.max_vel_x_backwards_m_s;
  m.max_vel_y_m_s = kin.max_vel_y_m_s;
  m.max_vel_theta_rad_s = kin.max_vel_theta_rad_s;
  m.acc_lim_x_m_s2 = kin.acc_lim_x_m_s2;
  m.acc_lim_y_m_s2 = kin.acc_lim_y_m_s2;
  m.acc_lim_theta_rad_s2 = kin.acc_lim_theta_rad_s2;
  m.epsilon = epsilon;
  m.sqrt_w_vel_x = sq(w.max_vel_x);
  m.sqrt_w_vel_y = sq(w.max_vel_y);
  m.sqrt_w_vel_theta = sq(w.max_vel_theta);
  m.sqrt_w_acc_x = sq(w.acc_lim_x);
  m.sqrt_w_acc_y = sq(w.acc_lim_y);
  m.sqrt_w_acc_theta = sq(w.acc_lim_theta);
  m.sqrt_w_nominal = nominal_vel_m_s > 0.0 ? sq(w.nominal_vel) : 0.0;
  m.nominal_vel_m_s = std::max(nominal_vel_m_s, 0.0);
  return m;
}

std::vector<std::optional<TimedElasticBand::Locator>> pairByTime(const TimedElasticBand& a,
                                                                 const TimedElasticBand& b) {
  std::vector<std::optional<TimedElasticBand::Locator>> out(a.size());
  if (b.size() < 2) return out;
  const auto ta = a.times_s();
  const auto tb = b.times_s();
  std::size_t j = 0;
  for (std::size_t i = 0; i < ta.size(); ++i) {
    const double t = ta[i];
    if (t > tb.back()) break;
    while (j + 2 < tb.size() && tb[j + 1] < t) ++j;
    const double dt = tb[j + 1] - tb[j];
    out[i] = TimedElasticBand::Locator{j, dt > 0.0 ? std::clamp((t - tb[j]) / dt, 0.0, 1.0) : 0.0};
  }
  return out;
}

OptimizeStats optimizeBands(std::vector<BandAgent>& agents, const DistanceMap& map,
                            const BandPlannerConfig& cfg, int max_iterations, double time_budget_s,
                            const std::function<double()>& clock_s) {
  OptimizeStats stats;
  if (agents.empty()) return stats;
  const int total_iter =
      max_iterations > 0 ? max_iterations : cfg.no_inner_iterations * cfg.no_outer_iterations;
  // The budget needs the caller's clock (lib/ has none); without one it is ignored.
  const bool budgeted = time_budget_s > 0.0 && static_cast<bool>(clock_s);
  const double t0_s = clock_s ? clock_s() : 0.0;
  const std::function<bool()> out_of_time = [&]() {
    return budgeted && clock_s() - t0_s >= time_budget_s;
  };
  // TEB resizes before every outer iteration; the problem is rebuilt only when that changed a
  // band. Resizing once per cycle would save most rebuilds (bench_band: 2.5 builds per cycle), but
  // a cold band stretched by the first outer iteration then keeps its long ΔT, and the limits
  // are only checked per segment (a planning human reached 0.65 m/s sideways against 0.4).
  auto resize = [&] {
    bool changed = false;
    for (auto& a : agents) {
      if (a.band->size() >= 2) {
        changed |=
            a.band->autoResize(cfg.dt_ref_s, cfg.dt_hysteresis_s, cfg.min_samples, cfg.max_samples);
      }
    }
    return changed;
  };
  resize();
  auto pb = std::make_unique<ProblemBuilder>(agents, map, cfg);
  pb->build();
  if (pb->residuals().empty()) return stats;
  auto backend = makeBackend(*pb, cfg);

  double multiplier = 1.0;
  // Each solve starts from λ₀ = 1 (Ceres' start) or, with cfg.initial_damping_scale, from the
  // problem's scale. Carrying the last solve's damping into the next outer iteration takes 6-7
  // of 8 steps instead of ~4 and ends ~15 % lower in cost, but, like the scale-aware start, it
  // changes the narrow-corridor bands enough to move the paper's round-2 decision there, so
  // every solve starts afresh.
  for (int outer = 0; outer < cfg.no_outer_iterations; ++outer) {
    const int left = total_iter - stats.iterations;
    if (left <= 0) break;
    if (out_of_time()) {
      stats.budget_exhausted = true;
      break;
    }
    if (outer > 0) {
      // Resized or not, a left-out pose pair that came close needs its safety term now.
      const bool resized = resize();
      const bool guarded = !resized && pb->leftOutPairCameClose();
      if (guarded) ++stats.guard_rebuilds;
      if (resized || guarded) {
        backend.reset();
        pb = std::make_unique<ProblemBuilder>(agents, map, cfg);
        pb->build();
        backend = makeBackend(*pb, cfg);
        ++stats.rebuilds;
      } else {
        pb->refresh();
      }
    }
    pb->setMultiplier(multiplier);
    const SolveOutcome o = backend->solve(std::min(cfg.no_inner_iterations, left), out_of_time);
    if (outer == 0) stats.initial_cost = o.initial_cost;
    stats.iterations += o.iterations;
    stats.accepted += o.accepted;
    stats.outer_iterations = outer + 1;
    for (auto& a : agents) a.band->normalize(cfg.dt_min_s);
    const bool last =
        outer + 1 == cfg.no_outer_iterations || stats.iterations >= total_iter || o.out_of_time;
    if (last) {
      stats.final_cost = evaluateTerms(*pb, *backend, &stats.terms);
      stats.budget_exhausted = o.out_of_time;
      break;
    }
    multiplier *= cfg.weight_adapt_factor;
  }
  if (clock_s) stats.solver_time_s = clock_s() - t0_s;
  return stats;
}

}  // namespace coopnav
