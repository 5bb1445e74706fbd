// Words against actions (tools/ctl/action_words.hpp): a dock after "I am passing on your right."
// without words of making room is a contradiction; with them, or after words that already said
// the robot may wait, it is not; words decided but too late to say are listed apart.
#include "action_words.hpp"

#include <gtest/gtest.h>

namespace coopnav::ctl {
namespace {

utterance_t say(double t_s, std::int32_t human, std::int8_t act,
                std::int8_t delivery = utterance_t::DELIVERY_SAID,
                std::vector<std::int32_t> group = {}) {
  utterance_t u{};
  u.utime = static_cast<std::int64_t>(t_s * 1e6);
  u.step = -1;
  u.human_id = human;
  u.speech_act = act;
  u.direction = situation_t::DIR_RIGHT;
  u.round = act == utterance_t::ACT_INFORM_DIRECTION ? 1 : 2;
  u.text = "words";
  u.delivery = delivery;
  u.n_group = static_cast<std::int16_t>(group.size());
  u.group_ids = std::move(group);
  return u;
}

robot_action_t dock(double t_s, std::int32_t human) {
  robot_action_t a{};
  a.utime = static_cast<std::int64_t>(t_s * 1e6);
  a.step = -1;
  a.action = robot_action_t::ACTION_DOCK;
  a.human_id = human;
  a.reason = "robot constrained";
  return a;
}

TEST(ActionWords, ADockAfterSayingThePassWithoutWordsContradictsThem) {
  RunLog run;
  run.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION));
  run.actions.push_back(dock(10.5, 1));
  const ActionWordsCheck c = checkActionWords(run);
  ASSERT_EQ(c.contradictions.size(), 1U);
  EXPECT_NE(c.contradictions[0].find("10.50 s human 1 DOCK: told INFORM_DIRECTION"),
            std::string::npos)
      << c.contradictions[0];
  EXPECT_TRUE(c.unsaid_too_late.empty());
}

// Going first (a stand-off's end, the person waiting for the robot) comes with its words:
// "Thank you, I will go first." decided with it; silent, or after "I will wait here" with
// nothing new, it contradicts what the person was told or leaves them guessing.
TEST(ActionWords, GoingFirstComesWithWordsOfGoing) {
  robot_action_t go = dock(20.0, 1);
  go.action = robot_action_t::ACTION_GO_FIRST;
  RunLog said;
  said.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DOCK_IF_NEEDED));
  said.actions.push_back(go);
  said.utterances.push_back(say(20.0, 1, utterance_t::ACT_INFORM_GOING_FIRST));
  EXPECT_TRUE(checkActionWords(said).contradictions.empty());
  RunLog silent;
  silent.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DOCK_IF_NEEDED));
  silent.actions.push_back(go);
  const ActionWordsCheck c = checkActionWords(silent);
  ASSERT_EQ(c.contradictions.size(), 1U);
  EXPECT_NE(c.contradictions[0].find("GO_FIRST: told INFORM_DOCK_IF_NEEDED"), std::string::npos)
      << c.contradictions[0];
  EXPECT_NE(c.contradictions[0].find("no words of going"), std::string::npos);
  RunLog nothing_before;
  nothing_before.actions.push_back(go);
  EXPECT_EQ(checkActionWords(nothing_before).contradictions.size(), 1U);
}

TEST(ActionWords, ToldToTheGroupCountsForEveryMember) {
  RunLog run;
  // Said to human 1 addressed to the pair {1, 2}; the dock is for human 2.
  run.utterances.push_back(
      say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION, utterance_t::DELIVERY_SAID, {2}));
  run.actions.push_back(dock(10.5, 2));
  EXPECT_EQ(checkActionWords(run).contradictions.size(), 1U);
}

TEST(ActionWords, WordsOfMakingRoomWithTheDockOrBeforeItAgree) {
  RunLog with;
  with.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION));
  with.actions.push_back(dock(10.5, 1));
  with.utterances.push_back(say(10.5, 1, utterance_t::ACT_INFORM_DOCKING));
  EXPECT_TRUE(checkActionWords(with).contradictions.empty());

  RunLog before;  // "It is narrow here. I will wait at the side if needed." then a dock
  before.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DOCK_IF_NEEDED));
  before.actions.push_back(dock(14.0, 1));
  EXPECT_TRUE(checkActionWords(before).contradictions.empty());

  RunLog nothing_told;  // a muted run: nothing said, nothing contradicted
  nothing_told.utterances.push_back(
      say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION, utterance_t::DELIVERY_MUTED));
  nothing_told.actions.push_back(dock(10.5, 1));
  EXPECT_TRUE(checkActionWords(nothing_told).contradictions.empty());

  RunLog late;  // words decided a second after the dock do not come with it
  late.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION));
  late.actions.push_back(dock(10.5, 1));
  late.utterances.push_back(say(11.5, 1, utterance_t::ACT_INFORM_DOCKING));
  EXPECT_EQ(checkActionWords(late).contradictions.size(), 1U);
}

TEST(ActionWords, WordsTooLateToSayAreListedApartNotAsAContradiction) {
  RunLog run;
  run.utterances.push_back(say(10.0, 1, utterance_t::ACT_INFORM_DIRECTION));
  run.actions.push_back(dock(10.5, 1));
  run.utterances.push_back(
      say(10.5, 1, utterance_t::ACT_INFORM_DOCKING, utterance_t::DELIVERY_TOO_LATE));
  const ActionWordsCheck c = checkActionWords(run);
  EXPECT_TRUE(c.contradictions.empty());
  ASSERT_EQ(c.unsaid_too_late.size(), 1U);
  EXPECT_NE(c.unsaid_too_late[0].find("INFORM_DOCKING not said: too late"), std::string::npos)
      << c.unsaid_too_late[0];
}

}  // namespace
}  // namespace coopnav::ctl
