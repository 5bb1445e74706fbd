// continuedTrack: a new tracker id continues a lost one where that one was heading.
#include "coopnav/geometry/track_continuity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace coopnav {
namespace {

LostTrack walker(std::int32_t id, double t_s, double x_m, double vx_m_s) {
  return {id, t_s, {x_m, 0.0}, {vx_m_s, 0.0}};
}

TEST(TrackContinuityTest, ANewIdWhereTheLostOneWalkedToContinuesIt) {
  const std::vector<LostTrack> lost{walker(4, 10.0, 0.0, 1.2)};
  // 0.5 s later, 0.6 m further along its line, 0.1 m off: the same person.
  EXPECT_EQ(continuedTrack(lost, 10.5, {0.6, 0.1}), std::optional<std::int32_t>(4));
}

TEST(TrackContinuityTest, SomeoneElseFarFromThePredictionIsNew) {
  const std::vector<LostTrack> lost{walker(4, 10.0, 0.0, 1.2)};
  EXPECT_FALSE(continuedTrack(lost, 10.5, {0.6, 1.5}).has_value());   // 1.5 m aside
  EXPECT_FALSE(continuedTrack(lost, 10.5, {-1.0, 0.0}).has_value());  // behind, 1.6 m off
}

TEST(TrackContinuityTest, ATrackLostTooLongAgoIsGone) {
  const std::vector<LostTrack> lost{walker(4, 10.0, 0.0, 0.0)};
  EXPECT_TRUE(continuedTrack(lost, 11.9, {0.0, 0.0}).has_value());
  EXPECT_FALSE(continuedTrack(lost, 12.1, {0.0, 0.0}).has_value());
  // A track "lost" after the new one appeared cannot be continued by it.
  EXPECT_FALSE(continuedTrack(lost, 9.9, {0.0, 0.0}).has_value());
}

TEST(TrackContinuityTest, TheGateGrowsWithTheGap) {
  const std::vector<LostTrack> lost{walker(4, 10.0, 0.0, 0.0)};
  TrackContinuityOptions o;
  o.gate_m = 0.5;
  o.gate_growth_m_s = 0.5;
  EXPECT_FALSE(continuedTrack(lost, 10.0, {0.8, 0.0}, o).has_value());
  EXPECT_TRUE(continuedTrack(lost, 11.0, {0.8, 0.0}, o).has_value());  // gate 1.0 m after 1 s
}

TEST(TrackContinuityTest, TheNearestPredictionWinsAndTiesGoToTheLowerId) {
  const std::vector<LostTrack> lost{walker(7, 10.0, 0.0, 1.0), walker(5, 10.0, 1.3, -1.0)};
  EXPECT_EQ(continuedTrack(lost, 10.2, {0.25, 0.0}), std::optional<std::int32_t>(7));
  EXPECT_EQ(continuedTrack(lost, 10.2, {1.05, 0.0}), std::optional<std::int32_t>(5));
  const std::vector<LostTrack> twins{walker(9, 10.0, 1.0, 0.0), walker(3, 10.0, 1.0, 0.0)};
  EXPECT_EQ(continuedTrack(twins, 10.1, {1.0, 0.2}), std::optional<std::int32_t>(3));
}

TEST(TrackContinuityTest, NonFiniteInputsContinueNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<LostTrack> lost{walker(4, 10.0, 0.0, 1.0), {6, 10.0, {nan, 0.0}, {0.0, 0.0}}};
  EXPECT_FALSE(continuedTrack(lost, nan, {0.0, 0.0}).has_value());
  EXPECT_FALSE(continuedTrack(lost, 10.1, {nan, 0.0}).has_value());
  EXPECT_EQ(continuedTrack(lost, 10.1, {0.1, 0.0}), std::optional<std::int32_t>(4));
  EXPECT_FALSE(continuedTrack({}, 10.1, {0.1, 0.0}).has_value());
}

}  // namespace
}  // namespace coopnav
