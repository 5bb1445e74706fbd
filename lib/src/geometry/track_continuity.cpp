#include "coopnav/geometry/track_continuity.hpp"

#include <cmath>
#include <limits>

namespace coopnav {

std::optional<std::int32_t> continuedTrack(const std::vector<LostTrack>& lost, double t_s,
                                           const Eigen::Vector2d& position_m,
                                           const TrackContinuityOptions& options) {
  if (!std::isfinite(t_s) || !position_m.allFinite()) return std::nullopt;
  std::optional<std::int32_t> best;
  double best_miss_m = std::numeric_limits<double>::infinity();
  for (const LostTrack& l : lost) {
    const double gap_s = t_s - l.t_s;
    if (!(gap_s >= 0.0 && gap_s <= options.max_gap_s)) continue;
    if (!l.position_m.allFinite() || !l.velocity_m_s.allFinite()) continue;
    const Eigen::Vector2d predicted = l.position_m + l.velocity_m_s * gap_s;
    const double miss_m = (position_m - predicted).norm();
    if (miss_m > options.gate_m + options.gate_growth_m_s * gap_s) continue;
    if (miss_m < best_miss_m || (miss_m == best_miss_m && best && l.id < *best)) {
      best = l.id;
      best_miss_m = miss_m;
    }
  }
  return best;
}

}  // namespace coopnav
