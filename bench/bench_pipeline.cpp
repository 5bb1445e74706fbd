// bench_pipeline: the whole system as real processes (distance server, band source, both
// assessors, dialogue manager, world simulator in lockstep) over the paper's four scenarios.
// Prints, in one run: suite wall time over simulated time, and the latency from a band message
// published to the dialogue manager's decision for that step (its step acknowledgement, which
// it sends after publishing whatever it decided), p50 / p99, beside a bare LCM echo measured in
// the same run (after the pipeline, alone, and on the pipeline's bus while it runs: the reference
// under the same load), and where that latency goes: per step, when each hop of the chain arrived
// (band source's ack, the distance request and reply, the situation, the path assessment, each
// assessor's ack, the dialogue manager's ack), p50 / p99 after the bands. Ends with RESULT lines.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;
const std::string kBuild = COOPNAV_BINARY_DIR;
const std::string kSource = COOPNAV_SOURCE_DIR;

std::string exe(const std::string& d) { return kBuild + "/daemons/" + d + "/coopnav_" + d; }

// The hops of the band -> decision chain, in the order the pipeline takes them.
const std::vector<std::string> kHops{
    "ack band_source",        "distance request", "distance reply",    "situation",
    "ack situation_assessor", "path assessment",  "ack path_assessor", "ack dialogue_manager"};

struct Observer : coopnav::bench::RunObserver {
  struct Step {
    Clock::time_point bands;
    std::map<std::string, Clock::time_point> hop;  // first arrival of each hop
  };
  std::map<std::int64_t, Step> steps;            // step -> its band and hop times
  std::map<std::int64_t, std::int64_t> step_of;  // utime -> step (distance traffic has no step)
  std::vector<double> latency_ms;
  std::map<std::string, std::vector<double>> hop_ms;  // hop -> after the bands [ms]

  // Each daemon's own handling time (its status: median and max over each second) [ms]: what
  // of a hop is the daemon's work, the rest being the bus and the wait for a core.
  std::map<std::string, std::vector<double>> handling_p50_ms, handling_max_ms;
  void onHandling(const lcm::ReceiveBuffer*, const std::string&,
                  const coopnav::daemon_status_t* m) {
    if (std::isfinite(m->cycle_p50_ms)) handling_p50_ms[m->name].push_back(m->cycle_p50_ms);
    if (std::isfinite(m->cycle_max_ms)) handling_max_ms[m->name].push_back(m->cycle_max_ms);
  }

  // A bare echo on the same bus while the pipeline runs: the reference under the same load.
  std::vector<double> concurrent_echo_ms;
  std::optional<Clock::time_point> ping_sent;
  void onEchoReply(const lcm::ReceiveBuffer*, const std::string&) {
    if (!ping_sent) return;
    concurrent_echo_ms.push_back(
        std::chrono::duration<double, std::milli>(Clock::now() - *ping_sent).count());
    ping_sent.reset();
  }

  std::size_t band_bytes{0};
  void onBands(const lcm::ReceiveBuffer* rb, const std::string&, const coopnav::bands_t* m) {
    steps[m->step].bands = Clock::now();
    step_of[m->utime] = m->step;
    band_bytes = std::max<std::size_t>(band_bytes, rb->data_size);
  }
  void note(std::int64_t step, const std::string& hop) {
    auto it = steps.find(step);
    if (it != steps.end()) it->second.hop.emplace(hop, Clock::now());
  }
  void noteUtime(std::int64_t utime, const std::string& hop) {
    auto it = step_of.find(utime);
    if (it != step_of.end()) note(it->second, hop);
  }
  void onRequest(const lcm::ReceiveBuffer*, const std::string&,
                 const coopnav::distance_request_t* m) {
    noteUtime(m->utime, "distance request");
  }
  void onReply(const lcm::ReceiveBuffer*, const std::string&, const coopnav::distance_reply_t* m) {
    noteUtime(m->utime, "distance reply");
  }
  void onSituation(const lcm::ReceiveBuffer*, const std::string&, const coopnav::situation_t* m) {
    note(m->step, "situation");
  }
  void onPath(const lcm::ReceiveBuffer*, const std::string&, const coopnav::path_assessment_t* m) {
    note(m->step, "path assessment");
  }
  void onAck(const lcm::ReceiveBuffer*, const std::string&, const coopnav::step_ack_t* m) {
    note(m->step, "ack " + m->participant);
    if (m->participant != "dialogue_manager") return;
    auto it = steps.find(m->step);
    if (it == steps.end()) return;
    const auto ms = [&](Clock::time_point t) {
      return std::chrono::duration<double, std::milli>(t - it->second.bands).count();
    };
    latency_ms.push_back(ms(Clock::now()));
    for (const auto& [hop, t] : it->second.hop) hop_ms[hop].push_back(ms(t));
    step_of.erase(m->utime);
    steps.erase(it);
  }
};

// Bare echo round trip [ms] of a bands-sized payload on the same URL, for scale.
std::vector<double> echoRoundTrips(const std::string& url, std::size_t bytes, int n) {
  const pid_t echo = coopnav::bench::startEcho(url, "BENCH_ECHO_REQ", "BENCH_ECHO_REP");
  lcm::LCM lcm(url);
  struct H {
    bool got{false};
    void on(const lcm::ReceiveBuffer*, const std::string&) { got = true; }
  } h;
  lcm.subscribe("BENCH_ECHO_REP", &H::on, &h);
  std::vector<std::uint8_t> payload(bytes, 0x5a);
  std::vector<double> ms;
  for (int i = 0; i < n + 20; ++i) {
    h.got = false;
    const auto t0 = Clock::now();
    lcm.publish("BENCH_ECHO_REQ", payload.data(), static_cast<unsigned>(payload.size()));
    while (!h.got && lcm.handleTimeout(1000) > 0) {
    }
    if (h.got && i >= 20)
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  ::kill(echo, SIGKILL);
  int st = 0;
  ::waitpid(echo, &st, 0);
  return ms;
}

}  // namespace

int main() {
  const std::vector<std::string> scenarios{"open_facilitating", "open_minimal",
                                           "narrow_facilitating", "narrow_minimal"};
  const std::string log_dir = kBuild + "/bench_pipeline_logs";
  ::mkdir(log_dir.c_str(), 0755);
  double wall_total_s = 0.0, sim_total_s = 0.0;
  std::vector<double> all_latency_ms, concurrent_echo_ms;
  std::map<std::string, std::vector<double>> all_hop_ms, handling_p50_ms, handling_max_ms;
  std::size_t band_bytes = 0;
  int port = 7971;
  for (const auto& name : scenarios) {
    const std::string url =
        "udpm://239.255.76.67:" + std::to_string(port++) + "?ttl=0&recv_buf_size=4194304";
    const std::string scenario = kSource + "/config/scenarios/" + name + ".yaml";
    const std::string cfg = kSource + "/config/";
    std::vector<pid_t> pids;
    for (const auto& [d, pid] :
         coopnav::bench::startDaemons(kBuild, kSource, url, scenario, log_dir + "/" + name))
      pids.push_back(pid);

    lcm::LCM lcm(url);
    Observer obs;
    lcm.subscribe(coopnav::channels::kBands, &Observer::onBands, &obs);
    lcm.subscribe(coopnav::channels::kStepAck, &Observer::onAck, &obs);
    lcm.subscribe(coopnav::channels::kDistanceRequest, &Observer::onRequest, &obs);
    lcm.subscribe(std::string(coopnav::channels::kDistanceReplyPrefix) + ".*", &Observer::onReply,
                  &obs);
    lcm.subscribe(coopnav::channels::kSituation, &Observer::onSituation, &obs);
    lcm.subscribe(coopnav::channels::kStatus, &Observer::onHandling, &obs);
    lcm.subscribe(coopnav::channels::kPathAssessment, &Observer::onPath, &obs);
    coopnav::bench::watchRun(lcm, obs);
    lcm.subscribe("BENCH_ECHO_REP", &Observer::onEchoReply, &obs);
    const pid_t echo = coopnav::bench::startEcho(url, "BENCH_ECHO_REQ", "BENCH_ECHO_REP");
    const auto ready_deadline = Clock::now() + std::chrono::seconds(60);
    while (obs.ready.size() < 5 && Clock::now() < ready_deadline) lcm.handleTimeout(100);

    const auto t0 = Clock::now();
    const pid_t sim =
        coopnav::bench::spawnProcess({exe("world_sim"), "-c", cfg + "world_sim.yaml", "--lcm-url",
                                      url, "--set", "scenario=" + scenario},
                                     log_dir + "/" + name + "_world_sim.log");
    const auto deadline = t0 + std::chrono::minutes(10);
    // One ping every 20 ms (a lost one is given up after 100 ms), the size of a bands message.
    const std::vector<std::uint8_t> ping(std::max<std::size_t>(band_bytes, 4096), 0x5a);
    auto next_ping = t0;
    while (!obs.done && Clock::now() < deadline) {
      const auto now = Clock::now();
      if (obs.ping_sent && now - *obs.ping_sent > std::chrono::milliseconds(100))
        obs.ping_sent.reset();
      if (!obs.ping_sent && now >= next_ping) {
        obs.ping_sent = now;
        lcm.publish("BENCH_ECHO_REQ", ping.data(), static_cast<unsigned>(ping.size()));
        next_ping = now + std::chrono::milliseconds(20);
      }
      lcm.handleTimeout(5);
    }
    const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    int st = 0;
    ::waitpid(sim, &st, 0);
    pids.push_back(echo);
    for (pid_t p : pids) ::kill(p, SIGTERM);
    for (pid_t p : pids) ::waitpid(p, &st, 0);
    std::printf("%-20s sim %.1f s in %.2f s wall (final state %d), %zu band->decision samples\n",
                name.c_str(), obs.sim_end_s, wall_s, obs.final_state, obs.latency_ms.size());
    wall_total_s += wall_s;
    sim_total_s += obs.sim_end_s;
    all_latency_ms.insert(all_latency_ms.end(), obs.latency_ms.begin(), obs.latency_ms.end());
    concurrent_echo_ms.insert(concurrent_echo_ms.end(), obs.concurrent_echo_ms.begin(),
                              obs.concurrent_echo_ms.end());
    band_bytes = std::max(band_bytes, obs.band_bytes);
    for (const auto& [hop, v] : obs.hop_ms)
      all_hop_ms[hop].insert(all_hop_ms[hop].end(), v.begin(), v.end());
    for (const auto& [d, v] : obs.handling_p50_ms)
      handling_p50_ms[d].insert(handling_p50_ms[d].end(), v.begin(), v.end());
    for (const auto& [d, v] : obs.handling_max_ms)
      handling_max_ms[d].insert(handling_max_ms[d].end(), v.begin(), v.end());
  }
  if (band_bytes == 0) band_bytes = 4096;
  const auto echo = echoRoundTrips("udpm://239.255.76.67:7979?ttl=0", band_bytes, 500);
  const double p50 = coopnav::bench::percentile(all_latency_ms, 0.5),
               p99 = coopnav::bench::percentile(all_latency_ms, 0.99);
  const double e50 = coopnav::bench::percentile(echo, 0.5),
               e99 = coopnav::bench::percentile(echo, 0.99);
  const double c50 = coopnav::bench::percentile(concurrent_echo_ms, 0.5),
               c99 = coopnav::bench::percentile(concurrent_echo_ms, 0.99);
  std::printf("suite: %.1f s simulated in %.1f s wall -> wall/sim %.4f (target <= 0.1)\n",
              sim_total_s, wall_total_s, wall_total_s / sim_total_s);
  std::printf(
      "band -> decision: p50 %.2f ms, p99 %.2f ms over %zu steps; bare LCM echo of %zu "
      "bytes: p50 %.3f ms, p99 %.3f ms (ratio p50 %.1f)\n",
      p50, p99, all_latency_ms.size(), band_bytes, e50, e99, p50 / e50);
  std::printf(
      "the same echo on the pipeline's bus while it ran (one ping per 20 ms): p50 %.3f ms, p99 "
      "%.3f ms over %zu pings\n",
      c50, c99, concurrent_echo_ms.size());
  std::printf("where it goes, after the bands arrived (ms; steps that had the hop):\n");
  for (const auto& hop : kHops) {
    const auto& v = all_hop_ms[hop];
    if (v.empty()) continue;
    std::printf("  %-24s p50 %7.3f  p99 %7.3f  (%zu steps)\n", hop.c_str(),
                coopnav::bench::percentile(v, 0.5), coopnav::bench::percentile(v, 0.99), v.size());
  }
  std::printf("each daemon's handling time per message (its status, per second; ms):\n");
  for (const auto& [d, v] : handling_p50_ms)
    std::printf("  %-26s median of p50 %7.3f  max %7.3f\n", d.c_str(),
                coopnav::bench::percentile(v, 0.5),
                handling_max_ms[d].empty()
                    ? std::nan("")
                    : *std::max_element(handling_max_ms[d].begin(), handling_max_ms[d].end()));
  std::printf("RESULT suite_wall_over_sim %.4f\n", wall_total_s / sim_total_s);
  std::printf("RESULT decision_latency_p50_ms %.3f\n", p50);
  std::printf("RESULT decision_latency_p99_ms %.3f\n", p99);
  std::printf("RESULT decision_latency_p99_vs_echo %.3f\n", p99 / e99);
  std::printf("RESULT decision_latency_p99_vs_concurrent_echo %.3f\n", p99 / c99);
  return 0;
}
