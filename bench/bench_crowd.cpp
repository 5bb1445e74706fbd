// bench_crowd: the whole system as real processes (as bench_pipeline) on scenes of 1, 5, 10 and
// 20 people (open_minimal and config/scenarios/crowd_{5,10,20}_flows), in one run. Per scene:
//  - the band cycle: from the world's agent states of a step to the band source's bands of that
//    step (plan time plus one hop), p50 / p99;
//  - band -> decision: from the bands of a step to the dialogue manager's acknowledgement of it
//    (sent after whatever it decided is published), p50 / p99;
//  - each daemon's CPU (user + system) over the run's wall time.
// The band source plans the nearest planner.max_planned_others (5) jointly and predicts the
// others' bands, so the cycle should grow little past 5 people. Ends with RESULT lines.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/step_ack_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;
const std::string kBuild = COOPNAV_BINARY_DIR;
const std::string kSource = COOPNAV_SOURCE_DIR;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Observer : coopnav::bench::RunObserver {
  std::map<std::int64_t, Clock::time_point> agents_at, band_at;  // step -> received
  std::vector<double> cycle_ms, decision_ms;
  int max_humans{0};

  void onAgents(const lcm::ReceiveBuffer*, const std::string&, const coopnav::agent_states_t* m) {
    agents_at.emplace(m->step, Clock::now());  // the first copy (a repeat re-sends it)
    max_humans = std::max(max_humans, static_cast<int>(m->num_humans));
  }
  void onBands(const lcm::ReceiveBuffer*, const std::string&, const coopnav::bands_t* m) {
    band_at[m->step] = Clock::now();
    if (auto it = agents_at.find(m->step); it != agents_at.end()) {
      cycle_ms.push_back(
          std::chrono::duration<double, std::milli>(band_at[m->step] - it->second).count());
      agents_at.erase(it);
    }
  }
  void onAck(const lcm::ReceiveBuffer*, const std::string&, const coopnav::step_ack_t* m) {
    if (m->participant != "dialogue_manager") return;
    auto it = band_at.find(m->step);
    if (it == band_at.end()) return;
    decision_ms.push_back(msSince(it->second));
    band_at.erase(it);
  }
};

struct SceneResult {
  int humans{0};
  double cycle_p50_ms{NAN}, cycle_p99_ms{NAN}, decision_p50_ms{NAN}, decision_p99_ms{NAN};
  std::map<std::string, double> cpu_fraction;
};

SceneResult runScene(const std::string& name, int port, const std::string& log_dir) {
  const std::string url =
      "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304";
  const std::string scenario = kSource + "/config/scenarios/" + name + ".yaml";
  auto daemons = coopnav::bench::startDaemons(kBuild, kSource, url, scenario, log_dir + "/" + name);
  lcm::LCM lcm(url);
  Observer obs;
  lcm.subscribe(coopnav::channels::kAgentStates, &Observer::onAgents, &obs);
  lcm.subscribe(coopnav::channels::kBands, &Observer::onBands, &obs);
  lcm.subscribe(coopnav::channels::kStepAck, &Observer::onAck, &obs);
  coopnav::bench::watchRun(lcm, obs);
  const auto ready_deadline = Clock::now() + std::chrono::seconds(60);
  while (obs.ready.size() < daemons.size() && Clock::now() < ready_deadline) lcm.handleTimeout(100);

  std::map<std::string, double> cpu0;
  for (const auto& [d, pid] : daemons) cpu0[d] = coopnav::bench::cpuSeconds(pid);
  const auto t0 = Clock::now();
  const pid_t sim = coopnav::bench::spawnProcess(
      {kBuild + "/daemons/world_sim/coopnav_world_sim", "-c", kSource + "/config/world_sim.yaml",
       "--lcm-url", url, "--set", "scenario=" + scenario},
      log_dir + "/" + name + "_world_sim.log");
  const auto deadline = t0 + std::chrono::minutes(15);
  while (!obs.done && Clock::now() < deadline) lcm.handleTimeout(100);
  const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  SceneResult r;
  for (const auto& [d, pid] : daemons)
    r.cpu_fraction[d] = (coopnav::bench::cpuSeconds(pid) - cpu0[d]) / wall_s;
  int st = 0;
  ::waitpid(sim, &st, 0);
  for (const auto& [d, pid] : daemons) ::kill(pid, SIGTERM);
  for (const auto& [d, pid] : daemons) ::waitpid(pid, &st, 0);
  r.humans = obs.max_humans;
  r.cycle_p50_ms = coopnav::bench::percentile(obs.cycle_ms, 0.5);
  r.cycle_p99_ms = coopnav::bench::percentile(obs.cycle_ms, 0.99);
  r.decision_p50_ms = coopnav::bench::percentile(obs.decision_ms, 0.5);
  r.decision_p99_ms = coopnav::bench::percentile(obs.decision_ms, 0.99);
  std::printf(
      "%-16s %2d humans: sim %.1f s in %.1f s wall (final state %d); band cycle p50 %.2f ms p99 "
      "%.2f ms (%zu); band->decision p50 %.2f ms p99 %.2f ms (%zu)\n",
      name.c_str(), r.humans, obs.sim_end_s, wall_s, obs.final_state, r.cycle_p50_ms,
      r.cycle_p99_ms, obs.cycle_ms.size(), r.decision_p50_ms, r.decision_p99_ms,
      obs.decision_ms.size());
  std::printf("%-16s CPU / wall:", "");
  for (const auto& [d, f] : r.cpu_fraction) std::printf(" %s %.3f", d.c_str(), f);
  std::printf("\n");
  std::fflush(stdout);
  return r;
}

}  // namespace

int main() {
  const std::vector<std::string> scenes{"open_minimal", "crowd_5_flows", "crowd_10_flows",
                                        "crowd_20_flows"};
  const std::string log_dir = kBuild + "/bench_crowd_logs";
  ::mkdir(log_dir.c_str(), 0755);
  std::vector<SceneResult> results;
  int port = 7981;
  for (const auto& s : scenes) results.push_back(runScene(s, port++, log_dir));
  const SceneResult& one = results.front();
  const SceneResult& twenty = results.back();
  std::printf(
      "\nhumans  cycle p50 [ms]  x1   cycle p99 [ms]  decision p99 [ms]  band_source CPU\n");
  for (const auto& r : results)
    std::printf("%6d  %14.2f  %4.1f  %14.2f  %17.2f  %15.3f\n", r.humans, r.cycle_p50_ms,
                r.cycle_p50_ms / one.cycle_p50_ms, r.cycle_p99_ms, r.decision_p99_ms,
                r.cpu_fraction.at("band_source"));
  std::printf("RESULT crowd_cycle_20_vs_1 %.3f\n", twenty.cycle_p50_ms / one.cycle_p50_ms);
  std::printf("RESULT crowd_cycle_p99_20_vs_1 %.3f\n", twenty.cycle_p99_ms / one.cycle_p99_ms);
  std::printf("RESULT crowd_decision_latency_p99_ms_20 %.3f\n", twenty.decision_p99_ms);
  std::printf("RESULT crowd_band_source_cpu_20 %.3f\n", twenty.cpu_fraction.at("band_source"));
  return 0;
}
