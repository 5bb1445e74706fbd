#pragma once
/// @file A planar laser scan with its sensor pose in the map frame (lcmtypes laser_scan_t,
/// sensor_msgs/LaserScan's fields), and the points its valid returns hit: the obstacles of the
/// moment the static map may not hold (issue 45).

#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

struct LaserScan {
  Pose2 sensor;                     ///< sensor pose, MAP frame, at the scan's time
  double angle_min_rad{0.0};        ///< first ray, SENSOR frame
  double angle_increment_rad{0.0};  ///< between consecutive rays (> 0: counter-clockwise)
  double range_min_m{0.0};          ///< returns below are invalid
  double range_max_m{0.0};          ///< returns above are invalid (nothing seen)
  std::vector<double> ranges_m;     ///< per ray; non-finite or outside the limits = no return
};

/// A return is valid when finite and within [range_min_m, range_max_m].
bool validReturn(const LaserScan& scan, double range_m);

/// The map-frame points of the valid returns, in ray order: ray i at sensor yaw + angle_min +
/// i * increment, range r -> sensor + r (cos a, sin a).
std::vector<Eigen::Vector2d> scanPoints(const LaserScan& scan);

}  // namespace coopnav
