#include "coopnav/band/costs/holonomic_motion_costs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace coopnav::band_costs {
namespace {

/// Body-frame velocity of a holonomic segment a → b in ΔT and its derivatives with respect to
/// (xa, ya, θa, xb, yb, θb, ΔT).
struct SegmentJacobian {
  SegmentVelocity<double> v;
  double dvx[7];
  double dvy[7];
  double dom[7];
};

SegmentJacobian segmentJacobian(const double* a, const double* b, double dt) {
  SegmentJacobian j;
  // The functors' own velocity, so that the residuals are theirs to the last bit.
  j.v = segmentVelocity(a, b, dt, true);
  const double c = std::cos(a[2]);
  const double s = std::sin(a[2]);
  const double inv = 1.0 / dt;
  const double vx = j.v.vx, vy = j.v.vy, om = j.v.omega;
  const double dvx[7] = {-c * inv, -s * inv, vy, c * inv, s * inv, 0.0, -vx * inv};
  const double dvy[7] = {s * inv, -c * inv, -vx, -s * inv, c * inv, 0.0, -vy * inv};
  const double dom[7] = {0.0, 0.0, -inv, 0.0, 0.0, inv, -om * inv};
  std::copy(dvx, dvx + 7, j.dvx);
  std::copy(dvy, dvy + 7, j.dvy);
  std::copy(dom, dom + 7, j.dom);
  return j;
}

/// Slope of penaltyInterval(x, lo, hi, eps) (penalties.hpp): the branches it takes.
double intervalSlope(double x, double lo, double hi, double eps) {
  return (x < lo + eps ? -1.0 : 0.0) + (x > hi - eps ? 1.0 : 0.0);
}

bool allZero(const double* r, int n) {
  return std::all_of(r, r + n, [](double v) { return v == 0.0; });
}

void zero(double** jacobians, const int* sizes, int num_blocks, int num_residuals) {
  for (int i = 0; i < num_blocks; ++i) {
    if (jacobians[i] != nullptr)
      std::fill(jacobians[i], jacobians[i] + num_residuals * sizes[i], 0.0);
  }
}

MotionLimits requireHolonomic(const MotionLimits& lim) {
  if (!lim.holonomic) throw std::invalid_argument("holonomic motion cost for a non-holonomic band");
  return lim;
}

/// Where an acceleration term's unknowns sit: block and column of each of the 7 segment
/// variables (xa, ya, θa, xb, yb, θb, ΔT) of one of its segments.
struct SegmentPlacement {
  int block[7];
  int column[7];
};

/// Acceleration residuals r = √w · penalty((v2 − v1) / S) and their Jacobians; v1 / v2 are
/// either a segment (with its placement) or fixed (nullptr). dS: ∂S per block, column 0.
void accelerationJacobian(const MotionLimits& lim, const SegmentJacobian* s1,
                          const SegmentPlacement* at1, const SegmentJacobian* s2,
                          const SegmentPlacement* at2, double S, const int* dS_blocks,
                          const double* dS, int num_dS, const double* r_ax_ay_al,
                          const int* block_sizes, double** jacobians) {
  const double a[3] = {r_ax_ay_al[0], r_ax_ay_al[1], r_ax_ay_al[2]};
  const double w[3] = {lim.sqrt_w_acc_x, lim.sqrt_w_acc_y, lim.sqrt_w_acc_theta};
  const double bound[3] = {lim.acc_lim_x_m_s2, lim.acc_lim_y_m_s2, lim.acc_lim_theta_rad_s2};
  for (int k = 0; k < 3; ++k) {
    const double slope = w[k] * intervalSlope(a[k], -bound[k], bound[k], lim.epsilon);
    auto dvOf = [k](const SegmentJacobian* sj) {
      return k == 0 ? sj->dvx : (k == 1 ? sj->dvy : sj->dom);
    };
    auto put = [&](int block, int col, double value) {
      if (jacobians[block] != nullptr) jacobians[block][k * block_sizes[block] + col] += value;
    };
    if (slope == 0.0) continue;
    if (s1 != nullptr) {
      const double* d = dvOf(s1);
      for (int q = 0; q < 7; ++q) put(at1->block[q], at1->column[q], -slope * d[q] / S);
    }
    if (s2 != nullptr) {
      const double* d = dvOf(s2);
      for (int q = 0; q < 7; ++q) put(at2->block[q], at2->column[q], slope * d[q] / S);
    }
    for (int q = 0; q < num_dS; ++q) put(dS_blocks[q], 0, -slope * a[k] * dS[q] / S);
  }
}

}  // namespace

HolonomicVelocityCostFunction::HolonomicVelocityCostFunction(const MotionLimits& lim)
    : functor_(requireHolonomic(lim)), lim_(lim) {}

bool HolonomicVelocityCostFunction::Evaluate(double const* const* p, double* r,
                                             double** jacobians) const {
  if (!functor_(p[0], p[1], p[2], r)) return false;
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[3] = {3, 3, 1};
  zero(jacobians, kSizes, 3, 4);
  if (functor_.zeroMeansInactive() && allZero(r, 4)) return true;
  const SegmentJacobian j = segmentJacobian(p[0], p[1], p[2][0]);
  const double slope[3] = {
      lim_.sqrt_w_vel_x *
          intervalSlope(j.v.vx, -lim_.max_vel_x_backwards_m_s, lim_.max_vel_x_m_s, lim_.epsilon),
      lim_.sqrt_w_vel_y *
          intervalSlope(j.v.vy, -lim_.max_vel_y_m_s, lim_.max_vel_y_m_s, lim_.epsilon),
      lim_.sqrt_w_vel_theta * intervalSlope(j.v.omega, -lim_.max_vel_theta_rad_s,
                                            lim_.max_vel_theta_rad_s, lim_.epsilon)};
  const double* dv[3] = {j.dvx, j.dvy, j.dom};
  // Segment variable q → (block, column): a = block 0, b = block 1, ΔT = block 2.
  static constexpr int kBlock[7] = {0, 0, 0, 1, 1, 1, 2};
  static constexpr int kColumn[7] = {0, 1, 2, 0, 1, 2, 0};
  for (int k = 0; k < 3; ++k) {
    if (slope[k] == 0.0) continue;
    for (int q = 0; q < 7; ++q) {
      if (jacobians[kBlock[q]] != nullptr)
        jacobians[kBlock[q]][k * kSizes[kBlock[q]] + kColumn[q]] += slope[k] * dv[k][q];
    }
  }
  if (lim_.sqrt_w_nominal > 0.0) {
    // r3 = √w (safeNorm(Δx, Δy) / ΔT − v_nominal).
    const double dx = p[1][0] - p[0][0];
    const double dy = p[1][1] - p[0][1];
    const double n = safeNorm(dx, dy);
    const double dt = p[2][0];
    const double g = lim_.sqrt_w_nominal / (n * dt);
    if (jacobians[0] != nullptr) {
      jacobians[0][3 * 3 + 0] = -g * dx;
      jacobians[0][3 * 3 + 1] = -g * dy;
    }
    if (jacobians[1] != nullptr) {
      jacobians[1][3 * 3 + 0] = g * dx;
      jacobians[1][3 * 3 + 1] = g * dy;
    }
    if (jacobians[2] != nullptr) jacobians[2][3] = -lim_.sqrt_w_nominal * n / (dt * dt);
  }
  return true;
}

HolonomicAccelerationCostFunction::HolonomicAccelerationCostFunction(const MotionLimits& lim)
    : functor_(requireHolonomic(lim)), lim_(lim) {}

bool HolonomicAccelerationCostFunction::Evaluate(double const* const* p, double* r,
                                                 double** jacobians) const {
  if (!functor_(p[0], p[1], p[2], p[3], p[4], r)) return false;
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[5] = {3, 3, 3, 1, 1};
  zero(jacobians, kSizes, 5, 3);
  if (allZero(r, 3)) return true;
  const SegmentJacobian s1 = segmentJacobian(p[0], p[1], p[3][0]);
  const SegmentJacobian s2 = segmentJacobian(p[1], p[2], p[4][0]);
  const double S = 0.5 * (p[3][0] + p[4][0]);
  const double a[3] = {(s2.v.vx - s1.v.vx) / S, (s2.v.vy - s1.v.vy) / S,
                       (s2.v.omega - s1.v.omega) / S};
  static constexpr SegmentPlacement kFirst{{0, 0, 0, 1, 1, 1, 3}, {0, 1, 2, 0, 1, 2, 0}};
  static constexpr SegmentPlacement kSecond{{1, 1, 1, 2, 2, 2, 4}, {0, 1, 2, 0, 1, 2, 0}};
  static constexpr int kDsBlocks[2] = {3, 4};
  static constexpr double kDs[2] = {0.5, 0.5};
  accelerationJacobian(lim_, &s1, &kFirst, &s2, &kSecond, S, kDsBlocks, kDs, 2, a, kSizes,
                       jacobians);
  return true;
}

HolonomicBoundaryAccelerationCostFunction::HolonomicBoundaryAccelerationCostFunction(
    const MotionLimits& lim, double vx_m_s, double vy_m_s, double omega_rad_s, bool at_start)
    : functor_(requireHolonomic(lim), vx_m_s, vy_m_s, omega_rad_s, at_start),
      lim_(lim),
      at_start_(at_start) {}

bool HolonomicBoundaryAccelerationCostFunction::Evaluate(double const* const* p, double* r,
                                                         double** jacobians) const {
  if (!functor_(p[0], p[1], p[2], r)) return false;
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[3] = {3, 3, 1};
  zero(jacobians, kSizes, 3, 3);
  if (allZero(r, 3)) return true;
  const SegmentJacobian s = segmentJacobian(p[0], p[1], p[2][0]);
  const double S = p[2][0];
  const SegmentVelocity<double> k = functor_.fixedVelocity();
  const double a[3] = {at_start_ ? (s.v.vx - k.vx) / S : (k.vx - s.v.vx) / S,
                       at_start_ ? (s.v.vy - k.vy) / S : (k.vy - s.v.vy) / S,
                       at_start_ ? (s.v.omega - k.omega) / S : (k.omega - s.v.omega) / S};
  static constexpr SegmentPlacement kOnly{{0, 0, 0, 1, 1, 1, 2}, {0, 1, 2, 0, 1, 2, 0}};
  static constexpr int kDsBlocks[1] = {2};
  static constexpr double kDs[1] = {1.0};
  if (at_start_) {
    accelerationJacobian(lim_, nullptr, nullptr, &s, &kOnly, S, kDsBlocks, kDs, 1, a, kSizes,
                         jacobians);
  } else {
    accelerationJacobian(lim_, &s, &kOnly, nullptr, nullptr, S, kDsBlocks, kDs, 1, a, kSizes,
                         jacobians);
  }
  return true;
}

KinematicsCostFunction::KinematicsCostFunction(double sqrt_w_nh, double sqrt_w_forward)
    : functor_(sqrt_w_nh, sqrt_w_forward), sw_nh_(sqrt_w_nh), sw_fwd_(sqrt_w_forward) {}

bool KinematicsCostFunction::Evaluate(double const* const* p, double* r, double** jacobians) const {
  if (!functor_(p[0], p[1], r)) return false;
  if (jacobians == nullptr) return true;
  const double* a = p[0];
  const double* b = p[1];
  const double dx = b[0] - a[0];
  const double dy = b[1] - a[1];
  const double ca = std::cos(a[2]), sa = std::sin(a[2]);
  const double cb = std::cos(b[2]), sb = std::sin(b[2]);
  const double w = sw_nh_;
  const double ja0[3] = {w * (sa + sb), -w * (ca + cb), w * (-sa * dy - ca * dx)};
  const double jb0[3] = {-w * (sa + sb), w * (ca + cb), w * (-sb * dy - cb * dx)};
  double ja1[3] = {0.0, 0.0, 0.0}, jb1[3] = {0.0, 0.0, 0.0};
  // r1 = w_fwd max(0, −f), f = ca Δx + sa Δy (penaltyBelow(f, 0, 0)): slope −w_fwd where f < 0.
  if (sw_fwd_ > 0.0 && ca * dx + sa * dy < 0.0) {
    const double g = -sw_fwd_;
    ja1[0] = g * -ca;
    ja1[1] = g * -sa;
    ja1[2] = g * (-sa * dx + ca * dy);
    jb1[0] = g * ca;
    jb1[1] = g * sa;
  }
  if (jacobians[0] != nullptr) {
    std::copy(ja0, ja0 + 3, jacobians[0]);
    std::copy(ja1, ja1 + 3, jacobians[0] + 3);
  }
  if (jacobians[1] != nullptr) {
    std::copy(jb0, jb0 + 3, jacobians[1]);
    std::copy(jb1, jb1 + 3, jacobians[1] + 3);
  }
  return true;
}

}  // namespace coopnav::band_costs
