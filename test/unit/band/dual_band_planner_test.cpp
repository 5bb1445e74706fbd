#include "coopnav/band/dual_band_planner.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "analytic_map.hpp"
#include "band_test_util.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

void dump(const PlanResult& r) {
  std::printf("status %s iters %d cost %.3f time %.1f ms\n", toString(r.status), r.iterations,
              r.final_cost, r.solver_time_s * 1e3);
  for (const auto& t : r.term_costs) std::printf("  %s %.4f\n", t.name.c_str(), t.cost);
  std::printf("robot band %zu poses, %.2f s\n", r.agent_band.poses.size(),
              r.agent_band.poses.back().t_s);
  for (std::size_t i = 0; i < r.agent_band.poses.size(); i += 8) {
    const auto& p = r.agent_band.poses[i];
    std::printf("  r t %.2f (%.2f %.2f %.2f)\n", p.t_s, p.pose.x_m, p.pose.y_m, p.pose.theta_rad);
  }
  for (const auto& o : r.others) {
    std::printf("human %d band %zu poses %.2f s\n", o.id, o.band.poses.size(),
                o.band.poses.back().t_s);
    for (std::size_t i = 0; i < o.band.poses.size(); i += 8) {
      const auto& p = o.band.poses[i];
      std::printf("  h t %.2f (%.2f %.2f %.2f)\n", p.t_s, p.pose.x_m, p.pose.y_m,
                  p.pose.theta_rad);
    }
  }
}

TEST(DualBandPlannerTest, HeadOnOpenCorridorDebug) {
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  BandPlannerConfig cfg;
  if (getenv("OUTER")) cfg.no_outer_iterations = atoi(getenv("OUTER"));
  if (getenv("INNER")) cfg.no_inner_iterations = atoi(getenv("INNER"));
  if (getenv("WREL")) cfg.weight_agent_robot_rel_vel = atof(getenv("WREL"));
  if (getenv("WSAFE")) cfg.weight_agent_robot_safety = atof(getenv("WSAFE"));
  if (getenv("WT")) cfg.planning_weights.optimaltime = atof(getenv("WT"));
  const int cycles = getenv("CYCLES") ? atoi(getenv("CYCLES")) : 1;
  DualBandPlanner dut(cfg, map);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  if (getenv("RV")) req.agent.velocity.vx_m_s = atof(getenv("RV"));
  PlanResult r;
  for (int c = 0; c < cycles; ++c) {
    r = dut.plan(req);
    std::printf("cycle %d cost %.3f iters %d %.1f ms\n", c, r.final_cost, r.iterations, r.solver_time_s*1e3);
  }
  dump(r);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  const double d = test::minPairedDistance(r.agent_band, r.others[0].band);
  const auto kr = test::measure(r.agent_band);
  const auto kh = test::measure(r.others[0].band);
  std::printf("min dist %.3f  robot dev %.3f human dev %.3f\n", d,
              test::maxDeviation(r.agent_band, r.agent_path),
              test::maxDeviation(r.others[0].band, r.others[0].reference_path));
  std::printf("robot vx [%.2f %.2f] vy %.2f om %.2f ax %.2f ay %.2f\n", kr.min_vx, kr.max_vx,
              kr.max_abs_vy, kr.max_abs_omega, kr.max_abs_ax, kr.max_abs_ay);
  std::printf("human vx [%.2f %.2f] vy %.2f om %.2f ax %.2f ay %.2f\n", kh.min_vx, kh.max_vx,
              kh.max_abs_vy, kh.max_abs_omega, kh.max_abs_ax, kh.max_abs_ay);
}

}  // namespace
}  // namespace coopnav
