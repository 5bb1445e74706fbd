#pragma once
/// @file Statistics of the population table. Header-only (see generator.hpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace coopnav::population {

/// Area under the ROC curve of a score separating positives from negatives, as the Mann-Whitney
/// U statistic over all pairs (Mann & Whitney 1947, doi 10.1214/aoms/1177730491; Hanley & McNeil
/// 1982, doi 10.1148/radiology.143.1.7063747): P(score of a positive > score of a negative), ties
/// counting one half. NaN when either side is empty; non-finite scores are left out.
inline double mannWhitneyAuc(const std::vector<double>& positives,
                             const std::vector<double>& negatives) {
  std::vector<double> pos, neg;
  for (double v : positives)
    if (std::isfinite(v)) pos.push_back(v);
  for (double v : negatives)
    if (std::isfinite(v)) neg.push_back(v);
  if (pos.empty() || neg.empty()) return std::nan("");
  double u = 0.0;
  for (double p : pos)
    for (double n : neg) u += p > n ? 1.0 : (p == n ? 0.5 : 0.0);
  return u / (static_cast<double>(pos.size()) * static_cast<double>(neg.size()));
}

/// Median of the finite values; NaN for none.
inline double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// The q-quantile of the finite values by nearest rank (the smallest value with at least a
/// fraction q of the values at or below it; q in (0, 1]); NaN for none.
inline double quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size(), std::max<std::size_t>(rank, 1)) - 1];
}

/// Mean of the finite values; NaN for none.
inline double mean(const std::vector<double>& v) {
  double sum = 0.0;
  std::size_t n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      sum += x;
      ++n;
    }
  return n ? sum / static_cast<double>(n) : std::nan("");
}

/// Two-sided exact sign test (binomial, p = 1/2; Conover 1999, "Practical nonparametric
/// statistics", §3.4): the probability of a split at least as uneven as `greater` against
/// `smaller` when neither direction is more likely; ties are left out before. 1 for no pairs.
inline double signTestP(int greater, int smaller) {
  const int n = greater + smaller;
  if (n <= 0) return 1.0;
  const int k = std::min(greater, smaller);
  // Sum of C(n, i) / 2^n for i <= k, in logs (n reaches a few hundred).
  double tail = 0.0;
  for (int i = 0; i <= k; ++i)
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) -
                     n * std::log(2.0));
  return std::min(1.0, 2.0 * tail);
}

/// Percentile bootstrap interval of the mean (Efron & Tibshirani 1993, "An introduction to the
/// bootstrap", §13.3) at `level` (e.g. 0.95), from `resamples` resamples drawn with `rng` (any
/// generator with index(n); a seeded one makes the interval reproducible). {NaN, NaN} for fewer
/// than two finite values.
template <class Rng>
std::pair<double, double> bootstrapMeanInterval(const std::vector<double>& values, double level,
                                                int resamples, Rng& rng) {
  std::vector<double> v;
  for (double x : values)
    if (std::isfinite(x)) v.push_back(x);
  if (v.size() < 2 || resamples < 1) return {std::nan(""), std::nan("")};
  std::vector<double> means;
  means.reserve(static_cast<std::size_t>(resamples));
  for (int b = 0; b < resamples; ++b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) sum += v[rng.index(v.size())];
    means.push_back(sum / static_cast<double>(v.size()));
  }
  std::sort(means.begin(), means.end());
  const double alpha = (1.0 - level) / 2.0;
  const auto at = [&](double q) {
    const double pos = q * static_cast<double>(means.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, means.size() - 1);
    return means[lo] + (pos - static_cast<double>(lo)) * (means[hi] - means[lo]);
  };
  return {at(alpha), at(1.0 - alpha)};
}

}  // namespace coopnav::population
