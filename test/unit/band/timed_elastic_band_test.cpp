#include "coopnav/band/timed_elastic_band.hpp"

#include <gtest/gtest.h>

#include "coopnav/band/velocity_command.hpp"

namespace coopnav {
namespace {

TimedElasticBand straight(double length_m, double speed_m_s, double dt_s) {
  return TimedElasticBand::fromPath({0.0, 0.0, 0.0}, {{0.0, 0.0}, {length_m, 0.0}}, speed_m_s,
                                    dt_s);
}

TEST(TimedElasticBandTest, FromPathSpacesPosesAtSpeedTimesDtRef) {
  const auto b = straight(7.0, 0.7, 0.125);
  EXPECT_EQ(b.size(), 81u);  // 7 m / 0.0875 m = 80 segments
  EXPECT_NEAR(b.duration_s(), 10.0, 1e-9);
  for (std::size_t i = 0; i + 1 < b.size(); ++i) EXPECT_NEAR(b.dt(i), 0.125, 1e-9);
  EXPECT_DOUBLE_EQ(b.pose(b.size() - 1).x_m, 7.0);
}

TEST(TimedElasticBandTest, SpeedProfileRespectsAcceleration) {
  TimedElasticBand::SpeedProfile prof;
  prof.start_speed_m_s = 0.0;
  prof.acc_m_s2 = 0.5;
  prof.stop_at_end = true;
  const auto b = TimedElasticBand::fromPath({0.0, 0.0, 0.0}, {{0.0, 0.0}, {5.0, 0.0}}, 1.0, 0.1,
                                            std::nullopt, prof);
  EXPECT_GT(b.dt(0), 0.1);                     // slow start
  EXPECT_GT(b.dt(b.size() - 2), 0.1);          // slow stop
  EXPECT_NEAR(b.dt(b.size() / 2), 0.1, 1e-6);  // cruise
}

TEST(TimedElasticBandTest, AutoResizeKeepsDtNearReference) {
  auto b = straight(4.0, 1.0, 0.5);  // dt 0.5 → must be split to ~0.125
  b.autoResize(0.125, 0.0125, 3, 500);
  for (std::size_t i = 0; i + 1 < b.size(); ++i) {
    EXPECT_NEAR(b.dt(i), 0.125, 0.0125 + 1e-9);
  }
  EXPECT_NEAR(b.duration_s(), 4.0, 1e-9);
  auto c = straight(4.0, 1.0, 0.03);  // too fine → merged
  const std::size_t before = c.size();
  c.autoResize(0.125, 0.0125, 3, 500);
  EXPECT_LT(c.size(), before / 2);
  EXPECT_NEAR(c.duration_s(), 4.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.pose(c.size() - 1).x_m, 4.0);  // ends kept
  EXPECT_DOUBLE_EQ(c.pose(0).x_m, 0.0);
}

TEST(TimedElasticBandTest, LocateAndInterpolate) {
  const auto b = straight(1.0, 1.0, 0.25);  // poses at 0, .25, .5, .75, 1
  const auto loc = b.locate(0.6);
  ASSERT_TRUE(loc.has_value());
  EXPECT_EQ(loc->segment, 2u);
  EXPECT_NEAR(loc->fraction, 0.4, 1e-9);
  EXPECT_NEAR(b.poseAt(0.6).x_m, 0.6, 1e-9);
  EXPECT_FALSE(b.locate(2.0).has_value());
  EXPECT_DOUBLE_EQ(b.poseAt(5.0).x_m, 1.0);
}

TEST(TimedElasticBandTest, PruneToStartDropsPassedPoses) {
  auto b = straight(2.0, 1.0, 0.25);
  const std::size_t n = b.size();
  const std::size_t removed = b.pruneToStart({0.52, 0.05, 0.0}, 0.5);
  EXPECT_EQ(removed, 2u);
  EXPECT_EQ(b.size(), n - 2);
  EXPECT_DOUBLE_EQ(b.pose(0).x_m, 0.52);
}

TEST(VelocityCommandTest, FirstSegmentInBodyFrameClamped) {
  AgentKinematics k;  // holonomic robot, 0.7 m/s
  auto b = TimedElasticBand::fromPath({0.0, 0.0, M_PI / 2}, {{0.0, 0.0}, {0.0, 5.0}}, 0.5, 0.1);
  b.setPose(0, {0.0, 0.0, M_PI / 2});
  const Velocity2 v = bandCommand(b, k);
  EXPECT_NEAR(v.vx_m_s, 0.5, 1e-9);  // forward in the body frame although moving +y
  EXPECT_NEAR(v.vy_m_s, 0.0, 1e-9);
  const auto fast = TimedElasticBand::fromPath({0.0, 0.0, 0.0}, {{0.0, 0.0}, {0.0, 5.0}}, 2.0, 0.1);
  const Velocity2 w = bandCommand(fast, k);  // sideways at 2 m/s → clamped to 0.7
  EXPECT_NEAR(w.vy_m_s, 0.7, 1e-9);
  k.holonomic = false;
  EXPECT_DOUBLE_EQ(bandCommand(fast, k).vy_m_s, 0.0);
  EXPECT_EQ(bandCommand(TimedElasticBand::single({1.0, 2.0, 0.0}), k), Velocity2{});
}

}  // namespace
}  // namespace coopnav
