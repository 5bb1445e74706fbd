// Our sparse Levenberg–Marquardt against known optima and against Ceres on the same residual
// blocks (our solver may replace Ceres only on the same problem).
#include "coopnav/band/sparse_lm.hpp"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

namespace coopnav {
namespace {

/// Rosenbrock as two residuals: (1 − x), 10 (y − x²); minimum 0 at (1, 1).
struct Rosenbrock {
  template <typename T>
  bool operator()(const T* x, const T* y, T* r) const {
    r[0] = T(1.0) - x[0];
    r[1] = T(10.0) * (y[0] - x[0] * x[0]);
    return true;
  }
};

/// A chain of 2-D points between fixed ends, neighbours tied by linear springs and every point
/// pulled down by a monotone nonlinear term: the band problem's shape (neighbour coupling, fixed
/// ends) in miniature, with a single minimum so that both solvers must find the same one.
struct Spring {
  double rest;
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    r[0] = b[0] - a[0] - T(rest);
    r[1] = b[1] - a[1];
    return true;
  }
};
struct Pull {
  template <typename T>
  bool operator()(const T* p, T* r) const {
    using std::exp;
    r[0] = T(0.3) * (exp(T(0.5) * p[1]) - T(0.5));
    return true;
  }
};

/// Rosenbrock's valley from its classic start (-1.2, 1), ready to solve.
struct RosenbrockProblem {
  double x{-1.2};
  double y{1.0};
  ceres::AutoDiffCostFunction<Rosenbrock, 2, 1, 1> f{new Rosenbrock};
  SparseLm lm;
  RosenbrockProblem() {
    lm.addParameterBlock(&x, 1, false);
    lm.addParameterBlock(&y, 1, false);
    lm.addResidualBlock(&f, {&x, &y});
  }
};

TEST(SparseLmTest, FindsTheRosenbrockMinimum) {
  RosenbrockProblem p;
  SparseLm::Options o;
  o.max_iterations = 200;
  const auto s = p.lm.solve(o);
  EXPECT_NEAR(p.x, 1.0, 1e-5);
  EXPECT_NEAR(p.y, 1.0, 1e-5);
  EXPECT_LT(s.final_cost, 1e-10);
  EXPECT_GT(s.initial_cost, s.final_cost);
  EXPECT_EQ(p.lm.numUnknowns(), 2u);
}

TEST(SparseLmTest, StartsFromTheDampingItIsGivenAndReportsWhereItEnded) {
  // Given the Rosenbrock problem, one step from Ceres' start (λ = 1) and one from a stiff λ.
  auto firstStep = [](double initial_lambda, SparseLm::Summary* s) {
    RosenbrockProblem p;
    SparseLm::Options o;
    o.max_iterations = 1;
    o.initial_lambda = initial_lambda;
    *s = p.lm.solve(o);
    return std::hypot(p.x + 1.2, p.y - 1.0);
  };
  SparseLm::Summary free_s, stiff_s;
  const double free_step = firstStep(0.0, &free_s);
  const double stiff_step = firstStep(1e4, &stiff_s);
  // Then the stiff damping shortens the step (δ ≈ -g / λ) and each reports where λ ended.
  EXPECT_LT(stiff_step, 0.1 * free_step);
  EXPECT_GT(stiff_step, 0.0);
  EXPECT_GT(free_s.final_lambda, 0.0);
  EXPECT_GT(stiff_s.final_lambda, 100.0 * free_s.final_lambda);
}

/// Rosenbrock with both residuals × k: the same valley, JᵀJ × k².
struct ScaledRosenbrock {
  double k;
  template <typename T>
  bool operator()(const T* x, const T* y, T* r) const {
    r[0] = T(k) * (T(1.0) - x[0]);
    r[1] = T(k) * T(10.0) * (y[0] - x[0] * x[0]);
    return true;
  }
};

TEST(SparseLmTest, StartsFromTheProblemsScaleWhenAskedTo) {
  // Given Rosenbrock's valley with residuals × 1000 from (-1.2, 1): JᵀJ's diagonal there is
  // 1e6 · (1 + (20 · 1.2)²) = 5.77e8 for x and 1e6 · 100 for y.
  auto solve = [](double scale, int solves) {
    double x = -1.2, y = 1.0;
    ceres::AutoDiffCostFunction<ScaledRosenbrock, 2, 1, 1> f(new ScaledRosenbrock{1000.0});
    SparseLm lm;
    lm.addParameterBlock(&x, 1, false);
    lm.addParameterBlock(&y, 1, false);
    lm.addResidualBlock(&f, {&x, &y});
    SparseLm::Options o;
    o.max_iterations = solves;
    o.initial_lambda_scale = scale;
    return lm.solve(o);
  };
  // When the start follows the scale (τ = 1e-2, eq. 3.14) it is τ · max diag, else 1.
  const SparseLm::Summary scaled = solve(1e-2, 1);
  EXPECT_NEAR(scaled.initial_lambda, 1e-2 * 5.77e8, 1e-6 * 5.77e6);
  EXPECT_EQ(solve(0.0, 1).initial_lambda, 1.0);
  // Then the scaled start's first step is taken, while from λ = 1, 3 orders below what the
  // valley needs, the first steps are rejected and after as many solves fewer are taken.
  EXPECT_EQ(scaled.accepted, 1);
  EXPECT_EQ(solve(0.0, 1).accepted, 0);
  const SparseLm::Summary from_scale = solve(1e-2, 8);
  const SparseLm::Summary from_one = solve(0.0, 8);
  EXPECT_GT(from_scale.accepted, from_one.accepted);
}

struct Chain {
  static constexpr int kN = 30;
  std::vector<std::array<double, 2>> pts;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<std::vector<double*>> params;
  Chain() {
    for (int i = 0; i < kN; ++i) pts.push_back({0.1 * i, 0.05 * std::sin(i)});
    for (int i = 0; i + 1 < kN; ++i) {
      costs.emplace_back(new ceres::AutoDiffCostFunction<Spring, 2, 2, 2>(new Spring{0.08}));
      params.push_back({pts[i].data(), pts[i + 1].data()});
    }
    for (int i = 1; i + 1 < kN; ++i) {
      costs.emplace_back(new ceres::AutoDiffCostFunction<Pull, 1, 2>(new Pull));
      params.push_back({pts[i].data()});
    }
  }
  bool constant(int i) const { return i == 0 || i == kN - 1; }
};

TEST(SparseLmTest, AgreesWithCeresAndKeepsConstantBlocks) {
  Chain ours, theirs;
  SparseLm lm;
  for (int i = 0; i < Chain::kN; ++i) lm.addParameterBlock(ours.pts[i].data(), 2, ours.constant(i));
  for (std::size_t k = 0; k < ours.costs.size(); ++k)
    lm.addResidualBlock(ours.costs[k].get(), ours.params[k]);
  SparseLm::Options o;
  o.max_iterations = 100;
  o.function_tolerance = 1e-12;
  const auto s = lm.solve(o);

  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (int i = 0; i < Chain::kN; ++i) {
    problem.AddParameterBlock(theirs.pts[i].data(), 2);
    if (theirs.constant(i)) problem.SetParameterBlockConstant(theirs.pts[i].data());
  }
  for (std::size_t k = 0; k < theirs.costs.size(); ++k)
    problem.AddResidualBlock(theirs.costs[k].get(), nullptr, theirs.params[k]);
  ceres::Solver::Options co;
  co.max_num_iterations = 100;
  co.function_tolerance = 1e-12;
  co.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  ceres::Solver::Summary cs;
  ceres::Solve(co, &problem, &cs);

  EXPECT_NEAR(s.final_cost, cs.final_cost, 1e-9 + 1e-6 * cs.final_cost);
  for (int i = 0; i < Chain::kN; ++i) {
    EXPECT_NEAR(ours.pts[i][0], theirs.pts[i][0], 1e-4) << i;
    EXPECT_NEAR(ours.pts[i][1], theirs.pts[i][1], 1e-4) << i;
  }
  // The fixed ends did not move.
  EXPECT_DOUBLE_EQ(ours.pts[0][1], 0.0);
  EXPECT_DOUBLE_EQ(ours.pts[Chain::kN - 1][1], 0.05 * std::sin(Chain::kN - 1));
  EXPECT_EQ(lm.numUnknowns(), 2u * (Chain::kN - 2));
  // blockCost is the block's ½ r² at the solution.
  double sum = 0.0;
  for (std::size_t k = 0; k < lm.numResidualBlocks(); ++k) sum += lm.blockCost(k);
  EXPECT_NEAR(sum, s.final_cost, 1e-12);
}

TEST(SparseLmTest, StopsWhenAskedAndCountsSolves) {
  Chain c;
  SparseLm lm;
  for (int i = 0; i < Chain::kN; ++i) lm.addParameterBlock(c.pts[i].data(), 2, c.constant(i));
  for (std::size_t k = 0; k < c.costs.size(); ++k)
    lm.addResidualBlock(c.costs[k].get(), c.params[k]);
  int polls = 0;
  SparseLm::Options o;
  o.max_iterations = 100;
  o.function_tolerance = 0.0;
  o.should_stop = [&] { return ++polls > 3; };
  const auto s = lm.solve(o);
  EXPECT_TRUE(s.stopped);
  EXPECT_EQ(s.iterations, 3);
  SparseLm::Options few;
  few.max_iterations = 2;
  few.function_tolerance = 0.0;
  EXPECT_LE(lm.solve(few).iterations, 2);
}

TEST(SparseLmTest, RejectsMisuse) {
  double x = 0.0, y = 0.0, z = 0.0;
  ceres::AutoDiffCostFunction<Rosenbrock, 2, 1, 1> f(new Rosenbrock);
  SparseLm lm;
  lm.addParameterBlock(&x, 1, false);
  EXPECT_THROW(lm.addParameterBlock(&x, 1, false), std::logic_error);
  EXPECT_THROW(lm.addResidualBlock(&f, {&x, &z}), std::logic_error);  // z undeclared
  EXPECT_THROW(lm.addResidualBlock(&f, {&x}), std::logic_error);      // wrong count
  EXPECT_THROW(lm.addResidualBlock(&f, {&x, &x}), std::logic_error);  // x twice
  std::array<double, 7> big{};
  EXPECT_THROW(lm.addParameterBlock(big.data(), 7, false), std::logic_error);  // over 6
  lm.addParameterBlock(&y, 1, true);
  lm.addResidualBlock(&f, {&x, &y});
  SparseLm::Options o;
  o.max_iterations = 50;
  o.function_tolerance = 1e-15;
  lm.solve(o);
  EXPECT_DOUBLE_EQ(y, 0.0);  // constant
  // With y held at 0 the cost is ½((1 − x)² + 100 x⁴): stationary where −(1 − x) + 200 x³ = 0.
  EXPECT_NEAR(-(1.0 - x) + 200.0 * x * x * x, 0.0, 1e-6);
}

}  // namespace
}  // namespace coopnav
