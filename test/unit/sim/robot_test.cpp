// Robot integration: velocity and acceleration limits, kinematics, end conditions, cues/events.

#include <gtest/gtest.h>

#include <cmath>

#include "coopnav/sim/simulation.hpp"
#include "corridor_map.hpp"

namespace coopnav::sim {
namespace {

WorldSpec robotOnly(Kinematics k = Kinematics::kDifferential) {
  WorldSpec w;
  w.robot.start = {0.0, 3.0, 0.0};
  w.robot.goal = {50.0, 3.0, 0.0};
  w.robot.kinematics = k;
  w.settings.time_limit_s = 100.0;
  return w;
}

TEST(RobotIntegration, RespectsAccelerationAndVelocityLimits) {
  const WorldSpec w = robotOnly();
  Simulation sim(w, nullptr);
  const RobotLimits& lim = w.robot.limits;
  const double dt_s = w.settings.physics_dt_s * w.settings.substeps_per_step;
  double v_prev = 0.0, w_prev = 0.0;
  for (int i = 0; i < 40; ++i) {
    sim.step({5.0, 0.0, 5.0});  // far beyond every limit
    const Velocity2 v = sim.robotBodyVelocity();
    EXPECT_LE(v.vx_m_s - v_prev, lim.max_acc_forward_m_s2 * dt_s + 1e-12);
    EXPECT_LE(v.omega_rad_s - w_prev, lim.max_acc_omega_rad_s2 * dt_s + 1e-12);
    EXPECT_LE(v.vx_m_s, lim.max_forward_m_s + 1e-12);
    EXPECT_LE(v.omega_rad_s, lim.max_omega_rad_s + 1e-12);
    v_prev = v.vx_m_s;
    w_prev = v.omega_rad_s;
  }
  EXPECT_DOUBLE_EQ(v_prev, lim.max_forward_m_s);
  // Braking is limited too.
  sim.step({-5.0, 0.0, 0.0});
  EXPECT_NEAR(sim.robotBodyVelocity().vx_m_s, v_prev - lim.max_acc_forward_m_s2 * dt_s, 1e-12);
}

TEST(RobotIntegration, StraightLineDistanceMatchesTheRampedProfile) {
  WorldSpec w = robotOnly();
  w.robot.limits.max_acc_forward_m_s2 = 0.5;
  w.robot.limits.max_forward_m_s = 0.5;
  Simulation sim(w, nullptr);
  for (int i = 0; i < 50; ++i) sim.step({0.5, 0.0, 0.0});  // 5 s: 1 s ramp + 4 s cruise
  // Ramp: v_k = 0.025 k for k = 1..20 (semi-implicit Euler), then 0.5 m/s.
  double expected_m = 0.0;
  for (int k = 1; k <= 100; ++k) expected_m += std::min(0.5, 0.025 * k) * 0.05;
  EXPECT_NEAR(sim.agents()[0].pose.x_m, expected_m, 1e-9);
  EXPECT_DOUBLE_EQ(sim.agents()[0].pose.y_m, 3.0);
}

TEST(RobotIntegration, DifferentialIgnoresLateralHolonomicUsesIt) {
  Simulation diff(robotOnly(Kinematics::kDifferential), nullptr);
  Simulation holo(robotOnly(Kinematics::kHolonomic), nullptr);
  for (int i = 0; i < 20; ++i) {
    diff.step({0.0, 0.4, 0.0});
    holo.step({0.0, 0.4, 0.0});
  }
  EXPECT_DOUBLE_EQ(diff.agents()[0].pose.y_m, 3.0);
  EXPECT_GT(holo.agents()[0].pose.y_m, 3.5);
}

TEST(RobotIntegration, WorldVelocityFollowsHeading) {
  WorldSpec w = robotOnly();
  w.robot.start.theta_rad = M_PI / 2;
  Simulation sim(w, nullptr);
  for (int i = 0; i < 20; ++i) sim.step({0.5, 0.0, 0.0});
  const AgentState r = sim.agents()[0];
  EXPECT_NEAR(r.velocity.vx_m_s, 0.0, 1e-12);
  EXPECT_NEAR(r.velocity.vy_m_s, 0.5, 1e-12);
  EXPECT_NEAR(r.pose.x_m, 0.0, 1e-9);
}

TEST(EndConditions, GoalReachedEndsTheRun) {
  WorldSpec w = robotOnly();
  w.robot.goal = {3.0, 3.0, 0.0};
  Simulation sim(w, nullptr);
  bool goal_event = false;
  while (sim.status() == SimStatus::kRunning) {
    const Velocity2 cmd = sim.agents()[0].pose.x_m < 3.0 ? Velocity2{0.5, 0, 0} : Velocity2{};
    for (const SimEvent& e : sim.step(cmd).events)
      goal_event |= e.kind == SimEvent::Kind::kGoalReached && e.agent_id == kRobotId;
  }
  EXPECT_EQ(sim.status(), SimStatus::kGoalsReached);
  EXPECT_TRUE(goal_event);
  EXPECT_GT(sim.summary().robot_goal_time_s, 0.0);
}

TEST(EndConditions, TimeLimitEndsTheRunAtExactlyTheLimit) {
  WorldSpec w = robotOnly();
  w.settings.time_limit_s = 2.0;
  Simulation sim(w, nullptr);
  StepResult last;
  while (sim.status() == SimStatus::kRunning) last = sim.step({});
  EXPECT_EQ(last.status, SimStatus::kTimeLimit);
  EXPECT_DOUBLE_EQ(last.t_s, 2.0);
  ASSERT_FALSE(last.events.empty());
  EXPECT_EQ(last.events.back().kind, SimEvent::Kind::kEnded);
  // Stepping after the end changes nothing.
  EXPECT_DOUBLE_EQ(sim.step({1.0, 0, 0}).t_s, 2.0);
}

TEST(EndConditions, RobotHittingAWallIsACollision) {
  test::CorridorMap map(0.0, 6.0);
  WorldSpec w = robotOnly();
  w.robot.start = {0.0, 3.0, M_PI / 2};
  Simulation sim(w, &map);
  StepResult r;
  while (sim.status() == SimStatus::kRunning) r = sim.step({0.8, 0.0, 0.0});
  EXPECT_EQ(sim.status(), SimStatus::kCollision);
  bool wall = false;
  for (const SimEvent& e : r.events)
    wall |= e.kind == SimEvent::Kind::kCollision && e.other_id == kWallId;
  EXPECT_TRUE(wall);
  EXPECT_NEAR(r.agents[0].pose.y_m, 6.0 - w.robot.radius_m, 0.05);
}

TEST(WorldSpecValidation, DuplicateHumanIdsAreRejected) {
  WorldSpec w = robotOnly();
  HumanSpec h;
  h.start = {5, 3, 0};
  h.goal = {9, 3, 0};
  w.humans = {h, h};
  EXPECT_THROW(Simulation(w, nullptr), std::invalid_argument);
}

TEST(WorldSpecValidation, SlowPhysicsIsRejected) {
  WorldSpec w = robotOnly();
  w.settings.physics_dt_s = 0.1;
  EXPECT_THROW(Simulation(w, nullptr), std::invalid_argument);
}

TEST(Rng, KnownSequenceAndMoments) {
  Rng a(123), b(123), c(124);
  const std::uint64_t first = a.next();
  EXPECT_EQ(first, b.next());
  EXPECT_NE(first, c.next());
  Rng r(5);
  double sum = 0.0, sum2 = 0.0;
  constexpr int kN = 200000;
  for (int i = 0; i < kN; ++i) {
    const double x = r.normal(1.0, 2.0);
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / kN;
  EXPECT_NEAR(mean, 1.0, 0.02);
  EXPECT_NEAR(std::sqrt(sum2 / kN - mean * mean), 2.0, 0.02);
  Rng u(9);
  for (int i = 0; i < 1000; ++i) {
    const double x = u.uniform01();
    EXPECT_GE(x, 0.0);
    EXPECT_LT(x, 1.0);
  }
  EXPECT_NE(Rng::forStream(1, 1).next(), Rng::forStream(1, 2).next());
}

}  // namespace
}  // namespace coopnav::sim
