#pragma once
/// @file Automatic differentiation that skips the derivative of an inactive hinge term. Most
/// band terms are penalties that are exactly zero inside their allowed set (penalties.hpp: the
/// zero branch is a constant, so its derivative is zero too): a cruising segment violates no
/// acceleration limit, a far pose pair no safety distance. When a term's functor says its zero
/// residuals carry no derivative (`zeroMeansInactive()`), and every residual is zero, the
/// Jacobians are zero, and evaluating them with dual numbers (the most expensive part of a
/// linearisation: Jet<11> with sin/cos/atan2 for the acceleration term) is skipped. The result
/// is exactly what ceres::AutoDiffCostFunction computes.
///
/// The functor lives inside this object and the dual numbers are Ceres' own AutoDifferentiate(),
/// the code ceres::AutoDiffCostFunction::Evaluate runs, without an AutoDiffCostFunction object
/// (whose base allocates its parameter-size list): two allocations per residual block instead
/// of four (the problem is rebuilt whenever the bands are resized, ~2.5 times a cycle, with
/// ~1000 blocks each time).

#include <ceres/internal/autodiff.h>
#include <ceres/internal/variadic_evaluate.h>
#include <ceres/sized_cost_function.h>

#include <algorithm>
#include <type_traits>
#include <utility>

namespace coopnav::band_costs {

/// True when Functor has `bool zeroMeansInactive() const`.
template <typename Functor, typename = void>
struct HasInactiveTest : std::false_type {};
template <typename Functor>
struct HasInactiveTest<Functor,
                       std::void_t<decltype(std::declval<const Functor&>().zeroMeansInactive())>>
    : std::true_type {};

template <typename Functor, int kNumResiduals, int... kBlockSizes>
class HingeAutoDiffCostFunction final
    : public ceres::SizedCostFunction<kNumResiduals, kBlockSizes...> {
 public:
  explicit HingeAutoDiffCostFunction(Functor functor) : functor_(std::move(functor)) {}
  HingeAutoDiffCostFunction(const HingeAutoDiffCostFunction&) = delete;
  HingeAutoDiffCostFunction& operator=(const HingeAutoDiffCostFunction&) = delete;

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if constexpr (!HasInactiveTest<Functor>::value) {
      return full(parameters, residuals, jacobians);
    } else {
      if (jacobians == nullptr || !functor_.zeroMeansInactive()) {
        return full(parameters, residuals, jacobians);
      }
      if (!call(parameters, residuals, std::make_index_sequence<sizeof...(kBlockSizes)>{})) {
        return false;
      }
      const bool inactive =
          std::all_of(residuals, residuals + kNumResiduals, [](double r) { return r == 0.0; });
      if (!inactive) return full(parameters, residuals, jacobians);
      constexpr int kSizes[] = {kBlockSizes...};
      for (std::size_t i = 0; i < sizeof...(kBlockSizes); ++i) {
        if (jacobians[i] != nullptr)
          std::fill(jacobians[i], jacobians[i] + kNumResiduals * kSizes[i], 0.0);
      }
      return true;
    }
  }

 private:
  using Dims = typename ceres::SizedCostFunction<kNumResiduals, kBlockSizes...>::ParameterDims;
  /// What ceres::AutoDiffCostFunction<Functor, kNumResiduals, kBlockSizes...>::Evaluate does.
  bool full(double const* const* parameters, double* residuals, double** jacobians) const {
    if (jacobians == nullptr)
      return ceres::internal::VariadicEvaluate<Dims>(functor_, parameters, residuals);
    return ceres::internal::AutoDifferentiate<kNumResiduals, Dims>(
        functor_, parameters, kNumResiduals, residuals, jacobians);
  }
  template <std::size_t... I>
  bool call(double const* const* p, double* r, std::index_sequence<I...>) const {
    return functor_(p[I]..., r);
  }

  Functor functor_;
};

}  // namespace coopnav::band_costs
