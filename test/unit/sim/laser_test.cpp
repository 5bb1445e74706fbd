// The simulated laser: exact ranges to walls and people without noise, nothing beyond its range,
// its rays' layout, and seeded noise that repeats bit for bit.
#include "coopnav/sim/laser.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "corridor_map.hpp"

namespace coopnav::sim {
namespace {

LaserOptions exact() {
  LaserOptions o;
  o.noise_sigma_m = 0.0;
  o.fov_rad = M_PI;                     // -90° .. +90°
  o.angular_resolution_rad = M_PI / 4;  // 5 rays
  o.range_max_m = 5.0;
  return o;
}

TEST(LaserTest, RaysSeeTheWallsAtTheirExactRange) {
  const test::CorridorMap corridor(0.0, 2.0);  // walls at y = 0 and y = 2
  Rng rng(1);
  const LaserScan s = simulateLaser(corridor, {}, {1.0, 0.5, 0.0}, exact(), rng);
  ASSERT_EQ(s.ranges_m.size(), 5U);
  EXPECT_EQ(laserRayCount(exact()), 5);
  EXPECT_DOUBLE_EQ(s.angle_min_rad, -M_PI / 2);
  EXPECT_NEAR(s.ranges_m[0], 0.5, 1e-12);  // straight down: the wall at y = 0
  EXPECT_NEAR(s.ranges_m[1], 0.5 * std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isinf(s.ranges_m[2]));  // along the corridor: nothing in 5 m
  EXPECT_NEAR(s.ranges_m[3], 1.5 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(s.ranges_m[4], 1.5, 1e-12);  // straight up: the wall at y = 2
  // The points of the returns lie on the walls.
  const std::vector<Eigen::Vector2d> pts = scanPoints(s);
  ASSERT_EQ(pts.size(), 4U);
  for (const auto& p : pts)
    EXPECT_NEAR(std::min(std::abs(p.y()), std::abs(p.y() - 2.0)), 0.0, 1e-9);
}

TEST(LaserTest, PeopleAreDiscsInFrontOfTheWalls) {
  const test::CorridorMap corridor(0.0, 2.0);
  Rng rng(1);
  // A person 2 m ahead on the sensor's line (radius 0.3): the middle ray stops at 1.7 m.
  const LaserScan s = simulateLaser(corridor, {{{3.0, 0.5}, 0.3}}, {1.0, 0.5, 0.0}, exact(), rng);
  EXPECT_NEAR(s.ranges_m[2], 1.7, 1e-12);
  // Behind the sensor, or the sensor inside it: not seen.
  const LaserScan behind = simulateLaser(corridor, {{{-1.0, 0.5}, 0.3}, {{1.1, 0.5}, 0.3}},
                                         {1.0, 0.5, 0.0}, exact(), rng);
  EXPECT_TRUE(std::isinf(behind.ranges_m[2]));
}

TEST(LaserTest, TheMountOffsetMovesTheSensorInTheBodyFrame) {
  const test::CorridorMap corridor(0.0, 2.0);
  LaserOptions o = exact();
  o.mount_x_m = 0.2;
  Rng rng(1);
  const LaserScan s = simulateLaser(corridor, {}, {1.0, 0.5, M_PI / 2}, o, rng);  // facing +y
  EXPECT_NEAR(s.sensor.x_m, 1.0, 1e-12);
  EXPECT_NEAR(s.sensor.y_m, 0.7, 1e-12);
  EXPECT_NEAR(s.ranges_m[2], 1.3, 1e-12);  // straight ahead: the wall at y = 2
}

TEST(LaserTest, NoiseIsSeededAndRepeatsBitForBit) {
  const test::CorridorMap corridor(0.0, 2.0);
  LaserOptions o = exact();
  o.noise_sigma_m = 0.02;
  Rng a = Rng::forStream(7, 99), b = Rng::forStream(7, 99), c = Rng::forStream(8, 99);
  const LaserScan sa = simulateLaser(corridor, {}, {1.0, 0.5, 0.0}, o, a);
  const LaserScan sb = simulateLaser(corridor, {}, {1.0, 0.5, 0.0}, o, b);
  const LaserScan sc = simulateLaser(corridor, {}, {1.0, 0.5, 0.0}, o, c);
  ASSERT_EQ(sa.ranges_m.size(), sb.ranges_m.size());
  for (std::size_t i = 0; i < sa.ranges_m.size(); ++i) {
    if (std::isinf(sa.ranges_m[i])) {
      EXPECT_TRUE(std::isinf(sb.ranges_m[i]));
      continue;
    }
    EXPECT_EQ(sa.ranges_m[i], sb.ranges_m[i]);
    EXPECT_NE(sa.ranges_m[i], sc.ranges_m[i]);
  }
  EXPECT_NEAR(sa.ranges_m[0], 0.5, 0.1);
}

TEST(LaserScanTest, InvalidReturnsGiveNoPoint) {
  LaserScan s;
  s.sensor = {0.0, 0.0, M_PI / 2};
  s.angle_min_rad = -0.1;
  s.angle_increment_rad = 0.1;
  s.range_min_m = 0.1;
  s.range_max_m = 5.0;
  s.ranges_m = {std::nan(""), 0.05, 2.0, 6.0, std::numeric_limits<double>::infinity()};
  const auto pts = scanPoints(s);
  ASSERT_EQ(pts.size(), 1U);  // only ray 2, at yaw + 0.1
  EXPECT_NEAR(pts[0].x(), 2.0 * std::cos(M_PI / 2 + 0.1), 1e-12);
  EXPECT_NEAR(pts[0].y(), 2.0 * std::sin(M_PI / 2 + 0.1), 1e-12);
}

}  // namespace
}  // namespace coopnav::sim
