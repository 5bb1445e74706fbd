/// @file Benchmark of the dual-band planner: solve time per cycle for the head-on case in the
/// wide corridor of open.pgm with CoHAN 2.0's sim settings, as a fraction of a 100 ms budget,
/// and the 1 robot + 5 humans case as a ratio to 1 human. The planner settings are band_source's
/// own: the `planner` section of config/band_source.yaml, loaded by the daemon's loader (CoHAN's
/// sim values, cold-started every cycle as CoHAN 2.0 runs), so the headline figures are those of
/// the deployed daemon. The lib default, warm start, is measured beside them. Closed loop: every
/// 0.1 s the agents advance along their planned bands and the planner runs again. Both solvers
/// (our SparseLm and Ceres) on the same problems, interleaved so they share the machine's load.
/// Ends with RESULT lines. `bench_band SOLVER HUMANS [REPEATS]` runs one case only (for a
/// profiler).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "band_source/band_source_node.hpp"
#include "common/config.hpp"
#include "common/map_loader.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/distance/grid_distance_field.hpp"

namespace {

using namespace coopnav;  // NOLINT

constexpr double kBudget_s = 0.1;  // CoHAN 2.0 controller rate 10 Hz
constexpr double kCycle_s = 0.1;
constexpr int kCycles = 60;
int g_repeats = 3;  // runs of kCycles per case; `bench_band SOLVER HUMANS REPEATS` sets it

/// CPU time of this thread [s]: unlike wall time it does not count the time the scheduler gave
/// to other processes of this shared machine.
double threadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

Eigen::Vector2d positionAt(const Band& b, double t) {
  if (b.poses.size() < 2 || t <= 0.0) return b.poses.front().pose.position();
  for (std::size_t i = 0; i + 1 < b.poses.size(); ++i) {
    const auto& p0 = b.poses[i];
    const auto& p1 = b.poses[i + 1];
    if (t <= p1.t_s) {
      const double s = (t - p0.t_s) / std::max(p1.t_s - p0.t_s, 1e-9);
      return (1.0 - s) * p0.pose.position() + s * p1.pose.position();
    }
  }
  return b.poses.back().pose.position();
}

void advance(AgentState* s, const Band& b) {
  const Eigen::Vector2d p = positionAt(b, kCycle_s);
  const Eigen::Vector2d v = (p - s->pose.position()) / kCycle_s;
  s->pose.x_m = p.x();
  s->pose.y_m = p.y();
  if (s->kind == AgentKind::kHuman && v.norm() > 0.1) s->pose.theta_rad = std::atan2(v.y(), v.x());
  s->velocity = {v.x(), v.y(), 0.0};
}

struct Stats {
  double p50_s{0.0};
  double p99_s{0.0};
  double cpu_p50_s{0.0};  ///< the planning thread's CPU time: what a dedicated core would take
  double cpu_p99_s{0.0};
  std::size_t robot_poses{0};
  std::size_t human_poses{0};
  double solver_share{0.0};     ///< Ceres' own time / plan() time, summed over cycles
  double mean_iterations{0.0};  ///< LM iterations per cycle
  double mean_robot_poses{0.0};
  double mean_human_poses{0.0};
  double mean_final_cost{0.0};  ///< ½ Σ r² after the cycle's last iteration: what the time bought
};

/// The planner settings band_source runs with (config/band_source.yaml).
BandPlannerConfig g_deployed;
int g_max_iterations = 0;  ///< band_source's max_iterations (0: inner x outer)

Stats run(const std::shared_ptr<const DistanceMap>& map, int n_humans, const std::string& solver,
          bool warm_start) {
  std::vector<double> times, cpu;
  std::size_t robot_poses = 0, human_poses = 0;
  double solver_s = 0.0, iterations = 0.0, final_cost = 0.0, sum_robot = 0.0, sum_human = 0.0;
  for (int rep = 0; rep < g_repeats; ++rep) {
    BandPlannerConfig cfg = g_deployed;
    cfg.solver = solver;
    cfg.warm_start = warm_start;
    DualBandPlanner planner(cfg, map);
    PlanRequest req;
    req.stamp_s = 0.0;
    req.agent.id = 0;
    req.agent.kind = AgentKind::kRobot;
    req.agent.pose = {6.5, 6.5, 0.0};
    req.agent.velocity = {0.7, 0.0, 0.0};
    req.agent.radius_m = 0.34;
    req.goal = {20.5, 6.5, 0.0};
    // As band_source in lockstep: the iteration budget only (CoHAN 8 x 4), no time limit.
    req.max_iterations = g_max_iterations;
    req.time_budget_s = 0.0;
    req.clock_s = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
    };
    const double ys[5] = {6.5, 5.0, 8.0, 4.2, 8.8};
    const double xs[5] = {20.5, 19.5, 19.0, 18.0, 17.5};
    for (int h = 0; h < n_humans; ++h) {
      OtherAgentInput o;
      o.state.id = h + 1;
      o.state.kind = AgentKind::kHuman;
      o.state.pose = {xs[h], ys[h], M_PI};
      o.state.velocity = {-1.0, 0.0, 0.0};
      o.state.radius_m = 0.3;
      o.goal = {6.5, ys[h], M_PI};
      req.others.push_back(o);
    }
    for (int c = 0; c < kCycles; ++c) {
      const double c0 = threadCpu_s();
      const auto t0 = std::chrono::steady_clock::now();
      const PlanResult r = planner.plan(req);
      const auto t1 = std::chrono::steady_clock::now();
      cpu.push_back(threadCpu_s() - c0);
      if (r.status != PlanStatus::kOk) break;
      times.push_back(std::chrono::duration<double>(t1 - t0).count());
      solver_s += r.solver_time_s;
      iterations += r.iterations;
      final_cost += r.final_cost;
      sum_robot += static_cast<double>(r.agent_band.poses.size());
      sum_human += r.others.empty() ? 0.0 : static_cast<double>(r.others[0].band.poses.size());
      if (c == 0 && rep == 0) {
        robot_poses = r.agent_band.poses.size();
        human_poses = r.others.empty() ? 0 : r.others[0].band.poses.size();
      }
      advance(&req.agent, r.agent_band);
      for (std::size_t h = 0; h < r.others.size(); ++h)
        advance(&req.others[h].state, r.others[h].band);
      req.stamp_s += kCycle_s;
    }
  }
  std::sort(times.begin(), times.end());
  Stats s;
  if (times.empty()) return s;
  s.p50_s = times[times.size() / 2];
  s.p99_s = times[std::min(times.size() - 1, static_cast<std::size_t>(0.99 * times.size()))];
  std::sort(cpu.begin(), cpu.end());
  s.cpu_p50_s = cpu[cpu.size() / 2];
  s.cpu_p99_s = cpu[std::min(cpu.size() - 1, static_cast<std::size_t>(0.99 * cpu.size()))];
  double total_s = 0.0;
  for (double t : times) total_s += t;
  const double n = static_cast<double>(times.size());
  s.solver_share = solver_s / total_s;
  s.mean_iterations = iterations / n;
  s.mean_robot_poses = sum_robot / n;
  s.mean_human_poses = sum_human / n;
  s.mean_final_cost = final_cost / n;
  s.robot_poses = robot_poses;
  s.human_poses = human_poses;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string config_path = std::string(COOPNAV_SOURCE_DIR) + "/config/band_source.yaml";
  try {
    const auto deployed = loadConfig<BandSourceConfig>(config_path);
    g_deployed = deployed.planner.config;
    g_max_iterations = deployed.max_iterations;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_band: %s\n", e.what());
    return 2;
  }
  const std::string yaml = std::string(COOPNAV_SOURCE_DIR) + "/config/maps/open.yaml";
  LoadedMap loaded = loadMap(yaml);
  auto map = std::make_shared<GridDistanceField>(std::move(loaded.grid));
  const bool deployed_warm = g_deployed.warm_start;
  if (argc == 3 || argc == 4) {
    if (argc == 4) g_repeats = std::max(1, std::atoi(argv[3]));
    // Profiling aid: one case only, e.g. `bench_band sparse_lm 5` under perf.
    const Stats s = run(map, std::atoi(argv[2]), argv[1], deployed_warm);
    std::printf(
        "%s, %s humans: p50 %.2f ms p99 %.2f ms (CPU p50 %.2f p99 %.2f), %.1f iterations, "
        "%.1f robot + %.1f human poses, final cost %.3f\n",
        argv[1], argv[2], s.p50_s * 1e3, s.p99_s * 1e3, s.cpu_p50_s * 1e3, s.cpu_p99_s * 1e3,
        s.mean_iterations, s.mean_robot_poses, s.mean_human_poses, s.mean_final_cost);
    return 0;
  }
  // Warm-up: the first planner of the process pays for page faults and the map's first reads.
  run(map, 1, "sparse_lm", deployed_warm);
  // Interleaved so that both solvers see the same machine load (this machine is shared).
  const Stats one = run(map, 1, "sparse_lm", deployed_warm);
  const Stats one_ceres = run(map, 1, "ceres", deployed_warm);
  const Stats five = run(map, 5, "sparse_lm", deployed_warm);
  const Stats five_ceres = run(map, 5, "ceres", deployed_warm);
  // The other warm-start setting (the lib default is warm, band_source.yaml runs cold).
  const Stats other = run(map, 1, "sparse_lm", !deployed_warm);
  const Stats other_five = run(map, 5, "sparse_lm", !deployed_warm);
  std::printf("map %s, %d cycles x %d runs, budget %.0f ms\n", yaml.c_str(), kCycles, g_repeats,
              kBudget_s * 1e3);
  std::printf("planner settings: %s (planner.*, max_iterations %d), %s\n", config_path.c_str(),
              g_max_iterations, deployed_warm ? "warm-started" : "cold-started every cycle");
  auto line = [](const std::string& what, const Stats& s) {
    std::printf(
        "%-28s p50 %7.2f ms  p99 %7.2f ms  (CPU p50 %7.2f p99 %7.2f) | mean %.1f robot + %.1f "
        "human poses, %.1f LM iterations, solver %.0f %% of plan()\n",
        what.c_str(), s.p50_s * 1e3, s.p99_s * 1e3, s.cpu_p50_s * 1e3, s.cpu_p99_s * 1e3,
        s.mean_robot_poses, s.mean_human_poses, s.mean_iterations, 100.0 * s.solver_share);
  };
  std::printf("first cycle (1 human): %zu robot + %zu human poses\n", one.robot_poses,
              one.human_poses);
  const std::string other_name = deployed_warm ? "cold start" : "warm start";
  line("1 human, sparse_lm", one);
  line("1 human, ceres", one_ceres);
  line("5 humans, sparse_lm", five);
  line("5 humans, ceres", five_ceres);
  line("1 human, " + other_name, other);
  line("5 humans, " + other_name, other_five);
  std::printf("sparse_lm / ceres: 1 human p50 %.3f p99 %.3f; 5 humans p50 %.3f p99 %.3f\n",
              one.p50_s / one_ceres.p50_s, one.p99_s / one_ceres.p99_s,
              five.p50_s / five_ceres.p50_s, five.p99_s / five_ceres.p99_s);
  std::printf("RESULT band_p99_budget_fraction %.4f\n", one.p99_s / kBudget_s);
  std::printf("RESULT band_5humans_vs_1 %.3f\n", five.p50_s / one.p50_s);
  std::printf("RESULT band_sparse_lm_vs_ceres_p50 %.3f\n", one.p50_s / one_ceres.p50_s);
  std::printf("RESULT band_ceres_p99_budget_fraction %.4f\n", one_ceres.p99_s / kBudget_s);
  const std::string other_key = deployed_warm ? "cold_start" : "warm_start";
  std::printf("RESULT band_%s_p99_budget_fraction %.4f\n", other_key.c_str(),
              other.p99_s / kBudget_s);
  std::printf("RESULT band_%s_5humans_vs_1 %.3f\n", other_key.c_str(),
              other_five.p50_s / other.p50_s);
  std::printf("RESULT band_cpu_p99_budget_fraction %.4f\n", one.cpu_p99_s / kBudget_s);
  std::printf("RESULT band_cpu_5humans_vs_1 %.3f\n", five.cpu_p50_s / one.cpu_p50_s);
  return 0;
}
