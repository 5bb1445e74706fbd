#pragma once
/// @file The simulated planar laser of the world simulator (issue 45): rays cast against the
/// world's obstacles (the walls and whatever stands in the world without being on the robot's
/// map, both in the world's distance field) and against the people (discs), with Gaussian range
/// noise from the simulator's seeded generator, so that a run repeats to the last bit. Pure.

#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/laser_scan.hpp"
#include "coopnav/sim/random.hpp"

namespace coopnav::sim {

struct LaserOptions {
  double range_min_m{0.05};          ///< returns nearer than this are invalid
  double range_max_m{8.0};           ///< beyond this nothing is seen
  double fov_rad{4.71238898038469};  ///< field of view, centred on the sensor's heading (270°)
  double angular_resolution_rad{0.00872664625997165};  ///< between rays (0.5°)
  double noise_sigma_m{0.01};  ///< std deviation of the Gaussian range noise (0: exact)
  /// Sensor position in the robot's body frame (forward, left) [m]; heading = the robot's.
  double mount_x_m{0.0};
  double mount_y_m{0.0};
};

/// A disc a ray may hit: a person's body.
struct LaserDisc {
  Eigen::Vector2d centre{0.0, 0.0};
  double radius_m{0.0};
};

/// Number of rays: floor(fov / resolution) + 1, the first at -fov/2.
int laserRayCount(const LaserOptions& o);

/// One scan from a robot at `robot`: ray i at -fov/2 + i * resolution from the heading, its range
/// the nearest of the world's free length along it (DistanceMap::ray) and the discs' entry points
/// (a sensor inside a disc does not see that disc), plus noise; nothing within range_max_m: +inf.
/// Draws exactly one normal per ray with a hit (none when noise_sigma_m is 0).
LaserScan simulateLaser(const DistanceMap& world, const std::vector<LaserDisc>& discs,
                        const Pose2& robot, const LaserOptions& o, Rng& rng);

}  // namespace coopnav::sim
