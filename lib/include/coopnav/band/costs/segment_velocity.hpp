#pragma once
/// @file Velocity of one band segment (pose a → pose b in ΔT), in the body frame of pose a, as
/// TEB's velocity edges compute it (Rösmann et al. 2013): holonomic agents get (vx, vy, ω);
/// differential-drive agents get a signed speed along the heading (vy = 0).

#include "coopnav/band/costs/penalties.hpp"

namespace coopnav::band_costs {

template <typename T>
struct SegmentVelocity {
  T vx;
  T vy;
  T omega;
};

/// The same from pose a's heading cosine / sine and the wrapped heading change θb − θa, which
/// segmentVelocity() computes and a BandTrig cache can supply (the same bits either way).
template <typename T>
SegmentVelocity<T> segmentVelocityFrom(const T* a, const T* b, const T& dt, bool holonomic,
                                       const T& c, const T& s, const T& dtheta) {
  const T dx = b[0] - a[0];
  const T dy = b[1] - a[1];
  SegmentVelocity<T> v;
  if (holonomic) {
    v.vx = (c * dx + s * dy) / dt;
    v.vy = (-s * dx + c * dy) / dt;
  } else {
    v.vx = safeNorm(dx, dy) / dt * smoothSign(c * dx + s * dy);
    v.vy = T(0.0);
  }
  v.omega = dtheta / dt;
  return v;
}

template <typename T>
SegmentVelocity<T> segmentVelocity(const T* a, const T* b, const T& dt, bool holonomic) {
  using std::cos;
  using std::sin;
  const T c = cos(a[2]);
  const T s = sin(a[2]);
  return segmentVelocityFrom(a, b, dt, holonomic, c, s, angleDiff(b[2], a[2]));
}

/// Limits and √weights of the velocity / acceleration terms of one band.
struct MotionLimits {
  bool holonomic{true};
  double max_vel_x_m_s{0.7};
  double max_vel_x_backwards_m_s{0.4};
  double max_vel_y_m_s{0.7};
  double max_vel_theta_rad_s{1.2};
  double acc_lim_x_m_s2{0.3};
  double acc_lim_y_m_s2{0.3};
  double acc_lim_theta_rad_s2{0.4};
  double epsilon{0.01};
  double sqrt_w_vel_x{1.0};
  double sqrt_w_vel_y{1.0};
  double sqrt_w_vel_theta{1.0};
  double sqrt_w_acc_x{1.0};
  double sqrt_w_acc_y{1.0};
  double sqrt_w_acc_theta{1.0};
  double sqrt_w_nominal{0.0};
  double nominal_vel_m_s{0.0};
};

}  // namespace coopnav::band_costs
