#pragma once
/// @file laser_scan_t (COOPNAV_SCAN) <-> lib's LaserScan: the obstacles of the moment.
/// Same rules as conversions.hpp: `fromLcm` validates and throws RejectedMessage with the reason;
/// `toLcm` sets every count.

#include <cstdint>

#include "coopnav/geometry/laser_scan.hpp"
#include "coopnav/laser_scan_t.hpp"

namespace coopnav {

struct LaserScanRecord {
  std::int64_t utime{0};
  std::int64_t step{-1};
  LaserScan scan;
};

/// Rejects num_ranges outside [0, MAX_RANGES] or unequal to the ranges carried, a non-finite
/// sensor pose or angle, an angle_increment that is not > 0 with more than one ray, and range
/// limits that are not finite with 0 <= range_min_m < range_max_m. Single rays that are NaN,
/// infinite or out of the limits are no return (sensor_msgs/LaserScan's convention), kept as
/// they are: scanPoints() skips them.
LaserScanRecord fromLcm(const laser_scan_t& msg);
/// Rays beyond MAX_RANGES are not sent (the simulator never makes that many).
laser_scan_t toLcm(const LaserScanRecord& r);

}  // namespace coopnav
