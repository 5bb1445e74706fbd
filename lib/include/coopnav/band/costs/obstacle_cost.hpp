#pragma once
/// @file Obstacle clearance of one pose from the DistanceMap (TEB EdgeObstacle, Rösmann et al.
/// 2015): clearance = nearest-obstacle distance − agent radius, penalised below
/// min_obstacle_dist. Analytic Jacobian: the nearest obstacle point o is treated as locally
/// constant, so ∂d/∂p = (p − o)/|p − o|. Inside an obstacle (or outside the map) the residual is
/// the full margin with a zero gradient: the band must not start there, and neighbouring poses'
/// gradients pull it out. The weight is √weight × *sqrt_multiplier: the outer loop raises it
/// between solves of one problem (TEB weight adaptation) without rebuilding.

#include <ceres/sized_cost_function.h>

#include <cmath>
#include <memory>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav::band_costs {

class ObstacleCost final : public ceres::SizedCostFunction<1, 3> {
 public:
  ObstacleCost(const DistanceMap* map, double sqrt_weight, const double* sqrt_multiplier,
               double min_clearance_m, double radius_m, double epsilon)
      : map_(map),
        sw_(sqrt_weight),
        mult_(sqrt_multiplier),
        min_(min_clearance_m),
        radius_(radius_m),
        eps_(epsilon) {}

  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    const Eigen::Vector2d p(params[0][0], params[0][1]);
    const DistanceResult res = map_->nearest(p);
    const double limit = min_ + eps_;
    double r = 0.0;
    Eigen::Vector2d grad = Eigen::Vector2d::Zero();
    if (res.status == DistanceStatus::kOk || res.status == DistanceStatus::kNotFound) {
      const double clearance = res.distance_m - radius_;
      if (res.status == DistanceStatus::kOk && clearance < limit) {
        r = limit - clearance;
        const Eigen::Vector2d away = p - res.obstacle;
        const double n = away.norm();
        if (n > 1e-9) grad = -away / n;
      }
    } else {
      r = limit + radius_;
    }
    const double sw = mult_ != nullptr ? sw_ * *mult_ : sw_;
    residuals[0] = sw * r;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      jacobians[0][0] = sw * grad.x();
      jacobians[0][1] = sw * grad.y();
      jacobians[0][2] = 0.0;
    }
    return true;
  }

 private:
  const DistanceMap* map_;
  double sw_;
  const double* mult_;
  double min_, radius_, eps_;
};

}  // namespace coopnav::band_costs
