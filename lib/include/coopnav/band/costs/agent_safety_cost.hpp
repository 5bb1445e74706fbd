#pragma once
/// @file Safety distance between two agents paired BY TIME (CoHAN EdgeAgentRobotSafety /
/// EdgeAgentAgentSafety, Singamaneni et al. 2021, pair by pose index; we interpolate the other
/// band at the pose's time; the fraction and the weight multiplier are read through pointers so
/// that the outer loop updates them between solves of one problem). d = centre distance −
/// both radii; with x = max(0, a + ε − d) the residual is x + x², CoHAN's shape, which pushes
/// harder the deeper the violation.

#include "coopnav/band/costs/penalties.hpp"

namespace coopnav::band_costs {

struct AgentSafetyCost {
  static constexpr int kResiduals = 1;
  bool zeroMeansInactive() const { return true; }
  /// *fraction: where the paired time falls between other poses b0 and b1.
  AgentSafetyCost(double sqrt_weight, const double* sqrt_multiplier, double min_dist_m,
                  double radii_sum_m, const double* fraction, double epsilon)
      : sw_(sqrt_weight),
        mult_(sqrt_multiplier),
        min_(min_dist_m),
        radii_(radii_sum_m),
        s_(fraction),
        eps_(epsilon) {}
  template <typename T>
  bool operator()(const T* a, const T* b0, const T* b1, T* r) const {
    const double s = *s_;
    const T bx = (1.0 - s) * b0[0] + s * b1[0];
    const T by = (1.0 - s) * b0[1] + s * b1[1];
    const T d = safeNorm(T(a[0] - bx), T(a[1] - by)) - radii_;
    const T x = penaltyBelow(d, min_, eps_);
    r[0] = (sw_ * *mult_) * (x + x * x);
    return true;
  }

 private:
  double sw_;
  const double* mult_;
  double min_, radii_;
  const double* s_;
  double eps_;
};

}  // namespace coopnav::band_costs
