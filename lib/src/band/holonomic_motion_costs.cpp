#include "coopnav/band/costs/holonomic_motion_costs.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace coopnav::band_costs {
namespace {

std::uint64_t bitsOf(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// Heading cosine / sine of pose a and the wrapped heading change of segment a → b, the k-th
/// segment of a term: from the band's cache, or computed as segmentVelocity() does.
struct SegmentTrig {
  double c;
  double s;
  double dtheta;
};

SegmentTrig segmentTrig(const TrigSlot& t, std::size_t k, const double* a, const double* b) {
  SegmentTrig out{};
  if (t.trig != nullptr) {
    t.trig->cosSin(t.first_pose + k, a[2], &out.c, &out.s);
    out.dtheta = t.trig->headingChange(t.first_pose + k, b[2], a[2]);
  } else {
    out.c = std::cos(a[2]);
    out.s = std::sin(a[2]);
    out.dtheta = angleDiff(b[2], a[2]);
  }
  return out;
}

SegmentVelocity<double> velocityOf(const double* a, const double* b, double dt,
                                   const SegmentTrig& t) {
  return segmentVelocityFrom(a, b, dt, true, t.c, t.s, t.dtheta);
}

/// Derivatives of a holonomic segment's velocity v with respect to (xa, ya, θa, xb, yb, θb, ΔT).
struct SegmentJacobian {
  SegmentVelocity<double> v;
  double dvx[7];
  double dvy[7];
  double dom[7];
};

SegmentJacobian segmentJacobian(const SegmentVelocity<double>& v, double dt, const SegmentTrig& t) {
  SegmentJacobian j;
  j.v = v;
  const double c = t.c, s = t.s;
  const double inv = 1.0 / dt;
  const double dvx[7] = {-c * inv, -s * inv, v.vy, c * inv, s * inv, 0.0, -v.vx * inv};
  const double dvy[7] = {s * inv, -c * inv, -v.vx, -s * inv, c * inv, 0.0, -v.vy * inv};
  const double dom[7] = {0.0, 0.0, -inv, 0.0, 0.0, inv, -v.omega * inv};
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

BandTrig::BandTrig(std::size_t num_poses) : poses_(num_poses), segments_(num_poses) {}

void BandTrig::cosSin(std::size_t i, double theta, double* c, double* s) const {
  if (i >= poses_.size()) {
    *c = std::cos(theta);
    *s = std::sin(theta);
    return;
  }
  PoseEntry& e = poses_[i];
  const std::uint64_t bits = bitsOf(theta);
  if (!e.valid || e.theta_bits != bits) {
    e.c = std::cos(theta);
    e.s = std::sin(theta);
    e.theta_bits = bits;
    e.valid = true;
  }
  *c = e.c;
  *s = e.s;
}

double BandTrig::headingChange(std::size_t i, double to, double from) const {
  if (i >= segments_.size()) return angleDiff(to, from);
  SegmentEntry& e = segments_[i];
  const std::uint64_t tb = bitsOf(to), fb = bitsOf(from);
  if (!e.valid || e.to_bits != tb || e.from_bits != fb) {
    e.change = angleDiff(to, from);
    e.to_bits = tb;
    e.from_bits = fb;
    e.valid = true;
  }
  return e.change;
}

HolonomicVelocityCostFunction::HolonomicVelocityCostFunction(const MotionLimits& lim, TrigSlot trig)
    : functor_(requireHolonomic(lim)), lim_(lim), trig_(trig) {}

bool HolonomicVelocityCostFunction::Evaluate(double const* const* p, double* r,
                                             double** jacobians) const {
  const double dt = p[2][0];
  const SegmentTrig t = segmentTrig(trig_, 0, p[0], p[1]);
  const SegmentVelocity<double> v = velocityOf(p[0], p[1], dt, t);
  functor_.residuals(v, p[0], p[1], dt, r);
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[3] = {3, 3, 1};
  zero(jacobians, kSizes, 3, 4);
  if (functor_.zeroMeansInactive() && allZero(r, 4)) return true;
  const SegmentJacobian j = segmentJacobian(v, dt, t);
  const double slope[3] = {
      lim_.sqrt_w_vel_x *
          intervalSlope(v.vx, -lim_.max_vel_x_backwards_m_s, lim_.max_vel_x_m_s, lim_.epsilon),
      lim_.sqrt_w_vel_y *
          intervalSlope(v.vy, -lim_.max_vel_y_m_s, lim_.max_vel_y_m_s, lim_.epsilon),
      lim_.sqrt_w_vel_theta * intervalSlope(v.omega, -lim_.max_vel_theta_rad_s,
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

HolonomicAccelerationCostFunction::HolonomicAccelerationCostFunction(const MotionLimits& lim,
                                                                     TrigSlot trig)
    : lim_(requireHolonomic(lim)), trig_(trig) {}

bool HolonomicAccelerationCostFunction::Evaluate(double const* const* p, double* r,
                                                 double** jacobians) const {
  const SegmentTrig t1 = segmentTrig(trig_, 0, p[0], p[1]);
  const SegmentTrig t2 = segmentTrig(trig_, 1, p[1], p[2]);
  const SegmentVelocity<double> v1 = velocityOf(p[0], p[1], p[3][0], t1);
  const SegmentVelocity<double> v2 = velocityOf(p[1], p[2], p[4][0], t2);
  // As AccelerationCost::operator().
  const double S = 0.5 * (p[3][0] + p[4][0]);
  accelerationResiduals(lim_, v1, v2, S, r);
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[5] = {3, 3, 3, 1, 1};
  zero(jacobians, kSizes, 5, 3);
  if (allZero(r, 3)) return true;
  const SegmentJacobian s1 = segmentJacobian(v1, p[3][0], t1);
  const SegmentJacobian s2 = segmentJacobian(v2, p[4][0], t2);
  const double a[3] = {(v2.vx - v1.vx) / S, (v2.vy - v1.vy) / S, (v2.omega - v1.omega) / S};
  static constexpr SegmentPlacement kFirst{{0, 0, 0, 1, 1, 1, 3}, {0, 1, 2, 0, 1, 2, 0}};
  static constexpr SegmentPlacement kSecond{{1, 1, 1, 2, 2, 2, 4}, {0, 1, 2, 0, 1, 2, 0}};
  static constexpr int kDsBlocks[2] = {3, 4};
  static constexpr double kDs[2] = {0.5, 0.5};
  accelerationJacobian(lim_, &s1, &kFirst, &s2, &kSecond, S, kDsBlocks, kDs, 2, a, kSizes,
                       jacobians);
  return true;
}

HolonomicBoundaryAccelerationCostFunction::HolonomicBoundaryAccelerationCostFunction(
    const MotionLimits& lim, double vx_m_s, double vy_m_s, double omega_rad_s, bool at_start,
    TrigSlot trig)
    : functor_(requireHolonomic(lim), vx_m_s, vy_m_s, omega_rad_s, at_start),
      lim_(lim),
      at_start_(at_start),
      trig_(trig) {}

bool HolonomicBoundaryAccelerationCostFunction::Evaluate(double const* const* p, double* r,
                                                         double** jacobians) const {
  const double S = p[2][0];
  const SegmentTrig t = segmentTrig(trig_, 0, p[0], p[1]);
  const SegmentVelocity<double> v = velocityOf(p[0], p[1], S, t);
  functor_.residuals(v, S, r);
  if (jacobians == nullptr) return true;
  static constexpr int kSizes[3] = {3, 3, 1};
  zero(jacobians, kSizes, 3, 3);
  if (allZero(r, 3)) return true;
  const SegmentJacobian s = segmentJacobian(v, S, t);
  const SegmentVelocity<double> k = functor_.fixedVelocity();
  const double a[3] = {at_start_ ? (v.vx - k.vx) / S : (k.vx - v.vx) / S,
                       at_start_ ? (v.vy - k.vy) / S : (k.vy - v.vy) / S,
                       at_start_ ? (v.omega - k.omega) / S : (k.omega - v.omega) / S};
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

KinematicsCostFunction::KinematicsCostFunction(double sqrt_w_nh, double sqrt_w_forward,
                                               TrigSlot trig)
    : functor_(sqrt_w_nh, sqrt_w_forward),
      sw_nh_(sqrt_w_nh),
      sw_fwd_(sqrt_w_forward),
      trig_(trig) {}

bool KinematicsCostFunction::Evaluate(double const* const* p, double* r, double** jacobians) const {
  const double* a = p[0];
  const double* b = p[1];
  double ca = 0.0, sa = 0.0, cb = 0.0, sb = 0.0;
  if (trig_.trig != nullptr) {
    trig_.trig->cosSin(trig_.first_pose, a[2], &ca, &sa);
    trig_.trig->cosSin(trig_.first_pose + 1, b[2], &cb, &sb);
  } else {
    ca = std::cos(a[2]);
    sa = std::sin(a[2]);
    cb = std::cos(b[2]);
    sb = std::sin(b[2]);
  }
  functor_.residuals(a, b, ca, sa, cb, sb, r);
  if (jacobians == nullptr) return true;
  const double dx = b[0] - a[0];
  const double dy = b[1] - a[1];
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
