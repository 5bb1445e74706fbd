#pragma once
/// @file Pull of a band pose towards its reference path (TEB/CoHAN EdgeViaPoint, Rösmann et al.
/// 2015; CoHAN holds the anticipated human to its predicted path with 10x the robot's weight,
/// Singamaneni et al. 2021). Own variant: the residual is the offset along the path normal at
/// the pose's projection, so the pull never drags poses along the path, only back onto it. The
/// projection is read through a pointer: the outer loop re-projects between the solves of one
/// problem instead of rebuilding it.

#include <Eigen/Core>

namespace coopnav::band_costs {

/// Projection of a pose on its reference path and the unit path normal there.
struct ViaAnchor {
  double x{0.0}, y{0.0};
  double nx{0.0}, ny{0.0};  ///< (0, 0): no projection, the term is off
};

struct ViaPointCost {
  static constexpr int kResiduals = 1;
  ViaPointCost(double sqrt_weight, const ViaAnchor* anchor) : sw_(sqrt_weight), a_(anchor) {}
  template <typename T>
  bool operator()(const T* p, T* r) const {
    const ViaAnchor& a = *a_;
    r[0] = sw_ * ((p[0] - a.x) * a.nx + (p[1] - a.y) * a.ny);
    return true;
  }

 private:
  double sw_;
  const ViaAnchor* a_;
};

}  // namespace coopnav::band_costs
