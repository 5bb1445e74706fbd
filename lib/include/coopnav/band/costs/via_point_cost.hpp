#pragma once
/// @file Pull of a band pose towards its reference path (TEB/CoHAN EdgeViaPoint, Rösmann et al.
/// 2015; CoHAN holds the anticipated human to its predicted path with 10x the robot's weight,
/// Singamaneni et al. 2021). Own variant: the residual is the offset along the path normal at
/// the pose's projection (fixed for one outer iteration), so the pull never drags poses along
/// the path, only back onto it.

#include <Eigen/Core>

namespace coopnav::band_costs {

struct ViaPointCost {
  static constexpr int kResiduals = 1;
  /// anchor: projection of the pose on the path; normal: unit path normal there.
  ViaPointCost(double sqrt_weight, const Eigen::Vector2d& anchor, const Eigen::Vector2d& normal)
      : sw_(sqrt_weight), ax_(anchor.x()), ay_(anchor.y()), nx_(normal.x()), ny_(normal.y()) {}
  template <typename T>
  bool operator()(const T* p, T* r) const {
    r[0] = sw_ * ((p[0] - ax_) * nx_ + (p[1] - ay_) * ny_);
    return true;
  }

 private:
  double sw_, ax_, ay_, nx_, ny_;
};

}  // namespace coopnav::band_costs
