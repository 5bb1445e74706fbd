#pragma once
/// @file Velocity-limit term of one segment (TEB EdgeVelocity / EdgeVelocityHolonomic; CoHAN
/// EdgeVelocityAgent adds the nominal-walking-speed residual |v| − v_nominal, Singamaneni et
/// al. 2021). Residuals: [vx outside [−back, max], vy outside ±max_y, ω outside ±max_θ,
/// |v| − v_nominal].

#include "coopnav/band/costs/segment_velocity.hpp"

namespace coopnav::band_costs {

struct VelocityCost {
  static constexpr int kResiduals = 4;
  /// The nominal-speed residual is no penalty: it may cross zero with a slope.
  bool zeroMeansInactive() const { return lim_.sqrt_w_nominal == 0.0; }
  explicit VelocityCost(const MotionLimits& lim) : lim_(lim) {}

  /// Parameters: pose a (x, y, θ), pose b, ΔT.
  template <typename T>
  bool operator()(const T* a, const T* b, const T* dt, T* r) const {
    residuals(segmentVelocity(a, b, dt[0], lim_.holonomic), a, b, dt[0], r);
    return true;
  }
  /// The residuals of the segment's velocity v.
  template <typename T>
  void residuals(const SegmentVelocity<T>& v, const T* a, const T* b, const T& dt, T* r) const {
    r[0] = lim_.sqrt_w_vel_x *
           penaltyInterval(v.vx, -lim_.max_vel_x_backwards_m_s, lim_.max_vel_x_m_s, lim_.epsilon);
    r[1] = lim_.holonomic ? T(lim_.sqrt_w_vel_y * penaltyInterval(v.vy, -lim_.max_vel_y_m_s,
                                                                  lim_.max_vel_y_m_s, lim_.epsilon))
                          : T(0.0);
    r[2] = lim_.sqrt_w_vel_theta * penaltyInterval(v.omega, -lim_.max_vel_theta_rad_s,
                                                   lim_.max_vel_theta_rad_s, lim_.epsilon);
    if (lim_.sqrt_w_nominal > 0.0) {
      r[3] = lim_.sqrt_w_nominal *
             (safeNorm(T(b[0] - a[0]), T(b[1] - a[1])) / dt - T(lim_.nominal_vel_m_s));
    } else {
      r[3] = T(0.0);
    }
  }

 private:
  MotionLimits lim_;
};

}  // namespace coopnav::band_costs
