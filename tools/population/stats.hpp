#pragma once
/// @file Statistics of the population table. Header-only (see generator.hpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
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

}  // namespace coopnav::population
