#include "scan_obstacles.hpp"

#include <algorithm>
#include <cmath>

#include "coopnav/geometry/laser_scan.hpp"

namespace coopnav {

void ScanObstacles::store(const LaserScanRecord& r, std::int64_t max_steps) {
  if (r.step < 0) {
    if (!latest_free_ || r.utime >= latest_free_->utime) latest_free_ = r;
    return;
  }
  by_step_[r.step] = r;
  while (static_cast<std::int64_t>(by_step_.size()) > std::max<std::int64_t>(1, max_steps))
    by_step_.erase(by_step_.begin());
}

ScanObstacles::Points ScanObstacles::take(const AgentStatesSnapshot& s, const DistanceMap& map) {
  Points out;
  const LaserScanRecord* scan = nullptr;
  if (s.step >= 0) {
    const auto it = by_step_.find(s.step);
    if (it != by_step_.end()) scan = &it->second;
  } else if (latest_free_ &&
             std::abs(utimeDiffSeconds(s.utime, latest_free_->utime)) <= config_.max_age_s) {
    scan = &*latest_free_;
  }
  if (scan != nullptr) {
    const Eigen::Vector2d robot = s.robot.pose.position();
    for (const Eigen::Vector2d& p : scanPoints(scan->scan)) {
      if ((p - robot).norm() > config_.max_range_m) continue;
      const DistanceResult known = map.nearest(p);
      if (known.status == DistanceStatus::kInObstacle ||
          known.status == DistanceStatus::kOutsideMap ||
          (known.status == DistanceStatus::kOk && known.distance_m <= config_.map_margin_m))
        continue;
      out.guard.push_back(p);
      bool person = false;
      for (const AgentState& h : s.humans)
        person = person || (p - h.pose.position()).norm() <= h.radius_m + config_.people_margin_m;
      if (!person) out.planner.push_back(p);
    }
  }
  if (s.step >= 0) by_step_.erase(by_step_.begin(), by_step_.upper_bound(s.step));
  return out;
}

}  // namespace coopnav
