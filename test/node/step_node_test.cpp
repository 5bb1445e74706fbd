// StepNode (daemons/common/runtime/step_node.hpp): the one lockstep harness. Every path through a
// node acknowledges its step, in order; a repeat is answered from the kept outputs and never
// computed again; an input is stored once. In-process over LCM's memq:// (no multicast route
// needed): the node and the probe share one runtime, whose own publications come back to it as on
// udpm.
#include "runtime/step_node.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"

namespace coopnav {
namespace {

/// A message shaped like ours: utime and step first.
struct FakeMsg {
  std::int64_t utime{0};
  std::int64_t step{-1};
  int getEncodedSize() const { return 16; }
  int encode(void* buf, int offset, int size) const {
    if (size < 16) return -1;
    auto* b = static_cast<std::uint8_t*>(buf) + offset;
    for (int i = 0; i < 8; ++i) b[i] = static_cast<std::uint8_t>(utime >> (8 * i));
    for (int i = 0; i < 8; ++i) b[8 + i] = static_cast<std::uint8_t>(step >> (8 * i));
    return 16;
  }
};

struct Ack {
  std::int64_t step;
  int outputs;  ///< messages counted on the status channel
};

class StepNodeTest : public ::testing::Test {
 protected:
  Runtime rt_{"step_dut", "memq://"};
  std::vector<Ack> acks_;
  std::vector<std::int64_t> status_steps_;  ///< step of each status output seen (our test output)

  void SetUp() override {
    rt_.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& a, std::int64_t) {
      if (a.participant != "step_dut") return;
      int n = 0;
      for (std::size_t i = 0; i < a.output_channels.size(); ++i)
        if (a.output_channels[i] == "TEST_OUT") n += a.output_counts[i];
      acks_.push_back({a.step, n});
    });
    rt_.subscribe<daemon_status_t>("TEST_OUT", [this](const daemon_status_t& s, std::int64_t) {
      status_steps_.push_back(s.utime);
    });
  }
  void spin() {
    for (int i = 0; i < 5; ++i) rt_.spinFor(0);
  }
  std::vector<std::int64_t> ackedSteps() const {
    std::vector<std::int64_t> s;
    for (const auto& a : acks_) s.push_back(a.step);
    return s;
  }
  static daemon_status_t out(std::int64_t step) {
    daemon_status_t s{};
    s.utime = step;
    s.name = "out";
    return s;
  }
  static FakeMsg msg(std::int64_t step) { return FakeMsg{1000 + step, step}; }
};

TEST_F(StepNodeTest, EveryPathAcknowledgesItsStep) {
  StepNode node(rt_, StepNodeOptions{});
  int computed = 0;
  // Computed and published.
  node.open("world", "IN", msg(0), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) {
      ++computed;
      s.publish("TEST_OUT", out(s.step()));
    };
  });
  // Rejected on conversion: acknowledged all the same, the exception goes on to be counted.
  EXPECT_THROW(
      node.open("world", "IN", msg(1), [&]() -> StepNode::Work { throw RejectedMessage("bad"); }),
      RejectedMessage);
  // Nothing to compute.
  node.open("world", "IN", msg(2), [&]() -> StepNode::Work { return nullptr; });
  // The work throws half-way: the step is still acknowledged with what it published.
  node.open("world", "IN", msg(3), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) {
      s.publish("TEST_OUT", out(s.step()));
      throw std::runtime_error("a bug");
    };
  });
  spin();
  EXPECT_EQ(computed, 1);
  EXPECT_EQ(ackedSteps(), (std::vector<std::int64_t>{0, 1, 2, 3}));
  ASSERT_EQ(acks_.size(), 4u);
  EXPECT_EQ(acks_[0].outputs, 1);
  EXPECT_EQ(acks_[1].outputs, 0);
  EXPECT_EQ(acks_[3].outputs, 1);
  EXPECT_EQ(rt_.counters().rejected, 1);  // the work's exception
}

TEST_F(StepNodeTest, AcksGoOutInStepOrderWhateverFinishesFirst) {
  StepNode node(rt_, StepNodeOptions{});
  std::vector<StepNode::Step> held;
  node.open("world", "IN", msg(0), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) { held.push_back(s); };  // answered later (a request/reply)
  });
  node.open("world", "IN", msg(1), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) { s.publish("TEST_OUT", out(1)); };
  });
  EXPECT_THROW(
      node.open("world", "IN", msg(2), [&]() -> StepNode::Work { throw DroppedMessage("stale"); }),
      DroppedMessage);
  spin();
  EXPECT_TRUE(acks_.empty()) << "step 0 is still being answered";
  held.front().publish("TEST_OUT", out(0));
  held.clear();  // the last handle goes: step 0 is finished
  spin();
  EXPECT_EQ(ackedSteps(), (std::vector<std::int64_t>{0, 1, 2}));
}

TEST_F(StepNodeTest, ARepeatIsAnsweredFromTheKeptOutputsNeverComputedAgain) {
  StepNode node(rt_, StepNodeOptions{});
  int computed = 0;
  auto prepare = [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) {
      ++computed;
      s.publish("TEST_OUT", out(s.step()));
    };
  };
  node.open("world", "IN", msg(0), prepare);
  node.open("world", "IN", msg(1), prepare);
  spin();
  acks_.clear();
  status_steps_.clear();
  node.open("world", "IN", msg(1), prepare);  // the world re-published step 1
  spin();
  EXPECT_EQ(computed, 2);
  EXPECT_EQ(ackedSteps(), (std::vector<std::int64_t>{0, 1})) << "steps k-1 and k again";
  EXPECT_EQ(status_steps_, (std::vector<std::int64_t>{0, 1})) << "with their outputs";
  EXPECT_EQ(rt_.counters().dropped, 1);
}

TEST_F(StepNodeTest, SameBytesRepeatsAllowAnOldStepWithOtherContent) {
  StepNodeOptions o;
  o.repeat = StepNodeOptions::Repeat::kSameBytes;
  StepNode node(rt_, o);
  int computed = 0;
  auto prepare = [&]() -> StepNode::Work { return [&](StepNode::Step&) { ++computed; }; };
  node.open("world", "IN", msg(5), prepare);
  node.open("world", "IN", msg(5), prepare);  // the same bytes: a repeat
  FakeMsg other = msg(3);
  node.open("world", "IN", other, prepare);  // an old step, other content: computed
  spin();
  EXPECT_EQ(computed, 2);
}

TEST_F(StepNodeTest, AStepWaitsForItsCountedInputsAndStoresEachOnce) {
  StepNodeOptions o;
  o.requirements = {{"peer", -1, {"PEER_OUT"}}};
  StepNode node(rt_, o);
  int stored = 0;
  std::vector<std::int64_t> ran;
  // The peer acknowledged step 0 with two messages on PEER_OUT.
  step_ack_t a{};
  a.utime = 1;
  a.step = 0;
  a.participant = "peer";
  a.output_channels = {"PEER_OUT"};
  a.output_counts = {2};
  a.num_outputs = 1;
  rt_.publish(channels::kStepAck, a);
  spin();
  node.open("world", "IN", msg(1), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) { ran.push_back(s.step()); };
  });
  node.input("peer", "PEER_OUT", 0, "a", [&] { ++stored; });
  EXPECT_TRUE(ran.empty()) << "one of two inputs of step 0";
  node.input("peer", "PEER_OUT", 0, "a", [&] { ++stored; });  // a repeat
  EXPECT_TRUE(ran.empty());
  // An input that fails to store still counts as received: the step is not held for it.
  EXPECT_THROW(node.input("peer", "PEER_OUT", 0, "b", [&] { throw RejectedMessage("bad"); }),
               RejectedMessage);
  EXPECT_EQ(ran, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(stored, 1);
  EXPECT_EQ(rt_.counters().dropped, 1);
  spin();
  EXPECT_EQ(ackedSteps(), (std::vector<std::int64_t>{1}));
}

TEST_F(StepNodeTest, StepsBelowMinusOneAreRejected) {
  StepNode node(rt_, StepNodeOptions{});
  EXPECT_THROW(node.open("world", "IN", msg(-2), [&]() -> StepNode::Work { return nullptr; }),
               RejectedMessage);
  EXPECT_THROW(node.input("peer", "X", -7, "k", [] {}), RejectedMessage);
  spin();
  EXPECT_TRUE(acks_.empty());
}

TEST_F(StepNodeTest, FreeRunningWorkRunsAtOnceAndIsNeverAcknowledged) {
  StepNode node(rt_, StepNodeOptions{});
  int computed = 0;
  node.open("world", "IN", msg(-1), [&]() -> StepNode::Work {
    return [&](StepNode::Step& s) {
      ++computed;
      s.publish("TEST_OUT", out(-1));
    };
  });
  spin();
  EXPECT_EQ(computed, 1);
  EXPECT_TRUE(acks_.empty());
  EXPECT_EQ(status_steps_, (std::vector<std::int64_t>{-1}));
}

}  // namespace
}  // namespace coopnav
