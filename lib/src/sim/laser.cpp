#include "coopnav/sim/laser.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopnav::sim {
namespace {

/// Distance along the unit direction d from p to where it enters the disc; +inf if it misses it
/// or p is inside.
double enterDisc(const Eigen::Vector2d& p, const Eigen::Vector2d& d, const LaserDisc& c) {
  const Eigen::Vector2d m = p - c.centre;
  const double b = m.dot(d);
  const double cc = m.squaredNorm() - c.radius_m * c.radius_m;
  if (cc <= 0.0) return std::numeric_limits<double>::infinity();
  const double disc = b * b - cc;
  if (disc < 0.0 || b > 0.0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(disc);
}

}  // namespace

int laserRayCount(const LaserOptions& o) {
  if (!(o.angular_resolution_rad > 0.0) || !(o.fov_rad >= 0.0)) return 0;
  return static_cast<int>(std::floor(o.fov_rad / o.angular_resolution_rad + 1e-9)) + 1;
}

LaserScan simulateLaser(const DistanceMap& world, const std::vector<LaserDisc>& discs,
                        const Pose2& robot, const LaserOptions& o, Rng& rng) {
  LaserScan s;
  const double c = std::cos(robot.theta_rad), sn = std::sin(robot.theta_rad);
  s.sensor = {robot.x_m + c * o.mount_x_m - sn * o.mount_y_m,
              robot.y_m + sn * o.mount_x_m + c * o.mount_y_m, robot.theta_rad};
  s.angle_min_rad = -0.5 * o.fov_rad;
  s.angle_increment_rad = o.angular_resolution_rad;
  s.range_min_m = o.range_min_m;
  s.range_max_m = o.range_max_m;
  const int n = laserRayCount(o);
  s.ranges_m.assign(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity());
  const Eigen::Vector2d p = s.sensor.position();
  for (int i = 0; i < n; ++i) {
    const double a = s.sensor.theta_rad + s.angle_min_rad + i * s.angle_increment_rad;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double hit = std::numeric_limits<double>::infinity();
    const DistanceResult r = world.ray(p, d, o.range_max_m);
    if (r.status == DistanceStatus::kOk) hit = r.distance_m;
    if (r.status == DistanceStatus::kInObstacle) hit = 0.0;
    for (const LaserDisc& disc : discs) hit = std::min(hit, enterDisc(p, d, disc));
    if (!(hit <= o.range_max_m)) continue;
    if (o.noise_sigma_m > 0.0) hit = std::max(0.0, hit + rng.normal(0.0, o.noise_sigma_m));
    s.ranges_m[static_cast<std::size_t>(i)] = hit;
  }
  return s;
}

}  // namespace coopnav::sim
