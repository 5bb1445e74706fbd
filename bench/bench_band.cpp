/// @file Benchmark of the dual-band planner: solve time per cycle for the head-on case in the
/// wide corridor of open.pgm with CoHAN 2.0's sim settings, as a fraction of a 100 ms budget,
/// and the 1 robot + 5 humans case as a ratio to 1 human. The planner settings are band_source's
/// own: the `planner` section of config/band_source.yaml, loaded by the daemon's loader (CoHAN's
/// sim values, cold-started every cycle as CoHAN 2.0 runs), so the headline figures are those of
/// the deployed daemon. The lib default, warm start, is measured beside them. Closed loop: every
/// 0.1 s world_sim's physics moves the robot by the planner's command and the humans as
/// minimally contributing walkers, and the planner runs again; every case's repeats interleaved
/// with the others' so that all share the machine's load. Then Ceres against our SparseLm on the
/// cycles of the deployed closed loop (one human, five humans): every Ceres configuration
/// band_optimizer.hpp exposes, same residual blocks, same iteration budget, at equal final cost
/// (compareCeres).
/// Ends with RESULT lines. `bench_band SOLVER HUMANS [REPEATS]` runs one case only (for a
/// profiler).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "band_source/band_source_node.hpp"
#include "bench_util.hpp"
#include "config/config.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/sim/simulation.hpp"
#include "maps/map_loader.hpp"

namespace {

using namespace coopnav;  // NOLINT

constexpr double kBudget_s = 0.1;  // CoHAN 2.0 controller rate 10 Hz
constexpr double kCycle_s = 0.1;
constexpr int kCycles = 120;  // 12 s: the approach, the crossing (~9 s) and the first steps apart
int g_repeats = 3;  // runs of kCycles per case; `bench_band SOLVER HUMANS REPEATS` sets it

/// CPU time of this thread [s]: unlike wall time it does not count the time the scheduler gave
/// to other processes of this shared machine.
double threadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// CPU time of the whole process [s]: the work of every thread, none of the waiting.
double processCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The head-on world of every case: world_sim's physics (lib/sim), as the daemons meet it in the
/// paper's scenarios. The robot follows the planner's velocity command under its acceleration
/// limits (its kinematics and limits are the planner's robot); each human walks at 1 m/s to its
/// goal as world_sim's minimally contributing human does (a sidestep of at most 0.3 m when the
/// robot is about to touch it), whatever the robot anticipated for it. 1 human: robot and human on
/// the corridor's middle line, 14 m apart; 5 humans: a group abreast and staggered around it.
sim::WorldSpec headOnWorld(const BandPlannerConfig& cfg, int n_humans) {
  sim::WorldSpec w;
  w.seed = 1;
  w.settings.physics_dt_s = kCycle_s / 2.0;
  w.settings.substeps_per_step = 2;  // one step() = one planning cycle
  w.settings.time_limit_s = 3600.0;
  w.settings.end_on_goals = false;
  w.settings.end_on_robot_collision = false;  // every case runs all its cycles
  const AgentKinematics& k = cfg.robot;
  w.robot.start = {6.5, 6.5, 0.0};
  w.robot.goal = {20.5, 6.5, 0.0};
  w.robot.radius_m = k.radius_m;
  w.robot.kinematics = k.holonomic ? sim::Kinematics::kHolonomic : sim::Kinematics::kDifferential;
  w.robot.limits.max_forward_m_s = k.max_vel_x_m_s;
  w.robot.limits.max_backward_m_s = k.max_vel_x_backwards_m_s;
  w.robot.limits.max_lateral_m_s = k.max_vel_y_m_s;
  w.robot.limits.max_omega_rad_s = k.max_vel_theta_rad_s;
  w.robot.limits.max_acc_forward_m_s2 = k.acc_lim_x_m_s2;
  w.robot.limits.max_acc_lateral_m_s2 = k.acc_lim_y_m_s2;
  w.robot.limits.max_acc_omega_rad_s2 = k.acc_lim_theta_rad_s2;
  w.robot.goal_tolerance_m = cfg.xy_goal_tolerance_m;
  const double ys[5] = {6.5, 5.0, 8.0, 4.2, 8.8};
  const double xs[5] = {20.5, 19.5, 19.0, 18.0, 17.5};
  for (int h = 0; h < n_humans; ++h) {
    sim::HumanSpec hs;
    hs.id = h + 1;
    hs.start = {xs[h], ys[h], M_PI};
    hs.goal = {6.5, ys[h], M_PI};
    hs.speed_m_s = 1.0;
    hs.radius_m = cfg.human.radius_m;
    hs.behaviour.type = sim::BehaviourType::kMinimal;
    w.humans.push_back(hs);
  }
  return w;
}

struct Stats {
  double p50_s{0.0};
  double p99_s{0.0};
  double cpu_p50_s{0.0};  ///< the planning thread's CPU time: what a dedicated core would take
  double cpu_p99_s{0.0};
  /// Over the cycles, each cycle's fastest repeat: every repeat plans the same cycles (the loop
  /// is deterministic), so the minimum strips what the shared host's other load added.
  double best_p50_s{0.0};
  double best_p99_s{0.0};
  std::size_t robot_poses{0};
  std::size_t human_poses{0};
  double solver_share{0.0};     ///< Ceres' own time / plan() time, summed over cycles
  double mean_iterations{0.0};  ///< LM iterations per cycle
  double mean_accepted{0.0};    ///< of them, steps taken (the rest rejected)
  double mean_robot_poses{0.0};
  double mean_human_poses{0.0};
  double mean_final_cost{0.0};  ///< ½ Σ r² after the cycle's last iteration: what the time bought
};

/// The planner settings band_source runs with (config/band_source.yaml).
BandPlannerConfig g_deployed;
int g_max_iterations = 0;  ///< band_source's max_iterations (0: inner x outer)

/// What the cycles of one case measured, over all its repeats so far.
struct Samples {
  std::vector<double> times, cpu;
  std::vector<double> best;  ///< per cycle index: the fastest repeat's wall time
  std::size_t robot_poses = 0, human_poses = 0;  ///< first cycle of the first repeat
  double solver_s = 0.0, iterations = 0.0, accepted = 0.0, final_cost = 0.0, sum_robot = 0.0,
         sum_human = 0.0;
};

/// One repeat of a case: kCycles closed-loop cycles from the start of the head-on world.
void runOnce(const std::shared_ptr<const DistanceMap>& map, int n_humans, const std::string& solver,
             bool warm_start, Samples* out, std::vector<PlanRequest>* record = nullptr) {
  BandPlannerConfig cfg = g_deployed;
  cfg.solver = solver;
  cfg.warm_start = warm_start;
  DualBandPlanner planner(cfg, map);
  const sim::WorldSpec spec = headOnWorld(cfg, n_humans);
  sim::Simulation world(spec, map.get());
  std::vector<AgentState> agents = world.agents();
  PlanRequest req;
  req.goal = spec.robot.goal;
  // As band_source in lockstep: the iteration budget only (CoHAN 8 x 4), no time limit.
  req.max_iterations = g_max_iterations;
  req.time_budget_s = 0.0;
  req.clock_s = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  const bool first_repeat = out->times.empty();
  double t_s = 0.0;
  for (int c = 0; c < kCycles; ++c) {
    // As band_source: the robot plans, every human with its known goal is anticipated.
    req.stamp_s = t_s;
    req.agent = agents.front();
    req.others.clear();
    for (std::size_t h = 1; h < agents.size(); ++h) {
      OtherAgentInput o;
      o.state = agents[h];
      o.goal = spec.humans[h - 1].goal;
      req.others.push_back(o);
    }
    if (record != nullptr) record->push_back(req);
    const double c0 = threadCpu_s();
    const auto t0 = std::chrono::steady_clock::now();
    const PlanResult r = planner.plan(req);
    const auto t1 = std::chrono::steady_clock::now();
    const double cpu_s = threadCpu_s() - c0;
    if (r.status != PlanStatus::kOk) break;
    out->cpu.push_back(cpu_s);
    out->times.push_back(std::chrono::duration<double>(t1 - t0).count());
    if (out->best.size() <= static_cast<std::size_t>(c)) {
      out->best.resize(c + 1, std::numeric_limits<double>::infinity());
    }
    out->best[c] = std::min(out->best[c], out->times.back());
    out->solver_s += r.solver_time_s;
    out->iterations += r.iterations;
    out->accepted += r.accepted_steps;
    out->final_cost += r.final_cost;
    out->sum_robot += static_cast<double>(r.agent_band.poses.size());
    out->sum_human += r.others.empty() ? 0.0 : static_cast<double>(r.others[0].band.poses.size());
    if (c == 0 && first_repeat) {
      out->robot_poses = r.agent_band.poses.size();
      out->human_poses = r.others.empty() ? 0 : r.others[0].band.poses.size();
    }
    world.setRobotBand(r.agent_band, t_s);
    const sim::StepResult step = world.step(r.command_body);
    agents = step.agents;
    t_s = step.t_s;
  }
}

Stats summarize(Samples in) {
  std::vector<double>& times = in.times;
  std::vector<double>& cpu = in.cpu;
  std::sort(times.begin(), times.end());
  Stats s;
  if (times.empty()) return s;
  s.p50_s = times[times.size() / 2];
  s.p99_s = times[std::min(times.size() - 1, static_cast<std::size_t>(0.99 * times.size()))];
  std::sort(cpu.begin(), cpu.end());
  s.cpu_p50_s = cpu[cpu.size() / 2];
  s.cpu_p99_s = cpu[std::min(cpu.size() - 1, static_cast<std::size_t>(0.99 * cpu.size()))];
  std::vector<double>& best = in.best;
  std::sort(best.begin(), best.end());
  s.best_p50_s = best[best.size() / 2];
  s.best_p99_s = best[std::min(best.size() - 1, static_cast<std::size_t>(0.99 * best.size()))];
  double total_s = 0.0;
  for (double t : times) total_s += t;
  const double n = static_cast<double>(times.size());
  s.solver_share = in.solver_s / total_s;
  s.mean_iterations = in.iterations / n;
  s.mean_accepted = in.accepted / n;
  s.mean_robot_poses = in.sum_robot / n;
  s.mean_human_poses = in.sum_human / n;
  s.mean_final_cost = in.final_cost / n;
  s.robot_poses = in.robot_poses;
  s.human_poses = in.human_poses;
  return s;
}

Stats run(const std::shared_ptr<const DistanceMap>& map, int n_humans, const std::string& solver,
          bool warm_start) {
  Samples samples;
  for (int rep = 0; rep < g_repeats; ++rep) runOnce(map, n_humans, solver, warm_start, &samples);
  return summarize(std::move(samples));
}

// --- Ceres' configurations against ours, on the same problem instances -----------------------
//
// An instance is one recorded request of the closed-loop sparse_lm run (deployed settings),
// planned cold: the bands it optimises, the reference paths and so the residual blocks depend on
// the requests only, never on which solver answered the previous cycles, so every configuration
// meets exactly the same problems as ours, with the same iteration budget (band_source's: 8 x 4
// LM iterations). Timed: optimizeBands (resize, build, solves; PlanResult::solver_time_s), the
// part the solvers differ in, as the PROCESS's CPU time: on this shared host wall time is
// dominated by the scheduler (one run: Ceres' wall p99 177 ms against a CPU p99 of ~35 ms), and
// process time still counts any helper thread a library might start (the "proc/thread" line
// shows there is none). plan()'s wall time, with its shared rest (global paths, band
// initialisation), is in the "plan p99" column.
//
// Two stages, to keep the bench short: a screen of every configuration on a few instances
// (fresh planner per instance, once), then the finalists on all instances in cycle order (one
// planner per pass: the very problems of the closed loop), passes interleaved with ours.

/// "Equal final cost": a configuration's final cost, summed over the instances, is at most ours
/// × (1 + kEqualCostRel) + kEqualCostAbs (lower is better, so a lower cost qualifies). Others
/// are reported but cannot be the best Ceres.
constexpr double kEqualCostRel = 0.01;
constexpr double kEqualCostAbs = 1e-6;
/// Screen: every kScreenStride-th instance, once. A configuration that takes more than
/// kClearlyLosing x our time on the first of them is stopped there by the solver's time budget
/// (dense Schur, exact iterative solves: 10-1000x ours, up to 13 s a cycle with five humans).
constexpr std::size_t kScreenStride = 20;
constexpr double kClearlyLosing = 12.0;
/// Finalists: Ceres' default configuration, and the kMaxFinalists fastest (mean time) of the
/// screen's equal-cost ones, each run kFullRepeats passes over all instances.
constexpr std::size_t kMaxFinalists = 2;
constexpr int kFullRepeats = 2;

/// One solver configuration on recorded instances.
struct Replay {
  bool ours{false};
  CeresBackendOptions ceres;
  std::string name;
  std::string unusable;                ///< not run: why
  std::vector<std::size_t> instances;  ///< which recorded requests
  int passes{0};
  bool stopped{false};                   ///< clearly losing: stopped after its first instance
  std::vector<double> solver_s, plan_s;  ///< every solve of every pass
  std::vector<double> cost;              ///< per instance solved (solves are deterministic)
  std::vector<double> best_s;            ///< per instance solved: fastest pass
  double thread_cpu_s{0.0}, process_cpu_s{0.0};  ///< summed over plan() calls
  double iterations{0.0};
  int solves{0};
  int failed{0};  ///< solves in which the solver did not run (no LM iteration)
};

/// Solves instances [begin, end) of r once more; `fresh`: a new planner per instance (its global
/// path cache would otherwise carry a subset's history into the problems), else one planner
/// for the range, as in the closed loop (the range must then be every instance).
void replay(const std::shared_ptr<const DistanceMap>& map, const std::vector<PlanRequest>& requests,
            Replay* r, std::size_t begin, std::size_t end, bool fresh, double budget_s = 0.0) {
  BandPlannerConfig cfg = g_deployed;
  cfg.solver = r->ours ? "sparse_lm" : "ceres";
  cfg.warm_start = false;  // the instance must not depend on the last solver's answer
  std::optional<ScopedCeresBackendOptions> scope;
  if (!r->ours) scope.emplace(r->ceres);
  std::optional<DualBandPlanner> planner;
  for (std::size_t k = begin; k < end; ++k) {
    if (fresh || !planner) planner.emplace(cfg, map);
    PlanRequest req = requests[r->instances[k]];
    req.clock_s = processCpu_s;
    req.time_budget_s = budget_s;
    const double thread0_s = threadCpu_s(), process0_s = processCpu_s();
    const auto t0 = std::chrono::steady_clock::now();
    const PlanResult res = planner->plan(req);
    const auto t1 = std::chrono::steady_clock::now();
    r->thread_cpu_s += threadCpu_s() - thread0_s;
    r->process_cpu_s += processCpu_s() - process0_s;
    const bool ok = res.status == PlanStatus::kOk;
    if (k >= r->cost.size()) {
      r->cost.push_back(ok ? res.final_cost : std::nan(""));
      r->best_s.push_back(std::numeric_limits<double>::infinity());
    }
    if (!ok) continue;
    if (res.budget_exhausted) r->stopped = true;
    r->solver_s.push_back(res.solver_time_s);
    r->plan_s.push_back(std::chrono::duration<double>(t1 - t0).count());
    r->best_s[k] = std::min(r->best_s[k], res.solver_time_s);
    r->iterations += res.iterations;
    ++r->solves;
    if (res.iterations == 0) ++r->failed;
  }
}

double sum(const std::vector<double>& v, std::size_t n) {
  double s = 0.0;
  for (std::size_t k = 0; k < std::min(n, v.size()); ++k) s += v[k];
  return s;
}
double p99(const std::vector<double>& v) { return bench::percentile(v, 0.99); }
double p50(const std::vector<double>& v) { return bench::percentile(v, 0.50); }
double mean(const std::vector<double>& v) {
  return v.empty() ? std::nan("") : sum(v, v.size()) / static_cast<double>(v.size());
}

struct Judged {
  double cost_ratio{0.0};  ///< Σ final cost / ours, over the instances r solved
  int worse{0};            ///< instances more than kEqualCostRel above ours
  bool equal_cost{false};
};

Judged judge(const Replay& r, const Replay& ours) {
  Judged j;
  const std::size_t n = r.cost.size();
  const double mine = sum(r.cost, n), theirs = sum(ours.cost, n);
  j.cost_ratio = theirs > 0.0 ? mine / theirs : 1.0;
  j.equal_cost = !r.stopped && r.failed == 0 && n == ours.cost.size() &&
                 mine <= theirs * (1.0 + kEqualCostRel) + kEqualCostAbs;
  for (std::size_t k = 0; k < n; ++k) {
    if (!(r.cost[k] <= ours.cost[k] * (1.0 + kEqualCostRel) + kEqualCostAbs)) ++j.worse;
  }
  return j;
}

void printHeader() {
  std::printf("  %-62s %-6s %8s  %7s %7s %7s %8s  %10s %7s %8s %4s  %s\n", "configuration", "stage",
              "inst x n", "p50 ms", "p99 ms", "best99", "plan p99", "mean cost", "cost/us",
              "worse>1%", "iter", "equal cost");
}

void printReplay(const Replay& r, const Replay& ours, const char* stage) {
  if (!r.unusable.empty()) {
    std::printf("  %-62s %-6s not available: %s\n", r.name.c_str(), stage, r.unusable.c_str());
    return;
  }
  const Judged j = judge(r, ours);
  const char* verdict = r.ours         ? "(ours)"
                        : r.failed > 0 ? "FAILED"
                        : r.stopped    ? "stopped: > 12x ours (time, cost: until stopped)"
                        : j.equal_cost ? "yes"
                                       : "no";
  std::printf(
      "  %-62s %-6s %4zu x %-2d  %7.2f %7.2f %7.2f %8.2f  %10.6g %7.4f %4d/%-3zu %4.1f  %s\n",
      r.name.c_str(), stage, r.cost.size(), r.passes, p50(r.solver_s) * 1e3, p99(r.solver_s) * 1e3,
      p99(r.best_s) * 1e3, p99(r.plan_s) * 1e3,
      sum(r.cost, r.cost.size()) / static_cast<double>(std::max<std::size_t>(1, r.cost.size())),
      j.cost_ratio, j.worse, r.cost.size(), r.iterations / std::max(1, r.solves), verdict);
}

/// What compareCeres found on one problem.
struct Comparison {
  double vs_best_p99{std::nan("")};  ///< ours / best equal-cost Ceres, solver p99
  Replay ours, ceres_default;        ///< full stage
};

/// Screens every Ceres configuration, runs the finalists on every instance and prints the table.
Comparison compareCeres(const std::shared_ptr<const DistanceMap>& map,
                        const std::vector<PlanRequest>& requests, const char* what) {
  std::vector<std::size_t> all(requests.size()), screen;
  for (std::size_t k = 0; k < requests.size(); ++k) {
    all[k] = k;
    if (k % kScreenStride == 0) screen.push_back(k);
  }
  auto make = [](bool ours, const CeresBackendOptions& o, const std::vector<std::size_t>& inst) {
    Replay r;
    r.ours = ours;
    r.ceres = o;
    r.name = ours ? "ours (sparse_lm)" : "ceres " + o.name();
    r.instances = inst;
    return r;
  };
  // Screen.
  Replay ours_screen = make(true, {}, screen);
  replay(map, requests, &ours_screen, 0, screen.size(), true);
  ours_screen.passes = 1;
  std::vector<Replay> screened;
  for (const CeresBackendOptions& o : ceresBackendConfigurations()) {
    Replay r = make(false, o, screen);
    if (!o.usable(&r.unusable)) {
      if (r.unusable.empty()) r.unusable = "rejected by Ceres";
    } else {
      r.unusable.clear();
      // The first instance with a budget: the clearly losing stop there (dense Schur: 13 s a
      // cycle with five humans).
      replay(map, requests, &r, 0, 1, true, kClearlyLosing * ours_screen.best_s[0]);
      if (!r.stopped) replay(map, requests, &r, 1, screen.size(), true);
      r.passes = 1;
    }
    screened.push_back(std::move(r));
  }
  // Finalists: the default, then the fastest equal-cost ones of the screen.
  std::vector<const Replay*> ranked;
  for (const Replay& r : screened) {
    if (r.unusable.empty() && judge(r, ours_screen).equal_cost) ranked.push_back(&r);
  }
  std::sort(ranked.begin(), ranked.end(),
            [](const Replay* a, const Replay* b) { return mean(a->solver_s) < mean(b->solver_s); });
  const std::string default_name = CeresBackendOptions{}.name();
  Comparison out;
  out.ours = make(true, {}, all);
  std::vector<Replay> finals{make(false, {}, all)};
  for (const Replay* r : ranked) {
    if (finals.size() > kMaxFinalists) break;
    if (r->ceres.name() != default_name) finals.push_back(make(false, r->ceres, all));
  }
  for (int pass = 0; pass < kFullRepeats; ++pass) {
    replay(map, requests, &out.ours, 0, all.size(), false);
    ++out.ours.passes;
    for (Replay& f : finals) {
      replay(map, requests, &f, 0, all.size(), false);
      ++f.passes;
    }
  }
  std::printf(
      "\n%s: Ceres' configurations on the same instances (screen: every %zu-th of %zu, once, "
      "stopped after one above %.0fx ours; full: all %zu in cycle order, %d passes interleaved "
      "with ours). ms = optimizeBands' process CPU time; best99 = p99 of each instance's fastest "
      "pass; plan p99 = plan() wall time; equal cost = summed final cost <= ours x %.2f; "
      "proc/thread CPU: ours %.3f, Ceres' default %.3f\n",
      what, kScreenStride, requests.size(), kClearlyLosing, requests.size(), kFullRepeats,
      1.0 + kEqualCostRel, out.ours.process_cpu_s / out.ours.thread_cpu_s,
      finals.front().process_cpu_s / finals.front().thread_cpu_s);
  printHeader();
  printReplay(out.ours, out.ours, "full");
  const Replay* best = nullptr;
  for (const Replay& f : finals) {
    printReplay(f, out.ours, "full");
    if (judge(f, out.ours).equal_cost && (best == nullptr || p99(f.solver_s) < p99(best->solver_s)))
      best = &f;
  }
  printReplay(ours_screen, ours_screen, "screen");
  for (const Replay& r : screened) printReplay(r, ours_screen, "screen");
  out.ceres_default = finals.front();
  if (best == nullptr) {
    std::printf("%s: no Ceres configuration reached our final cost\n", what);
    return out;
  }
  out.vs_best_p99 = p99(out.ours.solver_s) / p99(best->solver_s);
  std::printf(
      "%s: best Ceres (equal cost, lowest p99): %s; ours / it: p50 %.3f p99 %.3f (each instance's "
      "fastest pass: p50 %.3f p99 %.3f; plan() p99 %.3f)\n",
      what, best->name.c_str(), p50(out.ours.solver_s) / p50(best->solver_s), out.vs_best_p99,
      p50(out.ours.best_s) / p50(best->best_s), p99(out.ours.best_s) / p99(best->best_s),
      p99(out.ours.plan_s) / p99(best->plan_s));
  return out;
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
        "%s, %s humans: p50 %.2f ms p99 %.2f ms (CPU p50 %.2f p99 %.2f), %.1f iterations "
        "(%.1f steps taken), %.1f robot + %.1f human poses, final cost %.17g; per-cycle best of "
        "%d: p50 %.2f p99 %.2f ms\n",
        argv[1], argv[2], s.p50_s * 1e3, s.p99_s * 1e3, s.cpu_p50_s * 1e3, s.cpu_p99_s * 1e3,
        s.mean_iterations, s.mean_accepted, s.mean_robot_poses, s.mean_human_poses,
        s.mean_final_cost, g_repeats, s.best_p50_s * 1e3, s.best_p99_s * 1e3);
    return 0;
  }
  // Warm-up: the first planner of the process pays for page faults and the map's first reads.
  run(map, 1, "sparse_lm", deployed_warm);
  // Repeat by repeat, every case in turn: the host's speed drifts by up to 1.5x within minutes,
  // and interleaving gives every case, and so every ratio, the same share of that drift.
  struct Case {
    int humans;
    const char* solver;
    bool warm;
    Samples samples;
  };
  // The other warm-start setting beside the deployed one (the lib default is warm,
  // band_source.yaml runs cold). Ceres runs after these, on the recorded cycles (compareCeres):
  // it takes the same steps as ours (final costs equal to 12 digits), so its closed loop would
  // plan the very same cycles, at 5x the bench time. Both solvers run on one thread: Ceres'
  // parallel evaluation would run terms of one band concurrently, and they share the band's
  // heading cache (BandTrig).
  std::vector<Case> cases = {{1, "sparse_lm", deployed_warm, {}},
                             {5, "sparse_lm", deployed_warm, {}},
                             {1, "sparse_lm", !deployed_warm, {}},
                             {5, "sparse_lm", !deployed_warm, {}}};
  // The first repeat of the deployed cases records the instances the Ceres configurations are
  // compared on.
  std::vector<PlanRequest> one_requests, five_requests;
  for (int rep = 0; rep < g_repeats; ++rep) {
    for (std::size_t k = 0; k < cases.size(); ++k) {
      Case& c = cases[k];
      std::vector<PlanRequest>* record = nullptr;
      if (rep == 0 && k == 0) record = &one_requests;
      if (rep == 0 && k == 1) record = &five_requests;
      runOnce(map, c.humans, c.solver, c.warm, &c.samples, record);
    }
  }
  const Stats one = summarize(std::move(cases[0].samples));
  const Stats five = summarize(std::move(cases[1].samples));
  const Stats other = summarize(std::move(cases[2].samples));
  const Stats other_five = summarize(std::move(cases[3].samples));
  std::printf("map %s, %d cycles x %d runs, budget %.0f ms\n", yaml.c_str(), kCycles, g_repeats,
              kBudget_s * 1e3);
  std::printf(
      "planner settings: %s (planner.*, max_iterations %d), %s; CPU = the calling thread's\n",
      config_path.c_str(), g_max_iterations,
      deployed_warm ? "warm-started" : "cold-started every cycle");
  auto line = [](const std::string& what, const Stats& s) {
    std::printf(
        "%-28s p50 %7.2f ms  p99 %7.2f ms  (CPU p50 %7.2f p99 %7.2f) | mean %.1f robot + %.1f "
        "human poses, %.1f LM iterations (%.1f steps taken), solver %.0f %% of plan(); "
        "per-cycle best of %d: p50 %.2f p99 %.2f ms; final cost %.17g\n",
        what.c_str(), s.p50_s * 1e3, s.p99_s * 1e3, s.cpu_p50_s * 1e3, s.cpu_p99_s * 1e3,
        s.mean_robot_poses, s.mean_human_poses, s.mean_iterations, s.mean_accepted,
        100.0 * s.solver_share, g_repeats, s.best_p50_s * 1e3, s.best_p99_s * 1e3,
        s.mean_final_cost);
  };
  std::printf("first cycle (1 human): %zu robot + %zu human poses\n", one.robot_poses,
              one.human_poses);
  const std::string other_name = deployed_warm ? "cold start" : "warm start";
  line("1 human, sparse_lm", one);
  line("5 humans, sparse_lm", five);
  line("1 human, " + other_name, other);
  line("5 humans, " + other_name, other_five);
  const Comparison cmp_one = compareCeres(map, one_requests, "1 human");
  const Comparison cmp_five = compareCeres(map, five_requests, "5 humans");
  // Ceres' default (tuned SPARSE_NORMAL_CHOLESKY) against ours: plan() wall time, on the
  // cycles of the closed loop, passes interleaved.
  auto planLine = [](const char* what, const Replay& r) {
    std::printf("%-28s p50 %7.2f ms  p99 %7.2f ms (plan(), %zu cycles x %d passes)\n", what,
                p50(r.plan_s) * 1e3, p99(r.plan_s) * 1e3, r.cost.size(), r.passes);
  };
  std::printf("\n");
  planLine("1 human, sparse_lm", cmp_one.ours);
  planLine("1 human, ceres", cmp_one.ceres_default);
  planLine("5 humans, sparse_lm", cmp_five.ours);
  planLine("5 humans, ceres", cmp_five.ceres_default);
  const double one_p50_ratio = p50(cmp_one.ours.plan_s) / p50(cmp_one.ceres_default.plan_s);
  std::printf("sparse_lm / ceres: 1 human p50 %.3f p99 %.3f; 5 humans p50 %.3f p99 %.3f\n",
              one_p50_ratio, p99(cmp_one.ours.plan_s) / p99(cmp_one.ceres_default.plan_s),
              p50(cmp_five.ours.plan_s) / p50(cmp_five.ceres_default.plan_s),
              p99(cmp_five.ours.plan_s) / p99(cmp_five.ceres_default.plan_s));
  std::printf("RESULT band_p99_budget_fraction %.4f\n", one.p99_s / kBudget_s);
  std::printf("RESULT band_5humans_vs_1 %.3f\n", five.p50_s / one.p50_s);
  std::printf("RESULT band_sparse_lm_vs_ceres_p50 %.3f\n", one_p50_ratio);
  std::printf("RESULT band_ceres_p99_budget_fraction %.4f\n",
              p99(cmp_one.ceres_default.plan_s) / kBudget_s);
  const std::string other_key = deployed_warm ? "cold_start" : "warm_start";
  std::printf("RESULT band_%s_p99_budget_fraction %.4f\n", other_key.c_str(),
              other.p99_s / kBudget_s);
  std::printf("RESULT band_%s_5humans_vs_1 %.3f\n", other_key.c_str(),
              other_five.p50_s / other.p50_s);
  std::printf("RESULT band_cpu_p99_budget_fraction %.4f\n", one.cpu_p99_s / kBudget_s);
  std::printf("RESULT band_cpu_5humans_vs_1 %.3f\n", five.cpu_p50_s / one.cpu_p50_s);
  std::printf("RESULT band_best_p99_budget_fraction %.4f\n", one.best_p99_s / kBudget_s);
  std::printf("RESULT band_best_5humans_vs_1 %.3f\n", five.best_p50_s / one.best_p50_s);
  std::printf("RESULT band_p99_vs_best_ceres %.3f\n", cmp_one.vs_best_p99);
  std::printf("RESULT band_5humans_p99_vs_best_ceres %.3f\n", cmp_five.vs_best_p99);
  return 0;
}
