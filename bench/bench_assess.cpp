// Benchmark: latency of the situation assessor, from a bands message published to its situation
// message received, with the real obstacle distance server and situation assessor processes
// (the path includes the batched SIDE-query round trip to the server), beside a bare LCM echo of
// the same bytes measured in the same run, interleaved so machine load hits both alike.
//
// Also: the cost of goal inference (lib/planning/goal_inference.hpp) per cycle, for 1 and 20
// humans on open.pgm's corridors (candidates from the map, geodesic distance fields);
// `bench_assess --goals-only` runs only that part (no processes, no network).
//
// Executables come from the build tree: $COOPNAV_BUILD_DIR, else the directory above this binary
// (build/bench/bench_assess -> build/), else the configure-time build dir. Isolated port 7950.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "coopnav/situation_t.hpp"
#include "maps/map_loader.hpp"
#include "wire/conversions.hpp"

namespace {

using namespace coopnav;
using Clock = std::chrono::steady_clock;

constexpr const char* kBenchUrl = "udpm://239.255.76.67:7950?ttl=0&recv_buf_size=4194304";
constexpr const char* kEchoReq = "BENCH_ASSESS_ECHO_REQ";
constexpr const char* kEchoRep = "BENCH_ASSESS_ECHO_REP";

std::string buildDir() {
  if (const char* env = std::getenv("COOPNAV_BUILD_DIR")) return env;
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n > 0) {
    std::string exe(buf, static_cast<std::size_t>(n));
    const auto bench_dir = exe.substr(0, exe.rfind('/'));
    auto root = bench_dir.substr(0, bench_dir.rfind('/'));
    if (::access((root + "/daemons").c_str(), F_OK) == 0) return root;
  }
  return COOPNAV_BINARY_DIR;
}

Band straight(Eigen::Vector2d from, Eigen::Vector2d to, double duration_s, double dt_s) {
  Band b;
  const Eigen::Vector2d d = to - from;
  const int n = static_cast<int>(std::lround(duration_s / dt_s));
  for (int i = 0; i <= n; ++i) {
    const double t = i * dt_s;
    const Eigen::Vector2d p = from + d * (t / duration_s);
    b.poses.push_back({t, {p.x(), p.y(), std::atan2(d.y(), d.x())}});
  }
  return b;
}

/// Receives on one channel and remembers the last message's bytes.
struct Sink {
  std::vector<std::uint8_t> last;
  bool got{false};
  void onMessage(const lcm::ReceiveBuffer* rb, const std::string&) {
    const auto* p = static_cast<const std::uint8_t*>(rb->data);
    last.assign(p, p + rb->data_size);
    got = true;
  }
};

/// Publishes the bands (utime = id) and waits for the situation with that utime; [us] or < 0.
double assessRoundTrip(lcm::LCM& lcm, Sink& sink, bands_t bands, std::int64_t id) {
  bands.utime = id;
  const auto t0 = Clock::now();
  lcm.publish(channels::kBands, &bands);
  const auto end = t0 + std::chrono::seconds(2);
  while (Clock::now() < end) {
    sink.got = false;
    lcm.handleTimeout(100);
    if (!sink.got) continue;
    situation_t s;
    if (s.decode(sink.last.data(), 0, static_cast<int>(sink.last.size())) < 0) continue;
    if (s.utime == id) return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
  }
  return -1.0;
}

double echoRoundTrip(lcm::LCM& lcm, Sink& sink, const std::vector<std::uint8_t>& bytes) {
  const auto t0 = Clock::now();
  lcm.publish(kEchoReq, bytes.data(), static_cast<unsigned>(bytes.size()));
  const auto end = t0 + std::chrono::seconds(2);
  while (Clock::now() < end) {
    sink.got = false;
    lcm.handleTimeout(100);
    if (sink.got) return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
  }
  return -1.0;
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Goal inference on map_yaml: prints the set-up costs and the per-cycle cost of
/// GoalBelief::observe for 1 and 20 humans; returns the 20-human median [us per human].
double benchGoalInference(const std::string& map_yaml) {
  auto t0 = Clock::now();
  LoadedMap loaded = loadMap(map_yaml);
  const auto field = std::make_shared<GridDistanceField>(std::move(loaded.grid));
  std::printf("goal inference: map %s loaded in %.1f ms\n", map_yaml.c_str(), msSince(t0));
  t0 = Clock::now();
  std::vector<GoalRegion> goals = mapGoalCandidates(*field);
  const double candidates_ms = msSince(t0);
  const std::size_t from_map = goals.size();
  // open.pgm's hall has no dead end and no opening: the map's goal_regions (its corridors'
  // ends) supply the goals, as they do for the band source.
  for (const auto& r : loaded.goal_regions) goals.push_back({r.a, r.b});
  t0 = Clock::now();
  const auto distances = std::make_shared<GoalDistances>(field, goals);
  const double fields_ms = msSince(t0);
  std::printf(
      "goal inference: %zu map candidates in %.1f ms, %zu goals in all, distance fields in %.1f "
      "ms:",
      from_map, candidates_ms, goals.size(), fields_ms);
  for (const auto& g : goals) std::printf(" (%.2f, %.2f)", g.centre().x(), g.centre().y());
  std::printf("\n");

  constexpr int kCycles = 2000;
  constexpr double kDt_s = 0.1;
  double us_per_human_20 = 0.0;
  for (const int humans : {1, 20}) {
    // Walkers along the two corridors, both directions, spread along x.
    std::vector<GoalBelief> beliefs;
    std::vector<Eigen::Vector2d> start;
    std::vector<double> phase;
    for (int h = 0; h < humans; ++h) {
      beliefs.emplace_back(distances);
      start.emplace_back(14.0 + 0.9 * h, h % 2 == 0 ? 6.5 : 1.6);
      phase.push_back(0.7 * h);
    }
    std::vector<double> cycle_us;
    cycle_us.reserve(kCycles);
    int sink = 0;
    for (int c = 0; c < kCycles; ++c) {
      const double t = c * kDt_s;
      const auto c0 = Clock::now();
      for (int h = 0; h < humans; ++h) {
        // Walking back and forth along the corridor at up to 1 m/s (every step a real one).
        const double x = 4.0 * std::sin(0.25 * t + phase[h]);
        beliefs[h].observe(t, start[h] + Eigen::Vector2d(x, 0.0));
        sink += beliefs[h].mostLikely();
      }
      cycle_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - c0).count());
    }
    const double p50 = coopnav::bench::percentile(cycle_us, 0.5);
    const double p99 = coopnav::bench::percentile(cycle_us, 0.99);
    std::printf(
        "goal inference, %2d human(s), %zu goals: cycle p50 %.2f us, p99 %.2f us, %.3f us per "
        "human (checksum %d)\n",
        humans, goals.size(), p50, p99, p50 / humans, sink);
    if (humans == 20) us_per_human_20 = p50 / humans;
  }
  return us_per_human_20;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string build = buildDir();
  const std::string map = std::string(COOPNAV_SOURCE_DIR) + "/test/data/maps/open.yaml";
  std::printf("build dir %s, url %s\n", build.c_str(), kBenchUrl);
  // open.pgm with its corridor mouths annotated (the narrow paper scenario's map section).
  const double goal_us = benchGoalInference(std::string(COOPNAV_SOURCE_DIR) +
                                            "/config/scenarios/narrow_facilitating.yaml");
  if (argc > 1 && std::string(argv[1]) == "--goals-only") {  // no processes, no network
    std::printf("RESULT goal_inference_us_per_human %.3f\n", goal_us);
    return 0;
  }

  // One human crossing the robot in the bottom corridor of open.pgm, 10 s bands at 0.1 s.
  BandsSnapshot snap;
  snap.step = -1;
  snap.robot = straight({12.0, 1.5}, {22.0, 1.5}, 10.0, 0.1);
  snap.humans.emplace_back(1, straight({22.0, 1.9}, {12.0, 1.9}, 10.0, 0.1));
  const bands_t bands = toLcm(snap);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(bands.getEncodedSize()));
  bands.encode(bytes.data(), 0, static_cast<int>(bytes.size()));

  const pid_t echo = coopnav::bench::startEcho(kBenchUrl, kEchoReq, kEchoRep);
  const pid_t server = coopnav::bench::spawnProcess(
      {build + "/daemons/obstacle_distance_server/coopnav_obstacle_distance_server", "--lcm-url",
       kBenchUrl, "--set", "map_file=" + map, "--log-level", "warn"});
  const pid_t assessor = coopnav::bench::spawnProcess(
      {build + "/daemons/situation_assessor/coopnav_situation_assessor", "--lcm-url", kBenchUrl,
       "--log-level", "warn"});

  lcm::LCM lcm(kBenchUrl);
  if (!lcm.good()) {
    std::fprintf(stderr, "LCM unavailable at %s (multicast route?)\n", kBenchUrl);
    return 1;
  }
  Sink situations;
  Sink echoes;
  lcm.subscribe(channels::kSituation, &Sink::onMessage, &situations);
  lcm.subscribe(kEchoRep, &Sink::onMessage, &echoes);

  // Warm up until the assessor answers with distances known (the server has loaded its map).
  std::int64_t id = 1;
  bool ready = false;
  for (int i = 0; i < 200 && !ready; ++i) {
    if (assessRoundTrip(lcm, situations, bands, id++) < 0) continue;
    situation_t s;
    s.decode(situations.last.data(), 0, static_cast<int>(situations.last.size()));
    ready = !std::isnan(s.d_oh_m) && echoRoundTrip(lcm, echoes, bytes) >= 0;
  }
  if (!ready) std::fprintf(stderr, "warning: server/assessor/echo not ready after warm-up\n");

  std::vector<double> assess_us;
  std::vector<double> echo_us;
  int lost = 0;
  for (int round = 0; round < 20; ++round) {
    for (int i = 0; i < 25; ++i) {
      const double a = assessRoundTrip(lcm, situations, bands, id++);
      if (a < 0)
        ++lost;
      else
        assess_us.push_back(a);
    }
    for (int i = 0; i < 25; ++i) {
      const double e = echoRoundTrip(lcm, echoes, bytes);
      if (e < 0)
        ++lost;
      else
        echo_us.push_back(e);
    }
  }
  for (pid_t p : {assessor, server}) ::kill(p, SIGTERM);
  ::kill(echo, SIGKILL);
  for (pid_t p : {assessor, server, echo}) {
    int st = 0;
    ::waitpid(p, &st, 0);
  }

  const double a50 = coopnav::bench::percentile(assess_us, 0.5) / 1000.0;
  const double a99 = coopnav::bench::percentile(assess_us, 0.99) / 1000.0;
  const double e50 = coopnav::bench::percentile(echo_us, 0.5) / 1000.0;
  const double e99 = coopnav::bench::percentile(echo_us, 0.99) / 1000.0;
  std::printf("bands message %zu bytes (1 human, 2 x 101 poses); %zu + %zu samples, %d lost\n",
              bytes.size(), assess_us.size(), echo_us.size(), lost);
  std::printf("bands -> situation (assessor + distance server): p50 %.3f ms, p99 %.3f ms\n", a50,
              a99);
  std::printf("bare LCM echo of the same bytes:                 p50 %.3f ms, p99 %.3f ms\n", e50,
              e99);
  std::printf("ratio p50 %.2f, p99 %.2f\n", a50 / e50, a99 / e99);
  std::printf("RESULT assess_latency_p50_ms %.3f\n", a50);
  std::printf("RESULT assess_latency_p99_ms %.3f\n", a99);
  std::printf("RESULT assess_latency_ratio_vs_echo %.2f\n", a50 / e50);
  std::printf("RESULT goal_inference_us_per_human %.3f\n", goal_us);
  return lost > 0 && assess_us.empty() ? 1 : 0;
}
