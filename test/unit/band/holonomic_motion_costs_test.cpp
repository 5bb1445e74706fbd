// The hand-derived Jacobians of the holonomic velocity / acceleration terms and of the
// kinematics term against Ceres' automatic differentiation of the same functors, on random
// segments with every penalty branch (inside, below, above) and with the nominal-speed residual.
#include "coopnav/band/costs/holonomic_motion_costs.hpp"

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "coopnav/band/costs/hinge_autodiff.hpp"

namespace coopnav::band_costs {
namespace {

// One evaluation with Jacobians, every entry pre-filled with `fill` (so each must be written).
struct Evaluated {
  std::vector<double> r;
  std::vector<std::vector<double>> j;
};
Evaluated evaluate(const ceres::CostFunction& f, const std::vector<double*>& params, double fill) {
  const int m = f.num_residuals();
  Evaluated e{std::vector<double>(m), {}};
  std::vector<double*> jp;
  for (int s : f.parameter_block_sizes()) e.j.emplace_back(m * s, fill);
  for (auto& block : e.j) jp.push_back(block.data());
  EXPECT_TRUE(f.Evaluate(params.data(), e.r.data(), jp.data()));
  return e;
}

// Residuals and Jacobians to rounding: Ceres' dual numbers divide as f * (1 / g) and take
// atan2 of sin / cos with a derivative of 1 ± a few ulp, where ours divides and uses 1. With
// and without Jacobians our residuals are the same bits (the solver's cost and its
// linearisation agree).
void expectSameTerm(const ceres::CostFunction& ours, const ceres::CostFunction& autodiff,
                    const std::vector<double*>& params) {
  const int m = ours.num_residuals();
  ASSERT_EQ(m, autodiff.num_residuals());
  const auto& sizes = ours.parameter_block_sizes();
  ASSERT_EQ(sizes, autodiff.parameter_block_sizes());
  const Evaluated a = evaluate(ours, params, -7.0);
  const Evaluated b = evaluate(autodiff, params, 7.0);
  for (int k = 0; k < m; ++k)
    EXPECT_NEAR(a.r[k], b.r[k], 1e-12 * (1.0 + std::abs(b.r[k]))) << "residual " << k;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    for (int e = 0; e < m * sizes[i]; ++e) {
      EXPECT_NEAR(a.j[i][e], b.j[i][e], 1e-9 * (1.0 + std::abs(b.j[i][e])))
          << "block " << i << " row " << e / sizes[i] << " col " << e % sizes[i];
    }
  }
  // Without Jacobians: the same residuals.
  std::vector<double> r3(m);
  ASSERT_TRUE(ours.Evaluate(params.data(), r3.data(), nullptr));
  EXPECT_EQ(r3, a.r);
}

MotionLimits limits(bool nominal) {
  MotionLimits lim;
  lim.holonomic = true;
  lim.max_vel_x_m_s = 0.7;
  lim.max_vel_x_backwards_m_s = 0.3;
  lim.max_vel_y_m_s = 0.4;
  lim.max_vel_theta_rad_s = 1.0;
  lim.acc_lim_x_m_s2 = 0.5;
  lim.acc_lim_y_m_s2 = 0.4;
  lim.acc_lim_theta_rad_s2 = 0.6;
  lim.sqrt_w_vel_x = 1.4;
  lim.sqrt_w_vel_y = 1.1;
  lim.sqrt_w_vel_theta = 0.9;
  lim.sqrt_w_acc_x = 1.3;
  lim.sqrt_w_acc_y = 0.8;
  lim.sqrt_w_acc_theta = 1.2;
  if (nominal) {
    lim.sqrt_w_nominal = 1.5;
    lim.nominal_vel_m_s = 1.1;
  }
  return lim;
}

TEST(HolonomicMotionCosts, JacobiansMatchAutodiffOnRandomSegments) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-0.25, 0.25), ang(-3.0, 3.0), dt(0.05, 0.4);
  int active = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const MotionLimits lim = limits(trial % 2 == 0);
    double p0[3] = {pos(rng), pos(rng), ang(rng)};
    double p1[3] = {p0[0] + pos(rng), p0[1] + pos(rng), p0[2] + 0.3 * pos(rng)};
    double p2[3] = {p1[0] + pos(rng), p1[1] + pos(rng), p1[2] + 0.3 * pos(rng)};
    double t0[1] = {dt(rng)}, t1[1] = {dt(rng)};

    const HolonomicVelocityCostFunction vel(lim);
    const HingeAutoDiffCostFunction<VelocityCost, 4, 3, 3, 1> vel_ad{VelocityCost(lim)};
    expectSameTerm(vel, vel_ad, {p0, p1, t0});

    const HolonomicAccelerationCostFunction acc(lim);
    const HingeAutoDiffCostFunction<AccelerationCost, 3, 3, 3, 3, 1, 1> acc_ad{
        AccelerationCost(lim)};
    expectSameTerm(acc, acc_ad, {p0, p1, p2, t0, t1});
    double r[3];
    acc.Evaluate(std::vector<double*>{p0, p1, p2, t0, t1}.data(), r, nullptr);
    active += (r[0] != 0.0 || r[1] != 0.0 || r[2] != 0.0);

    for (bool at_start : {true, false}) {
      const HolonomicBoundaryAccelerationCostFunction b(lim, 0.4, -0.1, 0.2, at_start);
      const HingeAutoDiffCostFunction<BoundaryAccelerationCost, 3, 3, 3, 1> b_ad{
          BoundaryAccelerationCost(lim, 0.4, -0.1, 0.2, at_start)};
      expectSameTerm(b, b_ad, {p0, p1, t0});
    }

    for (double fwd : {0.0, 2.0}) {
      const KinematicsCostFunction kin(1.7, fwd);
      const HingeAutoDiffCostFunction<KinematicsCost, 2, 3, 3> kin_ad{KinematicsCost(1.7, fwd)};
      expectSameTerm(kin, kin_ad, {p0, p1});
    }
  }
  // The random segments exercise the penalties, not only their zero branch.
  EXPECT_GT(active, 200);
}

// HingeAutoDiffCostFunction's dual numbers are ceres::AutoDiffCostFunction's to the bit
// (residuals and Jacobians); an inactive hinge's skipped Jacobian is zero, as Ceres' is.
template <typename Functor, int kN, int... kBlocks>
void expectCeresBits(const Functor& f, const std::vector<double*>& params) {
  const HingeAutoDiffCostFunction<Functor, kN, kBlocks...> ours{Functor(f)};
  const ceres::AutoDiffCostFunction<Functor, kN, kBlocks...> ceres_ad{new Functor(f)};
  const Evaluated a = evaluate(ours, params, -7.0);
  const Evaluated b = evaluate(ceres_ad, params, 7.0);
  auto same = [](double x, double y) {
    return std::memcmp(&x, &y, sizeof x) == 0 || (x == 0.0 && y == 0.0);
  };
  for (int k = 0; k < kN; ++k) {
    EXPECT_EQ(std::memcmp(&a.r[k], &b.r[k], sizeof(double)), 0) << "residual " << k;
  }
  for (std::size_t i = 0; i < a.j.size(); ++i) {
    for (std::size_t e = 0; e < a.j[i].size(); ++e)
      EXPECT_TRUE(same(a.j[i][e], b.j[i][e])) << "block " << i << " entry " << e;
  }
  std::vector<double> r(kN), rc(kN);
  ASSERT_TRUE(ours.Evaluate(params.data(), r.data(), nullptr));
  ASSERT_TRUE(ceres_ad.Evaluate(params.data(), rc.data(), nullptr));
  EXPECT_EQ(std::memcmp(r.data(), rc.data(), sizeof(double) * kN), 0);
}

TEST(HolonomicMotionCosts, HingeAutodiffGivesCeresAutodiffBits) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(-0.25, 0.25), ang(-3.0, 3.0), dt(0.05, 0.4);
  for (int trial = 0; trial < 200; ++trial) {
    const MotionLimits lim = limits(trial % 2 == 0);
    double p0[3] = {pos(rng), pos(rng), ang(rng)};
    double p1[3] = {p0[0] + pos(rng), p0[1] + pos(rng), p0[2] + 0.3 * pos(rng)};
    double p2[3] = {p1[0] + pos(rng), p1[1] + pos(rng), p1[2] + 0.3 * pos(rng)};
    double t0[1] = {dt(rng)}, t1[1] = {dt(rng)};
    expectCeresBits<VelocityCost, 4, 3, 3, 1>(VelocityCost(lim), {p0, p1, t0});
    expectCeresBits<AccelerationCost, 3, 3, 3, 3, 1, 1>(AccelerationCost(lim),
                                                        {p0, p1, p2, t0, t1});
    expectCeresBits<BoundaryAccelerationCost, 3, 3, 3, 1>(
        BoundaryAccelerationCost(lim, 0.4, -0.1, 0.2, trial % 3 == 0), {p0, p1, t0});
    expectCeresBits<KinematicsCost, 2, 3, 3>(KinematicsCost(1.7, 2.0), {p0, p1});
  }
}

// Terms sharing a band's trigonometry cache give the bits of terms without one, also after
// the poses move (the cache notices by the exact bits: -0.0 is not 0.0 to sin).
TEST(HolonomicMotionCosts, TheSharedTrigCacheChangesNoBit) {
  const MotionLimits lim = limits(true);
  std::vector<double> poses = {0.0, 0.0, 0.3, 0.1, 0.02, 0.35, 0.22, 0.01, -0.0};
  double t0[1] = {0.12}, t1[1] = {0.15};
  const BandTrig trig(3);
  auto same = [](const ceres::CostFunction& a, const ceres::CostFunction& b,
                 const std::vector<double*>& params) {
    const Evaluated ea = evaluate(a, params, 0.0);
    const Evaluated eb = evaluate(b, params, 1.0);
    EXPECT_EQ(ea.r, eb.r);
    EXPECT_EQ(ea.j, eb.j);
  };
  for (int round = 0; round < 3; ++round) {
    double* p0 = poses.data();
    double* p1 = poses.data() + 3;
    double* p2 = poses.data() + 6;
    // Two terms of the same band read each entry: the second one hits the cache.
    for (int pass = 0; pass < 2; ++pass) {
      same(HolonomicVelocityCostFunction(lim, {&trig, 1}), HolonomicVelocityCostFunction(lim),
           {p1, p2, t1});
      same(HolonomicAccelerationCostFunction(lim, {&trig, 0}),
           HolonomicAccelerationCostFunction(lim), {p0, p1, p2, t0, t1});
      same(HolonomicBoundaryAccelerationCostFunction(lim, 0.5, 0.1, -0.2, true, {&trig, 0}),
           HolonomicBoundaryAccelerationCostFunction(lim, 0.5, 0.1, -0.2, true), {p0, p1, t0});
      same(KinematicsCostFunction(1.0, 2.0, {&trig, 1}), KinematicsCostFunction(1.0, 2.0),
           {p1, p2});
    }
    // The optimiser moves the poses: the cached entries must not be reused.
    poses[2] += 0.7;
    poses[5] = -poses[5];
    poses[8] = round == 0 ? 0.0 : -0.0;
    poses[3] += 0.05;
  }
}

TEST(HolonomicMotionCosts, ANonHolonomicBandIsRefused) {
  MotionLimits lim = limits(false);
  lim.holonomic = false;
  EXPECT_THROW(HolonomicVelocityCostFunction{lim}, std::invalid_argument);
  EXPECT_THROW(HolonomicAccelerationCostFunction{lim}, std::invalid_argument);
  EXPECT_THROW((HolonomicBoundaryAccelerationCostFunction{lim, 0.0, 0.0, 0.0, true}),
               std::invalid_argument);
}

}  // namespace
}  // namespace coopnav::band_costs
