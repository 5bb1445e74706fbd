#pragma once
/// @file Non-holonomic kinematics term (TEB EdgeKinematicsDiffDrive, Rösmann et al. 2012):
/// consecutive poses lie on a common arc iff (cosθ0 + cosθ1) Δy − (sinθ0 + sinθ1) Δx = 0.
/// For a differential-drive agent a second residual penalises driving against the heading
/// (forward-drive preference). Holonomic agents keep the first residual at a small weight so
/// their heading follows their motion.

#include "coopnav/band/costs/penalties.hpp"

namespace coopnav::band_costs {

struct KinematicsCost {
  static constexpr int kResiduals = 2;
  KinematicsCost(double sqrt_w_nh, double sqrt_w_forward)
      : sw_nh_(sqrt_w_nh), sw_fwd_(sqrt_w_forward) {}
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    using std::cos;
    using std::sin;
    residuals(a, b, T(cos(a[2])), T(sin(a[2])), T(cos(b[2])), T(sin(b[2])), r);
    return true;
  }
  /// The residuals from the headings' cosines and sines (a BandTrig cache can supply them).
  template <typename T>
  void residuals(const T* a, const T* b, const T& ca, const T& sa, const T& cb, const T& sb,
                 T* r) const {
    const T dx = b[0] - a[0];
    const T dy = b[1] - a[1];
    r[0] = sw_nh_ * ((ca + cb) * dy - (sa + sb) * dx);
    r[1] = sw_fwd_ > 0.0 ? T(sw_fwd_ * penaltyBelow(T(ca * dx + sa * dy), 0.0, 0.0)) : T(0.0);
  }

 private:
  double sw_nh_, sw_fwd_;
};

}  // namespace coopnav::band_costs
