#pragma once
/// @file Time-optimality term (TEB EdgeTimeOptimal: e = ΔT) plus a floor keeping ΔT positive.
/// TEB bounds ΔT in g2o; a Ceres parameter bound would switch on a projected line search that
/// re-evaluates Jacobians and takes ~3x as long per cycle, so a stiff one-sided penalty does the
/// job instead.

#include "coopnav/band/costs/penalties.hpp"

namespace coopnav::band_costs {

struct TimeOptimalCost {
  static constexpr int kResiduals = 2;
  TimeOptimalCost(double sqrt_weight, double dt_min_s) : sw_(sqrt_weight), dt_min_(dt_min_s) {}
  template <typename T>
  bool operator()(const T* dt, T* r) const {
    constexpr double kSqrtFloorWeight = 100.0;
    r[0] = sw_ * dt[0];
    r[1] = kSqrtFloorWeight * penaltyBelow(dt[0], dt_min_, 0.0);
    return true;
  }

 private:
  double sw_;
  double dt_min_;
};

}  // namespace coopnav::band_costs
