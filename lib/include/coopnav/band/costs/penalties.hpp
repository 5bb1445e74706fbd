#pragma once
/// @file Penalty functions shared by the band cost terms (TEB `penalties.h` semantics, own
/// code): a residual that is zero inside the allowed set and grows linearly outside it, with
/// the margin ε moving the bound inwards so that the optimum lies strictly inside.

#include <ceres/jet.h>

#include <cmath>

namespace coopnav::band_costs {

/// max(0, a + ε − x): penalises x below a.
template <typename T>
T penaltyBelow(const T& x, double a, double eps) {
  const T lim = T(a + eps);
  return x < lim ? T(lim - x) : T(0.0);
}

/// max(0, x − (b − ε)): penalises x above b.
template <typename T>
T penaltyAbove(const T& x, double b, double eps) {
  const T lim = T(b - eps);
  return x > lim ? T(x - lim) : T(0.0);
}

/// Penalises x outside [a, b] (one of the two sides is zero).
template <typename T>
T penaltyInterval(const T& x, double a, double b, double eps) {
  return penaltyBelow(x, a, eps) + penaltyAbove(x, b, eps);
}

/// Angle difference wrapped to (−π, π], differentiable (atan2 of sin/cos).
template <typename T>
T angleDiff(const T& to, const T& from) {
  using std::atan2;
  using std::cos;
  using std::sin;
  const T d = to - from;
  return atan2(sin(d), cos(d));
}

/// sqrt(x² + y² + tiny): a norm whose derivative stays finite at 0.
template <typename T>
T safeNorm(const T& x, const T& y) {
  using std::sqrt;
  return sqrt(x * x + y * y + T(1e-12));
}

/// Smooth sign in (−1, 1) used for the driving direction (TEB: fast_sigmoid(100 x)).
template <typename T>
T smoothSign(const T& x) {
  using std::abs;
  const T k = T(100.0) * x;
  return k / (T(1.0) + abs(k));
}

}  // namespace coopnav::band_costs
