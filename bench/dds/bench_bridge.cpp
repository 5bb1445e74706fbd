// bench_bridge: latency through coopnav_ros2_bridge (the real daemon, its shipped config) beside
// a bare DDS round trip measured in the same run, all on the loopback interface
// (test/dds/cyclonedds_loopback.xml unless CYCLONEDDS_URI is set) in a DDS domain of its own and
// an LCM port of its own (ttl=0).
//   in:   /odom written (DDS) -> COOPNAV_AGENT_STATES heard (LCM)  [one DDS hop, the listener's
//   wake-up, one LCM hop] out:  COOPNAV_ROBOT_CMD published (LCM) -> /cmd_vel read (DDS)  [one LCM
//   hop, one DDS hop] bare: a Twist written -> echoed by a forked bare DDS process -> read back
//   (two DDS hops)
// Each sample is sent after the previous one arrived (ping-pong), so none queues, and after a
// random pause of 0-5 ms (seeded) so that it arrives at any phase of the bridge's timers (the
// watchdog, the status), as a robot's messages do. Figures: p50 and p99 [ms]; RESULT lines also
// give each bridge p50 over the bare round trip's p50.
#include <dds/dds.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "ros2_conversions.hpp"

namespace {

using namespace coopnav;
using Clock = std::chrono::steady_clock;
const std::string kSource = COOPNAV_SOURCE_DIR;
const std::string kBuild = COOPNAV_BINARY_DIR;
constexpr int kDomain = 73;
const std::string kUrl = "udpm://239.255.76.67:7699?ttl=0&recv_buf_size=4194304";

dds_entity_t endpoint(dds_entity_t pp, const char* name, const dds_topic_descriptor_t* desc,
                      bool reader) {
  const dds_entity_t topic = dds_create_topic(pp, desc, name, nullptr, nullptr);
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
  const dds_entity_t e =
      reader ? dds_create_reader(pp, topic, q, nullptr) : dds_create_writer(pp, topic, q, nullptr);
  dds_delete_qos(q);
  return e;
}

/// Waits on a DDS reader (waitset, no polling delay) until a Twist with linear.x == want is taken
/// or `timeout` passes.
bool awaitTwist(dds_entity_t ws, dds_entity_t reader, double want,
                std::chrono::milliseconds timeout) {
  const auto end = Clock::now() + timeout;
  while (Clock::now() < end) {
    dds_waitset_wait(ws, nullptr, 0, DDS_MSECS(50));
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    const dds_return_t n = dds_take(reader, samples, infos, 8, 8);
    bool hit = false;
    for (dds_return_t i = 0; i < n; ++i)
      hit = hit ||
            (infos[i].valid_data && static_cast<const ros2::Twist*>(samples[i])->linear.x == want);
    if (n > 0) dds_return_loan(reader, samples, n);
    if (hit) return true;
  }
  return false;
}

/// The bare echo: every Twist on rt/bench_ping is written back on rt/bench_pong.
[[noreturn]] void echoProcess() {
  const dds_entity_t pp = dds_create_participant(kDomain, nullptr, nullptr);
  const dds_entity_t rd = endpoint(pp, "rt/bench_ping", &geometry_msgs_msg_dds__Twist__desc, true);
  const dds_entity_t wr = endpoint(pp, "rt/bench_pong", &geometry_msgs_msg_dds__Twist__desc, false);
  const dds_entity_t ws = dds_create_waitset(pp);
  const dds_entity_t rc = dds_create_readcondition(rd, DDS_ANY_STATE);
  dds_waitset_attach(ws, rc, rd);
  for (;;) {
    dds_waitset_wait(ws, nullptr, 0, DDS_SECS(1));
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    const dds_return_t n = dds_take(rd, samples, infos, 8, 8);
    for (dds_return_t i = 0; i < n; ++i)
      if (infos[i].valid_data) dds_write(wr, samples[i]);
    if (n > 0) dds_return_loan(rd, samples, n);
  }
}

struct Stats {
  std::vector<double> ms;
  double p(double q) const { return bench::percentile(ms, q); }
};

}  // namespace

int main(int argc, char** argv) {
  int samples = 1000;
  for (int i = 1; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--samples") samples = std::atoi(argv[i + 1]);
  if (std::getenv("CYCLONEDDS_URI") == nullptr)
    ::setenv("CYCLONEDDS_URI", ("file://" + kSource + "/test/dds/cyclonedds_loopback.xml").c_str(),
             1);

  const std::string log_dir = kBuild + "/bench_bridge_logs";
  std::filesystem::create_directories(log_dir);
  const pid_t bridge = bench::spawnProcess({kBuild + "/daemons/ros2_bridge/coopnav_ros2_bridge",
                                            "-c", kSource + "/config/ros2_bridge.yaml", "--lcm-url",
                                            kUrl, "--set", "domain_id=" + std::to_string(kDomain)},
                                           log_dir + "/ros2_bridge.log");
  const pid_t echo = ::fork();
  if (echo == 0) echoProcess();

  lcm::LCM lcm(kUrl);
  const dds_entity_t pp = dds_create_participant(kDomain, nullptr, nullptr);
  const dds_entity_t odom_w = endpoint(pp, "rt/odom", &nav_msgs_msg_dds__Odometry__desc, false);
  const dds_entity_t cmd_r = endpoint(pp, "rt/cmd_vel", &geometry_msgs_msg_dds__Twist__desc, true);
  const dds_entity_t ping_w =
      endpoint(pp, "rt/bench_ping", &geometry_msgs_msg_dds__Twist__desc, false);
  const dds_entity_t pong_r =
      endpoint(pp, "rt/bench_pong", &geometry_msgs_msg_dds__Twist__desc, true);
  const dds_entity_t ws_cmd = dds_create_waitset(pp);
  dds_waitset_attach(ws_cmd, dds_create_readcondition(cmd_r, DDS_ANY_STATE), cmd_r);
  const dds_entity_t ws_pong = dds_create_waitset(pp);
  dds_waitset_attach(ws_pong, dds_create_readcondition(pong_r, DDS_ANY_STATE), pong_r);

  struct StatesWatch {
    std::int64_t last_utime{-1};
    void on(const lcm::ReceiveBuffer*, const std::string&, const agent_states_t* m) {
      last_utime = m->utime;
    }
  } watch;
  lcm.subscribe(channels::kAgentStates, &StatesWatch::on, &watch);

  char odom_frame[] = "odom";
  char base[] = "base_link";
  ros2::Odometry odom{};
  odom.header.frame_id = odom_frame;
  odom.child_frame_id = base;
  odom.pose.pose.orientation = ros2::quaternionOfYaw(0.0);
  auto sendOdom = [&](std::int64_t k) {
    odom.header.stamp = ros2::utimeToStamp(1'000'000 + k * 1000);
    dds_write(odom_w, &odom);
  };
  auto awaitStates = [&](std::int64_t k, std::chrono::milliseconds timeout) {
    const auto end = Clock::now() + timeout;
    while (Clock::now() < end) {
      lcm.handleTimeout(50);
      if (watch.last_utime == 1'000'000 + k * 1000) return true;
    }
    return false;
  };

  // Warm-up: until the bridge, the echo and discovery are up (each direction heard once).
  bool up = false;
  for (int i = 0; i < 200 && !up; ++i) {
    sendOdom(-1000 + i);
    up = awaitStates(-1000 + i, std::chrono::milliseconds(50));
  }
  bool out_up = false;
  for (int i = 0; i < 200 && up && !out_up; ++i) {
    velocity_command_t c{};
    c.vx_m_s = -1.0 - i;
    lcm.publish(channels::kRobotCmd, &c);
    out_up = awaitTwist(ws_cmd, cmd_r, c.vx_m_s, std::chrono::milliseconds(50));
  }
  bool echo_up = false;
  for (int i = 0; i < 200 && !echo_up; ++i) {
    ros2::Twist t{};
    t.linear.x = -1.0 - i;
    dds_write(ping_w, &t);
    echo_up = awaitTwist(ws_pong, pong_r, t.linear.x, std::chrono::milliseconds(50));
  }
  int rc = 0;
  if (!up || !out_up || !echo_up) {
    std::fprintf(stderr, "bench_bridge: not up (bridge in %d, out %d, echo %d); see %s\n", up,
                 out_up, echo_up, log_dir.c_str());
    rc = 1;
  } else {
    Stats in, out, bare;
    int lost = 0;
    std::mt19937 rng(1);
    std::uniform_int_distribution<int> pause_us(0, 5000);
    const auto pause = [&] {
      std::this_thread::sleep_for(std::chrono::microseconds(pause_us(rng)));
    };
    for (int k = 0; k < samples; ++k) {
      pause();
      auto t0 = Clock::now();
      sendOdom(k);
      if (awaitStates(k, std::chrono::milliseconds(500)))
        in.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      else
        ++lost;
      velocity_command_t c{};
      c.vx_m_s = 1.0 + k;
      pause();
      t0 = Clock::now();
      lcm.publish(channels::kRobotCmd, &c);
      if (awaitTwist(ws_cmd, cmd_r, c.vx_m_s, std::chrono::milliseconds(500)))
        out.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      else
        ++lost;
      ros2::Twist t{};
      t.linear.x = 1.0 + k;
      pause();
      t0 = Clock::now();
      dds_write(ping_w, &t);
      if (awaitTwist(ws_pong, pong_r, t.linear.x, std::chrono::milliseconds(500)))
        bare.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      else
        ++lost;
    }
    std::printf("bench_bridge: %d samples per path, %d lost\n", samples, lost);
    std::printf("  DDS in -> LCM out (/odom -> agent states):  p50 %.3f ms  p99 %.3f ms\n",
                in.p(0.5), in.p(0.99));
    std::printf("  LCM in -> DDS out (command -> /cmd_vel):    p50 %.3f ms  p99 %.3f ms\n",
                out.p(0.5), out.p(0.99));
    std::printf("  bare DDS round trip (two hops):             p50 %.3f ms  p99 %.3f ms\n",
                bare.p(0.5), bare.p(0.99));
    std::printf("RESULT bridge_dds_in_p50_ms %.3f\n", in.p(0.5));
    std::printf("RESULT bridge_dds_in_p99_ms %.3f\n", in.p(0.99));
    std::printf("RESULT bridge_dds_out_p50_ms %.3f\n", out.p(0.5));
    std::printf("RESULT bridge_dds_out_p99_ms %.3f\n", out.p(0.99));
    std::printf("RESULT bare_dds_round_trip_p50_ms %.3f\n", bare.p(0.5));
    std::printf("RESULT bare_dds_round_trip_p99_ms %.3f\n", bare.p(0.99));
    std::printf("RESULT bridge_in_over_bare_rtt %.2f\n", in.p(0.5) / bare.p(0.5));
    std::printf("RESULT bridge_out_over_bare_rtt %.2f\n", out.p(0.5) / bare.p(0.5));
    std::printf("RESULT bridge_lost %d\n", lost);
  }
  dds_delete(pp);
  for (pid_t p : {bridge, echo}) {
    ::kill(p, SIGTERM);
    int st = 0;
    ::waitpid(p, &st, 0);
  }
  return rc;
}
