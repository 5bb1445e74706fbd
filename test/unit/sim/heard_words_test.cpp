// Words said to the simulated people until the step that applies them (lib/sim
// heard_words.hpp): the time bounds, at most so many unended utterances per person (counting the
// simulation's), the group hearing them too, and words that ended early heard at the step.
#include "coopnav/sim/heard_words.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace coopnav::sim {
namespace {

WorldSpec twoPeople() {
  WorldSpec w;
  w.robot.start = {0.0, 3.0, 0.0};
  w.robot.goal = {50.0, 3.0, 0.0};
  w.settings.time_limit_s = 100.0;
  for (const std::int32_t id : {1, 2}) {
    HumanSpec h;
    h.id = id;
    h.start = {40.0, 2.0 + id, 3.14159};
    h.goal = {0.0, 2.0 + id, 3.14159};
    w.humans.push_back(h);
  }
  return w;
}

Cue cueFor(std::int32_t id, double t_s) {
  Cue c;
  c.human_id = id;
  c.kind = CueKind::kKeepSide;
  c.side = Side::kLeft;
  c.t_s = t_s;
  return c;
}

TEST(HeardWords, WordsEndingTooFarAheadOrLongAgoAreNotKept) {
  const Simulation sim(twoPeople(), nullptr);
  HeardWords words;
  EXPECT_EQ(words.offer(cueFor(1, 10.1), 3, {}, 5.0, 5.0, 30.0, sim),
            HeardWords::Verdict::kEndsTooFarAhead);
  EXPECT_EQ(words.offer(cueFor(1, -25.1), 3, {}, 5.0, 5.0, 30.0, sim),
            HeardWords::Verdict::kEndedTooLongAgo);
  Cue nan = cueFor(1, 0.0);
  nan.t_s = std::nan("");
  EXPECT_EQ(words.offer(nan, 3, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kEndsTooFarAhead);
  EXPECT_EQ(words.size(), 0U);
  EXPECT_EQ(words.offer(cueFor(1, 10.0), 3, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  EXPECT_EQ(words.size(), 1U);
}

TEST(HeardWords, AGroupHearsTheWordsEachWhileItHasRoom) {
  const Simulation sim(twoPeople(), nullptr);
  HeardWords words(2);
  EXPECT_EQ(words.offer(cueFor(2, 6.0), 1, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  EXPECT_EQ(words.offer(cueFor(2, 6.5), 1, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  // Said to 1 with 2 in its group: 2 has two unended utterances already, 1 gets it.
  EXPECT_EQ(words.offer(cueFor(1, 7.0), 2, {2}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  EXPECT_EQ(words.size(), 3U);
  EXPECT_EQ(words.offer(cueFor(2, 7.5), 2, {1}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kFull);
  EXPECT_EQ(words.offer(cueFor(1, 7.5), 2, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  EXPECT_EQ(words.offer(cueFor(1, 8.0), 2, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kFull);
}

TEST(HeardWords, TheSimulationsUnendedCuesCountToo) {
  Simulation sim(twoPeople(), nullptr);
  sim.addCue(cueFor(1, 50.0));
  HeardWords words(1);
  EXPECT_EQ(words.offer(cueFor(1, 6.0), 1, {}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kFull);
  EXPECT_EQ(words.offer(cueFor(2, 6.0), 1, {1}, 5.0, 5.0, 30.0, sim), HeardWords::Verdict::kKept);
  EXPECT_EQ(words.size(), 1U);  // 1 has no room: only 2 hears it
}

TEST(HeardWords, TakeGivesTheCuesInOrderHeardNoEarlierThanNow) {
  const Simulation sim(twoPeople(), nullptr);
  HeardWords words;
  words.offer(cueFor(1, 4.2), 41, {2}, 5.0, 5.0, 30.0, sim);  // ended before this step
  words.offer(cueFor(2, 6.0), 42, {}, 5.0, 5.0, 30.0, sim);
  const auto taken = words.take(5.0);
  ASSERT_EQ(taken.size(), 3U);
  EXPECT_EQ(taken[0].cue.human_id, 1);
  EXPECT_DOUBLE_EQ(taken[0].cue.t_s, 5.0);
  EXPECT_EQ(taken[0].step, 41);
  EXPECT_EQ(taken[1].cue.human_id, 2);
  EXPECT_DOUBLE_EQ(taken[1].cue.t_s, 5.0);
  EXPECT_EQ(taken[2].cue.human_id, 2);
  EXPECT_DOUBLE_EQ(taken[2].cue.t_s, 6.0);
  EXPECT_EQ(taken[2].step, 42);
  EXPECT_EQ(words.size(), 0U);
  EXPECT_TRUE(words.take(6.0).empty());
}

}  // namespace
}  // namespace coopnav::sim
