// The hostile-input suite of docs/bad-inputs.md: every daemon as a real process on this
// executable's own udpm port, fed what a broken or malicious peer could send (bytes that are not
// the channel's type, non-finite and absurd numbers, arrays at and over their bounds, times that
// go backwards or jump, unknown ids) and started with corrupt maps and invalid configs. Each test
// checks the documented answer: the message counted as rejected or dropped in the daemon's status
// (every such message is also logged), a lockstep step still acknowledged, a reply that names the
// problem, or the exit code at start; and that the daemon goes on answering good input. The rows
// of the table name these tests; the node tests of each daemon cover the rest.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/band/band_config.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "messages.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kHuge = 1e300;  // finite, but no map or robot is that large
const std::string kMap = ::coopnav::test::testDataDir() + "/maps/open.yaml";

template <class Msg>
Bytes encode(const Msg& m) {
  Bytes b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

/// Five payloads no daemon may accept on a channel whose good message encodes to `good`: random
/// bytes, nothing, the good message truncated, the good message with trailing bytes, and a
/// well-formed message of another type (another LCM fingerprint).
std::vector<Bytes> hostilePayloads(const Bytes& good, const Bytes& other_type) {
  Bytes truncated(good.begin(), good.end() - 5);
  Bytes trailing = good;
  trailing.insert(trailing.end(), {0, 0, 0, 1});
  return {Bytes(37, 0xAB), Bytes{}, truncated, trailing, other_type};
}

step_ack_t someAck() {
  step_ack_t a{};
  a.utime = 1;
  a.step = 1;
  a.participant = "intruder";
  return a;
}
goals_t someGoals() {
  goals_t g{};
  g.utime = 1;
  return g;
}
/// A message of a type no daemon expects on `channel`.
Bytes otherTypeFor(const std::string& channel) {
  return channel == channels::kStepAck ? encode(someGoals()) : encode(someAck());
}

/// One daemon under test as a child process, and the probe that talks to it.
class Dut {
 public:
  Dut(const std::string& name, std::vector<std::string> args) : name_(name) {
    probe_.subscribe<daemon_status_t>(channels::kStatus,
                                      [this](const daemon_status_t& m, std::int64_t) {
                                        if (m.name == name_ && child_ && m.pid == child_->pid())
                                          status_ = m;
                                      });
    args.insert(args.begin(), {"--lcm-url", test::testLcmUrl(), "--log-level", "warn"});
    child_ = std::make_unique<test::ChildProcess>(test::daemonPath(name), args);
    ready_ = spinUntil([&] { return status_.has_value(); }, 20s);
  }

  bool ready() const { return ready_; }
  Runtime& probe() { return probe_; }
  test::ChildProcess& child() { return *child_; }

  bool spinUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout = 10s) {
    return test::waitFor(pred, timeout, [&] { probe_.spinFor(5); });
  }
  void settle(std::chrono::milliseconds d = 200ms) { probe_.spinFor(static_cast<int>(d.count())); }

  template <class Msg>
  void publish(const std::string& channel, const Msg& m) {
    probe_.publish(channel, m);
  }
  void publishRaw(const std::string& channel, const Bytes& b) {
    probe_.lcm().publish(channel, b.data(), static_cast<unsigned>(b.size()));
  }

  /// A status published after now (its counters include what was handled before).
  daemon_status_t freshStatus() {
    const std::int64_t now_us = std::chrono::duration_cast<std::chrono::microseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count();
    EXPECT_TRUE(spinUntil([&] { return status_ && status_->utime > now_us; }, 5s))
        << name_ << ": no fresh status";
    return *status_;
  }
  /// Waits until the status counts at least `rejected` / `dropped`, then one more status to see
  /// that nothing beyond was counted; returns that status.
  daemon_status_t countersReach(std::int64_t rejected, std::int64_t dropped = 0) {
    spinUntil(
        [&] { return status_ && status_->rejected >= rejected && status_->dropped >= dropped; },
        10s);
    return freshStatus();
  }

  /// Publishes the hostile payloads on `channel` (good = a valid message of its type) and checks
  /// that each is counted as rejected and nothing else happens to the counters.
  /// `subscriptions`: how many of the daemon's subscriptions receive the channel (each counts).
  void expectHostileBytesRejected(const std::string& channel, const Bytes& good,
                                  int subscriptions = 1) {
    SCOPED_TRACE(name_ + " on " + channel);
    const daemon_status_t before = freshStatus();
    const auto payloads = hostilePayloads(good, otherTypeFor(channel));
    for (const auto& p : payloads) publishRaw(channel, p);
    const auto n = static_cast<std::int64_t>(payloads.size()) * subscriptions;
    const daemon_status_t after = countersReach(before.rejected + n, before.dropped);
    EXPECT_EQ(after.rejected, before.rejected + n);
    EXPECT_EQ(after.dropped, before.dropped);
    EXPECT_TRUE(child_->running());
  }

 private:
  std::string name_;
  Runtime probe_{"bad_inputs_probe", test::testLcmUrl()};
  std::optional<daemon_status_t> status_;
  std::unique_ptr<test::ChildProcess> child_;
  bool ready_{false};
};

std::string tempPath(const std::string& file) { return (test::scratchDir() / file).string(); }

std::string writeFile(const std::string& name, const std::string& text) {
  std::string p = tempPath(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// ---------------------------------------------------------------------------------------------
// Start-up: invalid configs, command lines and corrupt maps (exit codes 2 and 3, every daemon)

/// Runs a daemon that must stop at start; returns its exit code (-1: still running after 20 s).
int exitCodeOf(const std::string& daemon, std::vector<std::string> args) {
  args.insert(args.begin(), {"--lcm-url", test::testLcmUrl(), "--log-level", "off"});
  test::ChildProcess p(test::daemonPath(daemon), args);
  return p.waitExit(20s);
}

/// What each daemon needs to start at all (a map or a scenario), and one numeric key of it.
struct DaemonStart {
  std::string name;
  std::vector<std::string> base_args;
  std::string numeric_key;
};

std::vector<DaemonStart> allDaemons() {
  const std::string scenario = ::coopnav::test::sourceDir() + "/config/scenarios/open_minimal.yaml";
  return {
      {"obstacle_distance_server", {"--set", "map_file=" + kMap}, "max_range_cap_m"},
      {"band_source", {"--set", "map_file=" + kMap}, "control_hz"},
      {"situation_assessor", {}, "tau_h_m"},
      {"path_assessor", {}, "gamma"},
      {"dialogue_manager", {}, "round1_t_cross_s"},
      {"world_sim", {"--set", "scenario=" + scenario}, "real_time_factor"},
  };
}

TEST(BadStart, InvalidConfigsExitTwoInEveryDaemon) {
  const std::string syntax = writeFile("syntax.yaml", "a: [1, 2\nb: {\n");
  const std::string not_map = writeFile("list.yaml", "- 1\n- 2\n");
  for (const auto& d : allDaemons()) {
    SCOPED_TRACE(d.name);
    auto with = [&](std::vector<std::string> extra) {
      auto a = d.base_args;
      a.insert(a.end(), extra.begin(), extra.end());
      return exitCodeOf(d.name, a);
    };
    EXPECT_EQ(with({"--config", "/nonexistent/coopnav.yaml"}), kExitUsage) << "missing file";
    EXPECT_EQ(with({"--config", syntax}), kExitUsage) << "YAML syntax error";
    EXPECT_EQ(with({"--config", not_map}), kExitUsage) << "not a mapping";
    EXPECT_EQ(with({"--set", d.numeric_key + "=1e9"}), kExitUsage) << "out of range";
    EXPECT_EQ(with({"--set", d.numeric_key + "=.nan"}), kExitUsage) << "NaN";
    EXPECT_EQ(with({"--set", d.numeric_key + "=-.inf"}), kExitUsage) << "-inf";
    EXPECT_EQ(with({"--set", d.numeric_key + "=fast"}), kExitUsage) << "wrong type";
    EXPECT_EQ(with({"--set", d.numeric_key + "=[1, 2]"}), kExitUsage) << "list for a scalar";
    EXPECT_EQ(with({"--set", "no_equals_sign"}), kExitUsage) << "malformed --set";
    EXPECT_EQ(with({"--no-such-option"}), kExitUsage) << "unknown option";
    EXPECT_EQ(with({"--log-level", "loud"}), kExitUsage) << "unknown log level";
  }
}

TEST(BadStart, UnusableLcmUrlExitsOne) {
  for (const auto& d : allDaemons()) {
    SCOPED_TRACE(d.name);
    auto a = d.base_args;
    a.insert(a.end(), {"--lcm-url", "nosuchprovider://x"});
    test::ChildProcess p(test::daemonPath(d.name), a);
    EXPECT_EQ(p.waitExit(20s), kExitRuntime);
  }
}

/// Map files that must stop a map-loading daemon at start with exit 3 (never a crash or a hang).
std::vector<std::pair<std::string, std::string>> corruptMaps() {
  const std::string meta =
      "resolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
      "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  writeFile("short.pgm", "P5\n10 10\n255\nshort");
  writeFile("huge.pgm", "P5\n2000000000 2000000000\n255\n\x01\x02");
  writeFile("negative.pgm", "P5\n-10 10\n255\n");
  writeFile("notpgm.pgm", "GIF89a this is not a PGM");
  writeFile("p2bad.pgm", "P2\n3 2\n255\n1 2 x 4 5 6\n");
  writeFile("maxval0.pgm", std::string("P5\n2 2\n0\n") + std::string(4, '\0'));
  writeFile("ok.pgm", std::string("P5\n4 4\n255\n") + std::string(16, '\xff'));
  return {
      {"missing file", tempPath("does_not_exist.yaml")},
      {"empty file", writeFile("empty.yaml", "")},
      {"yaml syntax", writeFile("syntax_map.yaml", "image: [x\n")},
      {"image missing", writeFile("noimage.yaml", "image: nothing_here.pgm\n" + meta)},
      {"truncated pgm", writeFile("short.yaml", "image: short.pgm\n" + meta)},
      {"absurd pgm size", writeFile("huge.yaml", "image: huge.pgm\n" + meta)},
      {"negative pgm size", writeFile("negative.yaml", "image: negative.pgm\n" + meta)},
      {"not a pgm", writeFile("notpgm.yaml", "image: notpgm.pgm\n" + meta)},
      {"bad P2 pixel", writeFile("p2bad.yaml", "image: p2bad.pgm\n" + meta)},
      {"pgm maxval 0", writeFile("maxval0.yaml", "image: maxval0.pgm\n" + meta)},
      {"negative resolution", writeFile("negres.yaml",
                                        "image: ok.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n"
                                        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")},
      {"NaN origin", writeFile("nanorigin.yaml",
                               "image: ok.pgm\nresolution: 0.05\norigin: [.nan, 0, 0]\n"
                               "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")},
      {"thresholds swapped", writeFile("thresh.yaml",
                                       "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                       "negate: 0\noccupied_thresh: 0.1\nfree_thresh: 0.9\n")},
      {"corrupt octomap", writeFile("corrupt.bt",
                                    "# Octomap OcTree binary file\nres 0.05\n"
                                    "size 99999999\ndata\n\x01\x02\x03")},
      {"walls with NaN", writeFile("walls.yaml",
                                   "walls:\n  - {x0_m: .nan, y0_m: 0, x1_m: 5, "
                                   "y1_m: 0}\n")},
  };
}

TEST(BadStart, CorruptMapsExitThreeInTheMapLoadingDaemons) {
  const auto maps = corruptMaps();
  for (const std::string daemon : {"obstacle_distance_server", "band_source"}) {
    for (const auto& [what, file] : maps) {
      SCOPED_TRACE(daemon + ": " + what);
      EXPECT_EQ(exitCodeOf(daemon, {"--set", "map_file=" + file}), kExitBadInput);
    }
  }
}

std::string scenarioWithMap(const std::string& tag, const std::string& map_file) {
  return writeFile(
      "scenario_" + tag + ".yaml",
      "name: bad_map\nseed: 1\ntime_limit_s: 5\nmap: {file: " + map_file +
          "}\nlockstep: {enabled: false}\nrobot:\n"
          "  start: {x_m: 6.5, y_m: 6.5, theta_rad: 0}\n  goal: {x_m: 20.5, y_m: 6.5}\n"
          "humans: []\n");
}

TEST(BadStart, CorruptScenarioMapsExitThreeInWorldSim) {
  {
    // The same scenario with a good map runs: exit 3 below is the map's doing.
    test::ChildProcess p(test::daemonPath("world_sim"),
                         {"--lcm-url", test::testLcmUrl(), "--log-level", "off", "--set",
                          "scenario=" + scenarioWithMap("good", kMap)});
    EXPECT_EQ(p.waitExit(1500ms), -1) << "the control scenario does not run";
  }
  int i = 0;
  for (const auto& [what, file] : corruptMaps()) {
    SCOPED_TRACE(what);
    const std::string scenario = scenarioWithMap(std::to_string(i++), file);
    EXPECT_EQ(exitCodeOf("world_sim", {"--set", "scenario=" + scenario}), kExitBadInput);
  }
}

// ---------------------------------------------------------------------------------------------
// obstacle_distance_server

class BadInputDistanceServer : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(dut_.ready()); }

  static distance_query_t query(std::int8_t kind, double x, double y, double nx = 1.0,
                                double ny = 0.0, double range_m = 5.0) {
    distance_query_t q{};
    q.kind = kind;
    q.px_m = x;
    q.py_m = y;
    q.nx = nx;
    q.ny = ny;
    q.max_range_m = range_m;
    return q;
  }
  static distance_request_t request(std::int64_t id, std::vector<distance_query_t> qs,
                                    const std::string& reply = "COOPNAV_DIST_REP_BAD_INPUTS") {
    distance_request_t r{};
    r.utime = 1;
    r.request_id = id;
    r.reply_channel = reply;
    r.queries = std::move(qs);
    r.num_queries = static_cast<std::int16_t>(r.queries.size());
    return r;
  }
  /// Sends and waits for the reply with this id (nothing within 3 s: nullopt).
  std::optional<distance_reply_t> ask(const distance_request_t& req) {
    std::optional<distance_reply_t> reply;
    if (!subscribed_.count(req.reply_channel)) {
      dut_.probe().subscribe<distance_reply_t>(
          req.reply_channel,
          [this](const distance_reply_t& r, std::int64_t) { replies_[r.request_id] = r; });
      subscribed_[req.reply_channel] = true;
    }
    dut_.publish(channels::kDistanceRequest, req);
    dut_.spinUntil([&] { return replies_.count(req.request_id) > 0; }, 3s);
    if (replies_.count(req.request_id)) reply = replies_[req.request_id];
    return reply;
  }

  Dut dut_{"obstacle_distance_server", {"--set", "map_file=" + kMap}};
  std::map<std::string, bool> subscribed_;
  std::map<std::int64_t, distance_reply_t> replies_;
};

TEST_F(BadInputDistanceServer, BytesThatAreNotARequestAreRejected) {
  dut_.expectHostileBytesRejected(
      channels::kDistanceRequest,
      encode(request(1, {query(distance_query_t::KIND_NEAREST, 10.0, 6.5)})));
  const auto r = ask(request(2, {query(distance_query_t::KIND_NEAREST, 10.0, 6.5)}));
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, distance_reply_t::STATUS_OK);
}

TEST_F(BadInputDistanceServer, ExactlyMaxQueriesAreAllAnswered) {
  std::vector<distance_query_t> qs(distance_request_t::MAX_QUERIES,
                                   query(distance_query_t::KIND_SIDE, 10.0, 6.5, 0.0, 1.0));
  const auto r = ask(request(3, qs));
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, distance_reply_t::STATUS_OK);
  EXPECT_EQ(r->num_results, distance_request_t::MAX_QUERIES);
}

TEST_F(BadInputDistanceServer, AbsurdQueriesAreAnsweredPerQueryAndTheRestOfTheBatchStands) {
  using Q = distance_query_t;
  const std::vector<distance_query_t> qs = {
      query(Q::KIND_NEAREST, kHuge, 6.5),              // 0 far outside the map
      query(Q::KIND_NEAREST, -kHuge, -kHuge),          // 1
      query(Q::KIND_SIDE, 10.0, 6.5, kHuge, kHuge),    // 2 huge normal
      query(Q::KIND_RAY, 10.0, 6.5, 1.0, 0.0, kHuge),  // 3 huge range: clamped
      query(Q::KIND_RAY, 10.0, 6.5, 0.0, 0.0),         // 4 zero direction
      query(Q::KIND_SIDE, 10.0, 6.5, kInf, 0.0),       // 5 infinite normal
      query(Q::KIND_SIDE, 10.0, 6.5, 0.0, 1.0, -1.0),  // 6 negative range
      query(7, 10.0, 6.5),                             // 7 unknown kind
      query(Q::KIND_RAY, kHuge, 6.5, -1.0, 0.0, 1e6),  // 8 ray from far outside
      query(Q::KIND_NEAREST, 10.0, 6.5),               // 9 good
  };
  const auto r = ask(request(4, qs));
  ASSERT_TRUE(r.has_value());
  ASSERT_EQ(r->status, distance_reply_t::STATUS_OK);
  ASSERT_EQ(r->num_results, static_cast<std::int16_t>(qs.size()));
  using R = distance_result_t;
  EXPECT_EQ(r->results[0].status, R::STATUS_OUTSIDE_MAP);
  EXPECT_EQ(r->results[1].status, R::STATUS_OUTSIDE_MAP);
  EXPECT_EQ(r->results[2].status, R::STATUS_INVALID_QUERY);  // its length overflows
  EXPECT_EQ(r->results[3].status, R::STATUS_OK);
  EXPECT_LE(r->results[3].distance_m, 1000.0);
  EXPECT_EQ(r->results[4].status, R::STATUS_INVALID_QUERY);
  EXPECT_EQ(r->results[5].status, R::STATUS_INVALID_QUERY);
  EXPECT_EQ(r->results[6].status, R::STATUS_INVALID_QUERY);
  EXPECT_EQ(r->results[7].status, R::STATUS_INVALID_QUERY);
  EXPECT_EQ(r->results[8].status, R::STATUS_OUTSIDE_MAP);
  EXPECT_EQ(r->results[9].status, R::STATUS_OK);
  for (const auto& res : r->results)
    EXPECT_FALSE(std::isnan(res.distance_m) && res.status == R::STATUS_OK);
}

TEST_F(BadInputDistanceServer, UnusableReplyChannelsAreRejectedWithoutAReply) {
  const daemon_status_t before = dut_.freshStatus();
  dut_.publish(channels::kDistanceRequest,
               request(5, {query(distance_query_t::KIND_NEAREST, 10.0, 6.5)}, ""));
  dut_.publish(
      channels::kDistanceRequest,
      request(6, {query(distance_query_t::KIND_NEAREST, 10.0, 6.5)}, std::string(64, 'X')));
  const daemon_status_t after = dut_.countersReach(before.rejected + 2);
  EXPECT_EQ(after.rejected, before.rejected + 2);
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputDistanceServer, TimeAndIdsAreEchoedNeverInterpreted) {
  // The server is stateless: a utime going backwards, a repeated request id and a negative id are
  // answered like any other request.
  auto a = request(-7, {query(distance_query_t::KIND_NEAREST, 10.0, 6.5)});
  a.utime = 5'000'000;
  auto r = ask(a);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, distance_reply_t::STATUS_OK);
  replies_.clear();
  a.utime = -5;
  r = ask(a);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->utime, -5);
  EXPECT_EQ(r->status, distance_reply_t::STATUS_OK);
}

// ---------------------------------------------------------------------------------------------
// band_source

constexpr std::int64_t kStart_us = 1'000'000'000;
constexpr std::int64_t kStep_us = 100'000;

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double th, double vx) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = th;
  a.vx_m_s = vx;
  a.radius_m = kind == agent_state_t::KIND_ROBOT ? 0.34 : 0.3;
  return a;
}

/// Robot and one human head-on in the 6 m corridor of open.pgm (as band_source_test).
agent_states_t corridorStates(std::int64_t step) {
  const double t = static_cast<double>(step) * 0.1;
  agent_states_t m{};
  m.utime = kStart_us + step * kStep_us;
  m.step = step;
  m.robot = agent(0, agent_state_t::KIND_ROBOT, 6.5 + 0.7 * t, 6.5, 0.0, 0.7);
  m.humans.push_back(agent(1, agent_state_t::KIND_HUMAN, 20.5 - t, 6.5, M_PI, -1.0));
  m.num_humans = 1;
  return m;
}

goals_t corridorGoals() {
  goals_t g{};
  g.utime = kStart_us;
  goal_t r{};
  r.agent_id = 0;
  r.kind = agent_state_t::KIND_ROBOT;
  r.x_m = 20.5;
  r.y_m = 6.5;
  goal_t h{};
  h.agent_id = 1;
  h.kind = agent_state_t::KIND_HUMAN;
  h.x_m = 6.5;
  h.y_m = 6.5;
  h.theta_rad = kNaN;
  g.goals = {r, h};
  g.num_goals = 2;
  return g;
}

class BadInputBandSource : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(dut_.ready());
    dut_.probe().subscribe<bands_t>(channels::kBands,
                                    [this](const bands_t& m, std::int64_t) { bands_[m.step] = m; });
    dut_.probe().subscribe<velocity_command_t>(
        channels::kRobotCmd,
        [this](const velocity_command_t& m, std::int64_t) { cmds_[m.step] = m; });
    dut_.probe().subscribe<step_ack_t>(channels::kStepAck,
                                       [this](const step_ack_t& m, std::int64_t) {
                                         if (m.participant == "band_source") acks_[m.step] = m;
                                       });
    dut_.publish(channels::kGoals, corridorGoals());
    dut_.settle(50ms);
  }
  /// Publishes a lockstep step and waits for its ack.
  bool step(const agent_states_t& m, std::chrono::milliseconds timeout = 20s) {
    dut_.publish(channels::kAgentStates, m);
    return dut_.spinUntil([&] { return acks_.count(m.step) > 0; }, timeout);
  }

  Dut dut_{"band_source", {"--set", "map_file=" + kMap, "--set", "step_gate_timeout_s=0.5"}};
  std::map<std::int64_t, bands_t> bands_;
  std::map<std::int64_t, velocity_command_t> cmds_;
  std::map<std::int64_t, step_ack_t> acks_;
};

TEST_F(BadInputBandSource, BytesThatAreNotTheirTypeAreRejectedOnEveryInput) {
  ASSERT_TRUE(step(corridorStates(0)));
  dut_.expectHostileBytesRejected(channels::kAgentStates, encode(corridorStates(1)));
  dut_.expectHostileBytesRejected(channels::kGoals, encode(corridorGoals()));
  robot_action_t a{};
  a.action = robot_action_t::ACTION_RESUME;
  a.human_id = 1;
  dut_.expectHostileBytesRejected(channels::kRobotAction, encode(a));
  step_ack_t ack{};
  ack.participant = "dialogue_manager";
  dut_.expectHostileBytesRejected(channels::kStepAck, encode(ack));
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_EQ(bands_.count(1), 1u);
}

TEST_F(BadInputBandSource, NonFiniteAndInvalidAgentsAreRejectedButAcknowledged) {
  const daemon_status_t before = dut_.freshStatus();
  std::int64_t k = 0;
  std::vector<std::function<void(agent_states_t&)>> faults = {
      [](agent_states_t& m) { m.humans[0].vx_m_s = kInf; },
      [](agent_states_t& m) { m.robot.theta_rad = -kInf; },
      [](agent_states_t& m) { m.humans[0].radius_m = 0.0; },
      [](agent_states_t& m) { m.robot.radius_m = kNaN; },
      [](agent_states_t& m) { m.humans[0].kind = 5; },
      [](agent_states_t& m) { m.humans[0].kind = agent_state_t::KIND_ROBOT; },
      [](agent_states_t& m) { m.robot.kind = agent_state_t::KIND_HUMAN; },
      [](agent_states_t& m) {
        m.humans.push_back(m.humans[0]);  // duplicate id
        m.num_humans = 2;
      },
  };
  for (const auto& f : faults) {
    auto m = corridorStates(k);
    f(m);
    ASSERT_TRUE(step(m)) << "fault " << k << " not acknowledged";
    EXPECT_EQ(bands_.count(k), 0u) << "fault " << k << " was planned";
    ++k;
  }
  ASSERT_TRUE(step(corridorStates(k)));
  EXPECT_EQ(bands_.count(k), 1u);
  const daemon_status_t after = dut_.countersReach(before.rejected + 8);
  EXPECT_EQ(after.rejected, before.rejected + 8);
}

TEST_F(BadInputBandSource, AbsurdPositionsGiveInvalidInputAndAZeroCommand) {
  auto robot_far = corridorStates(0);
  robot_far.robot.x_m = kHuge;
  ASSERT_TRUE(step(robot_far));
  ASSERT_EQ(bands_.count(0), 1u);
  EXPECT_EQ(bands_[0].status, bands_t::STATUS_INVALID_INPUT);
  ASSERT_EQ(cmds_.count(0), 1u);
  EXPECT_EQ(cmds_[0].vx_m_s, 0.0);
  EXPECT_EQ(cmds_[0].mode, velocity_command_t::MODE_STOPPED);

  auto human_far = corridorStates(1);  // a tracker glitch: the human somewhere absurd
  human_far.humans[0].x_m = -kHuge;
  human_far.humans[0].y_m = kHuge;
  ASSERT_TRUE(step(human_far));
  ASSERT_EQ(bands_.count(1), 1u);
  for (const auto& h : bands_[1].humans)
    for (const auto& p : h.poses) EXPECT_TRUE(std::isfinite(p.x_m) && std::isfinite(p.y_m));
  for (const auto& p : bands_[1].robot.poses)
    EXPECT_TRUE(std::isfinite(p.x_m) && std::abs(p.x_m) < 1000.0) << p.x_m;
  ASSERT_EQ(cmds_.count(1), 1u);
  EXPECT_TRUE(std::isfinite(cmds_[1].vx_m_s));
  EXPECT_LE(std::abs(cmds_[1].vx_m_s), 2.0);

  auto fast = corridorStates(2);  // absurd velocities
  fast.robot.vx_m_s = kHuge;
  fast.humans[0].vx_m_s = -kHuge;
  ASSERT_TRUE(step(fast));
  ASSERT_EQ(cmds_.count(2), 1u);
  EXPECT_TRUE(std::isfinite(cmds_[2].vx_m_s));
  EXPECT_LE(std::abs(cmds_[2].vx_m_s), 2.0);
  ASSERT_TRUE(step(corridorStates(3)));
  EXPECT_EQ(bands_[3].status, bands_t::STATUS_OK);
}

TEST_F(BadInputBandSource, ExactlyMaxHumansArePlannedUpToTheCapAndTheStepCompletes) {
  // 64 humans (the bound): before planner.max_planned_others one such cycle took minutes.
  auto crowd = corridorStates(0);
  crowd.humans.clear();
  for (int k = 0; k < 64; ++k) {
    crowd.humans.push_back(agent(k + 1, agent_state_t::KIND_HUMAN, 12.0 + 0.9 * (k % 8),
                                 4.2 + 0.7 * static_cast<double>(k / 8), M_PI, -1.0));
  }
  crowd.num_humans = 64;
  ASSERT_TRUE(step(crowd));
  ASSERT_EQ(bands_.count(0), 1u);
  EXPECT_EQ(bands_[0].status, bands_t::STATUS_OK);
  // Every human has a band: the nearest max_planned_others planned jointly (first), the others
  // predicted.
  ASSERT_EQ(bands_[0].num_humans, 64);
  // The nearest to the robot at (6.5, 6.5): the column at x = 12.0, around y = 6.5.
  for (int i = 0; i < 64; ++i) {
    const auto& h = bands_[0].humans[static_cast<std::size_t>(i)];
    ASSERT_FALSE(h.poses.empty());
    if (i < BandPlannerConfig{}.max_planned_others) {
      EXPECT_NEAR(h.poses[0].x_m, 12.0, 1e-6) << "human " << h.agent_id;
    }
  }
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_EQ(bands_[1].num_humans, 1);
}

TEST_F(BadInputBandSource, NoHumansArePlanned) {
  auto none = corridorStates(0);
  none.humans.clear();
  none.num_humans = 0;
  ASSERT_TRUE(step(none));
  ASSERT_EQ(bands_.count(0), 1u);
  EXPECT_EQ(bands_[0].status, bands_t::STATUS_OK);
  EXPECT_EQ(bands_[0].num_humans, 0);
}

TEST_F(BadInputBandSource, TimeGoingBackwardsIsDroppedAndAcknowledged) {
  ASSERT_TRUE(step(corridorStates(5)));
  const daemon_status_t before = dut_.freshStatus();
  auto back = corridorStates(6);
  back.utime = corridorStates(4).utime;  // next step, earlier time
  ASSERT_TRUE(step(back));
  EXPECT_EQ(bands_.count(6), 0u);
  ASSERT_TRUE(step(corridorStates(7)));
  EXPECT_EQ(bands_.count(7), 1u);
  const daemon_status_t after = dut_.countersReach(before.rejected, before.dropped + 1);
  EXPECT_EQ(after.dropped, before.dropped + 1);
  // Free-running: a utime going backwards is dropped the same way.
  auto f1 = corridorStates(20);
  f1.step = -1;
  auto f0 = corridorStates(10);
  f0.step = -1;
  dut_.publish(channels::kAgentStates, f1);
  dut_.spinUntil([&] { return bands_.count(-1) > 0; });
  dut_.publish(channels::kAgentStates, f0);
  const daemon_status_t later = dut_.countersReach(before.rejected, before.dropped + 2);
  EXPECT_EQ(later.dropped, before.dropped + 2);
  EXPECT_EQ(bands_[-1].utime, f1.utime);
}

TEST_F(BadInputBandSource, TimeJumpingFarAheadIsRejectedUntilTimeResyncMessagesAgree) {
  const int resync = InputLimits{}.time_resync_messages;
  ASSERT_TRUE(step(corridorStates(0)));
  const daemon_status_t before = dut_.freshStatus();
  // ~32 years later from step 1 on: the clock does not move for the first messages (rejected,
  // acknowledged, not planned), and follows once time_resync_messages of them agree.
  constexpr std::int64_t kJump_us = 1'000'000'000'000'000LL;
  for (std::int64_t k = 1; k <= resync + 1; ++k) {
    auto jump = corridorStates(k);
    jump.utime += kJump_us;
    ASSERT_TRUE(step(jump, 10s)) << "step " << k;
    EXPECT_EQ(bands_.count(k), k < resync ? 0u : 1u) << "step " << k;
  }
  const daemon_status_t after = dut_.countersReach(before.rejected + resync - 1);
  EXPECT_EQ(after.rejected, before.rejected + resync - 1);
  EXPECT_EQ(after.dropped, before.dropped);
}

TEST_F(BadInputBandSource, ExtremeTimestampsNeverCrashOrHang) {
  // Free-running from the lowest time to the highest: the throttle's time difference must not
  // overflow (UBSan aborts on it); the second is too far from the first to move the clock.
  auto low = corridorStates(0);
  low.step = -1;
  low.utime = std::numeric_limits<std::int64_t>::min();
  dut_.publish(channels::kAgentStates, low);
  ASSERT_TRUE(dut_.spinUntil([&] { return bands_.count(-1) > 0; }));
  const daemon_status_t before = dut_.freshStatus();
  auto high = corridorStates(1);
  high.step = -1;
  high.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kAgentStates, high);
  EXPECT_EQ(dut_.countersReach(before.rejected + 1).rejected, before.rejected + 1);
  EXPECT_EQ(bands_[-1].utime, low.utime);
  // Lockstep at normal times after that: rejected (acknowledged) until time_resync_messages of
  // them agree, then planned.
  const int resync = InputLimits{}.time_resync_messages;
  for (std::int64_t k = 2; k < 2 + resync; ++k) {
    ASSERT_TRUE(step(corridorStates(k)));
    EXPECT_EQ(bands_.count(k), k < 1 + resync ? 0u : 1u) << "step " << k;
  }
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputBandSource, AFirstMessageStampedInt64MaxThenNormalTrafficGetsCommandsAgain) {
  // The probe: free-running, one agent-states message stamped INT64_MAX (it sets the
  // clock: nothing came before it), then normal traffic 0.1 s apart. The daemon follows the
  // normal time after time_resync_messages of it; before, every later message was dropped.
  const int resync = InputLimits{}.time_resync_messages;
  auto high = corridorStates(0);
  high.step = -1;
  high.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kAgentStates, high);
  dut_.settle(100ms);
  std::vector<std::int64_t> commanded;  // indices of the normal messages with a command
  for (int i = 0; i < 10; ++i) {
    auto m = corridorStates(i);
    m.step = -1;
    dut_.publish(channels::kAgentStates, m);
    dut_.spinUntil([&] { return cmds_.count(-1) > 0 && cmds_[-1].utime == m.utime; },
                   i + 1 < resync ? 300ms : 10s);
    if (cmds_.count(-1) > 0 && cmds_[-1].utime == m.utime) commanded.push_back(i);
  }
  ASSERT_FALSE(commanded.empty()) << "no velocity command after the INT64_MAX message";
  EXPECT_EQ(commanded.front(), resync - 1) << "the first normal message followed";
  EXPECT_EQ(commanded.size(), 10u - static_cast<std::size_t>(resync - 1));
  EXPECT_GT(cmds_[-1].vx_m_s, 0.0);
}

TEST_F(BadInputBandSource, AMessageStampedInt64MaxAmidNormalTrafficIsRejectedAndIgnored) {
  ASSERT_TRUE(step(corridorStates(0)));
  const daemon_status_t before = dut_.freshStatus();
  auto high = corridorStates(1);
  high.utime = std::numeric_limits<std::int64_t>::max();
  ASSERT_TRUE(step(high));
  EXPECT_EQ(bands_.count(1), 0u);
  ASSERT_TRUE(step(corridorStates(2)));  // planned at once: the clock never moved
  EXPECT_EQ(bands_.count(2), 1u);
  EXPECT_GT(cmds_[2].vx_m_s, 0.0);
  const daemon_status_t after = dut_.countersReach(before.rejected + 1);
  EXPECT_EQ(after.rejected, before.rejected + 1);
  EXPECT_EQ(after.dropped, before.dropped);
}

TEST_F(BadInputBandSource, GoalsStampedInt64MaxNeverPinTheGoals) {
  // The robot's band ends towards its goal: ahead of it (x 20.5) or behind it (x 3.0).
  auto bandEnd_m = [&](std::int64_t k) { return bands_.at(k).robot.poses.back().x_m; };
  ASSERT_TRUE(step(corridorStates(0)));
  // Goals stamped INT64_MAX sending the robot back: rejected (before, every later goal was
  // "older" and ignored for good).
  auto back = corridorGoals();
  back.utime = std::numeric_limits<std::int64_t>::max();
  back.goals[0].x_m = 3.0;
  dut_.publish(channels::kGoals, back);
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_GT(bandEnd_m(1), 6.5) << "the INT64_MAX goal was taken";
  auto later = back;  // the same goal at normal time: taken
  later.utime = corridorStates(2).utime;
  dut_.publish(channels::kGoals, later);
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(2)));
  EXPECT_LT(bandEnd_m(2), 6.5) << "the later goal was not taken";
}

TEST_F(BadInputBandSource, BadGoalsAreRejectedAndThePreviousGoalsStay) {
  ASSERT_TRUE(step(corridorStates(0)));
  const daemon_status_t before = dut_.freshStatus();
  std::vector<std::function<void(goals_t&)>> faults = {
      [](goals_t& g) { g.goals[0].x_m = kNaN; },
      [](goals_t& g) { g.goals[1].y_m = kInf; },
      [](goals_t& g) { g.goals[1].agent_id = 0; },  // duplicate id
      [](goals_t& g) { g.goals[0].kind = 9; },
      [](goals_t& g) {  // over MAX_GOALS
        while (g.goals.size() <= static_cast<std::size_t>(goals_t::MAX_GOALS)) {
          g.goals.push_back(g.goals[1]);
          g.goals.back().agent_id = static_cast<std::int32_t>(g.goals.size());
        }
        g.num_goals = static_cast<std::int16_t>(g.goals.size());
      },
  };
  for (const auto& f : faults) {
    auto g = corridorGoals();
    f(g);
    dut_.publish(channels::kGoals, g);
  }
  const daemon_status_t after = dut_.countersReach(before.rejected + 5);
  EXPECT_EQ(after.rejected, before.rejected + 5);
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_EQ(bands_[1].status, bands_t::STATUS_OK);
  EXPECT_GT(cmds_[1].vx_m_s, 0.0) << "still driving to the previous goal";
}

TEST_F(BadInputBandSource, UnreachableGoalsStopTheRobotAndAGoodGoalRestartsIt) {
  auto g = corridorGoals();
  g.goals[0].x_m = kHuge;  // outside the map
  dut_.publish(channels::kGoals, g);
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(0)));
  EXPECT_NE(bands_[0].status, bands_t::STATUS_OK);
  EXPECT_EQ(cmds_[0].vx_m_s, 0.0);
  g.goals[0].x_m = 3.0;  // inside the wall of the outer corridor (y 6.5 is free, y 0 is wall)
  g.goals[0].y_m = 0.0;
  dut_.publish(channels::kGoals, g);
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_NE(bands_[1].status, bands_t::STATUS_OK);
  EXPECT_EQ(cmds_[1].vx_m_s, 0.0);
  dut_.publish(channels::kGoals, corridorGoals());
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(2)));
  EXPECT_EQ(bands_[2].status, bands_t::STATUS_OK);
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputBandSource, UnknownActionsAreRejectedAndADockForAnUnknownHumanIsIgnored) {
  ASSERT_TRUE(step(corridorStates(0)));
  const daemon_status_t before = dut_.freshStatus();
  robot_action_t bad{};
  bad.utime = corridorStates(0).utime;
  bad.step = 0;
  bad.action = 42;
  bad.human_id = 1;
  dut_.publish(channels::kRobotAction, bad);
  bad.action = robot_action_t::ACTION_DOCK;
  bad.step = -7;  // a step below -1
  dut_.publish(channels::kRobotAction, bad);
  const daemon_status_t after = dut_.countersReach(before.rejected + 2);
  EXPECT_EQ(after.rejected, before.rejected + 2);
  robot_action_t ghost{};
  ghost.utime = corridorStates(0).utime;
  ghost.step = 0;
  ghost.action = robot_action_t::ACTION_DOCK;
  ghost.human_id = 999;
  dut_.publish(channels::kRobotAction, ghost);
  dut_.settle(50ms);
  ASSERT_TRUE(step(corridorStates(1)));
  EXPECT_EQ(cmds_[1].mode, velocity_command_t::MODE_NAVIGATING) << "docked for a ghost";
}

TEST_F(BadInputBandSource, AcksFromStrangersOrTheFarFutureDoNotReorderSteps) {
  ASSERT_TRUE(step(corridorStates(0)));
  step_ack_t a{};
  a.utime = 0;
  a.step = 5;
  a.participant = "someone_else";
  dut_.publish(channels::kStepAck, a);
  a.participant = "";
  dut_.publish(channels::kStepAck, a);
  a.participant = std::string(500, 'p');
  dut_.publish(channels::kStepAck, a);
  ASSERT_TRUE(step(corridorStates(1)));
  ASSERT_TRUE(step(corridorStates(2)));
  EXPECT_EQ(bands_.count(2), 1u);
  EXPECT_TRUE(dut_.child().running());
}

// ---------------------------------------------------------------------------------------------
// situation_assessor (with a real distance server)

/// `n` poses `dt_s` apart.
band_t straightBand(std::int32_t id, std::int8_t kind, double x0, double y0, double x1, double y1,
                    int n, double dt_s) {
  return hostile::straightBand(id, kind, x0, y0, x1, y1, n, (n > 1 ? n - 1 : 0) * dt_s);
}

/// Bottom corridor of open.pgm, as situation_assessor_test: robot +x, human -x, 0.4 m apart.
bands_t corridorBands(std::int64_t step) {
  bands_t m{};
  m.utime = kStart_us + step * kStep_us;
  m.step = step;
  m.status = bands_t::STATUS_OK;
  m.robot = straightBand(0, agent_state_t::KIND_ROBOT, 12.0, 1.5, 20.0, 1.5, 17, 0.5);
  m.humans.push_back(straightBand(1, agent_state_t::KIND_HUMAN, 20.0, 1.9, 12.0, 1.9, 21, 0.4));
  m.num_humans = 1;
  m.room_plans.assign(1, bands_t::ROOM_UNKNOWN);
  return m;
}

reference_paths_t corridorReference(std::int32_t revision = 1) {
  reference_paths_t r{};
  r.utime = kStart_us;
  r.step = -1;
  path_t p{};
  p.agent_id = 1;
  p.x_m = {20.0, 12.0};
  p.y_m = {2.3, 2.3};
  p.num_points = 2;
  r.paths = {p};
  r.revision = {revision};
  r.num_paths = 1;
  return r;
}

class BadInputSituationAssessor : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new test::ChildProcess(
        test::daemonPath("obstacle_distance_server"),
        {"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap, "--log-level", "warn"});
  }
  static void TearDownTestSuite() { delete server_; }

  void SetUp() override {
    ASSERT_TRUE(dut_.ready());
    dut_.probe().subscribe<situation_t>(channels::kSituation,
                                        [this](const situation_t& m, std::int64_t) {
                                          situations_[{m.step, m.human_id}] = m;
                                        });
    dut_.probe().subscribe<step_ack_t>(channels::kStepAck,
                                       [this](const step_ack_t& m, std::int64_t) {
                                         if (m.participant == "situation_assessor")
                                           acks_.push_back(m.step);
                                       });
    dut_.publish(channels::kReferencePaths, corridorReference());
    dut_.settle(50ms);
  }
  bool acked(std::int64_t step) const {
    return std::find(acks_.begin(), acks_.end(), step) != acks_.end();
  }
  bool step(const bands_t& m) {
    dut_.publish(channels::kBands, m);
    return dut_.spinUntil([&] { return acked(m.step); });
  }
  const situation_t* sit(std::int64_t step, std::int32_t id) const {
    const auto it = situations_.find({step, id});
    return it == situations_.end() ? nullptr : &it->second;
  }

  static test::ChildProcess* server_;
  Dut dut_{"situation_assessor", {}};
  std::map<std::pair<std::int64_t, std::int32_t>, situation_t> situations_;
  std::vector<std::int64_t> acks_;
};
test::ChildProcess* BadInputSituationAssessor::server_ = nullptr;

TEST_F(BadInputSituationAssessor, BytesThatAreNotTheirTypeAreRejectedOnEveryInput) {
  ASSERT_TRUE(step(corridorBands(0)));
  dut_.expectHostileBytesRejected(channels::kBands, encode(corridorBands(1)));
  dut_.expectHostileBytesRejected(channels::kReferencePaths, encode(corridorReference()));
  distance_reply_t rep{};
  rep.request_id = 1;
  const std::string reply_channel = std::string(channels::kDistanceReplyPrefix) +
                                    "situation_assessor_" + std::to_string(dut_.child().pid());
  dut_.expectHostileBytesRejected(reply_channel, encode(rep));
  ASSERT_TRUE(step(corridorBands(1)));
  ASSERT_NE(sit(1, 1), nullptr);
  EXPECT_EQ(sit(1, 1)->crossing_status, situation_t::CROSSING_OK);
}

TEST_F(BadInputSituationAssessor, BandsAtTheirBoundsAreAssessedAndOverThemRejectedButAcked) {
  auto at = corridorBands(0);  // MAX_POSES poses, MAX_HUMANS humans
  at.robot =
      straightBand(0, agent_state_t::KIND_ROBOT, 12.0, 1.5, 20.0, 1.5, band_t::MAX_POSES, 0.004);
  at.humans.clear();
  for (int i = 0; i < bands_t::MAX_HUMANS; ++i)
    at.humans.push_back(
        straightBand(i + 1, agent_state_t::KIND_HUMAN, 20.0, 1.9, 12.0, 1.9, 21, 0.4));
  at.num_humans = bands_t::MAX_HUMANS;
  at.room_plans.assign(bands_t::MAX_HUMANS, bands_t::ROOM_UNKNOWN);
  ASSERT_TRUE(step(at));
  for (int i = 1; i <= bands_t::MAX_HUMANS; ++i) EXPECT_NE(sit(0, i), nullptr) << i;

  const daemon_status_t before = dut_.freshStatus();
  auto poses_over = corridorBands(1);
  poses_over.robot = straightBand(0, agent_state_t::KIND_ROBOT, 12.0, 1.5, 20.0, 1.5,
                                  band_t::MAX_POSES + 1, 0.004);
  ASSERT_TRUE(step(poses_over));
  auto humans_over = corridorBands(2);
  while (humans_over.humans.size() <= static_cast<std::size_t>(bands_t::MAX_HUMANS)) {
    humans_over.humans.push_back(humans_over.humans[0]);
    humans_over.humans.back().agent_id = static_cast<std::int32_t>(humans_over.humans.size());
  }
  humans_over.num_humans = static_cast<std::int16_t>(humans_over.humans.size());
  humans_over.room_plans.assign(humans_over.humans.size(), bands_t::ROOM_UNKNOWN);
  ASSERT_TRUE(step(humans_over));
  EXPECT_EQ(sit(1, 1), nullptr);
  EXPECT_EQ(sit(2, 1), nullptr);
  const daemon_status_t after = dut_.countersReach(before.rejected + 2);
  EXPECT_EQ(after.rejected, before.rejected + 2);
}

TEST_F(BadInputSituationAssessor, EmptyNonFiniteAndBackwardsBandsAreUnknownNeverGarbage) {
  std::vector<std::pair<std::string, std::function<void(bands_t&)>>> faults = {
      {"empty human band",
       [](bands_t& m) {
         m.humans[0].poses.clear();
         m.humans[0].num_poses = 0;
       }},
      {"one-pose human band",
       [](bands_t& m) {
         m.humans[0].poses.resize(1);
         m.humans[0].num_poses = 1;
       }},
      {"infinite pose", [](bands_t& m) { m.humans[0].poses[3].y_m = kInf; }},
      {"NaN time", [](bands_t& m) { m.humans[0].poses[3].t_s = kNaN; }},
      {"time going backwards", [](bands_t& m) { m.humans[0].poses[5].t_s = 0.1; }},
      {"all poses at t = 0",
       [](bands_t& m) {
         for (auto& p : m.humans[0].poses) p.t_s = 0.0;
       }},
      {"absurd coordinates",
       [](bands_t& m) {
         for (auto& p : m.humans[0].poses) p.x_m = kHuge;
       }},
  };
  std::int64_t k = 0;
  for (const auto& [what, f] : faults) {
    SCOPED_TRACE(what);
    auto m = corridorBands(k);
    f(m);
    ASSERT_TRUE(step(m));
    const situation_t* s = sit(k, 1);
    ASSERT_NE(s, nullptr);
    if (what == "absurd coordinates") {
      // A crossing may not exist: whatever the status, nothing is claimed on a far-away human.
      EXPECT_NE(s->human_needs_to_contribute, situation_t::PRED_TRUE);
      EXPECT_NE(s->robot_is_constrained, situation_t::PRED_TRUE);
    } else {
      EXPECT_EQ(s->crossing_status, situation_t::CROSSING_BAD_BANDS);
      EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_UNKNOWN);
      EXPECT_EQ(s->human_is_constrained, situation_t::PRED_UNKNOWN);
      EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN);
      EXPECT_FALSE(s->reason.empty());
    }
    ++k;
  }
  ASSERT_TRUE(step(corridorBands(k)));
  EXPECT_EQ(sit(k, 1)->crossing_status, situation_t::CROSSING_OK);
}

TEST_F(BadInputSituationAssessor, StepsAndTimesGoingBackwardsAreAssessedInArrivalOrder) {
  // The assessor keeps no time state of its own: every bands message is assessed on its own and
  // acknowledged; ordering is the world simulator's and the dialogue manager's business.
  ASSERT_TRUE(step(corridorBands(5)));
  auto back = corridorBands(3);
  ASSERT_TRUE(step(back));
  ASSERT_NE(sit(3, 1), nullptr);
  auto jump = corridorBands(6);
  jump.utime += 1'000'000'000'000'000LL;
  ASSERT_TRUE(step(jump));
  ASSERT_NE(sit(6, 1), nullptr);
  EXPECT_EQ(sit(6, 1)->crossing_status, situation_t::CROSSING_OK);
}

TEST_F(BadInputSituationAssessor, BadReferencePathsAreRejectedAndTheStoredOnesStay) {
  ASSERT_TRUE(step(corridorBands(0)));
  const double d_h_before = sit(0, 1)->d_h_m;
  const daemon_status_t before = dut_.freshStatus();
  std::vector<std::function<void(reference_paths_t&)>> faults = {
      [](reference_paths_t& r) { r.paths[0].x_m[1] = kNaN; },
      [](reference_paths_t& r) { r.paths[0].y_m[0] = -kInf; },
      [](reference_paths_t& r) {  // over MAX_POINTS
        r.paths[0].x_m.assign(path_t::MAX_POINTS + 1, 15.0);
        r.paths[0].y_m.assign(path_t::MAX_POINTS + 1, 2.3);
        r.paths[0].num_points = path_t::MAX_POINTS + 1;
      },
      [](reference_paths_t& r) {  // over MAX_PATHS
        while (r.paths.size() <= static_cast<std::size_t>(reference_paths_t::MAX_PATHS)) {
          r.paths.push_back(r.paths[0]);
          r.revision.push_back(1);
        }
        r.num_paths = static_cast<std::int16_t>(r.paths.size());
      },
  };
  for (const auto& f : faults) {
    auto r = corridorReference(2);
    f(r);
    dut_.publish(channels::kReferencePaths, r);
  }
  const daemon_status_t after = dut_.countersReach(before.rejected + 4);
  EXPECT_EQ(after.rejected, before.rejected + 4);
  ASSERT_TRUE(step(corridorBands(1)));
  EXPECT_DOUBLE_EQ(sit(1, 1)->d_h_m, d_h_before) << "a rejected path replaced the stored one";
  // A path for an id without a band is kept and harmless; a band without a path is unknown.
  auto other = corridorReference();
  other.paths[0].agent_id = 77;
  dut_.publish(channels::kReferencePaths, other);
  auto two = corridorBands(2);
  two.humans.push_back(two.humans[0]);
  two.humans.back().agent_id = 5;
  two.num_humans = 2;
  two.room_plans.assign(2, bands_t::ROOM_UNKNOWN);
  ASSERT_TRUE(step(two));
  EXPECT_EQ(sit(2, 5)->crossing_status, situation_t::CROSSING_NO_REFERENCE);
  EXPECT_EQ(sit(2, 5)->human_needs_to_contribute, situation_t::PRED_UNKNOWN);
}

TEST_F(BadInputSituationAssessor, ForgedDistanceRepliesAreDroppedOrTreatedAsServerErrors) {
  ASSERT_TRUE(step(corridorBands(0)));
  const daemon_status_t before = dut_.freshStatus();
  const std::string reply_channel = std::string(channels::kDistanceReplyPrefix) +
                                    "situation_assessor_" + std::to_string(dut_.child().pid());
  distance_reply_t forged{};
  forged.request_id = 123456789;  // nobody asked
  forged.status = distance_reply_t::STATUS_OK;
  dut_.publish(reply_channel, forged);
  const daemon_status_t after = dut_.countersReach(before.rejected, before.dropped + 1);
  EXPECT_EQ(after.dropped, before.dropped + 1);
  ASSERT_TRUE(step(corridorBands(1)));
  EXPECT_EQ(sit(1, 1)->crossing_status, situation_t::CROSSING_OK);
}

// ---------------------------------------------------------------------------------------------
// path_assessor

std::int64_t paUtime(std::int64_t step) { return 5'000'000 + step * 100'000; }

agent_states_t paStates(std::int64_t step) {
  agent_states_t m{};
  m.utime = paUtime(step);
  m.step = step;
  const double t = 0.1 * static_cast<double>(step);
  m.robot = agent(0, agent_state_t::KIND_ROBOT, 1.0 + 0.8 * t, 5.4, 0.0, 0.8);
  m.humans.push_back(agent(1, agent_state_t::KIND_HUMAN, 9.0 - 0.8 * t, 4.8, M_PI, -0.8));
  m.num_humans = 1;
  return m;
}

reference_paths_t paReference() {
  reference_paths_t r{};
  r.utime = paUtime(0);
  r.step = -1;
  path_t p{};
  p.agent_id = 1;
  p.x_m = {10.0, 0.0};
  p.y_m = {5.0, 5.0};
  p.num_points = 2;
  r.paths = {p};
  r.revision = {1};
  r.num_paths = 1;
  return r;
}

path_assessor_control_t paControl(std::int64_t step, std::int8_t command, std::int32_t id = 1) {
  path_assessor_control_t c{};
  c.utime = paUtime(step);
  c.step = step;
  c.human_id = id;
  c.command = command;
  c.reason = "bad_inputs_test";
  return c;
}

class BadInputPathAssessor : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(dut_.ready());
    dut_.probe().subscribe<path_assessment_t>(channels::kPathAssessment,
                                              [this](const path_assessment_t& m, std::int64_t) {
                                                published_[{m.step, m.human_id}] = m;
                                              });
    dut_.probe().subscribe<step_ack_t>(channels::kStepAck,
                                       [this](const step_ack_t& m, std::int64_t) {
                                         if (m.participant == "path_assessor")
                                           acks_.push_back(m.step);
                                       });
    dut_.publish(channels::kReferencePaths, paReference());
    dut_.settle(50ms);
  }
  bool acked(std::int64_t step) const {
    return std::find(acks_.begin(), acks_.end(), step) != acks_.end();
  }
  bool step(const agent_states_t& m, std::chrono::milliseconds timeout = 10s) {
    dut_.publish(channels::kAgentStates, m);
    return dut_.spinUntil([&] { return acked(m.step); }, timeout);
  }
  const path_assessment_t* at(std::int64_t step, std::int32_t id) const {
    const auto it = published_.find({step, id});
    return it == published_.end() ? nullptr : &it->second;
  }
  /// Steps 0..n-1 with the recorder of human 1 started at step 0.
  void record(std::int64_t n) {
    ASSERT_TRUE(step(paStates(0)));
    dut_.publish(channels::kPathAssessorControl,
                 paControl(0, path_assessor_control_t::COMMAND_START));
    dut_.settle(50ms);
    for (std::int64_t k = 1; k < n; ++k) ASSERT_TRUE(step(paStates(k)));
    ASSERT_EQ(at(n - 1, 1)->recording, path_assessment_t::REC_RECORDING);
  }

  Dut dut_{"path_assessor", {}};
  std::map<std::pair<std::int64_t, std::int32_t>, path_assessment_t> published_;
  std::vector<std::int64_t> acks_;
};

TEST_F(BadInputPathAssessor, BytesThatAreNotTheirTypeAreRejectedOnEveryInput) {
  ASSERT_TRUE(step(paStates(0)));
  dut_.expectHostileBytesRejected(channels::kAgentStates, encode(paStates(1)));
  dut_.expectHostileBytesRejected(channels::kReferencePaths, encode(paReference()));
  dut_.expectHostileBytesRejected(channels::kPathAssessorControl,
                                  encode(paControl(0, path_assessor_control_t::COMMAND_START)));
  step_ack_t ack{};
  ack.participant = "dialogue_manager";
  dut_.expectHostileBytesRejected(channels::kStepAck, encode(ack));
  ASSERT_TRUE(step(paStates(1)));
  EXPECT_NE(at(1, 1), nullptr);
}

TEST_F(BadInputPathAssessor, TimeGoingBackwardsIsIgnoredAndTheAssessmentStillPublished) {
  record(5);
  const auto samples = at(4, 1)->num_samples;
  auto back = paStates(5);
  back.utime = paUtime(2);
  back.humans[0].y_m = -50.0;  // would be a huge contribution if it were taken
  ASSERT_TRUE(step(back));
  ASSERT_NE(at(5, 1), nullptr);
  EXPECT_EQ(at(5, 1)->num_samples, samples);
  EXPECT_DOUBLE_EQ(at(5, 1)->cm_m, at(4, 1)->cm_m);
  ASSERT_TRUE(step(paStates(6)));
  EXPECT_GT(at(6, 1)->num_samples, samples);
}

TEST_F(BadInputPathAssessor, TimeJumpingFarAheadIsRejectedWithoutAHang) {
  record(5);
  auto jump = paStates(5);
  jump.utime += 1'000'000'000'000'000LL;  // ~32 years: 10^10 samples at 10 Hz if interpolated
  ASSERT_TRUE(step(jump, 5s)) << "a jump of the clock hung the path assessor";
  // Beyond limits.max_time_jump_s: rejected (its step acknowledged), nothing assessed.
  EXPECT_EQ(at(5, 1), nullptr);
  ASSERT_TRUE(step(paStates(6), 5s));
  ASSERT_NE(at(6, 1), nullptr);
  EXPECT_EQ(at(6, 1)->recording, path_assessment_t::REC_RECORDING);
}

TEST_F(BadInputPathAssessor, ExtremeTimestampsNeverCrashOrHang) {
  record(3);
  auto lowest = paStates(3);
  lowest.utime = std::numeric_limits<std::int64_t>::min();
  ASSERT_TRUE(step(lowest, 5s));
  auto control = paControl(3, path_assessor_control_t::COMMAND_RESET);
  control.utime = std::numeric_limits<std::int64_t>::min();
  dut_.publish(channels::kPathAssessorControl, control);
  auto highest = paStates(4);
  highest.utime = std::numeric_limits<std::int64_t>::max();
  ASSERT_TRUE(step(highest, 5s));
  control.utime = std::numeric_limits<std::int64_t>::max();
  control.command = path_assessor_control_t::COMMAND_STOP;
  dut_.publish(channels::kPathAssessorControl, control);
  ASSERT_TRUE(step(paStates(5), 5s));
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputPathAssessor, ControlsStampedFarFromTheDataNeverHang) {
  ASSERT_TRUE(step(paStates(0)));
  auto start_past = paControl(0, path_assessor_control_t::COMMAND_START);
  start_past.utime = paUtime(0) - 1'000'000'000'000'000LL;
  dut_.publish(channels::kPathAssessorControl, start_past);
  dut_.settle(50ms);
  ASSERT_TRUE(step(paStates(1), 5s));
  auto start_future = paControl(1, path_assessor_control_t::COMMAND_START);
  start_future.utime = paUtime(1) + 1'000'000'000'000'000LL;
  dut_.publish(channels::kPathAssessorControl, start_future);
  auto reset_future = paControl(1, path_assessor_control_t::COMMAND_RESET);
  reset_future.utime = start_future.utime;
  dut_.publish(channels::kPathAssessorControl, reset_future);
  dut_.settle(50ms);
  ASSERT_TRUE(step(paStates(2), 5s));
  ASSERT_TRUE(step(paStates(3), 5s));
  ASSERT_NE(at(3, 1), nullptr);
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputPathAssessor, BadReferencePathsAreRejectedAndAnEmptyOneKeepsThePrevious) {
  record(3);
  const daemon_status_t before = dut_.freshStatus();
  auto nan = paReference();
  nan.paths[0].y_m[0] = kNaN;
  dut_.publish(channels::kReferencePaths, nan);
  auto over = paReference();
  over.paths[0].x_m.assign(path_t::MAX_POINTS + 1, 1.0);
  over.paths[0].y_m.assign(path_t::MAX_POINTS + 1, 5.0);
  over.paths[0].num_points = path_t::MAX_POINTS + 1;
  dut_.publish(channels::kReferencePaths, over);
  const daemon_status_t after = dut_.countersReach(before.rejected + 2);
  EXPECT_EQ(after.rejected, before.rejected + 2);
  auto empty = paReference();
  empty.paths[0].x_m.clear();
  empty.paths[0].y_m.clear();
  empty.paths[0].num_points = 0;
  dut_.publish(channels::kReferencePaths, empty);
  dut_.settle(50ms);
  ASSERT_TRUE(step(paStates(3)));
  ASSERT_TRUE(step(paStates(4)));
  EXPECT_EQ(at(4, 1)->recording, path_assessment_t::REC_RECORDING);
  EXPECT_TRUE(std::isfinite(at(4, 1)->cm_m));
}

TEST_F(BadInputPathAssessor, ExactlyMaxHumansAreAssessedAndOverIsRejectedButAcked) {
  auto crowd = paStates(0);
  crowd.humans.clear();
  for (int i = 0; i < agent_states_t::MAX_HUMANS; ++i)
    crowd.humans.push_back(agent(i + 1, agent_state_t::KIND_HUMAN, 5.0 + 0.1 * i, 4.0, M_PI, -0.8));
  crowd.num_humans = agent_states_t::MAX_HUMANS;
  ASSERT_TRUE(step(crowd));
  for (int i = 1; i <= agent_states_t::MAX_HUMANS; ++i) EXPECT_NE(at(0, i), nullptr) << i;
  auto over = crowd;
  over.step = 1;
  over.utime = paUtime(1);
  over.humans.push_back(agent(99, agent_state_t::KIND_HUMAN, 1.0, 1.0, 0.0, 0.0));
  over.num_humans = static_cast<std::int16_t>(over.humans.size());
  ASSERT_TRUE(step(over));
  EXPECT_EQ(at(1, 1), nullptr);
}

// ---------------------------------------------------------------------------------------------
// dialogue_manager (the test plays both assessors; lockstep)

situation_t dmSituation(std::int64_t step, std::int32_t id, double t_cross_s) {
  return hostile::situation(1'000'000 + step * 100'000, step, id, t_cross_s, "");
}

path_assessment_t dmPath(std::int64_t step, std::int32_t id, double cm_m) {
  path_assessment_t m{};
  m.utime = 1'000'000 + step * 100'000;
  m.step = step;
  m.human_id = id;
  m.recording = path_assessment_t::REC_RECORDING;
  m.window_samples = 10;
  m.cm_m = cm_m;
  m.is_contributing = situation_t::PRED_FALSE;
  m.interaction_samples = 10;
  m.cm_interaction_m = cm_m;
  m.is_contributing_interaction = situation_t::PRED_FALSE;
  m.gamma = 0.98;
  m.profile = "paper";
  m.tau_m = 0.4;
  return m;
}

class BadInputDialogueManager : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(dut_.ready());
    dut_.probe().subscribe<utterance_t>(
        channels::kUtterance,
        [this](const utterance_t& m, std::int64_t) { utterances_.push_back(m); });
    dut_.probe().subscribe<robot_action_t>(
        channels::kRobotAction,
        [this](const robot_action_t& m, std::int64_t) { actions_.push_back(m); });
    dut_.probe().subscribe<step_ack_t>(channels::kStepAck,
                                       [this](const step_ack_t& m, std::int64_t) {
                                         if (m.participant == "dialogue_manager")
                                           acks_.push_back(m.step);
                                       });
  }
  void ackBoth(std::int64_t step) {
    for (const char* who : {"path_assessor", "situation_assessor"}) {
      step_ack_t a{};
      a.utime = 1'000'000 + step * 100'000;
      a.step = step;
      a.participant = who;
      dut_.publish(channels::kStepAck, a);
    }
  }
  bool acked(std::int64_t step) const {
    return std::find(acks_.begin(), acks_.end(), step) != acks_.end();
  }
  bool finishStep(std::int64_t step) {
    ackBoth(step);
    return dut_.spinUntil([&] { return acked(step); }, 5s);
  }

  Dut dut_{"dialogue_manager", {"--set", "round2_response_s=0"}};  // the paper's round 2 timing
  std::vector<utterance_t> utterances_;
  std::vector<robot_action_t> actions_;
  std::vector<std::int64_t> acks_;
};

TEST_F(BadInputDialogueManager, BytesThatAreNotTheirTypeAreRejectedOnEveryInput) {
  ASSERT_TRUE(finishStep(0));
  dut_.expectHostileBytesRejected(channels::kSituation, encode(dmSituation(1, 1, 9.0)));
  dut_.expectHostileBytesRejected(channels::kPathAssessment, encode(dmPath(1, 1, 0.0)));
  dut_.expectHostileBytesRejected(channels::kAgentStates, encode(paStates(1)));
  step_ack_t ack{};
  ack.participant = "path_assessor";
  // Acks feed both the step gate and the node (a step with no input still runs): two counts.
  dut_.expectHostileBytesRejected(channels::kStepAck, encode(ack), 2);
  dut_.publish(channels::kSituation, dmSituation(1, 1, 6.9));
  ASSERT_TRUE(finishStep(1));
  EXPECT_EQ(utterances_.size(), 1u);
}

TEST_F(BadInputDialogueManager, AnAckOfAStepFarAheadIsRefusedAndTheRunGoesOn) {
  ASSERT_TRUE(finishStep(0));
  const daemon_status_t before = dut_.freshStatus();
  step_ack_t forged{};
  forged.utime = 1'000'000;
  forged.step = std::int64_t{1} << 50;  // one ack must not become the newest step
  forged.participant = "situation_assessor";
  dut_.publish(channels::kStepAck, forged);
  dut_.countersReach(before.rejected + 1);
  dut_.publish(channels::kSituation, dmSituation(1, 1, 6.9));
  ASSERT_TRUE(finishStep(1));
  EXPECT_EQ(utterances_.size(), 1u) << "the real step 1 was taken for one going backwards";
}

TEST_F(BadInputDialogueManager, ImpossibleNumbersAreRejectedAndNeverSpokenOrDockedOn) {
  ASSERT_TRUE(finishStep(0));
  const daemon_status_t before = dut_.freshStatus();
  std::vector<situation_t> sits;
  auto s = dmSituation(1, 1, kInf);  // infinite t_CROSS
  sits.push_back(s);
  s = dmSituation(1, 2, -3.0);  // negative t_CROSS
  sits.push_back(s);
  s = dmSituation(1, 3, 6.9);
  s.d_h_m = -1.0;  // negative distance
  sits.push_back(s);
  s = dmSituation(1, 4, 6.9);
  s.d_hr_m = -kInf;
  sits.push_back(s);
  s = dmSituation(1, 5, 6.9);
  s.step = -9;  // a step below -1
  sits.push_back(s);
  for (const auto& m : sits) dut_.publish(channels::kSituation, m);
  std::vector<path_assessment_t> paths;
  auto p = dmPath(1, 1, 0.1);
  p.num_samples = path_assessment_t::MAX_SAMPLES + 1;  // over the bound
  p.ca_m.assign(static_cast<std::size_t>(p.num_samples), 0.1);
  paths.push_back(p);
  p = dmPath(1, 2, kNaN);  // NaN CM while samples are claimed
  paths.push_back(p);
  p = dmPath(1, 3, 0.1);
  p.gamma = 0.0;
  paths.push_back(p);
  p = dmPath(1, 4, 0.1);
  p.is_contributing = 7;
  paths.push_back(p);
  for (const auto& m : paths) dut_.publish(channels::kPathAssessment, m);
  auto nan_states = paStates(1);
  nan_states.step = 1;
  nan_states.humans[0].x_m = kNaN;
  dut_.publish(channels::kAgentStates, nan_states);
  ASSERT_TRUE(finishStep(1));
  EXPECT_TRUE(utterances_.empty());
  EXPECT_TRUE(actions_.empty());
  const daemon_status_t after = dut_.countersReach(before.rejected + 10);
  EXPECT_EQ(after.rejected, before.rejected + 10);
  dut_.publish(channels::kSituation, dmSituation(2, 6, 6.9));
  ASSERT_TRUE(finishStep(2));
  EXPECT_EQ(utterances_.size(), 1u);
}

TEST_F(BadInputDialogueManager, ExtremeTimestampsNeverCrashOrDecide) {
  ASSERT_TRUE(finishStep(0));
  auto st = paStates(1);
  st.utime = std::numeric_limits<std::int64_t>::min();
  dut_.publish(channels::kAgentStates, st);
  auto sit = dmSituation(1, 1, 9.0);
  sit.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kSituation, sit);
  ASSERT_TRUE(finishStep(1));
  st = paStates(2);
  st.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kAgentStates, st);
  ASSERT_TRUE(finishStep(2));
  st.utime = std::numeric_limits<std::int64_t>::min();
  st.step = 3;
  dut_.publish(channels::kAgentStates, st);
  ASSERT_TRUE(finishStep(3));
  EXPECT_TRUE(dut_.child().running());
}

TEST_F(BadInputDialogueManager, ASituationStampedInt64MaxFirstIsFollowedOutOfAndDecisionsResume) {
  // The probe, free-running: the first situation is stamped INT64_MAX (it sets the
  // clock: nothing came before it), then situations at normal time with t_CROSS falling from 9 s
  // by 0.2 s. The daemon follows their time after time_resync_messages, so round 1 speaks when
  // t_CROSS reaches 7 s (the 11th); before, its times stayed pinned at INT64_MAX.
  auto first = dmSituation(0, 1, 9.0);
  first.step = -1;
  first.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kSituation, first);
  dut_.settle(100ms);
  std::int64_t round1_utime = 0;
  for (int i = 0; i < 16; ++i) {
    auto s = dmSituation(i, 1, 9.0 - 0.2 * i);
    s.step = -1;
    if (round1_utime == 0 && s.t_cross_s <= 7.0) round1_utime = s.utime;  // round1_t_cross_s
    dut_.publish(channels::kSituation, s);
    dut_.settle(30ms);
  }
  ASSERT_TRUE(dut_.spinUntil([&] { return !utterances_.empty(); }, 5s)) << "no decision resumed";
  EXPECT_EQ(utterances_.size(), 1u);
  EXPECT_EQ(utterances_[0].utime, round1_utime);
  EXPECT_EQ(utterances_[0].round, 1);
}

TEST_F(BadInputDialogueManager, ASituationStampedInt64MaxAmidNormalTrafficIsRejected) {
  ASSERT_TRUE(finishStep(0));
  dut_.publish(channels::kSituation, dmSituation(1, 1, 9.5));
  ASSERT_TRUE(finishStep(1));
  const daemon_status_t before = dut_.freshStatus();
  auto high = dmSituation(2, 1, 6.9);
  high.utime = std::numeric_limits<std::int64_t>::max();
  dut_.publish(channels::kSituation, high);
  ASSERT_TRUE(finishStep(2));
  EXPECT_TRUE(utterances_.empty()) << "decided on a situation stamped INT64_MAX";
  dut_.publish(channels::kSituation, dmSituation(3, 1, 6.9));
  ASSERT_TRUE(finishStep(3));
  ASSERT_EQ(utterances_.size(), 1u) << "the next situation was not decided at once";
  EXPECT_EQ(utterances_[0].step, 3);
  const daemon_status_t after = dut_.countersReach(before.rejected + 1);
  EXPECT_EQ(after.rejected, before.rejected + 1);
}

TEST_F(BadInputDialogueManager, AssessmentsOfUnknownHumansDecideNothing) {
  ASSERT_TRUE(finishStep(0));
  // A path assessment of a human no situation ever named, and agent states of other people.
  dut_.publish(channels::kPathAssessment, dmPath(1, 4242, 0.0));
  auto states = paStates(1);
  states.humans[0].id = 31337;
  dut_.publish(channels::kAgentStates, states);
  ASSERT_TRUE(finishStep(1));
  EXPECT_TRUE(utterances_.empty());
  EXPECT_TRUE(actions_.empty());
}

TEST_F(BadInputDialogueManager, AClockJumpWithoutTheHumanNeverStallsOrThanks) {
  ASSERT_TRUE(finishStep(0));
  auto st = paStates(1);
  st.utime = 1'000'000 + 100'000;
  dut_.publish(channels::kAgentStates, st);
  dut_.publish(channels::kSituation, dmSituation(1, 1, 6.9));
  ASSERT_TRUE(finishStep(1));
  ASSERT_EQ(utterances_.size(), 1u);
  const daemon_status_t before = dut_.freshStatus();
  // The tracker's clock jumps 32 years ahead and the human is missing from that message: it is
  // rejected (limits.max_time_jump_s), so the human is not taken for gone 32 years.
  auto jump = paStates(2);
  jump.utime += 1'000'000'000'000'000LL;
  jump.humans.clear();
  jump.num_humans = 0;
  dut_.publish(channels::kAgentStates, jump);
  dut_.publish(channels::kSituation, dmSituation(2, 1, 3.9));
  dut_.publish(channels::kPathAssessment, dmPath(2, 1, 0.0));
  ASSERT_TRUE(finishStep(2));
  // Round 2 decides on the situations (the human did not move: a dock), and the dock stands.
  for (const auto& u : utterances_) EXPECT_NE(u.speech_act, utterance_t::ACT_THANK);
  ASSERT_EQ(actions_.size(), 1u);
  EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
  const daemon_status_t after = dut_.countersReach(before.rejected + 1);
  EXPECT_EQ(after.rejected, before.rejected + 1);
  EXPECT_TRUE(dut_.child().running());
}

// ---------------------------------------------------------------------------------------------
// world_sim (real time, long time limit; the test sends what the pipeline would)

std::string longScenario() {
  return writeFile("long_scenario.yaml",
                   "name: bad_inputs\nseed: 1\ntime_limit_s: 600\nmap:\n  walls:\n"
                   "    - {x0_m: -1, y0_m: 0, x1_m: 16, y1_m: 0}\n"
                   "    - {x0_m: -1, y0_m: 6, x1_m: 16, y1_m: 6}\n"
                   "rates: {physics_hz: 20, publish_hz: 10, real_time_factor: 1}\n"
                   "lockstep: {enabled: false}\n"
                   "robot:\n  start: {x_m: 1, y_m: 3, theta_rad: 0}\n  goal: {x_m: 14, y_m: 3}\n"
                   "humans:\n  - id: 1\n    start: {x_m: 14, y_m: 1.5, theta_rad: 3.14159}\n"
                   "    goal: {x_m: 0.5, y_m: 1.5}\n    behaviour: responsive\n"
                   "    speed_m_s: 0.2\n");
}

class BadInputWorldSim : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(dut_.ready());
    dut_.probe().subscribe<agent_states_t>(
        channels::kAgentStates,
        [this](const agent_states_t& m, std::int64_t) { states_.push_back(m); });
    ASSERT_TRUE(dut_.spinUntil([&] { return !states_.empty(); }));
  }
  /// Waits for `n` more agent-states messages; true if they came and are all finite.
  bool moreFiniteStates(std::size_t n = 5) {
    const std::size_t from = states_.size();
    if (!dut_.spinUntil([&] { return states_.size() >= from + n; }, 10s)) return false;
    for (std::size_t i = from; i < states_.size(); ++i) {
      const auto& s = states_[i];
      if (!std::isfinite(s.robot.x_m) || !std::isfinite(s.robot.y_m)) return false;
      for (const auto& h : s.humans)
        if (!std::isfinite(h.x_m) || !std::isfinite(h.y_m)) return false;
    }
    return true;
  }
  velocity_command_t command(double vx, double vy, double omega) const {
    velocity_command_t c{};
    c.utime = states_.back().utime;
    c.step = -1;
    c.vx_m_s = vx;
    c.vy_m_s = vy;
    c.omega_rad_s = omega;
    c.mode = velocity_command_t::MODE_NAVIGATING;
    return c;
  }

  Dut dut_{"world_sim", {"--set", "scenario=" + longScenario(), "--set", "mode=real_time"}};
  std::vector<agent_states_t> states_;
};

TEST_F(BadInputWorldSim, BytesThatAreNotTheirTypeAreRejectedOnEveryInput) {
  dut_.expectHostileBytesRejected(channels::kRobotCmd, encode(command(0.1, 0.0, 0.0)));
  utterance_t u{};
  u.speech_act = utterance_t::ACT_THANK;
  u.human_id = 1;
  dut_.expectHostileBytesRejected(channels::kUtterance, encode(u));
  dut_.expectHostileBytesRejected(channels::kBands, encode(corridorBands(0)));
  // (Acks are subscribed in lockstep only; the status channel always: participants' readiness.)
  daemon_status_t st{};
  st.name = "band_source";
  dut_.expectHostileBytesRejected(channels::kStatus, encode(st));
  EXPECT_TRUE(moreFiniteStates());
}

TEST_F(BadInputWorldSim, NonFiniteCommandsAreRejectedAndAbsurdOnesClampedToTheLimits) {
  const daemon_status_t before = dut_.freshStatus();
  dut_.publish(channels::kRobotCmd, command(kNaN, 0.0, 0.0));
  dut_.publish(channels::kRobotCmd, command(0.0, kInf, 0.0));
  dut_.publish(channels::kRobotCmd, command(0.0, 0.0, -kInf));
  const daemon_status_t after = dut_.countersReach(before.rejected + 3);
  EXPECT_EQ(after.rejected, before.rejected + 3);
  ASSERT_TRUE(moreFiniteStates());
  // A finite but absurd command: the robot moves no faster than its limits allow.
  dut_.publish(channels::kRobotCmd, command(kHuge, -kHuge, kHuge));
  ASSERT_TRUE(moreFiniteStates(10));
  const auto& a = states_[states_.size() - 2];
  const auto& b = states_.back();
  const double dt_s = static_cast<double>(b.utime - a.utime) * 1e-6;
  ASSERT_GT(dt_s, 0.0);
  const double speed_m_s = std::hypot(b.robot.x_m - a.robot.x_m, b.robot.y_m - a.robot.y_m) / dt_s;
  EXPECT_LT(speed_m_s, 3.0) << "the robot was not clamped";
}

TEST_F(BadInputWorldSim, BadBandsAndUtterancesAreRejectedOrDroppedAndTheRunGoesOn) {
  const daemon_status_t before = dut_.freshStatus();
  auto b = corridorBands(-1);
  b.step = -1;
  b.robot.poses[2].x_m = kNaN;
  dut_.publish(channels::kBands, b);
  b = corridorBands(-1);
  b.step = -1;
  b.robot =
      straightBand(0, agent_state_t::KIND_ROBOT, 1.0, 3.0, 2.0, 3.0, band_t::MAX_POSES + 1, 0.01);
  dut_.publish(channels::kBands, b);
  utterance_t u{};
  u.utime = states_.back().utime;
  u.step = -1;
  u.human_id = 1;
  u.round = 1;
  u.delivery = utterance_t::DELIVERY_SAID;
  u.speech_act = 99;
  dut_.publish(channels::kUtterance, u);
  u.speech_act = utterance_t::ACT_ASK_TO_MOVE;
  u.direction = 3;
  dut_.publish(channels::kUtterance, u);
  u.direction = situation_t::DIR_UNDEFINED;  // ask to move, but to no side
  dut_.publish(channels::kUtterance, u);
  u.direction = situation_t::DIR_LEFT;
  u.delivery = 9;
  dut_.publish(channels::kUtterance, u);
  u.delivery = utterance_t::DELIVERY_SAID;
  u.speech_duration_s = std::nan("");  // words that never end would never be heard
  dut_.publish(channels::kUtterance, u);
  u.speech_duration_s = 1.5;
  u.speech_start_s = 1e12;
  dut_.publish(channels::kUtterance, u);
  u.speech_start_s = 0.0;
  u.human_id = 404;  // not in the scenario
  dut_.publish(channels::kUtterance, u);
  const daemon_status_t after = dut_.countersReach(before.rejected + 8, before.dropped + 1);
  EXPECT_EQ(after.rejected, before.rejected + 8);
  EXPECT_EQ(after.dropped, before.dropped + 1);
  // Finite but absurd robot bands: the humans' predictions must not turn into NaN.
  b = corridorBands(-1);
  b.step = -1;
  for (auto& p : b.robot.poses) {
    p.x_m = kHuge;
    p.t_s = 0.0;
  }
  dut_.publish(channels::kBands, b);
  EXPECT_TRUE(moreFiniteStates(10));
}

}  // namespace
}  // namespace coopnav
