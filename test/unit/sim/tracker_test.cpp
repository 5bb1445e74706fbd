// The tracker model (lib/sim/tracker): what a people tracker would publish from the true humans.

#include "coopnav/sim/tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace coopnav::sim {
namespace {

constexpr double kDt_s = 0.1;

AgentState robotAt(double x_m, double y_m) {
  AgentState r;
  r.id = 0;
  r.kind = AgentKind::kRobot;
  r.pose = {x_m, y_m, 0.0};
  r.radius_m = 0.47;
  return r;
}

AgentState humanAt(std::int32_t id, double x_m, double y_m, double vx_m_s = 0.0,
                   double vy_m_s = 0.0) {
  AgentState h;
  h.id = id;
  h.pose = {x_m, y_m, std::atan2(vy_m_s, vx_m_s)};
  h.velocity = {vx_m_s, vy_m_s, 0.0};
  return h;
}

/// `n` persons standing on a line, ids 1..n.
std::vector<AgentState> standing(int n) {
  std::vector<AgentState> out;
  for (int i = 0; i < n; ++i) out.push_back(humanAt(i + 1, 2.0 * i, 1.0));
  return out;
}

std::vector<std::int32_t> idsOf(const std::vector<AgentState>& humans) {
  std::vector<std::int32_t> ids;
  for (const auto& h : humans) ids.push_back(h.id);
  return ids;
}

TEST(Tracker, WithEveryKeyAtItsDefaultItPublishesTheTruth) {
  const TrackerParams off;
  EXPECT_FALSE(off.active());
  const auto humans = standing(3);
  Tracker dut(off, 7, idsOf(humans), 60.0);
  const auto seen = dut.observe(0.0, robotAt(0, 0), humans);
  ASSERT_EQ(seen.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(seen[i].person, i);
    EXPECT_EQ(seen[i].state.id, humans[i].id);
    EXPECT_EQ(seen[i].state.pose, humans[i].pose);
    EXPECT_EQ(seen[i].state.velocity, humans[i].velocity);
  }
}

TEST(Tracker, PositionNoiseHasTheConfiguredSpreadAndNoBias) {
  // Given a person standing still, observed 4000 times with sigma 0.1 m.
  TrackerParams p;
  p.position_sigma_m = 0.1;
  const std::vector<AgentState> humans = {humanAt(1, 3.0, -2.0)};
  Tracker dut(p, 11, {1}, 1000.0);
  constexpr int kN = 4000;
  double sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, svx2 = 0.0;
  for (int k = 0; k < kN; ++k) {
    const auto seen = dut.observe(k * kDt_s, robotAt(0, 0), humans);
    ASSERT_EQ(seen.size(), 1u);
    const double ex = seen[0].state.pose.x_m - 3.0, ey = seen[0].state.pose.y_m + 2.0;
    sx += ex, sy += ey, sxx += ex * ex, syy += ey * ey;
    if (k >= 3) svx2 += seen[0].state.velocity.vx_m_s * seen[0].state.velocity.vx_m_s;
  }
  // Then the mean error is within 4 standard errors of 0 and the spread within 5 % of sigma.
  EXPECT_NEAR(sx / kN, 0.0, 4.0 * 0.1 / std::sqrt(kN));
  EXPECT_NEAR(sy / kN, 0.0, 4.0 * 0.1 / std::sqrt(kN));
  EXPECT_NEAR(std::sqrt(sxx / kN), 0.1, 0.005);
  EXPECT_NEAR(std::sqrt(syy / kN), 0.1, 0.005);
  // And the velocity, a difference over 3 samples, has the spread sigma * sqrt(2) / (3 dt).
  EXPECT_NEAR(std::sqrt(svx2 / (kN - 3)), 0.1 * std::sqrt(2.0) / (3 * kDt_s), 0.03);
}

TEST(Tracker, VelocityAndHeadingAreEstimatedFromThePositions) {
  // Given a noise-free tracker that is on (a range far beyond the scene), a person walking at
  // (0.8, 0.6) m/s.
  TrackerParams p;
  p.range_m = 100.0;
  Tracker dut(p, 1, {1}, 60.0);
  for (int k = 0; k < 10; ++k) {
    const double t = k * kDt_s;
    const auto seen = dut.observe(t, robotAt(0, 0), {humanAt(1, 0.8 * t, 0.6 * t, 0.8, 0.6)});
    ASSERT_EQ(seen.size(), 1u);
    const AgentState& s = seen[0].state;
    if (k < p.velocity_window_steps) {
      // Then a new track has no velocity until its window is full, and the body's heading.
      EXPECT_EQ(s.velocity.vx_m_s, 0.0);
      EXPECT_NEAR(s.pose.theta_rad, std::atan2(0.6, 0.8), 1e-12);
    } else {
      // Then the finite difference of a straight walk is its velocity.
      EXPECT_NEAR(s.velocity.vx_m_s, 0.8, 1e-9);
      EXPECT_NEAR(s.velocity.vy_m_s, 0.6, 1e-9);
      EXPECT_NEAR(s.pose.theta_rad, std::atan2(0.6, 0.8), 1e-9);
    }
  }
}

TEST(Tracker, MissedDetectionsHappenAtTheConfiguredRate) {
  TrackerParams p;
  p.miss_probability = 0.2;
  p.drop_after_s = 1000.0;  // no track is dropped: every id stays
  const auto humans = standing(10);
  Tracker dut(p, 5, idsOf(humans), 1000.0);
  constexpr int kSteps = 2000;
  std::size_t published = 0;
  for (int k = 0; k < kSteps; ++k) {
    const auto seen = dut.observe(k * kDt_s, robotAt(0, 0), humans);
    published += seen.size();
    for (const auto& h : seen) EXPECT_EQ(h.state.id, humans[h.person].id);
  }
  const double miss_rate = 1.0 - static_cast<double>(published) / (10.0 * kSteps);
  // 20000 Bernoulli draws: standard error 0.0028.
  EXPECT_NEAR(miss_rate, 0.2, 0.012);
  EXPECT_EQ(dut.stats().missed + static_cast<std::int64_t>(published), 10 * kSteps);
  EXPECT_EQ(dut.stats().dropped, 0);
}

TEST(Tracker, APersonBeyondTheRangeIsNotPublishedAndALongAbsenceGivesANewId) {
  TrackerParams p;
  p.range_m = 5.0;
  p.drop_after_s = 1.0;
  Tracker dut(p, 3, {4, 1500}, 60.0);
  const AgentState robot = robotAt(0, 0);
  double t = 0.0;
  auto observe = [&](double x_m) {
    const auto seen = dut.observe(t, robot, {humanAt(4, x_m, 0.0), humanAt(1500, 1.0, 1.0)});
    t += kDt_s;
    return seen;
  };
  // In range: published under its own id; the robot is never among the humans.
  auto seen = observe(4.0);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].state.id, 4);
  // Out of range for 0.5 s (< drop_after_s): absent, then back under the same id.
  for (int k = 0; k < 5; ++k) {
    seen = observe(6.0);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].state.id, 1500);
  }
  seen = observe(4.5);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].state.id, 4);
  // Out of range for 2 s: back under a new id, above every scenario id.
  for (int k = 0; k < 20; ++k) observe(7.0);
  seen = observe(4.5);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].state.id, 1501);
  EXPECT_EQ(dut.personOf(1501), std::optional<std::size_t>{0});
  EXPECT_EQ(dut.personOf(4), std::optional<std::size_t>{0});
  EXPECT_EQ(dut.currentId(0), 1501);
  EXPECT_EQ(dut.stats().dropped, 1);
  EXPECT_EQ(dut.stats().out_of_range, 25);
}

TEST(Tracker, IdSwitchesHappenAsOftenAsConfiguredAndGiveFreshIds) {
  TrackerParams p;
  p.id_switches = 4;
  p.id_switch_window_s = 8.0;
  const auto humans = standing(3);
  Tracker dut(p, 9, idsOf(humans), 60.0);
  ASSERT_EQ(dut.switchSchedule().size(), 4u);
  std::set<std::int32_t> ids;
  for (int k = 0; k <= 100; ++k) {
    for (const auto& h : dut.observe(k * kDt_s, robotAt(0, 0), humans)) {
      ids.insert(h.state.id);
      EXPECT_EQ(dut.personOf(h.state.id), std::optional<std::size_t>{h.person});
    }
  }
  EXPECT_EQ(dut.stats().switches, 4);
  // The 3 scenario ids and 4 new ones from 1000 on, none reused.
  EXPECT_EQ(ids, (std::set<std::int32_t>{1, 2, 3, 1000, 1001, 1002, 1003}));
  for (const auto& [t_s, person] : dut.switchSchedule()) {
    EXPECT_GT(t_s, 0.0);
    EXPECT_LE(t_s, 8.0);
    EXPECT_LT(person, 3u);
  }
}

TEST(Tracker, TheSameSeedGivesTheSameStreamAndAnotherSeedAnother) {
  TrackerParams p;
  p.position_sigma_m = 0.05;
  p.miss_probability = 0.1;
  p.id_switches = 1;
  const auto humans = standing(4);
  auto run = [&](std::uint64_t seed) {
    Tracker dut(p, seed, idsOf(humans), 10.0);
    std::vector<double> out;
    for (int k = 0; k < 100; ++k)
      for (const auto& h : dut.observe(k * kDt_s, robotAt(0, 0), humans)) {
        out.push_back(h.state.id);
        out.push_back(h.state.pose.x_m);
        out.push_back(h.state.velocity.vy_m_s);
      }
    return out;
  };
  EXPECT_EQ(run(42), run(42));
  EXPECT_NE(run(42), run(43));
}

TEST(Tracker, OnePersonsDrawsDoNotDependOnTheOthers) {
  // The noise on person 1 is the same whether person 2 is in range or not.
  TrackerParams p;
  p.position_sigma_m = 0.05;
  p.range_m = 10.0;
  auto firstX = [&](double x2_m) {
    Tracker dut(p, 5, {1, 2}, 10.0);
    std::vector<double> out;
    for (int k = 0; k < 20; ++k)
      out.push_back(
          dut.observe(k * kDt_s, robotAt(0, 0), {humanAt(1, 1, 1), humanAt(2, x2_m, 0)})[0]
              .state.pose.x_m);
    return out;
  };
  EXPECT_EQ(firstX(2.0), firstX(20.0));
}

TEST(Tracker, InvalidParametersAreRejectedNamingEachKey) {
  TrackerParams p;
  p.position_sigma_m = -0.1;
  p.miss_probability = 1.0;
  p.velocity_window_steps = 0;
  const auto errors = p.validate();
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_NE(errors[0].find("tracker.position_sigma_m"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("tracker.velocity_window_steps"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find("tracker.miss_probability"), std::string::npos) << errors[2];
  EXPECT_THROW(Tracker(p, 1, {1}, 10.0), std::invalid_argument);
  EXPECT_THROW(Tracker(TrackerParams{}, 1, {1, 1}, 10.0), std::invalid_argument);
}

}  // namespace
}  // namespace coopnav::sim
