#pragma once
/// @file Acceleration-limit terms (TEB EdgeAcceleration / ...Start / ...Goal, Rösmann et al.
/// 2013): a = 2 (v2 − v1) / (ΔT1 + ΔT2) over three consecutive poses; at the band start the
/// first segment is compared with the measured velocity, at a goal with standstill.
/// Residuals: [ax, ay, α] outside their ± limits.

#include "coopnav/band/costs/segment_velocity.hpp"

namespace coopnav::band_costs {

template <typename T>
void accelerationResiduals(const MotionLimits& lim, const SegmentVelocity<T>& v1,
                           const SegmentVelocity<T>& v2, const T& dt_sum, T* r) {
  const T ax = (v2.vx - v1.vx) / dt_sum;
  const T ay = (v2.vy - v1.vy) / dt_sum;
  const T al = (v2.omega - v1.omega) / dt_sum;
  r[0] =
      lim.sqrt_w_acc_x * penaltyInterval(ax, -lim.acc_lim_x_m_s2, lim.acc_lim_x_m_s2, lim.epsilon);
  r[1] = lim.holonomic ? T(lim.sqrt_w_acc_y * penaltyInterval(ay, -lim.acc_lim_y_m_s2,
                                                              lim.acc_lim_y_m_s2, lim.epsilon))
                       : T(0.0);
  r[2] = lim.sqrt_w_acc_theta *
         penaltyInterval(al, -lim.acc_lim_theta_rad_s2, lim.acc_lim_theta_rad_s2, lim.epsilon);
}

/// Interior: poses p0, p1, p2, ΔT0, ΔT1.
struct AccelerationCost {
  static constexpr int kResiduals = 3;
  /// Every residual is a penalty: zero only in its constant zero branch (hinge_autodiff.hpp).
  bool zeroMeansInactive() const { return true; }
  explicit AccelerationCost(const MotionLimits& lim) : lim_(lim) {}
  template <typename T>
  bool operator()(const T* p0, const T* p1, const T* p2, const T* dt0, const T* dt1, T* r) const {
    const auto v1 = segmentVelocity(p0, p1, dt0[0], lim_.holonomic);
    const auto v2 = segmentVelocity(p1, p2, dt1[0], lim_.holonomic);
    accelerationResiduals(lim_, v1, v2, T(0.5) * (dt0[0] + dt1[0]), r);
    return true;
  }

 private:
  MotionLimits lim_;
};

/// Boundary: one segment (p0, p1, ΔT) against a known body-frame velocity. `at_start` true:
/// (v_known → v_segment), false: goal (v_segment → v_known, normally 0).
struct BoundaryAccelerationCost {
  static constexpr int kResiduals = 3;
  bool zeroMeansInactive() const { return true; }
  BoundaryAccelerationCost(const MotionLimits& lim, double vx_m_s, double vy_m_s,
                           double omega_rad_s, bool at_start)
      : lim_(lim), vx_(vx_m_s), vy_(vy_m_s), om_(omega_rad_s), at_start_(at_start) {}
  /// The measured (start) or standstill (goal) velocity the band's end segment is compared with.
  SegmentVelocity<double> fixedVelocity() const { return {vx_, lim_.holonomic ? vy_ : 0.0, om_}; }
  template <typename T>
  bool operator()(const T* p0, const T* p1, const T* dt, T* r) const {
    residuals(segmentVelocity(p0, p1, dt[0], lim_.holonomic), dt[0], r);
    return true;
  }
  /// The residuals of the end segment's velocity v.
  template <typename T>
  void residuals(const SegmentVelocity<T>& v, const T& dt, T* r) const {
    const SegmentVelocity<T> k{T(vx_), T(lim_.holonomic ? vy_ : 0.0), T(om_)};
    if (at_start_) {
      accelerationResiduals(lim_, k, v, dt, r);
    } else {
      accelerationResiduals(lim_, v, k, dt, r);
    }
  }

 private:
  MotionLimits lim_;
  double vx_, vy_, om_;
  bool at_start_;
};

}  // namespace coopnav::band_costs
