#pragma once
/// @file Our own sparse Levenberg–Marquardt solver for the band problem.
/// Why ours: ~1/5 of Ceres' time on the same blocks (bench_band: ours / Ceres p50 0.18-0.20).
/// Ceres' `CostFunction` is used only as the evaluation interface of a residual block (its
/// autodiff and our analytic terms), so both solvers (band_optimizer.cpp runs either, and
/// bench_band both, with Ceres' tuned SPARSE_NORMAL_CHOLESKY LM) see exactly the same residuals
/// and Jacobians.
///
/// Where the difference comes from: the unknowns are grouped and ordered ONCE per problem (Ceres
/// re-derives the JᵀJ product structure every iteration and goes through CHOLMOD's supernodal
/// BLAS/OpenMP path, whose hand-offs cost more than this ~750-unknown factorisation); here every
/// residual block writes its JᵀJ and Jᵀr contributions straight into their places in the
/// factorisation's own storage (tiles of nodes: a band's ΔT and the pose after it), the nodes are
/// numbered in a minimum-degree order of their graph, and the factorisation is a block LDLᵀ on
/// the pattern of the tiles that are not zero at that linearisation (block_ldlt.hpp): terms
/// inside their limits add exact zeros and so no fill. Single-threaded: every sum runs in block
/// order, so a solve is deterministic to the last bit.
///
/// Damping is plain λI, as g2o does for TEB and CoHAN (Jacobi-scaled damping barely damps a
/// band's flat θ / y directions, and LM stalls there), with Nielsen's λ update (Madsen, Nielsen &
/// Tingleff, "Methods for non-linear least squares problems", 2004, §3.2).

#include <ceres/cost_function.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace coopnav {

class SparseLm {
 public:
  struct Options {
    int max_iterations{8};  ///< linear solves (accepted or rejected steps), as Ceres counts them
    /// Stop when an accepted step lowers the cost by less than this fraction (Ceres' default).
    double function_tolerance{1e-6};
    /// Stop when max |gradient| is below this (Ceres' default).
    double gradient_tolerance{1e-10};
    /// Stop when |δ| < parameter_tolerance · (|x| + parameter_tolerance) (Ceres' default).
    double parameter_tolerance{1e-8};
    /// Checked before every linear solve; returning true stops the solve (time budgets: the
    /// caller owns the clock, lib/ has none).
    std::function<bool()> should_stop;
    /// Damping λ to start from; <= 0: initial_lambda_scale decides. A caller that solves a
    /// sequence of similar problems may pass the previous Summary::final_lambda.
    double initial_lambda{0.0};
    /// Without initial_lambda: λ₀ = this · max_i (JᵀJ)_ii at the start point (Madsen, Nielsen &
    /// Tingleff 2004, eq. 3.14: τ · max a_ii), so that the start follows the problem's scale;
    /// <= 0: λ₀ = 1 (Ceres' 1 / initial trust radius 1), whatever the scale.
    double initial_lambda_scale{0.0};
  };

  struct Summary {
    double initial_cost{0.0};    ///< ½ Σ r² before the first step
    double initial_lambda{0.0};  ///< damping of the first step
    double final_cost{0.0};
    double final_lambda{0.0};  ///< damping at the end (for the next solve's initial_lambda)
    int iterations{0};         ///< linear solves
    int accepted{0};
    bool stopped{false};  ///< should_stop ended it
  };

  SparseLm();
  ~SparseLm();
  SparseLm(const SparseLm&) = delete;
  SparseLm& operator=(const SparseLm&) = delete;

  /// Declares a parameter block of 1..6 values (its storage is optimised in place; the
  /// factorisation's nodes are at most 6 unknowns). Constant blocks enter the residuals but are
  /// not unknowns. Must precede the residual blocks that use it.
  void addParameterBlock(double* values, int size, bool constant);

  /// Adds a residual block over declared parameter blocks; `cost` is not owned and must outlive
  /// the solver. Returns its index.
  std::size_t addResidualBlock(const ceres::CostFunction* cost, const std::vector<double*>& params);
  /// The same for params[0, num_params).
  std::size_t addResidualBlock(const ceres::CostFunction* cost, double* const* params,
                               int num_params);

  /// Runs LM from the current parameter values.
  Summary solve(const Options& options);

  /// ½ Σ r² of one residual block at the current parameters. Not const: the first call after
  /// blocks were added lays out the structure, and evaluation uses the solver's scratch.
  double blockCost(std::size_t block);

  /// Unknowns of the non-constant parameter blocks (lays out the structure if needed).
  std::size_t numUnknowns();
  std::size_t numResidualBlocks() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coopnav
