#pragma once
/// @file The velocity, acceleration and kinematics terms of a holonomic band (velocity_cost.hpp,
/// acceleration_cost.hpp: TEB EdgeVelocityHolonomic / EdgeAcceleration*, CoHAN's nominal
/// walking speed) with hand-derived Jacobians. They are the band problem's most frequent terms
/// and, with dual numbers, its most expensive ones (bench_band: the acceleration term's Jet<11>
/// with sin / cos / atan2 takes 7 % of a cycle). Residuals are the functors' own, evaluated on
/// doubles, so they are exactly the autodiff terms' residuals; the Jacobians agree with the
/// autodiff ones to rounding (test/unit/band/holonomic_motion_costs_test.cpp).
///
/// Derivatives (segment a → b in ΔT, c = cos θa, s = sin θa, body-frame velocity of pose a):
///   vx = (c Δx + s Δy) / ΔT,  vy = (−s Δx + c Δy) / ΔT,  ω = wrap(θb − θa) / ΔT,
///   ∂vx/∂(xa, ya, θa, xb, yb, ΔT) = (−c, −s, vy ΔT, c, s, −vx) / ΔT,
///   ∂vy/∂(xa, ya, θa, xb, yb, ΔT) = (s, −c, −vx ΔT, −s, c, −vy) / ΔT,
///   ∂ω/∂(θa, θb, ΔT) = (−1, 1, −ω) / ΔT (away from the wrap at ±π, where the atan2 form is
///   not differentiable either);
///   acceleration a = (v2 − v1) / S with S = (ΔT1 + ΔT2) / 2 (at a band end: S = ΔT and one
///   velocity fixed): ∂a = (∂v2 − ∂v1) / S − a ∂S / S;
///   a penalty's slope is −1 below its lower bound, +1 above its upper bound, 0 inside;
///   kinematics (any band): r0 = w ((ca + cb) Δy − (sa + sb) Δx), r1 = w_fwd max(0, −(ca Δx + sa
///   Δy)).

#include <ceres/sized_cost_function.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coopnav/band/costs/acceleration_cost.hpp"
#include "coopnav/band/costs/kinematics_cost.hpp"
#include "coopnav/band/costs/velocity_cost.hpp"

namespace coopnav::band_costs {

/// Heading trigonometry of one band, each value computed once: cos / sin of every pose's θ and
/// the wrapped heading change of every segment (angleDiff). A pose's heading enters up to five
/// terms (its velocity, two accelerations, two kinematics terms), a segment's change three;
/// computed by every term, the sin / cos / atan2 behind them take ~12 % of a cycle (bench_band).
/// An entry is reused while its inputs keep their exact bits, so every term sees what it would
/// compute itself. Entries are filled while the terms evaluate, so the terms of one band must not
/// be evaluated on two threads at once: SparseLm evaluates on one, and the Ceres backend runs
/// with num_threads = 1.
class BandTrig {
 public:
  explicit BandTrig(std::size_t num_poses);
  /// cos and sin of θ, the heading of pose i.
  void cosSin(std::size_t i, double theta, double* c, double* s) const;
  /// angleDiff(to, from) of segment i (pose i to pose i + 1).
  double headingChange(std::size_t i, double to, double from) const;

 private:
  struct PoseEntry {
    std::uint64_t theta_bits{0};
    bool valid{false};
    double c{0.0}, s{0.0};
  };
  struct SegmentEntry {
    std::uint64_t to_bits{0}, from_bits{0};
    bool valid{false};
    double change{0.0};
  };
  mutable std::vector<PoseEntry> poses_;
  mutable std::vector<SegmentEntry> segments_;
};

/// Where a term sits in its band, for the cache: the index of its first pose (its other poses
/// follow). trig nullptr: the term computes its trigonometry itself.
struct TrigSlot {
  const BandTrig* trig{nullptr};
  std::size_t first_pose{0};
};

/// VelocityCost of a holonomic band. Parameters: pose a, pose b, ΔT.
class HolonomicVelocityCostFunction final : public ceres::SizedCostFunction<4, 3, 3, 1> {
 public:
  /// lim.holonomic must be true (std::invalid_argument otherwise).
  explicit HolonomicVelocityCostFunction(const MotionLimits& lim, TrigSlot trig = {});
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  VelocityCost functor_;
  MotionLimits lim_;
  TrigSlot trig_;
};

/// AccelerationCost of a holonomic band. Parameters: poses 0, 1, 2, ΔT0, ΔT1.
class HolonomicAccelerationCostFunction final : public ceres::SizedCostFunction<3, 3, 3, 3, 1, 1> {
 public:
  explicit HolonomicAccelerationCostFunction(const MotionLimits& lim, TrigSlot trig = {});
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  MotionLimits lim_;
  TrigSlot trig_;
};

/// BoundaryAccelerationCost of a holonomic band. Parameters: pose 0, pose 1, ΔT.
class HolonomicBoundaryAccelerationCostFunction final
    : public ceres::SizedCostFunction<3, 3, 3, 1> {
 public:
  HolonomicBoundaryAccelerationCostFunction(const MotionLimits& lim, double vx_m_s, double vy_m_s,
                                            double omega_rad_s, bool at_start, TrigSlot trig = {});
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  BoundaryAccelerationCost functor_;
  MotionLimits lim_;
  bool at_start_;
  TrigSlot trig_;
};

/// KinematicsCost (any band: it holds no holonomic assumption). Parameters: pose a, pose b.
class KinematicsCostFunction final : public ceres::SizedCostFunction<2, 3, 3> {
 public:
  KinematicsCostFunction(double sqrt_w_nh, double sqrt_w_forward, TrigSlot trig = {});
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  KinematicsCost functor_;
  double sw_nh_, sw_fwd_;
  TrigSlot trig_;
};

}  // namespace coopnav::band_costs
