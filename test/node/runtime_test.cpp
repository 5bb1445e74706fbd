// The shared daemon runtime, in-process over memq:// (test/CMakeLists.txt): safe decoding with
// counters, status, step acks, timers, the distance client's timeout when no server answers.
#include "runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "distance_client/distance_client.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

TEST(RuntimeTest, BadUrlIsReportedAtConstruction) {
  EXPECT_THROW(Runtime("x", "nosuchprovider://"), LcmUnavailable);
}

TEST(RuntimeTest, WrongTypeOnAChannelIsRejectedAndCountedNotFatal) {
  Runtime rt("dut", test::testLcmUrl());
  int good = 0;
  rt.subscribe<agent_states_t>("RT_TEST_STATES",
                               [&](const agent_states_t&, std::int64_t) { ++good; });
  step_ack_t wrong{};
  wrong.participant = "x";
  rt.publish("RT_TEST_STATES", wrong);
  agent_states_t right{};
  right.robot.radius_m = 0.3;
  rt.publish("RT_TEST_STATES", right);
  test::waitFor([&] { return rt.counters().received >= 2; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  EXPECT_EQ(good, 1);
  EXPECT_EQ(rt.counters().rejected, 1);
}

TEST(RuntimeTest, TruncatedAndCorruptCountsAreRejected) {
  Runtime rt("dut", test::testLcmUrl());
  int good = 0;
  rt.subscribe<agent_states_t>("RT_TEST_TRUNC",
                               [&](const agent_states_t&, std::int64_t) { ++good; });
  agent_states_t m{};
  m.num_humans = 1;
  m.humans.resize(1);
  std::vector<uint8_t> buf(m.getEncodedSize());
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  rt.lcm().publish("RT_TEST_TRUNC", buf.data(), static_cast<unsigned>(buf.size() - 9));
  // Negative human count: the generated decoder would throw on resize.
  const std::size_t count_offset =
      8 + 8 + 8 + static_cast<std::size_t>(m.robot._getEncodedSizeNoHash());
  buf[count_offset] = 0xff;
  buf[count_offset + 1] = 0xf0;
  rt.lcm().publish("RT_TEST_TRUNC", buf.data(), static_cast<unsigned>(buf.size()));
  test::waitFor([&] { return rt.counters().received >= 2; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  EXPECT_EQ(good, 0);
  EXPECT_EQ(rt.counters().rejected, 2);
}

TEST(RuntimeTest, HandlerExceptionsAreCountedAndTheLoopGoesOn) {
  Runtime rt("dut", test::testLcmUrl());
  rt.subscribe<step_ack_t>("RT_TEST_THROW", [&](const step_ack_t& a, std::int64_t) {
    if (a.step == 1) throw RejectedMessage("bad");
    if (a.step == 2) throw DroppedMessage("stale");
  });
  for (int s = 1; s <= 3; ++s) {
    step_ack_t a{};
    a.step = s;
    rt.publish("RT_TEST_THROW", a);
  }
  test::waitFor([&] { return rt.counters().received >= 3; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  EXPECT_EQ(rt.counters().rejected, 1);
  EXPECT_EQ(rt.counters().dropped, 1);
}

// Issue 47: a peer publishing faster than a daemon handles grew LCM's queue without bound (a
// path assessor to 2.95 GB in 30 s). Each subscription now keeps limits.queue_messages and
// limits.queue_mib waiting, the oldest dropped first and counted. memq:// delivers every message,
// so what is dropped is exactly the queue's doing.
TEST(RuntimeTest, AFloodKeepsTheNewestWaitingMessagesOfAChannelAndCountsTheDroppedOnes) {
  Runtime rt("dut", "memq://");
  InputLimits limits;
  limits.queue_messages = 50;
  rt.setLimits(limits);
  std::vector<std::int64_t> got;
  std::vector<std::string> order;
  rt.subscribe<agent_states_t>("RT_TEST_FLOOD", [&](const agent_states_t& m, std::int64_t) {
    got.push_back(m.utime);
    order.push_back("flood");
  });
  int latest_only = 0;
  std::int64_t latest_utime = -1;
  rt.subscribe<agent_states_t>(
      "RT_TEST_LATEST",
      [&](const agent_states_t& m, std::int64_t) {
        ++latest_only;
        latest_utime = m.utime;
        order.push_back("latest");
      },
      /*queue_capacity=*/1);
  for (int i = 0; i < 1000; ++i) {
    agent_states_t m{};
    m.utime = i;
    rt.publish("RT_TEST_FLOOD", m);
    if (i % 100 == 99) rt.publish("RT_TEST_LATEST", m);
  }
  test::waitFor([&] { return got.size() >= 50 && latest_only >= 1; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  rt.spinFor(20);
  ASSERT_EQ(got.size(), 50u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], 950 + static_cast<int>(i));
  EXPECT_EQ(latest_only, 1);
  EXPECT_EQ(latest_utime, 999);
  EXPECT_EQ(rt.queueDropped("RT_TEST_FLOOD"), 950);
  EXPECT_EQ(rt.queueDropped("RT_TEST_LATEST"), 9);
  EXPECT_EQ(rt.counters().dropped, 959);
  EXPECT_EQ(rt.queued(), 0u);
  // Handled in arrival order across channels: the latest was sent after the last flood message.
  ASSERT_EQ(order.size(), 51u);
  EXPECT_EQ(order.back(), "latest");
}

TEST(RuntimeTest, TheBytesWaitingOnAChannelAreCappedButOneMessageOfAnySizeGetsThrough) {
  Runtime rt("dut", "memq://");
  InputLimits limits;
  limits.queue_mib = 1;
  rt.setLimits(limits);
  rt.subscribe<agent_states_t>("RT_TEST_BIG", [](const agent_states_t&, std::int64_t) {});
  const std::vector<std::uint8_t> third(300 * 1024, 0xAB);  // not an agent state: rejected
  for (int i = 0; i < 10; ++i)
    rt.lcm().publish("RT_TEST_BIG", third.data(), static_cast<unsigned>(third.size()));
  test::waitFor([&] { return rt.counters().received >= 3; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  rt.spinFor(20);
  EXPECT_EQ(rt.counters().received, 3);  // 3 x 300 KiB fit in 1 MiB
  EXPECT_EQ(rt.queueDropped("RT_TEST_BIG"), 7);
  const std::vector<std::uint8_t> huge(3 * 1024 * 1024, 0xCD);
  rt.lcm().publish("RT_TEST_BIG", huge.data(), static_cast<unsigned>(huge.size()));
  test::waitFor([&] { return rt.counters().received >= 4; }, std::chrono::seconds(2),
                [&] { rt.spinFor(5); });
  EXPECT_EQ(rt.counters().received, 4);
  EXPECT_EQ(rt.queueDropped("RT_TEST_BIG"), 7);
}

TEST(RuntimeTest, StepAcksCarryTheParticipantName) {
  Runtime dut("situation_assessor", test::testLcmUrl());
  Runtime probe("probe", test::testLcmUrl());
  std::vector<step_ack_t> acks;
  probe.subscribe<step_ack_t>(channels::kStepAck,
                              [&](const step_ack_t& a, std::int64_t) { acks.push_back(a); });
  dut.ackStep(100000, 1);
  dut.ackStep(200000, -1);  // free-running: not published
  test::waitFor([&] { return !acks.empty(); }, std::chrono::seconds(2), [&] { probe.spinFor(5); });
  probe.spinFor(50);
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].participant, "situation_assessor");
  EXPECT_EQ(acks[0].step, 1);
}

// A process that starts after the daemons (the world waiting for its participants) hears each
// one's status when it says it is there, not up to a status period later: answered once per name,
// only by a daemon that is up, never to its own name or a stopping peer.
TEST(RuntimeTest, ANewPeersFirstStatusIsAnsweredOnceByADaemonThatIsUp) {
  Runtime dut("path_assessor", test::testLcmUrl());
  Runtime probe("probe", test::testLcmUrl());
  int answers = 0;
  probe.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.name == "path_assessor" && s.pid == ::getpid()) ++answers;  // the dut's, not ours
  });
  auto say = [&](const std::string& name, std::int8_t state) {
    daemon_status_t s{};
    s.name = name;
    s.pid = 4242;
    s.state = state;
    s.cycle_p50_ms = s.cycle_max_ms = 0.0;
    probe.publish(channels::kStatus, s);
    for (int i = 0; i < 5; ++i) {
      dut.spinFor(5);
      probe.spinFor(5);
    }
  };
  say("world_sim", daemon_status_t::STATE_RUNNING);
  EXPECT_EQ(answers, 0) << "a daemon still starting says nothing";
  dut.setRunning("up");
  say("band_source", daemon_status_t::STATE_RUNNING);
  test::waitFor([&] { return answers >= 1; }, std::chrono::seconds(2),
                [&] {
                  dut.spinFor(5);
                  probe.spinFor(5);
                });
  EXPECT_EQ(answers, 1);
  say("band_source", daemon_status_t::STATE_RUNNING);        // heard before: no answer
  say("path_assessor", daemon_status_t::STATE_RUNNING);      // its own name: the duplicate check's
  say("dialogue_manager", daemon_status_t::STATE_STOPPING);  // leaving: nobody to tell
  EXPECT_EQ(answers, 1);
  say("world_sim", daemon_status_t::STATE_STARTING);  // new since the daemon is up
  test::waitFor([&] { return answers >= 2; }, std::chrono::seconds(2),
                [&] {
                  dut.spinFor(5);
                  probe.spinFor(5);
                });
  EXPECT_EQ(answers, 2);
}

TEST(RuntimeTest, DistanceClientGivesUpAfterItsAttemptsWhenNoServerAnswers) {
  Runtime rt("dut", test::testLcmUrl());
  DistanceClient::Options o;
  o.timeout = std::chrono::milliseconds(30);
  o.attempts = 2;
  DistanceClient client(rt, "rt_test_nobody", o);
  std::optional<DistanceClient::Outcome> out;
  client.query({DistanceQuery{}}, 0, [&](const DistanceClient::Outcome& r) { out = r; });
  test::waitFor([&] { return out.has_value(); }, std::chrono::seconds(2), [&] { rt.spinFor(5); });
  ASSERT_TRUE(out.has_value());
  EXPECT_FALSE(out->ok);
  EXPECT_EQ(out->attempts_used, 2);
  EXPECT_NE(out->error.find("no reply"), std::string::npos);
}

}  // namespace
}  // namespace coopnav
