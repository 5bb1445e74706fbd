#pragma once
/// @file Automatic differentiation that skips the derivative of an inactive hinge term. Most
/// band terms are penalties that are exactly zero inside their allowed set (penalties.hpp: the
/// zero branch is a constant, so its derivative is zero too): a cruising segment violates no
/// acceleration limit, a far pose pair no safety distance. When a term's functor says its zero
/// residuals carry no derivative (`zeroMeansInactive()`), and every residual is zero, the
/// Jacobians are zero, and evaluating them with dual numbers (the most expensive part of a
/// linearisation: Jet<11> with sin/cos/atan2 for the acceleration term) is skipped.
///
/// Otherwise the dual numbers are those of ceres::AutoDiffCostFunction, on Ceres' public Jet
/// type: one ceres::Jet<double, N> per parameter, N the parameters of all blocks, each seeded
/// with its own unit derivative; the residuals and Jacobians are the same to the bit
/// (test/unit/band/holonomic_motion_costs_test.cpp). The functor lives inside this object, not
/// on the heap behind it as in ceres::AutoDiffCostFunction: one allocation fewer per residual
/// block (the problem is rebuilt whenever the bands are resized, ~2.5 times a cycle, with ~1000
/// blocks each time).

#include <ceres/jet.h>
#include <ceres/sized_cost_function.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
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
      if (!call(parameters, residuals, Blocks{})) return false;
      const bool inactive =
          std::all_of(residuals, residuals + kNumResiduals, [](double r) { return r == 0.0; });
      if (!inactive) return full(parameters, residuals, jacobians);
      for (int i = 0; i < kNumBlocks; ++i) {
        if (jacobians[i] != nullptr)
          std::fill(jacobians[i], jacobians[i] + kNumResiduals * kSizes[i], 0.0);
      }
      return true;
    }
  }

 private:
  static_assert(kNumResiduals > 0 && sizeof...(kBlockSizes) > 0 && ((kBlockSizes > 0) && ...),
                "fixed, positive residual and parameter block sizes");
  static constexpr int kNumBlocks = static_cast<int>(sizeof...(kBlockSizes));
  static constexpr std::array<int, kNumBlocks> kSizes{kBlockSizes...};
  static constexpr int kNumParameters = (kBlockSizes + ...);
  static constexpr std::array<int, kNumBlocks> offsets() {
    std::array<int, kNumBlocks> o{};
    for (int i = 0, sum = 0; i < kNumBlocks; sum += kSizes[i], ++i) o[i] = sum;
    return o;
  }
  /// First parameter of each block among the kNumParameters.
  static constexpr std::array<int, kNumBlocks> kOffsets = offsets();
  using Blocks = std::make_index_sequence<sizeof...(kBlockSizes)>;
  using JetT = ceres::Jet<double, kNumParameters>;

  /// Residuals, and the Jacobians (row-major, kNumResiduals × block size) that are asked for.
  bool full(double const* const* parameters, double* residuals, double** jacobians) const {
    if (jacobians == nullptr) return call(parameters, residuals, Blocks{});
    std::array<JetT, kNumParameters> x;
    for (int i = 0; i < kNumBlocks; ++i) {
      for (int j = 0; j < kSizes[i]; ++j) {
        x[kOffsets[i] + j] = JetT(parameters[i][j], kOffsets[i] + j);
      }
    }
    // A residual the functor leaves unset shows as NaN.
    std::array<JetT, kNumResiduals> r;
    for (JetT& e : r) {
      e.a = std::numeric_limits<double>::quiet_NaN();
      e.v.setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    if (!callJets(x.data(), r.data(), Blocks{})) return false;
    for (int k = 0; k < kNumResiduals; ++k) residuals[k] = r[k].a;
    for (int i = 0; i < kNumBlocks; ++i) {
      if (jacobians[i] == nullptr) continue;
      for (int k = 0; k < kNumResiduals; ++k) {
        for (int j = 0; j < kSizes[i]; ++j) {
          jacobians[i][k * kSizes[i] + j] = r[k].v[kOffsets[i] + j];
        }
      }
    }
    return true;
  }
  template <std::size_t... I>
  bool call(double const* const* p, double* r, std::index_sequence<I...>) const {
    return functor_(p[I]..., r);
  }
  template <std::size_t... I>
  bool callJets(const JetT* x, JetT* r, std::index_sequence<I...>) const {
    return functor_((x + kOffsets[I])..., r);
  }

  Functor functor_;
};

}  // namespace coopnav::band_costs
