// JumpGuard / MessageClock (daemons/common/runtime/message_clock.hpp): the time and step guard
// every daemon keeps against messages stamped far away.
#include "runtime/message_clock.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

using V = JumpGuard::Verdict;
constexpr std::int64_t kS = 1'000'000;  // 1 s in utime

TEST(MessageClockTest, OrdinaryTimeMovesForwardAndSmallRegressionsAreBackwards) {
  MessageClock clock(60.0, 3);
  EXPECT_FALSE(clock.now());
  EXPECT_EQ(clock.offer(10 * kS), V::kAccepted);
  EXPECT_EQ(clock.offer(11 * kS), V::kAccepted);
  EXPECT_EQ(clock.offer(11 * kS), V::kAccepted);  // equal: no move, no complaint
  EXPECT_EQ(clock.offer(9 * kS), V::kBackwards);
  EXPECT_EQ(*clock.now(), 11 * kS);
  EXPECT_EQ(clock.offer(70 * kS), V::kAccepted);  // 59 s: within the jump limit
}

TEST(MessageClockTest, OneMessageFarAheadIsRefusedAndDoesNotMoveTheClock) {
  MessageClock clock(60.0, 3);
  clock.offer(10 * kS);
  EXPECT_EQ(clock.offer(std::numeric_limits<std::int64_t>::max()), V::kJump);
  EXPECT_EQ(*clock.now(), 10 * kS);
  EXPECT_EQ(clock.offer(10 * kS + 100'000), V::kAccepted);  // normal traffic goes on
  EXPECT_NE(clock.describe(std::numeric_limits<std::int64_t>::max()).find("after the clock"),
            std::string::npos);
}

TEST(MessageClockTest, AClockPinnedByAFirstBadMessageFollowsAgreeingTrafficAfterResyncMessages) {
  MessageClock clock(60.0, 3);
  EXPECT_EQ(clock.offer(std::numeric_limits<std::int64_t>::max()), V::kAccepted);  // no clock yet
  EXPECT_EQ(clock.offer(5 * kS), V::kJump);
  EXPECT_EQ(clock.offer(5 * kS + 100'000), V::kJump);
  EXPECT_EQ(clock.offer(5 * kS + 200'000), V::kResynced);
  EXPECT_EQ(*clock.now(), 5 * kS + 200'000);
  EXPECT_EQ(clock.offer(5 * kS + 300'000), V::kAccepted);
}

TEST(MessageClockTest, ScatteredFarValuesNeverAgreeAndNeverMoveTheClock) {
  MessageClock clock(60.0, 3);
  clock.offer(0);
  for (int i = 0; i < 20; ++i) {
    // Alternating far ahead and far behind: no run of three agreeing values.
    const std::int64_t v = (i % 2 == 0 ? 1 : -1) * (1000 + i) * kS;
    EXPECT_EQ(clock.offer(v), V::kJump) << i;
  }
  EXPECT_EQ(*clock.now(), 0);
}

TEST(MessageClockTest, AnInClockMessageBreaksARunOfFarOnes) {
  MessageClock clock(60.0, 3);
  clock.offer(0);
  EXPECT_EQ(clock.offer(1000 * kS), V::kJump);
  EXPECT_EQ(clock.offer(1001 * kS), V::kJump);
  EXPECT_EQ(clock.offer(kS), V::kAccepted);  // the run is broken
  EXPECT_EQ(clock.offer(1002 * kS), V::kJump);
  EXPECT_EQ(*clock.now(), kS);
}

TEST(MessageClockTest, TakeRejectsAJumpCallsBackOnAResyncAndTellsBehind) {
  MessageClock clock(60.0, 2);
  int resyncs = 0;
  const auto resync = [&] { ++resyncs; };
  EXPECT_TRUE(clock.take(10 * kS, "agent states", resync));
  EXPECT_TRUE(clock.take(11 * kS, "agent states", resync));
  EXPECT_FALSE(clock.take(10 * kS, "agent states", resync));  // a little behind: the caller's call
  try {
    clock.take(1000 * kS, "agent states", resync);
    ADD_FAILURE() << "a jump is rejected";
  } catch (const RejectedMessage& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("agent states: utime 1000000000 is ", 0), 0U) << what;
    EXPECT_NE(what.find("(over limits.max_time_jump_s)"), std::string::npos) << what;
  }
  EXPECT_EQ(*clock.now(), 11 * kS);
  EXPECT_EQ(resyncs, 0);
  EXPECT_TRUE(clock.take(1001 * kS, "agent states", resync));  // two agreeing: a new time line
  EXPECT_EQ(resyncs, 1);
  EXPECT_EQ(*clock.now(), 1001 * kS);
  EXPECT_TRUE(clock.take(1002 * kS, "goals"));  // no callback needed
}

TEST(JumpGuardTest, StepsUseTheSameRuleInStepUnits) {
  JumpGuard steps(256, 3);
  steps.offer(0);
  EXPECT_EQ(steps.offer(1), V::kAccepted);
  EXPECT_EQ(steps.offer(1LL << 62), V::kJump);
  EXPECT_EQ(steps.offer(2), V::kAccepted);
  // A new run from step 0 after a long one: followed after three of its steps.
  JumpGuard run(256, 3);
  run.offer(900);
  EXPECT_EQ(run.offer(0), V::kJump);
  EXPECT_EQ(run.offer(0), V::kJump);  // a repeat counts: the world re-publishes a step
  EXPECT_EQ(run.offer(1), V::kResynced);
  EXPECT_EQ(*run.now(), 1);
  // Values at the ends of int64 never overflow.
  JumpGuard ends(256, 2);
  ends.offer(std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(ends.offer(std::numeric_limits<std::int64_t>::max()), V::kJump);
}

}  // namespace
}  // namespace coopnav
