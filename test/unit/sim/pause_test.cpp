// A person who pauses (PauseParams): stops where it has walked after_m along its path, stands for
// duration_s whatever comes, then walks on to its goal.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "coopnav/sim/simulation.hpp"
#include "corridor_map.hpp"

namespace coopnav::sim {
namespace {

struct Walk {
  std::vector<double> t_s, x_m, speed_m_s;
  std::vector<std::string> mode;
  double goal_t_s{-1.0};
};

/// One human walking +x along a 3 m corridor from x 2 to x 20; the robot stands at x 30, out of
/// its way (its goal is its start).
Walk walk(BehaviourType type, const PauseParams& pause) {
  test::CorridorMap map(0.0, 3.0);
  WorldSpec w;
  w.seed = 3;
  w.settings.time_limit_s = 60.0;
  w.robot.start = {30.0, 1.5, M_PI};
  w.robot.goal = {30.0, 1.5, M_PI};
  HumanSpec hs;
  hs.id = 1;
  hs.start = {2.0, 1.5, 0.0};
  hs.goal = {20.0, 1.5, 0.0};
  hs.speed_m_s = 1.0;
  hs.behaviour.type = type;
  hs.behaviour.pause = pause;
  w.humans.push_back(hs);
  Simulation sim(w, &map);
  Walk out;
  while (sim.status() == SimStatus::kRunning && sim.time_s() < 40.0) {
    const StepResult r = sim.step({});
    const AgentState& h = r.agents[1];
    out.t_s.push_back(r.t_s);
    out.x_m.push_back(h.pose.x_m);
    out.speed_m_s.push_back(std::hypot(h.velocity.vx_m_s, h.velocity.vy_m_s));
    out.mode.push_back(sim.behaviourStatus().at(0).mode);
    if (out.goal_t_s < 0.0 && sim.summary().human_goal_time_s.at(0) >= 0.0)
      out.goal_t_s = sim.summary().human_goal_time_s.at(0);
  }
  return out;
}

TEST(PausingHuman, StandsWhereItReachesAfterMForDurationThenWalksOn) {
  for (const BehaviourType type :
       {BehaviourType::kMinimal, BehaviourType::kOblivious, BehaviourType::kSocialForce}) {
    SCOPED_TRACE(toString(type));
    const Walk plain = walk(type, {});
    const Walk paused = walk(type, {6.0, 5.0});
    ASSERT_GT(plain.goal_t_s, 0.0);
    ASSERT_GT(paused.goal_t_s, 0.0);  // it goes on
    // Paused from the first sample at 6 m walked (x 8) for 5 s; the person decelerates under its
    // acceleration limit (1.5 m/s^2 from 1 m/s: 0.33 m) and stands.
    std::size_t first = 0, last = 0;
    for (std::size_t i = 0; i < paused.mode.size(); ++i) {
      if (paused.mode[i] != "pause") continue;
      if (first == 0) first = i;
      last = i;
    }
    ASSERT_GT(first, 0U);
    EXPECT_NEAR(paused.x_m[first], 8.0, 0.15);
    EXPECT_NEAR(paused.t_s[last] - paused.t_s[first], 5.0, 0.15);
    EXPECT_LT(paused.x_m[last] - paused.x_m[first], 0.4);
    EXPECT_LT(paused.speed_m_s[last], 0.01);  // standing
    // Then walks on, and is late by the pause (plus slowing down and speeding up again).
    EXPECT_NEAR(paused.goal_t_s - plain.goal_t_s, 5.0, 1.5);
  }
}

TEST(PausingHuman, NoPauseWithoutDuration) {
  const Walk plain = walk(BehaviourType::kMinimal, {});
  const Walk zero = walk(BehaviourType::kMinimal, {6.0, 0.0});
  EXPECT_EQ(plain.x_m, zero.x_m);
  for (const auto& m : zero.mode) EXPECT_NE(m, "pause");
}

TEST(PausingHuman, PausesOnceOnly) {
  const Walk paused = walk(BehaviourType::kMinimal, {6.0, 2.0});
  int starts = 0;
  for (std::size_t i = 1; i < paused.mode.size(); ++i)
    starts += paused.mode[i] == "pause" && paused.mode[i - 1] != "pause";
  EXPECT_EQ(starts, 1);
}

}  // namespace
}  // namespace coopnav::sim
