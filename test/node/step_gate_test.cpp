// StepGate (daemons/common/runtime/step_gate.hpp): the lockstep ordering every pipeline daemon
// relies on. Acks are fed with onAck and timeouts driven with checkTimeouts(fake now), except one
// test that goes through a real step_ack_t on the in-process bus.
#include "runtime/step_gate.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "coopnav/step_ack_t.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using std::chrono::milliseconds;
using std::chrono::steady_clock;

struct Ran {
  std::int64_t step;
  bool degraded;
  std::string missing;
};

class StepGateTest : public ::testing::Test {
 protected:
  Runtime rt_{"gate_dut", test::testLcmUrl()};
  std::vector<Ran> ran_;

  StepGate::Work record(std::int64_t step) {
    return [this, step](bool degraded, const std::string& missing) {
      ran_.push_back({step, degraded, missing});
    };
  }
  std::vector<std::int64_t> steps() const {
    std::vector<std::int64_t> s;
    for (const auto& r : ran_) s.push_back(r.step);
    return s;
  }
  static StepGateOptions options(std::vector<StepRequirement> req,
                                 milliseconds timeout = milliseconds(500)) {
    StepGateOptions o;
    o.requirements = std::move(req);
    o.timeout = timeout;
    return o;
  }
};

TEST_F(StepGateTest, OffsetZeroWaitsForTheAckOfTheSameStep) {
  StepGate gate(rt_, options({{"situation_assessor", 0}}));
  gate.onAck("situation_assessor", 4);  // seen: from now on waited for
  gate.submit(5, record(5));
  EXPECT_TRUE(ran_.empty());
  EXPECT_EQ(gate.pending(), 1u);
  gate.onAck("situation_assessor", 4);  // a repeated old ack changes nothing
  EXPECT_TRUE(ran_.empty());
  gate.onAck("situation_assessor", 5);
  ASSERT_EQ(ran_.size(), 1u);
  EXPECT_EQ(ran_[0].step, 5);
  EXPECT_FALSE(ran_[0].degraded);
  EXPECT_EQ(gate.pending(), 0u);
  EXPECT_EQ(gate.lastAck("situation_assessor"), 5);
}

TEST_F(StepGateTest, OffsetMinusOneWaitsForThePreviousStepOnly) {
  StepGate gate(rt_, options({{"dialogue_manager", -1}}));
  gate.onAck("dialogue_manager", 3);
  gate.submit(5, record(5));
  EXPECT_TRUE(ran_.empty()) << "needs the ack of step 4";
  gate.onAck("dialogue_manager", 4);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({5}));
  // Step 0 needs step -1: nothing to wait for.
  gate.submit(0, record(0));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({5, 0}));
}

TEST_F(StepGateTest, BothOffsetsTogetherAndAnAckOfALaterStepSatisfiesEarlierOnes) {
  StepGate gate(rt_, options({{"a", 0}, {"b", -1}}));
  gate.onAck("a", 0);
  gate.onAck("b", 0);
  gate.submit(2, record(2));
  gate.onAck("a", 2);
  EXPECT_TRUE(ran_.empty()) << "b has acked 0, step 2 needs b's 1";
  gate.onAck("b", 7);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2}));
}

TEST_F(StepGateTest, QueuedWorkRunsInSubmissionOrderAndNeverOvertakes) {
  StepGate gate(rt_, options({{"p", 0}}));
  gate.onAck("p", 0);
  gate.submit(1, record(1));
  gate.submit(2, record(2));
  gate.submit(-1, record(-1));  // free-running work queues behind lockstep work
  gate.submit(3, record(3));
  EXPECT_TRUE(ran_.empty());
  gate.onAck("p", 1);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({1}));
  gate.onAck("p", 3);  // 2 and 3 met at once: still in order, with the -1 in between
  EXPECT_EQ(steps(), std::vector<std::int64_t>({1, 2, -1, 3}));
}

TEST_F(StepGateTest, HeadOfLineBlocksLaterStepsEvenWhenTheirOwnRequirementsAreMet) {
  StepGate gate(rt_, options({{"a", 0}, {"b", -1}}));
  gate.onAck("a", 0);
  gate.onAck("b", 0);
  gate.submit(3, record(3));  // needs a:3, b:2
  gate.submit(4, record(4));  // needs a:4, b:3
  gate.onAck("a", 4);
  EXPECT_TRUE(ran_.empty());
  gate.onAck("b", 3);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({3, 4}));
}

TEST_F(StepGateTest, PeersNeverHeardFromAreNotWaitedFor) {
  StepGate gate(rt_, options({{"situation_assessor", 0}, {"path_assessor", 0}}));
  gate.submit(7, record(7));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({7}));
  gate.onAck("path_assessor", 7);  // now path_assessor is waited for, situation_assessor still not
  gate.submit(8, record(8));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({7}));
  gate.onAck("path_assessor", 8);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({7, 8}));
}

TEST_F(StepGateTest, WaitForUnseenWaitsFromTheFirstStep) {
  StepGateOptions o = options({{"band_source", 0}});
  o.wait_for_unseen = true;
  StepGate gate(rt_, o);
  gate.submit(0, record(0));
  EXPECT_TRUE(ran_.empty());
  gate.onAck("band_source", 0);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({0}));
}

TEST_F(StepGateTest, AcksOfParticipantsNotRequiredAreIgnored) {
  StepGate gate(rt_, options({{"a", 0}}));
  gate.onAck("a", 1);
  gate.submit(2, record(2));
  gate.onAck("someone_else", 99);
  EXPECT_TRUE(ran_.empty());
  EXPECT_EQ(gate.lastAck("someone_else"), -1);
}

TEST_F(StepGateTest, TimeoutRunsDegradedAndThePeerIsAbsentUntilItsNextAck) {
  StepGate gate(rt_, options({{"situation_assessor", 0}, {"path_assessor", 0}}, milliseconds(500)));
  gate.onAck("situation_assessor", 1);
  gate.onAck("path_assessor", 1);
  gate.submit(2, record(2));
  gate.submit(3, record(3));
  gate.onAck("path_assessor", 3);
  const auto t0 = steady_clock::now();
  gate.checkTimeouts(t0 + milliseconds(100));  // not yet
  EXPECT_TRUE(ran_.empty());
  gate.checkTimeouts(t0 + milliseconds(600));
  ASSERT_EQ(ran_.size(), 2u) << "step 3 was held only by the absent peer";
  EXPECT_EQ(ran_[0].step, 2);
  EXPECT_TRUE(ran_[0].degraded);
  EXPECT_NE(ran_[0].missing.find("situation_assessor (step 2)"), std::string::npos)
      << ran_[0].missing;
  EXPECT_EQ(ran_[0].missing.find("path_assessor"), std::string::npos) << ran_[0].missing;
  EXPECT_EQ(ran_[1].step, 3);
  EXPECT_FALSE(ran_[1].degraded);
  // Absent: not waited for (path_assessor, present, still is).
  gate.onAck("path_assessor", 5);
  gate.submit(4, record(4));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2, 3, 4}));
  // Back with its next ack (even an old step's): waited for again.
  gate.onAck("situation_assessor", 2);
  gate.submit(5, record(5));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2, 3, 4}));
  gate.onAck("situation_assessor", 5);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2, 3, 4, 5}));
}

TEST_F(StepGateTest, TimeoutCountsFromSubmissionOfTheHead) {
  StepGate gate(rt_, options({{"p", 0}}, milliseconds(500)));
  gate.onAck("p", 0);
  const auto before = steady_clock::now();
  gate.submit(1, record(1));
  gate.checkTimeouts(before + milliseconds(400));
  EXPECT_TRUE(ran_.empty());
  gate.checkTimeouts(steady_clock::now() + milliseconds(501));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({1}));
}

TEST_F(StepGateTest, FreeRunningWorkRunsAtOnce) {
  StepGate gate(rt_, options({{"p", 0}}));
  gate.onAck("p", 10);  // present, and would block step 11
  gate.submit(-1, record(-1));
  gate.submit(-1, record(-1));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({-1, -1}));
  EXPECT_FALSE(ran_[0].degraded);
  EXPECT_EQ(gate.pending(), 0u);
}

TEST_F(StepGateTest, OffsetsOtherThanZeroAndMinusOneAreRefused) {
  EXPECT_THROW(StepGate(rt_, options({{"p", 1}})), std::invalid_argument);
  EXPECT_THROW(StepGate(rt_, options({{"p", -2}})), std::invalid_argument);
}

TEST_F(StepGateTest, WorkSubmittingWorkAndAckingFromInsideKeepsTheOrder) {
  StepGate gate(rt_, options({{"p", 0}}));
  gate.onAck("p", 0);
  gate.submit(1, [&](bool, const std::string&) {
    ran_.push_back({1, false, ""});
    gate.submit(2, record(2));  // re-entrant submit while draining
    gate.onAck("p", 2);         // re-entrant ack while draining
    ran_.push_back({100, false, ""});
  });
  gate.onAck("p", 1);
  EXPECT_EQ(steps(), std::vector<std::int64_t>({1, 100, 2}));
}

TEST_F(StepGateTest, ThrowingWorkIsCountedAndDoesNotStallTheGate) {
  StepGate gate(rt_, options({{"p", 0}}));
  gate.onAck("p", 0);
  gate.submit(1, [](bool, const std::string&) { throw std::runtime_error("bug"); });
  gate.submit(2, record(2));
  EXPECT_NO_THROW(gate.onAck("p", 2));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2}));
  EXPECT_EQ(rt_.counters().rejected, 1);
  // And from a timeout.
  gate.submit(3, [](bool, const std::string&) { throw std::runtime_error("bug"); });
  gate.submit(4, record(4));
  EXPECT_NO_THROW(gate.checkTimeouts(steady_clock::now() + milliseconds(600)));
  gate.onAck("p", 5);
  gate.submit(5, record(5));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({2, 4, 5}));
  EXPECT_NO_THROW(gate.submit(-1, [](bool, const std::string&) { throw std::runtime_error("x"); }));
  EXPECT_EQ(rt_.counters().rejected, 3);
}

TEST_F(StepGateTest, AcksArriveOverLcm) {
  StepGate gate(rt_, options({{"situation_assessor", 0}}));
  Runtime peer("situation_assessor", test::testLcmUrl());
  peer.ackStep(1000, 0);
  ASSERT_TRUE(test::waitFor([&] { return gate.lastAck("situation_assessor") == 0; },
                            std::chrono::seconds(2), [&] { rt_.spinFor(5); }));
  gate.submit(1, record(1));
  EXPECT_TRUE(ran_.empty());
  peer.ackStep(2000, 1);
  ASSERT_TRUE(test::waitFor([&] { return !ran_.empty(); }, std::chrono::seconds(2),
                            [&] { rt_.spinFor(5); }));
  EXPECT_EQ(steps(), std::vector<std::int64_t>({1}));
}

TEST_F(StepGateTest, AcksCountingImpossibleNumbersOfOutputsAreRejectedAndNeverWaitedFor) {
  StepGate gate(rt_, options({{"situation_assessor", 0, {"SITUATION"}}}, milliseconds(60000)));
  Runtime peer("situation_assessor", test::testLcmUrl());
  peer.ackStep(1000, 0);
  ASSERT_TRUE(test::waitFor([&] { return gate.lastAck("situation_assessor") == 0; },
                            std::chrono::seconds(2), [&] { rt_.spinFor(5); }));
  gate.submit(1, record(1));
  const auto rejected0 = rt_.counters().rejected;
  // A forged ack of step 1 counting -1, then INT32_MAX situations: refused whole (a gate that
  // took either waited for messages that never come, up to its timeout, every step).
  for (const std::int32_t bad : {-1, std::numeric_limits<std::int32_t>::max()}) {
    step_ack_t ack{};
    ack.utime = 2000;
    ack.step = 1;
    ack.participant = "situation_assessor";
    ack.output_channels = {"SITUATION"};
    ack.output_counts = {bad};
    ack.num_outputs = 1;
    peer.publish(channels::kStepAck, ack);
  }
  ASSERT_TRUE(test::waitFor([&] { return rt_.counters().rejected == rejected0 + 2; },
                            std::chrono::seconds(2), [&] { rt_.spinFor(5); }));
  EXPECT_EQ(gate.lastAck("situation_assessor"), 0);
  EXPECT_TRUE(ran_.empty());
  // The real ack (one situation, received) runs the step at once, not at the timeout.
  EXPECT_TRUE(gate.noteReceived("situation_assessor", "SITUATION", 1, "7"));
  step_ack_t ack{};
  ack.utime = 2000;
  ack.step = 1;
  ack.participant = "situation_assessor";
  ack.output_channels = {"SITUATION"};
  ack.output_counts = {1};
  ack.num_outputs = 1;
  peer.publish(channels::kStepAck, ack);
  ASSERT_TRUE(test::waitFor([&] { return !ran_.empty(); }, std::chrono::seconds(2),
                            [&] { rt_.spinFor(5); }));
  EXPECT_FALSE(ran_[0].degraded);
  EXPECT_EQ(rt_.counters().rejected, rejected0 + 2);
}

TEST_F(StepGateTest, TheTimerRunsADegradedStepWithoutAnyCallFromTheTest) {
  StepGate gate(rt_, options({{"p", 0}}, milliseconds(100)));
  gate.onAck("p", 0);
  gate.submit(1, record(1));
  ASSERT_TRUE(test::waitFor([&] { return !ran_.empty(); }, std::chrono::seconds(3),
                            [&] { rt_.spinFor(20); }));
  EXPECT_TRUE(ran_[0].degraded);
}

}  // namespace
}  // namespace coopnav
