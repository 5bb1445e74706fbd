#pragma once
/// @file Automatic differentiation that skips the derivative of an inactive hinge term. Most
/// band terms are penalties that are exactly zero inside their allowed set (penalties.hpp: the
/// zero branch is a constant, so its derivative is zero too): a cruising segment violates no
/// acceleration limit, a far pose pair no safety distance. When a term's functor says its zero
/// residuals carry no derivative (`zeroMeansInactive()`), and every residual is zero, the
/// Jacobians are zero, and evaluating them with dual numbers (the most expensive part of a
/// linearisation: Jet<11> with sin/cos/atan2 for the acceleration term) is skipped. The result
/// is exactly what ceres::AutoDiffCostFunction computes.

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <algorithm>
#include <memory>
#include <utility>

namespace coopnav::band_costs {

template <typename Functor, int kNumResiduals, int... kBlockSizes>
class HingeAutoDiffCostFunction final
    : public ceres::SizedCostFunction<kNumResiduals, kBlockSizes...> {
 public:
  /// Takes ownership of `functor`.
  explicit HingeAutoDiffCostFunction(Functor* functor)
      : functor_(functor),
        autodiff_(
            std::make_unique<ceres::AutoDiffCostFunction<Functor, kNumResiduals, kBlockSizes...>>(
                functor, ceres::DO_NOT_TAKE_OWNERSHIP)) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (jacobians == nullptr || !functor_->zeroMeansInactive()) {
      return autodiff_->Evaluate(parameters, residuals, jacobians);
    }
    if (!call(parameters, residuals, std::make_index_sequence<sizeof...(kBlockSizes)>{})) {
      return false;
    }
    const bool inactive =
        std::all_of(residuals, residuals + kNumResiduals, [](double r) { return r == 0.0; });
    if (!inactive) return autodiff_->Evaluate(parameters, residuals, jacobians);
    constexpr int kSizes[] = {kBlockSizes...};
    for (std::size_t i = 0; i < sizeof...(kBlockSizes); ++i) {
      if (jacobians[i] != nullptr)
        std::fill(jacobians[i], jacobians[i] + kNumResiduals * kSizes[i], 0.0);
    }
    return true;
  }

 private:
  template <std::size_t... I>
  bool call(double const* const* p, double* r, std::index_sequence<I...>) const {
    return (*functor_)(p[I]..., r);
  }

  std::unique_ptr<Functor> functor_;
  std::unique_ptr<ceres::CostFunction> autodiff_;
};

}  // namespace coopnav::band_costs
