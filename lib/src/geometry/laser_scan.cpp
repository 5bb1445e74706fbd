#include "coopnav/geometry/laser_scan.hpp"

#include <cmath>

namespace coopnav {

bool validReturn(const LaserScan& scan, double range_m) {
  return std::isfinite(range_m) && range_m >= scan.range_min_m && range_m <= scan.range_max_m;
}

std::vector<Eigen::Vector2d> scanPoints(const LaserScan& scan) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(scan.ranges_m.size());
  const Eigen::Vector2d origin = scan.sensor.position();
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double r = scan.ranges_m[i];
    if (!validReturn(scan, r)) continue;
    const double a = scan.sensor.theta_rad + scan.angle_min_rad +
                     static_cast<double>(i) * scan.angle_increment_rad;
    out.emplace_back(origin + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return out;
}

}  // namespace coopnav
