// laser_scan_t <-> LaserScan (daemons/common/wire/scan.hpp): a round trip, and the rejections.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "runtime/runtime.hpp"
#include "wire/scan.hpp"

namespace coopnav {
namespace {

LaserScanRecord sample() {
  LaserScanRecord r;
  r.utime = 4200000;
  r.step = 42;
  r.scan.sensor = {3.0, 1.5, 0.25};
  r.scan.angle_min_rad = -1.5;
  r.scan.angle_increment_rad = 0.5;
  r.scan.range_min_m = 0.05;
  r.scan.range_max_m = 8.0;
  r.scan.ranges_m = {1.0, 2.5, std::numeric_limits<double>::infinity(), 0.75, 7.5, 3.25, 4.0};
  return r;
}

TEST(ScanConversionsTest, RoundTripKeepsEveryFieldAndThePoints) {
  const LaserScanRecord r = sample();
  const laser_scan_t m = toLcm(r);
  EXPECT_EQ(m.num_ranges, 7);
  const LaserScanRecord back = fromLcm(m);
  EXPECT_EQ(back.utime, r.utime);
  EXPECT_EQ(back.step, r.step);
  EXPECT_EQ(back.scan.sensor, r.scan.sensor);
  EXPECT_EQ(back.scan.ranges_m.size(), r.scan.ranges_m.size());
  // Ranges and angles travel as float: these are exact in float.
  EXPECT_EQ(back.scan.ranges_m, r.scan.ranges_m);
  EXPECT_EQ(back.scan.angle_min_rad, r.scan.angle_min_rad);
  const auto pts = scanPoints(back.scan);
  ASSERT_EQ(pts.size(), 6U);  // the infinite ray gives none
  EXPECT_NEAR(pts[0].x(), 3.0 + std::cos(0.25 - 1.5), 1e-12);
  EXPECT_NEAR(pts[0].y(), 1.5 + std::sin(0.25 - 1.5), 1e-12);
}

TEST(ScanConversionsTest, BadScansAreRejectedWithTheReason) {
  auto rejected = [](laser_scan_t m, const std::string& what) {
    try {
      fromLcm(m);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const RejectedMessage& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const laser_scan_t good = toLcm(sample());
  laser_scan_t m = good;
  m.num_ranges = 8;
  rejected(m, "num_ranges 8 with 7 ranges");
  m = good;
  m.sensor_yaw_rad = std::numeric_limits<double>::quiet_NaN();
  rejected(m, "non-finite sensor pose");
  m = good;
  m.angle_increment_rad = 0.0F;
  rejected(m, "is not > 0");
  m = good;
  m.range_max_m = 0.01F;
  rejected(m, "range limits");
  m = good;
  m.angle_min_rad = std::numeric_limits<float>::infinity();
  rejected(m, "non-finite angle");
  // A single NaN ray is no return, not a bad scan.
  m = good;
  m.ranges_m[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(scanPoints(fromLcm(m).scan).size(), 5U);
}

}  // namespace
}  // namespace coopnav
