#pragma once
/// @file Relative-velocity ("directional") term between the robot and a human (CoHAN
/// EdgeAgentRobotRelVelocity, HATEB's EdgeHumanRobotDirectional; Khambhaita & Alami 2020,
/// Singamaneni et al. 2021): with d_rh = p_h − p_r (not normalised),
///   c = (max((v_r − v_h)·d_rh, 0) + |v_r| + 1) / |d_rh|,
/// penalised above `threshold`. It grows as the agents close in on each other head-on, long
/// before the safety distance is reached, which is what bends the bands early.
/// Pairing by time: segment a (a0 → a1 in ΔT_a) of one band and segment b of the other band,
/// with the position on b interpolated at a0's time (fraction read through a pointer, updated
/// between the solves of one problem).

#include "coopnav/band/costs/penalties.hpp"

namespace coopnav::band_costs {

struct RelativeVelocityCost {
  static constexpr int kResiduals = 1;
  bool zeroMeansInactive() const { return true; }
  /// robot_is_a: which segment is the robot's (|v_r| enters the formula, not |v_h|).
  RelativeVelocityCost(double sqrt_weight, double threshold, const double* fraction,
                       bool robot_is_a, double epsilon)
      : sw_(sqrt_weight), thr_(threshold), s_(fraction), robot_is_a_(robot_is_a), eps_(epsilon) {}
  template <typename T>
  bool operator()(const T* a0, const T* a1, const T* dta, const T* b0, const T* b1, const T* dtb,
                  T* r) const {
    const T pax = a0[0], pay = a0[1];
    const double s = *s_;
    const T pbx = (1.0 - s) * b0[0] + s * b1[0];
    const T pby = (1.0 - s) * b0[1] + s * b1[1];
    const T vax = (a1[0] - a0[0]) / dta[0], vay = (a1[1] - a0[1]) / dta[0];
    const T vbx = (b1[0] - b0[0]) / dtb[0], vby = (b1[1] - b0[1]) / dtb[0];
    // Robot r, human h.
    const T prx = robot_is_a_ ? pax : pbx, pry = robot_is_a_ ? pay : pby;
    const T phx = robot_is_a_ ? pbx : pax, phy = robot_is_a_ ? pby : pay;
    const T vrx = robot_is_a_ ? vax : vbx, vry = robot_is_a_ ? vay : vby;
    const T vhx = robot_is_a_ ? vbx : vax, vhy = robot_is_a_ ? vby : vay;
    const T dx = phx - prx, dy = phy - pry;
    T closing = (vrx - vhx) * dx + (vry - vhy) * dy;
    if (closing < T(0.0)) closing = T(0.0);
    // Floor on the distance: coinciding poses (a symmetric head-on start) would make c explode
    // (initial cost ~7e12 on an exactly symmetric start); the safety term takes over at such
    // range anyway.
    constexpr double kMinDist_m = 0.1;
    T dist = safeNorm(dx, dy);
    if (dist < T(kMinDist_m)) dist = T(kMinDist_m);
    const T c = (closing + safeNorm(vrx, vry) + T(1.0)) / dist;
    r[0] = sw_ * penaltyAbove(c, thr_, eps_);
    return true;
  }

 private:
  double sw_, thr_;
  const double* s_;
  bool robot_is_a_;
  double eps_;
};

}  // namespace coopnav::band_costs
