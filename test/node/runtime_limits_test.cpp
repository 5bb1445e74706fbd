// The runtime's caps on what a bus peer can make a daemon hold (runtime/limits.hpp), in process
// over memq://: far-future and flooding steps at the step gate and the step harness, a second
// process of the same name, and the restart journal's size.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "runtime/journal.hpp"
#include "runtime/step_gate.hpp"
#include "runtime/step_node.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

TEST(StepGateLimits, InputsFarAheadOfThePeersAckAreRejected) {
  Runtime rt("limits_gate", test::testLcmUrl());
  StepGate gate(rt, StepGateOptions{{{"band_source", 0, {"X"}}}, 2000ms, false});
  gate.onAck("band_source", 10);
  EXPECT_TRUE(gate.noteReceived("band_source", "X", 11, "1"));
  EXPECT_TRUE(gate.noteReceived("band_source", "X", 10 + 256, "1"));
  EXPECT_THROW(gate.noteReceived("band_source", "X", 10 + 257, "1"), RejectedMessage);
  EXPECT_THROW(gate.noteReceived("band_source", "X", 1LL << 62, "1"), RejectedMessage);
}

TEST(StepGateLimits, AnAckFarAheadIsRefusedAndANewRunIsFollowed) {
  Runtime rt("limits_gate_ack", test::testLcmUrl());
  StepGate gate(rt, StepGateOptions{{{"band_source", 0, {"X"}}}, 2000ms, false});
  gate.onAck("band_source", 10);
  EXPECT_THROW(gate.onAck("band_source", std::int64_t{1} << 50), RejectedMessage);
  EXPECT_EQ(gate.lastAck("band_source"), 10);
  EXPECT_TRUE(gate.noteReceived("band_source", "X", 11, "1")) << "a real input is not a repeat";
  // A new run from step 0: refused as a jump back until time_resync_messages acks agree.
  gate.onAck("band_source", 200);
  gate.onAck("band_source", 400);
  EXPECT_EQ(gate.lastAck("band_source"), 400);
  EXPECT_THROW(gate.onAck("band_source", 0), RejectedMessage);
  EXPECT_THROW(gate.onAck("band_source", 1), RejectedMessage);
  gate.onAck("band_source", 2);
  EXPECT_EQ(gate.lastAck("band_source"), 2);
  EXPECT_TRUE(gate.noteReceived("band_source", "X", 3, "1"));
}

TEST(StepGateLimits, DistinctFutureStepsAreBoundedByCount) {
  Runtime rt("limits_gate2", test::testLcmUrl());
  InputLimits limits;
  limits.max_pending_steps = 16;
  rt.setLimits(limits);
  StepGate gate(rt, StepGateOptions{{{"band_source", 0, {"X"}}}, 2000ms, false});
  // A peer that acks: its inputs are held up to its ack + max_pending_steps, and at most
  // max_pending_steps + 64 steps of them at once.
  gate.onAck("band_source", 0);
  int accepted = 0;
  int rejected = 0;
  for (std::int64_t k = 0; k < 20000; ++k) {
    try {
      if (gate.noteReceived("band_source", "X", 1 + (k % 16), std::to_string(k))) ++accepted;
      if (gate.noteReceived("band_source", "X", 17 + k, "1")) ++accepted;
    } catch (const RejectedMessage&) {
      ++rejected;
    }
  }
  EXPECT_LE(accepted, 20000 + 16);
  EXPECT_GT(rejected, 20000 - 100);
  // A peer that never acks (a log replay): its oldest steps are forgotten, nothing is refused.
  StepGate replay(rt, StepGateOptions{{{"dialogue_manager", 0, {"X"}}}, 2000ms, false});
  for (std::int64_t k = 0; k < 20000; ++k)
    EXPECT_TRUE(replay.noteReceived("dialogue_manager", "X", k, "1"));
}

class StepNodeLimits : public ::testing::Test {
 protected:
  Runtime rt_{"limits_node", test::testLcmUrl()};
  std::vector<std::int64_t> computed_;

  void open(StepNode& node, std::int64_t step) {
    agent_states_t m{};
    m.step = step;
    m.utime = step * 100000;
    node.open("world_sim", channels::kAgentStates, m, [&, step]() -> StepNode::Work {
      return [&, step](StepNode::Step&) { computed_.push_back(step); };
    });
  }
};

TEST_F(StepNodeLimits, AStepFarAheadIsRefusedAndDoesNotMakeLaterStepsRepeats) {
  StepNode node(rt_, StepNodeOptions{});
  open(node, 0);
  open(node, 1);
  EXPECT_THROW(open(node, std::int64_t{1} << 40), RejectedMessage);
  open(node, 2);
  open(node, 2);  // a repeat: answered from the kept outputs, not computed
  EXPECT_EQ(computed_, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(node.lastOpened(), 2);
}

TEST_F(StepNodeLimits, ARunStartingAgainFromZeroIsFollowedAfterAFewSteps) {
  StepNode node(rt_, StepNodeOptions{});
  for (std::int64_t k = 0; k <= 900; k += 100) open(node, k);  // within the jump each time
  EXPECT_THROW(open(node, 0), RejectedMessage);
  EXPECT_THROW(open(node, 1), RejectedMessage);
  open(node, 2);  // the third agreeing step: a new run
  open(node, 3);
  EXPECT_EQ(computed_.back(), 3);
  EXPECT_EQ(node.lastOpened(), 3);
}

TEST_F(StepNodeLimits, AFloodOfWaitingStepsIsCappedAtMaxPendingSteps) {
  InputLimits limits;
  limits.max_pending_steps = 8;
  rt_.setLimits(limits);
  StepNodeOptions options;
  options.requirements = {{"band_source", 0}};
  options.wait_for_unseen = true;  // every step waits for band_source, which never acks
  StepNode node(rt_, options);
  int rejected = 0;
  for (std::int64_t k = 0; k < 100; ++k) {
    try {
      open(node, k);
    } catch (const RejectedMessage&) {
      ++rejected;
    }
  }
  EXPECT_EQ(node.pending(), 8u);
  EXPECT_EQ(rejected, 92);
}

TEST(DuplicateName, AnotherProcessOfTheSameNameMakesTheDaemonDegradedWhileItIsHeard) {
  Runtime rt("dup_dut", test::testLcmUrl());
  Runtime probe("probe", test::testLcmUrl());
  daemon_status_t other{};
  other.name = "dup_dut";
  other.pid = static_cast<std::int32_t>(::getpid()) + 1;
  other.state = daemon_status_t::STATE_RUNNING;
  probe.publish(channels::kStatus, other);
  ASSERT_TRUE(test::waitFor([&] { return rt.state() == daemon_status_t::STATE_DEGRADED; }, 2000ms,
                            [&] { rt.spinFor(5); }));
  EXPECT_NE(rt.detail().find(std::to_string(other.pid)), std::string::npos) << rt.detail();
  // Its own status (same pid) and a stopping one are no second process.
  Runtime rt2("dup_dut2", test::testLcmUrl());
  daemon_status_t self{};
  self.name = "dup_dut2";
  self.pid = static_cast<std::int32_t>(::getpid());
  self.state = daemon_status_t::STATE_RUNNING;
  probe.publish(channels::kStatus, self);
  self.pid += 1;
  self.state = daemon_status_t::STATE_STOPPING;
  probe.publish(channels::kStatus, self);
  rt2.spinFor(50);
  EXPECT_NE(rt2.state(), daemon_status_t::STATE_DEGRADED);
}

TEST(JournalLimits, AJournalAtItsCapStopsGrowingAndARestartFromItSaysTheStateIsLost) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("coopnav_journal_cap_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  InputLimits limits;
  limits.journal_max_mib = 1;
  Runtime probe("probe", test::testLcmUrl());
  int handled = 0;
  {
    Runtime rt("journal_cap_dut", test::testLcmUrl());
    rt.setLimits(limits);
    rt.subscribe<agent_states_t>(channels::kAgentStates,
                                 [&](const agent_states_t&, std::int64_t) { ++handled; });
    Journal journal(rt, dir.string());
    journal.replayAndRecord();
    agent_states_t s{};
    s.robot.radius_m = 0.3;
    s.num_humans = 60;
    s.humans.resize(60);
    for (int k = 0; k < 1000; ++k) {  // ~4 kB each: 4 MB in all
      s.step = k;
      probe.publish(channels::kAgentStates, s);
      rt.spinFor(0);
    }
    ASSERT_TRUE(test::waitFor([&] { return handled == 1000; }, 5000ms, [&] { rt.spinFor(5); }));
    EXPECT_EQ(rt.state(), daemon_status_t::STATE_DEGRADED);
    EXPECT_NE(rt.detail().find("journal_max_mib"), std::string::npos) << rt.detail();
    EXPECT_LE(std::filesystem::file_size(journal.path()), 1024u * 1024u + 64u);
  }
  Runtime rt("journal_cap_dut", test::testLcmUrl());
  rt.setLimits(limits);
  int replayed = 0;
  rt.subscribe<agent_states_t>(channels::kAgentStates,
                               [&](const agent_states_t&, std::int64_t) { ++replayed; });
  Journal journal(rt, dir.string());
  EXPECT_EQ(journal.replayAndRecord(), 0u);
  EXPECT_EQ(replayed, 0);
  step_ack_t a{};
  a.step = 5;
  rt.fillRestart(a);
  EXPECT_EQ(a.restart, step_ack_t::RESTART_STATE_LOST);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace coopnav
