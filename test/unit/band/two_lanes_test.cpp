// TwoLanes (the second thread of sparse_lm) and what it promises the planner: every lane runs
// exactly once per run(), and a planner with two solver threads plans the same bands, to the last
// bit, as with one.
#include "coopnav/band/two_lanes.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <vector>

#include "analytic_map.hpp"
#include "band_test_util.hpp"
#include "coopnav/band/dual_band_planner.hpp"

namespace coopnav {
namespace {

/// Work that takes a few microseconds, so that the worker has time to claim lane 1.
double busyWork(int n) {
  double x = 1.0;
  for (int k = 0; k < n; ++k) x = x * 1.0000001 + 1e-9;
  return x;
}

TEST(TwoLanesTest, EveryLaneRunsOncePerRunAndTheWorkerTakesPart) {
  TwoLanes lanes;
  lanes.awake();
  constexpr int kRuns = 4000;
  std::vector<int> ran(2 * kRuns, 0);
  std::atomic<int> concurrent_max{0};
  std::atomic<int> inside{0};
  for (int r = 0; r < kRuns; ++r) {
    lanes.run([&](int lane) {
      const int now = ++inside;
      int seen = concurrent_max.load();
      while (now > seen && !concurrent_max.compare_exchange_weak(seen, now)) {
      }
      ++ran[2 * r + lane];
      volatile double sink = busyWork(2000);
      (void)sink;
      --inside;
    });
    // Both lanes are done when run() returns: nothing of run r is still running.
    ASSERT_EQ(ran[2 * r], 1);
    ASSERT_EQ(ran[2 * r + 1], 1);
  }
  lanes.rest();
  EXPECT_GT(lanes.workerLanes(), 0u);
  EXPECT_LE(lanes.workerLanes(), static_cast<std::uint64_t>(kRuns));
  EXPECT_LE(concurrent_max.load(), 2);
}

TEST(TwoLanesTest, ASleepingWorkerNeverHoldsTheCallerUp) {
  // Without awake() the worker sleeps; the caller runs lane 1 itself whenever the worker has not
  // taken it, so every run completes and each lane still runs once.
  TwoLanes lanes;
  int count[2] = {0, 0};
  for (int r = 0; r < 1000; ++r) lanes.run([&](int lane) { ++count[lane]; });
  EXPECT_EQ(count[0], 1000);
  EXPECT_EQ(count[1], 1000);
}

TEST(TwoLanesTest, DestroyedWhileAwakeOrAsleep) {
  { TwoLanes asleep; }
  {
    TwoLanes awake;
    awake.awake();
    std::atomic<int> count{0};
    awake.run([&](int lane) { count += lane + 1; });
    EXPECT_EQ(count.load(), 3);
  }
}

bool sameBand(const Band& a, const Band& b) {
  if (a.poses.size() != b.poses.size()) return false;
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    const auto& p = a.poses[i];
    const auto& q = b.poses[i];
    const double x[4] = {p.pose.x_m, p.pose.y_m, p.pose.theta_rad, p.t_s};
    const double y[4] = {q.pose.x_m, q.pose.y_m, q.pose.theta_rad, q.t_s};
    if (std::memcmp(x, y, sizeof x) != 0) return false;
  }
  return true;
}

TEST(TwoLanesTest, PlannerWithTwoSolverThreadsPlansTheSameBandsToTheBit) {
  // Given the head-on case with two humans (one dead ahead, one beside it), planned for a few
  // closed-loop cycles with one and with two solver threads.
  auto map = test::BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  BandPlannerConfig one, two;
  one.solver_threads = 1;
  two.solver_threads = 2;
  DualBandPlanner p1(one, map), p2(two, map);
  PlanRequest req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.agent.velocity.vx_m_s = 0.7;
  OtherAgentInput second = req.others.front();
  second.state.id = 7;
  second.state.pose.y_m = 4.2;
  second.goal.y_m = 4.2;
  req.others.push_back(second);
  for (int cycle = 0; cycle < 4; ++cycle) {
    const PlanResult a = p1.plan(req);
    const PlanResult b = p2.plan(req);
    ASSERT_EQ(a.status, PlanStatus::kOk);
    ASSERT_EQ(b.status, PlanStatus::kOk);
    // Then every band, the command and the final cost are bit-identical.
    EXPECT_TRUE(sameBand(a.agent_band, b.agent_band)) << "cycle " << cycle;
    ASSERT_EQ(a.others.size(), b.others.size());
    for (std::size_t h = 0; h < a.others.size(); ++h)
      EXPECT_TRUE(sameBand(a.others[h].band, b.others[h].band)) << "cycle " << cycle;
    EXPECT_EQ(std::memcmp(&a.final_cost, &b.final_cost, sizeof(double)), 0);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.accepted_steps, b.accepted_steps);
    // Next cycle: the robot 0.1 s along its command, the humans towards it.
    req.stamp_s += 0.1;
    req.agent.pose.x_m += 0.1 * a.command_body.vx_m_s;
    for (auto& o : req.others) o.state.pose.x_m -= 0.1;
  }
}

}  // namespace
}  // namespace coopnav
