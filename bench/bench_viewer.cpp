// The browser viewer serving one page (headless Chromium) of a 5-human scene at 10 Hz: frame
// latency, bus message -> frame drawn (the viewer notes when each scene utime arrived, the page
// acknowledges each frame it drew with its utime: /ack, /stats.json), and the viewer's CPU over
// wall time. The scene is synthetic: the robot and five people crossing the 6 m corridor of
// open.pgm, every channel the viewer draws at the pipeline's rates (agent states, bands of 60
// poses, situations, path assessments with growing CA windows at 10 Hz; reference paths and six
// daemon statuses at 1 Hz).
//
//   bench_viewer [--seconds 20] [--chromium /usr/bin/chromium]
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/channels.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"
// After Eigen: httplib.h brings <resolv.h>, whose `_res` macro breaks Eigen's headers after it.
#include <httplib.h>

namespace {

using Clock = std::chrono::steady_clock;
using namespace coopnav;

const std::string kSource = COOPNAV_SOURCE_DIR;
const std::string kBuild = COOPNAV_BINARY_DIR;
constexpr int kHumans = 5;
constexpr int kHttpPort = 9322;
const std::string kUrl = "udpm://239.255.76.67:9301?ttl=0&recv_buf_size=4194304";

/// Human i walks along the corridor (y 3.5-9.5 of open.pgm), either way.
Pose2 humanPose(int i, double t) {
  const double dir = i % 2 == 0 ? -1.0 : 1.0;
  const double x0 = dir < 0 ? 32.0 - 2.0 * i : 12.0 + 2.0 * i;
  return {x0 + dir * 0.8 * t, 4.5 + 1.0 * i, dir < 0 ? M_PI : 0.0};
}
Pose2 robotPose(double t) { return {11.0 + 0.5 * t, 6.5, 0.0}; }

struct Publisher {
  lcm::LCM& lcm;
  void tick(int k) {
    const double t = 0.1 * k;
    const std::int64_t utime = secondsToUtime(100.0 + t);
    AgentStatesSnapshot s;
    s.utime = utime;
    s.robot = {0, AgentKind::kRobot, robotPose(t), {0.5, 0.0, 0.0}, 0.34};
    for (int i = 0; i < kHumans; ++i)
      s.humans.push_back({i + 1, AgentKind::kHuman, humanPose(i, t), {0.8, 0.0, 0.0}, 0.3});
    const agent_states_t states = toLcm(s);
    lcm.publish(channels::kAgentStates, &states);

    BandsSnapshot b;
    b.utime = utime;
    b.robot_mode = velocity_command_t::MODE_NAVIGATING;
    for (int j = 0; j < 60; ++j) b.robot.poses.push_back({0.1 * j, robotPose(t + 0.1 * j)});
    for (int i = 0; i < kHumans; ++i) {
      Band hb;
      for (int j = 0; j < 60; ++j) hb.poses.push_back({0.1 * j, humanPose(i, t + 0.1 * j)});
      b.humans.emplace_back(i + 1, hb);
      b.room_plans.push_back(bands_t::ROOM_DOCK_HERE);
    }
    const bands_t bands = toLcm(b);
    lcm.publish(channels::kBands, &bands);

    for (int i = 0; i < kHumans; ++i) {
      const Pose2 h = humanPose(i, t + 3.0), r = robotPose(t + 3.0);
      situation_t m{};
      m.utime = utime;
      m.step = -1;
      m.human_id = i + 1;
      m.crossing_status = situation_t::CROSSING_OK;
      m.i_star = 60;
      m.t_cross_s = 3.0;
      m.cp_h_x_m = h.x_m;
      m.cp_h_y_m = h.y_m;
      m.cp_r_x_m = r.x_m;
      m.cp_r_y_m = r.y_m;
      m.dir = situation_t::DIR_LEFT;
      m.d_h_m = 0.2;
      m.d_oh_m = 0.8;
      m.d_or_m = 0.5;
      m.d_hr_m = std::hypot(h.x_m - r.x_m, h.y_m - r.y_m);
      m.human_needs_to_contribute = situation_t::PRED_FALSE;
      m.human_is_constrained = situation_t::PRED_TRUE;
      m.robot_is_constrained = situation_t::PRED_FALSE;
      m.tau_h_m = 0.3;
      m.tau_oh_m = 1.0;
      m.tau_or_m = 0.3;
      m.tau_hr_m = 1.2;
      m.reason = "";
      lcm.publish(channels::kSituation, &m);

      PathAssessmentRecord p;
      p.utime = utime;
      p.human_id = i + 1;
      p.snapshot.state = assessment::RecorderState::kRecording;
      for (int j = 0; j <= std::min(k, 100); ++j) p.window_ca_m.push_back(0.002 * j);
      p.snapshot.window_samples = p.window_ca_m.size();
      p.snapshot.cm_window_m = 0.1;
      p.snapshot.interaction_samples = p.window_ca_m.size();
      p.snapshot.cm_interaction_m = 0.1;
      const path_assessment_t pa = toLcm(p);
      lcm.publish(channels::kPathAssessment, &pa);
    }
    if (k % 10 == 0) {
      ReferencePaths refs;
      refs.utime = utime;
      for (int i = 0; i < kHumans; ++i) {
        const Pose2 a = humanPose(i, 0.0), z = humanPose(i, 30.0);
        refs.paths.push_back({i + 1, 1, {{a.x_m, a.y_m}, {z.x_m, z.y_m}}});
      }
      const reference_paths_t rp = toLcm(refs);
      lcm.publish(channels::kReferencePaths, &rp);
      for (const char* name : {"obstacle_distance_server", "band_source", "situation_assessor",
                               "path_assessor", "dialogue_manager", "world_sim"}) {
        daemon_status_t st{};
        // Statuses carry their sender's wall clock (the viewer checks it against its receive
        // clock and rejects a stamp far before it).
        st.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
        st.name = name;
        st.pid = 1;
        st.state = daemon_status_t::STATE_RUNNING;
        st.received = k;
        st.published = k;
        st.last_logic_utime = utime;
        st.cycle_p50_ms = 0.3;
        st.cycle_max_ms = 1.2;
        st.detail = "";
        lcm.publish(channels::kStatus, &st);
      }
    }
  }
};

void stop(pid_t pid) {
  if (pid <= 0) return;
  ::kill(pid, SIGTERM);
  int st = 0;
  for (int i = 0; i < 50; ++i) {
    if (::waitpid(pid, &st, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &st, 0);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 20.0;
  std::string chromium = "/usr/bin/chromium";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--seconds") seconds = std::stod(argv[i + 1]);
    if (a == "--chromium") chromium = argv[i + 1];
  }
  if (::access(chromium.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "bench_viewer: no Chromium at %s (--chromium PATH)\n", chromium.c_str());
    return 1;
  }
  const std::string log_dir = kBuild + "/bench_viewer_logs";
  std::filesystem::create_directories(log_dir);
  const pid_t viewer = bench::spawnProcess(
      {kBuild + "/daemons/viewer/coopnav_viewer", "-c", kSource + "/config/viewer.yaml",
       "--lcm-url", kUrl, "--set", "http_port=" + std::to_string(kHttpPort), "--set",
       "map_file=" + kSource + "/config/scenarios/open_minimal.yaml"},
      log_dir + "/viewer.log");
  httplib::Client http("127.0.0.1", kHttpPort);
  http.set_read_timeout(5, 0);
  bool up = false;
  for (int i = 0; i < 100 && !up; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    up = static_cast<bool>(http.Get("/scene.json"));
  }
  if (!up) {
    std::fprintf(stderr, "bench_viewer: the viewer did not come up (%s/viewer.log)\n",
                 log_dir.c_str());
    stop(viewer);
    return 1;
  }
  const std::string profile = log_dir + "/chromium-profile";
  std::filesystem::remove_all(profile);
  const pid_t browser = bench::spawnProcess(
      {chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
       "--window-size=1280,800", "--user-data-dir=" + profile,
       "http://127.0.0.1:" + std::to_string(kHttpPort) + "/"},
      log_dir + "/chromium.log");

  lcm::LCM lcm(kUrl);
  Publisher pub{lcm};
  const auto period = std::chrono::milliseconds(100);
  const int warm_ticks = 50;  // 5 s: the browser starts and the page loads
  const int ticks = warm_ticks + static_cast<int>(std::lround(seconds * 10.0));
  auto next = Clock::now();
  double cpu0 = 0.0;
  Clock::time_point t0;
  for (int k = 0; k < ticks; ++k) {
    if (k == warm_ticks) {
      http.Post("/stats/reset", "", "text/plain");
      cpu0 = bench::cpuSeconds(viewer);
      t0 = Clock::now();
    }
    pub.tick(k);
    next += period;
    std::this_thread::sleep_until(next);
  }
  const double cpu = bench::cpuSeconds(viewer) - cpu0;
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the last acks
  const auto stats = http.Get("/stats.json");
  stop(browser);
  stop(viewer);
  if (!stats) {
    std::fprintf(stderr, "bench_viewer: no /stats.json\n");
    return 1;
  }
  const nlohmann::json j = nlohmann::json::parse(stats->body);
  const nlohmann::json& lat = j["latency"];
  const auto num = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
  std::printf("viewer, one page (headless Chromium), %d humans at 10 Hz, %.1f s measured\n",
              kHumans, wall);
  std::printf("  frames sent %lld, frames drawn and acknowledged %lld (unmatched %lld)\n",
              j["frames"].get<long long>(), lat["n"].get<long long>(),
              lat["unmatched"].get<long long>());
  std::printf(
      "  frame latency (bus message -> frame drawn): p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
      num(lat["p50_ms"]), num(lat["p99_ms"]), num(lat["max_ms"]));
  std::printf("  viewer CPU %.2f s over %.1f s wall\n", cpu, wall);
  std::printf("RESULT viewer_frame_latency_p50_ms %.2f\n", num(lat["p50_ms"]));
  std::printf("RESULT viewer_frame_latency_p99_ms %.2f\n", num(lat["p99_ms"]));
  std::printf("RESULT viewer_cpu_fraction %.4f\n", cpu / wall);
  return 0;
}
