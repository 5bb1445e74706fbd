// The words behind a person ahead walking the robot's way: silent while following, "Excuse me, I
// will pass on your left." once in the lane beside them and near, then GO_FIRST once said.

#include "coopnav/dialogue/overtake_words.hpp"

#include <gtest/gtest.h>

namespace coopnav::dialogue {
namespace {

constexpr double kRobotRadius_m = 0.47;

SameWayPerson person(double gap_m, double lateral_m) {
  SameWayPerson p;
  p.id = 2;
  p.radius_m = 0.3;
  p.lateral_m = lateral_m;
  p.along_m = gap_m + 0.77;
  p.gap_m = gap_m;
  p.speed_along_m_s = 0.5;
  p.robot_side =
      lateral_m < -0.01 ? Side::kLeft : (lateral_m > 0.01 ? Side::kRight : Side::kUndefined);
  return p;
}

OvertakeWords::Input at(double t_s, std::optional<SameWayPerson> p,
                        std::optional<double> heard_by_s = std::nullopt) {
  OvertakeWords::Input in;
  in.t_s = t_s;
  in.person = p;
  in.robot_radius_m = kRobotRadius_m;
  in.heard_by_s = heard_by_s;
  return in;
}

TEST(OvertakeWordsTest, SilentWhileFollowingBehindOrFar) {
  OvertakeWords w;
  const OvertakeWordsConfig c;
  const TextTemplates t;
  EXPECT_TRUE(w.step(at(0.0, person(1.2, 0.0)), c, t).empty());   // straight behind
  EXPECT_TRUE(w.step(at(0.1, person(1.2, 0.9)), c, t).empty());   // clears by 0.13 < 0.2
  EXPECT_TRUE(w.step(at(0.2, person(3.5, -1.1)), c, t).empty());  // in the lane, too far
  EXPECT_TRUE(w.step(at(0.3, std::nullopt), c, t).empty());
  EXPECT_FALSE(w.engaged());
}

TEST(OvertakeWordsTest, SaysTheSideThenPassesOnceTheWordsAreSaid) {
  OvertakeWords w;
  const OvertakeWordsConfig c;
  const TextTemplates t;
  // The person 1.02 m to the robot's right: the robot, in the lane, is on their left.
  const DecisionOutput said = w.step(at(10.0, person(1.2, -1.02)), c, t);
  ASSERT_EQ(said.utterances.size(), 1U);
  EXPECT_EQ(said.utterances[0].act, SpeechAct::kInformDirection);
  EXPECT_EQ(said.utterances[0].direction, Side::kLeft);
  EXPECT_EQ(said.utterances[0].round, 1);
  EXPECT_EQ(said.utterances[0].text, "Excuse me, I will pass on your left.");
  EXPECT_TRUE(said.robot_actions.empty());  // words first
  ASSERT_EQ(said.rounds.size(), 1U);
  EXPECT_NE(said.rounds[0].branch.find("overtake:"), std::string::npos);
  EXPECT_TRUE(w.engaged());
  // Still being said (they end at 11.8 s): no action yet, and nothing said again.
  EXPECT_TRUE(w.step(at(10.1, person(1.2, -1.02), 11.8), c, t).empty());
  EXPECT_TRUE(w.step(at(11.7, person(1.1, -1.02), 11.8), c, t).empty());
  const DecisionOutput go = w.step(at(11.8, person(1.1, -1.02), 11.8), c, t);
  ASSERT_EQ(go.robot_actions.size(), 1U);
  EXPECT_EQ(go.robot_actions[0], RobotAction::kGoFirst);
  EXPECT_TRUE(go.utterances.empty());
  EXPECT_NE(go.rounds.at(0).branch.find("overtake:"), std::string::npos);
  EXPECT_EQ(w.state(), OvertakeWords::State::kPassing);
  // Once: passing, nothing more.
  EXPECT_TRUE(w.step(at(12.0, person(0.5, -1.02), 11.8), c, t).empty());
  EXPECT_TRUE(w.step(at(20.0, std::nullopt, 11.8), c, t).empty());
}

TEST(OvertakeWordsTest, MutedPassesAtOnceAndTheWordsFollowTheTemplates) {
  OvertakeWords w;
  OvertakeWordsConfig c;
  c.text = "Pardon, {dir} side, {dir}.";
  TextTemplates t;
  t.right_word = "droite";
  const DecisionOutput said = w.step(at(3.0, person(2.0, 1.1)), c, t);
  ASSERT_EQ(said.utterances.size(), 1U);
  EXPECT_EQ(said.utterances[0].direction, Side::kRight);
  EXPECT_EQ(said.utterances[0].text, "Pardon, droite side, droite.");
  // Nothing heard, muted: the next step passes as if it had been said.
  OvertakeWords::Input muted = at(3.1, person(2.0, 1.1));
  muted.muted = true;
  EXPECT_EQ(w.step(muted, c, t).robot_actions.size(), 1U);
}

TEST(OvertakeWordsTest, WordsNotSaidAreNoPassAndNothingWhileMakingRoom) {
  OvertakeWords w;
  const OvertakeWordsConfig c;
  const TextTemplates t;
  // The robot makes room for someone else: nothing announced.
  OvertakeWords::Input docked = at(1.0, person(1.2, -1.02));
  docked.robot_making_room = true;
  EXPECT_TRUE(w.step(docked, c, t).empty());
  ASSERT_EQ(w.step(at(2.0, person(1.2, -1.02)), c, t).utterances.size(), 1U);
  // Not said (heard_by_s not after the words were decided, not muted): no GO_FIRST, following.
  const DecisionOutput none = w.step(at(2.1, person(1.2, -1.02), 1.5), c, t);
  EXPECT_TRUE(none.robot_actions.empty());
  EXPECT_TRUE(none.utterances.empty());
  EXPECT_FALSE(w.engaged());
  // Said again no sooner than retry_s later.
  EXPECT_TRUE(w.step(at(4.0, person(1.2, -1.02), 1.5), c, t).empty());
  EXPECT_EQ(w.step(at(5.2, person(1.2, -1.02), 1.5), c, t).utterances.size(), 1U);
}

}  // namespace
}  // namespace coopnav::dialogue
