// The obstacle distance server answers only on reply channels (channels::kDistanceReplyPrefix,
// "COOPNAV_DIST_REP_"): a request naming another channel would make it publish a
// distance_reply_t onto that channel (COOPNAV_STATUS, a daemon's input) for whoever asked.
// Such a request is rejected (counted, logged) and gets no reply; a prefixed one is answered, and
// the client library's channel keeps the prefix whatever the client's name.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "distance_client/distance_client.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

const std::string kMap = ::coopnav::test::testDataDir() + "/maps/open.yaml";

DistanceQuery corridorQuery() {
  DistanceQuery q;
  q.point = {10.0, 6.5};
  return q;
}

class DistanceReplyChannel : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new test::ChildProcess(
        test::daemonPath("obstacle_distance_server"),
        {"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap, "--log-level", "warn"});
    ASSERT_TRUE(test::waitFor(
        [&] {
          return DistanceClient::querySync(test::testLcmUrl(), {corridorQuery()}, {200ms, 1}).ok;
        },
        20s));
  }
  static void TearDownTestSuite() { delete server_; }
  static test::ChildProcess* server_;
};
test::ChildProcess* DistanceReplyChannel::server_ = nullptr;

/// What arrived on one channel: distance replies by request id, and anything else.
struct Heard {
  std::map<std::int64_t, distance_reply_t> replies;
  int other{0};
};

TEST_F(DistanceReplyChannel, ARequestNamingAnotherChannelIsRejectedWithoutAReply) {
  Runtime rt("reply_channel_test", test::testLcmUrl());
  // The server's rejected count, from its status.
  std::int64_t rejected_first = -1, rejected_now = -1;
  rt.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.name != "obstacle_distance_server") return;
    if (rejected_first < 0) rejected_first = s.rejected;
    rejected_now = s.rejected;
  });
  // Every message on the channels the bad requests name, decoded as a reply where it is one.
  const std::vector<std::string> bad = {
      channels::kStatus,       // another daemon's channel: the case that was measured
      "COOPNAV_AGENT_STATES",  // a daemon's input
      "COOPNAV_DIST_REP",      // the prefix cut short
      "coopnav_dist_rep_x",    // the prefix in the wrong case
      "X_COOPNAV_DIST_REP_Y",  // the prefix, not at the start
  };
  const std::string good = std::string(channels::kDistanceReplyPrefix) + "REPLY_CHANNEL_TEST";
  std::map<std::string, Heard> heard;
  std::vector<lcm::Subscription*> raw;
  for (const std::string& channel : bad) {
    raw.push_back(rt.lcm().subscribeFunction(
        channel,
        +[](const lcm::ReceiveBuffer* rbuf, const std::string&, Heard* h) {
          distance_reply_t r;
          if (r.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) ==
              static_cast<int>(rbuf->data_size)) {
            h->replies[r.request_id] = r;
          } else {
            ++h->other;
          }
        },
        &heard[channel]));
  }
  rt.subscribe<distance_reply_t>(good, [&](const distance_reply_t& r, std::int64_t) {
    heard[good].replies[r.request_id] = r;
  });
  ASSERT_TRUE(test::waitFor([&] { return rejected_first >= 0; }, 3s, [&] { rt.spinFor(5); }));
  const std::int64_t base = rejected_now;

  std::int64_t id = 1000;
  for (const std::string& channel : bad)
    rt.publish(channels::kDistanceRequest, toLcm(1, id++, channel, {corridorQuery()}));
  const std::int64_t good_id = id;
  rt.publish(channels::kDistanceRequest, toLcm(1, good_id, good, {corridorQuery()}));

  // The prefixed request is answered; each of the others counted rejected.
  ASSERT_TRUE(test::waitFor([&] { return heard[good].replies.count(good_id) > 0; }, 3s,
                            [&] { rt.spinFor(5); }));
  EXPECT_EQ(heard[good].replies[good_id].status, distance_reply_t::STATUS_OK);
  EXPECT_EQ(heard[good].replies[good_id].num_results, 1);
  EXPECT_TRUE(
      test::waitFor([&] { return rejected_now >= base + static_cast<std::int64_t>(bad.size()); },
                    4s, [&] { rt.spinFor(5); }));
  EXPECT_EQ(rejected_now - base, static_cast<std::int64_t>(bad.size()));
  rt.spinFor(300);  // a reply would have come with the good one's
  for (const std::string& channel : bad) {
    EXPECT_TRUE(heard[channel].replies.empty()) << "a distance reply was published on " << channel;
  }
  EXPECT_TRUE(server_->running());
  for (auto* s : raw) rt.lcm().unsubscribe(s);
}

TEST_F(DistanceReplyChannel, TheClientsChannelKeepsThePrefixWhateverItsName) {
  Runtime rt("reply_channel_client", test::testLcmUrl());
  const std::string long_name(200, 'n');
  DistanceClient client(rt, long_name, {500ms, 3});
  const std::string prefix = channels::kDistanceReplyPrefix;
  EXPECT_EQ(client.replyChannel().compare(0, prefix.size(), prefix), 0) << client.replyChannel();
  EXPECT_LE(client.replyChannel().size(), 63u);
  const std::string pid_suffix = "_" + std::to_string(::getpid());
  EXPECT_EQ(client.replyChannel().substr(client.replyChannel().size() - pid_suffix.size()),
            pid_suffix);
  bool ok = false, done = false;
  client.query({corridorQuery()}, 1, [&](const DistanceClient::Outcome& o) {
    ok = o.ok;
    done = true;
  });
  ASSERT_TRUE(test::waitFor([&] { return done; }, 3s, [&] { rt.spinFor(5); }));
  EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace coopnav
