// The obstacle distance server as a real process over an isolated udpm port: batched answers
// equal the library's on the same map, bad requests are answered or rejected without losing
// the server, bad maps and configs stop it at start with a message, SIGTERM stops it cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "distance_client/distance_client.hpp"
#include "maps/map_loader.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

const std::string kMap = ::coopnav::test::testDataDir() + "/maps/open.yaml";

/// One server process for the suite; every test talks to it through its own client instance.
class ServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new test::ChildProcess(
        test::daemonPath("obstacle_distance_server"),
        {"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap, "--log-level", "warn"});
    // Ready = it answers.
    DistanceQuery q;
    q.point = {10.0, 6.5};
    ASSERT_TRUE(test::waitFor(
        [&] {
          return DistanceClient::querySync(test::testLcmUrl(), {q}, {200ms, 1}).ok;
        },
        20s));
    field_ = new GridDistanceField(loadMap(kMap, {}).grid, UnknownPolicy::kObstacle);
  }
  static void TearDownTestSuite() {
    delete server_;
    delete field_;
  }
  static test::ChildProcess* server_;
  static GridDistanceField* field_;
};
test::ChildProcess* ServerTest::server_ = nullptr;
GridDistanceField* ServerTest::field_ = nullptr;

std::vector<DistanceQuery> mixedBatch() {
  std::vector<DistanceQuery> qs;
  for (int i = 0; i < 300; ++i) {
    const double x = 5.0 + 0.07 * i, y = 1.0 + 0.023 * i;
    DistanceQuery q;
    q.point = {x, y};
    q.max_range_m = 8.0;
    q.kind = static_cast<DistanceQueryKind>(i % 3);
    q.vector = Eigen::Vector2d(std::cos(0.1 * i), std::sin(0.1 * i));
    qs.push_back(q);
  }
  return qs;
}

TEST_F(ServerTest, BatchedAnswersEqualTheLibraryOnTheSameMap) {
  const auto qs = mixedBatch();
  const auto out = DistanceClient::querySync(test::testLcmUrl(), qs, {1000ms, 3});
  ASSERT_TRUE(out.ok) << out.error;
  ASSERT_EQ(out.results.size(), qs.size());
  int ok = 0;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const DistanceResult want = answerQuery(*field_, qs[i]);
    EXPECT_EQ(out.results[i].status, want.status) << "query " << i;
    if (want.status == DistanceStatus::kOk) {
      ++ok;
      EXPECT_DOUBLE_EQ(out.results[i].distance_m, want.distance_m) << "query " << i;
      EXPECT_DOUBLE_EQ(out.results[i].obstacle.x(), want.obstacle.x());
      EXPECT_DOUBLE_EQ(out.results[i].obstacle.y(), want.obstacle.y());
    }
  }
  EXPECT_GT(ok, 100);  // the batch really exercises free space, not only walls
}

TEST_F(ServerTest, SixMetreCorridorIsSeenAsSixMetresWide) {
  // Upper corridor of open.pgm (maps/README): walls near y 3.5 and 9.5 at x = 10.
  DistanceQuery up, down;
  up.kind = down.kind = DistanceQueryKind::kRay;
  up.point = down.point = {10.0, 6.5};
  up.vector = {0.0, 1.0};
  down.vector = {0.0, -1.0};
  const auto out = DistanceClient::querySync(test::testLcmUrl(), {up, down}, {1000ms, 3});
  ASSERT_TRUE(out.ok) << out.error;
  const double width = out.results[0].distance_m + out.results[1].distance_m;
  EXPECT_NEAR(width, 6.0, 0.15);
}

TEST_F(ServerTest, NonFiniteQueryIsAnsweredInvalidAndTheRestOfTheBatchStands) {
  DistanceQuery bad, good;
  bad.point = {std::numeric_limits<double>::quiet_NaN(), 6.5};
  good.point = {10.0, 6.5};
  DistanceQuery inf_range = good;
  inf_range.max_range_m = std::numeric_limits<double>::infinity();
  const auto out =
      DistanceClient::querySync(test::testLcmUrl(), {bad, good, inf_range}, {1000ms, 3});
  ASSERT_TRUE(out.ok) << out.error;
  EXPECT_EQ(out.results[0].status, DistanceStatus::kInvalidQuery);
  EXPECT_EQ(out.results[1].status, DistanceStatus::kOk);
}

/// Sends a raw request and returns the reply (or nothing within 2 s).
std::optional<distance_reply_t> rawRequest(Runtime& rt, const distance_request_t& req) {
  std::optional<distance_reply_t> reply;
  rt.subscribe<distance_reply_t>(req.reply_channel, [&](const distance_reply_t& r, std::int64_t) {
    if (r.request_id == req.request_id) reply = r;
  });
  rt.publish(channels::kDistanceRequest, req);
  test::waitFor([&] { return reply.has_value(); }, 2s, [&] { rt.spinFor(5); });
  return reply;
}

TEST_F(ServerTest, EmptyAndOversizedRequestsGetBadRequestRepliesWithTheReason) {
  Runtime rt("test_client", test::testLcmUrl());
  distance_request_t empty{};
  empty.request_id = 11;
  empty.reply_channel = "COOPNAV_DIST_REP_TEST_EMPTY";
  empty.num_queries = 0;
  auto r = rawRequest(rt, empty);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, distance_reply_t::STATUS_BAD_REQUEST);
  EXPECT_FALSE(r->error.empty());

  distance_request_t big{};
  big.request_id = 12;
  big.reply_channel = "COOPNAV_DIST_REP_TEST_BIG";
  big.num_queries = distance_request_t::MAX_QUERIES + 1;
  big.queries.resize(big.num_queries);
  for (auto& q : big.queries) {
    q.kind = distance_query_t::KIND_NEAREST;
    q.px_m = 10.0;
    q.py_m = 6.5;
    q.max_range_m = 5.0;
  }
  r = rawRequest(rt, big);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, distance_reply_t::STATUS_BAD_REQUEST);
  EXPECT_NE(r->error.find(std::to_string(distance_request_t::MAX_QUERIES)), std::string::npos)
      << r->error;
}

TEST_F(ServerTest, GarbageAndTruncatedRequestsAreRejectedAndTheServerKeepsAnswering) {
  Runtime rt("test_client", test::testLcmUrl());
  std::int64_t rejected_before = -1, rejected_after = -1;
  rt.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.name != "obstacle_distance_server") return;
    if (rejected_before < 0) rejected_before = s.rejected;
    rejected_after = s.rejected;
  });
  ASSERT_TRUE(test::waitFor([&] { return rejected_before >= 0; }, 3s, [&] { rt.spinFor(5); }));
  const std::int64_t base = rejected_after;

  const std::vector<std::uint8_t> garbage(37, 0xAB);
  rt.lcm().publish(channels::kDistanceRequest, garbage.data(),
                   static_cast<unsigned>(garbage.size()));
  DistanceQuery q;
  q.point = {10.0, 6.5};
  auto req = toLcm(1, 99, "COOPNAV_DIST_REP_TEST_TRUNC", {q, q, q});
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(req.getEncodedSize()));
  req.encode(buf.data(), 0, static_cast<int>(buf.size()));
  rt.lcm().publish(channels::kDistanceRequest, buf.data(), static_cast<unsigned>(buf.size() - 11));

  ASSERT_TRUE(
      test::waitFor([&] { return rejected_after >= base + 2; }, 4s, [&] { rt.spinFor(5); }));
  EXPECT_TRUE(server_->running());
  const auto out = DistanceClient::querySync(test::testLcmUrl(), {q}, {1000ms, 3});
  EXPECT_TRUE(out.ok) << out.error;
}

TEST(ServerStartTest, MissingMapStopsAtStartNamingTheFile) {
  test::ChildProcess p(test::daemonPath("obstacle_distance_server"),
                       {"--lcm-url", test::testLcmUrl(), "--set", "map_file=/nonexistent/x.yaml"});
  EXPECT_EQ(p.waitExit(10s), kExitBadInput);
}

TEST(ServerStartTest, CorruptPgmStopsAtStart) {
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/bad.pgm") << "P5\n10 10\n255\nshort";
  std::ofstream(dir + "/bad.yaml") << "image: bad.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                      "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  test::ChildProcess p(test::daemonPath("obstacle_distance_server"),
                       {"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + dir + "/bad.yaml"});
  EXPECT_EQ(p.waitExit(10s), kExitBadInput);
}

TEST(ServerStartTest, OutOfRangeConfigStopsWithUsageError) {
  test::ChildProcess p(test::daemonPath("obstacle_distance_server"),
                       {"--lcm-url", test::testLcmUrl(), "--set", "max_range_cap_m=-3"});
  EXPECT_EQ(p.waitExit(10s), kExitUsage);
}

TEST(ServerStartTest, SigtermStopsWithinOneSecond) {
  test::ChildProcess p(test::daemonPath("obstacle_distance_server"),
                       {"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap});
  DistanceQuery q;
  q.point = {10.0, 6.5};
  ASSERT_TRUE(test::waitFor(
      [&] {
        return DistanceClient::querySync(test::testLcmUrl(), {q}, {200ms, 1}).ok;
      },
      20s));
  p.signal(SIGTERM);
  EXPECT_EQ(p.waitExit(1000ms), kExitOk);
}

}  // namespace
}  // namespace coopnav
