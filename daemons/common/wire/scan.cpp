#include "wire/scan.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/runtime.hpp"

namespace coopnav {

LaserScanRecord fromLcm(const laser_scan_t& msg) {
  if (msg.num_ranges < 0 || msg.num_ranges > laser_scan_t::MAX_RANGES ||
      static_cast<std::size_t>(msg.num_ranges) != msg.ranges_m.size())
    throw RejectedMessage("laser scan: num_ranges " + std::to_string(msg.num_ranges) + " with " +
                          std::to_string(msg.ranges_m.size()) + " ranges (at most " +
                          std::to_string(laser_scan_t::MAX_RANGES) + ")");
  if (!std::isfinite(msg.sensor_x_m) || !std::isfinite(msg.sensor_y_m) ||
      !std::isfinite(msg.sensor_yaw_rad))
    throw RejectedMessage("laser scan: non-finite sensor pose");
  if (!std::isfinite(msg.angle_min_rad) || !std::isfinite(msg.angle_increment_rad))
    throw RejectedMessage("laser scan: non-finite angle_min_rad or angle_increment_rad");
  if (msg.num_ranges > 1 && !(msg.angle_increment_rad > 0.0F))
    throw RejectedMessage("laser scan: angle_increment_rad " +
                          std::to_string(msg.angle_increment_rad) + " is not > 0");
  if (!std::isfinite(msg.range_min_m) || !std::isfinite(msg.range_max_m) ||
      !(msg.range_min_m >= 0.0F) || !(msg.range_max_m > msg.range_min_m))
    throw RejectedMessage("laser scan: range limits [" + std::to_string(msg.range_min_m) + ", " +
                          std::to_string(msg.range_max_m) + "] are not 0 <= min < max");
  LaserScanRecord r;
  r.utime = msg.utime;
  r.step = msg.step;
  r.scan.sensor = {msg.sensor_x_m, msg.sensor_y_m, msg.sensor_yaw_rad};
  r.scan.angle_min_rad = msg.angle_min_rad;
  r.scan.angle_increment_rad = msg.angle_increment_rad;
  r.scan.range_min_m = msg.range_min_m;
  r.scan.range_max_m = msg.range_max_m;
  r.scan.ranges_m.assign(msg.ranges_m.begin(), msg.ranges_m.end());
  return r;
}

laser_scan_t toLcm(const LaserScanRecord& r) {
  laser_scan_t m{};
  m.utime = r.utime;
  m.step = r.step;
  m.sensor_x_m = r.scan.sensor.x_m;
  m.sensor_y_m = r.scan.sensor.y_m;
  m.sensor_yaw_rad = r.scan.sensor.theta_rad;
  m.angle_min_rad = static_cast<float>(r.scan.angle_min_rad);
  m.angle_increment_rad = static_cast<float>(r.scan.angle_increment_rad);
  m.range_min_m = static_cast<float>(r.scan.range_min_m);
  m.range_max_m = static_cast<float>(r.scan.range_max_m);
  const std::size_t n =
      std::min(r.scan.ranges_m.size(), static_cast<std::size_t>(laser_scan_t::MAX_RANGES));
  m.ranges_m.reserve(n);
  for (std::size_t i = 0; i < n; ++i) m.ranges_m.push_back(static_cast<float>(r.scan.ranges_m[i]));
  m.num_ranges = static_cast<std::int16_t>(n);
  return m;
}

}  // namespace coopnav
