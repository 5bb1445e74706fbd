// Progress of the robot from a log (tools/ctl/progress_metrics.hpp): stalled time leaves out the
// goal and a requested dock; a mutual wait is robot and a near person both still.
#include "progress_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace coopnav::ctl {
namespace {

agent_state_t agent(std::int32_t id, double x, double vx) {
  agent_state_t a{};
  a.id = id;
  a.kind = id == 0 ? agent_state_t::KIND_ROBOT : agent_state_t::KIND_HUMAN;
  a.x_m = x;
  a.vx_m_s = vx;
  a.radius_m = 0.3;
  return a;
}

/// Step k at 10 Hz: the robot at x 0 with speed robot_vx, one human at human_x with speed
/// human_vx; and the band source's command mode for that step.
void step(RunLog& run, std::int64_t k, double robot_vx, double human_x, double human_vx,
          std::int8_t mode) {
  agent_states_t s{};
  s.utime = k * 100000;
  s.step = k;
  s.robot = agent(0, 0.0, robot_vx);
  s.humans.push_back(agent(1, human_x, human_vx));
  s.num_humans = 1;
  run.agent_states.push_back(s);
  velocity_command_t c{};
  c.utime = s.utime;
  c.step = k;
  c.mode = mode;
  run.commands.push_back(c);
}

TEST(ProgressMetrics, StalledTimeLeavesOutTheGoalAndARequestedDock) {
  RunLog run;
  std::int64_t k = 0;
  for (int i = 0; i < 10; ++i) step(run, k++, 0.5, 20.0, -1.0, velocity_command_t::MODE_NAVIGATING);
  for (int i = 0; i < 30; ++i) step(run, k++, 0.0, 20.0, -1.0, velocity_command_t::MODE_NAVIGATING);
  for (int i = 0; i < 20; ++i) step(run, k++, 0.0, 20.0, -1.0, velocity_command_t::MODE_HOLDING);
  for (int i = 0; i < 20; ++i)
    step(run, k++, 0.0, 20.0, -1.0, velocity_command_t::MODE_GOAL_REACHED);
  const ProgressMetrics m = progressMetrics(run);
  EXPECT_NEAR(m.stalled_s, 3.0, 1e-9);
  EXPECT_EQ(m.max_mutual_wait_s, 0.0);  // the human walked on, far away
  EXPECT_TRUE(std::isnan(m.max_mutual_wait_start_s));
}

TEST(ProgressMetrics, AMutualWaitIsBothStillAndNearAndEndsWhenOneMoves) {
  RunLog run;
  std::int64_t k = 0;
  for (int i = 0; i < 10; ++i) step(run, k++, 0.5, 3.0, -1.0, velocity_command_t::MODE_NAVIGATING);
  // Face to face 1.4 m apart (0.8 m surface to surface), both still for 12 s; the robot holds.
  for (int i = 0; i <= 120; ++i) step(run, k++, 0.0, 1.4, 0.05, velocity_command_t::MODE_HOLDING);
  // The person walks: no longer waiting, however still the robot.
  for (int i = 0; i < 50; ++i) step(run, k++, 0.0, 1.4, -0.8, velocity_command_t::MODE_HOLDING);
  const ProgressMetrics m = progressMetrics(run);
  EXPECT_NEAR(m.max_mutual_wait_s, 12.0, 1e-9);
  EXPECT_NEAR(m.max_mutual_wait_start_s, 1.0, 1e-9);
  EXPECT_EQ(m.max_mutual_wait_human, 1);
  EXPECT_EQ(m.stalled_s, 0.0);  // a requested hold is not stalled time

  RunLog far;  // the same, the person 5 m away: no mutual wait
  for (int i = 0; i <= 120; ++i) step(far, i, 0.0, 5.6, 0.0, velocity_command_t::MODE_NAVIGATING);
  EXPECT_EQ(progressMetrics(far).max_mutual_wait_s, 0.0);
  EXPECT_NEAR(progressMetrics(far).stalled_s, 12.0, 1e-9);
}

}  // namespace
}  // namespace coopnav::ctl
