// Speaking to several people (crowd.hpp): groups, addresses, one plan per group, no contradiction
// while the robot makes room; and the decision's crossing gate (DecisionConfig::crossing_range_m).
#include "coopnav/dialogue/crowd.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "coopnav/dialogue/decision.hpp"

namespace coopnav::dialogue {
namespace {

CrowdMember member(std::int32_t id, double x, double y, double vx = -1.0, double vy = 0.0) {
  return {id, {x, y}, {vx, vy}};
}

Utterance said(SpeechAct act, Side dir, int round) {
  return {act, dir, round, renderText(TextTemplates{}, act, dir)};
}

const Pose2 kRobot{0.0, 0.0, 0.0};  // at the origin, facing +x: +y is its left

TEST(CrowdGroups, NearAndMovingAlikeAreOneGroupChainedThroughNeighbours) {
  // 1-2-3 abreast 0.8 m apart at the same velocity (3 is 1.6 m from 1: linked through 2); 4 near
  // 3 but walking the other way; 5 alone far off.
  const std::vector<CrowdMember> scene{member(3, 8.0, 1.6), member(1, 8.0, 0.0),
                                       member(2, 8.0, 0.8), member(4, 8.5, 2.2, 1.0),
                                       member(5, 20.0, 0.0)};
  const auto groups = findGroups(scene, {});
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[0], (std::vector<std::int32_t>{1, 2, 3}));
  EXPECT_EQ(groups[1], (std::vector<std::int32_t>{4}));
  EXPECT_EQ(groups[2], (std::vector<std::int32_t>{5}));
}

TEST(CrowdGroups, StandingTogetherIsAGroupAndAPasserByIsNot) {
  const std::vector<CrowdMember> scene{member(1, 5.0, 2.0, 0.0), member(2, 5.0, 2.9, 0.0),
                                       member(3, 5.5, 1.5, -1.0)};
  const auto groups = findGroups(scene, {});
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0], (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(groups[1], (std::vector<std::int32_t>{3}));
}

TEST(CrowdAddress, BearingAndCountNameTheAddressees) {
  const CrowdConfig c;
  EXPECT_EQ(addressPhrase(kRobot, {{5.0, 0.5}}, c), "You ahead");
  EXPECT_EQ(addressPhrase(kRobot, {{5.0, 3.0}}, c), "You on my left");
  EXPECT_EQ(addressPhrase(kRobot, {{5.0, -3.0}}, c), "You on my right");
  EXPECT_EQ(addressPhrase(kRobot, {{5.0, -3.0}, {5.0, -3.8}}, c), "You two on my right");
  std::vector<Eigen::Vector2d> six(6, Eigen::Vector2d{4.0, 0.0});
  EXPECT_EQ(addressPhrase(kRobot, six, c), "All of you ahead");
  // The robot's heading turns the frame: facing +y, a person at +y is ahead, at +x on the right.
  const Pose2 facing_y{0.0, 0.0, 1.5707963267948966};
  EXPECT_EQ(addressPhrase(facing_y, {{0.0, 5.0}}, c), "You ahead");
  EXPECT_EQ(addressPhrase(facing_y, {{5.0, 1.0}}, c), "You on my right");
}

TEST(CrowdConversation, AloneTheWordsAreThePapersUnaddressed) {
  CrowdConversation conv;
  const auto out = conv.coordinate(kRobot, {member(1, 8.0, 0.0)},
                                   {{1, said(SpeechAct::kInformDirection, Side::kLeft, 1)}}, false);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
  EXPECT_EQ(out[0].utterance.text, "I will pass on your left.");
  EXPECT_TRUE(out[0].group.empty());
}

TEST(CrowdConversation, SeveralPeopleHearWhomTheWordsAreFor) {
  CrowdConversation conv;
  const auto out = conv.coordinate(kRobot, {member(1, 8.0, 4.0), member(2, 15.0, -7.0)},
                                   {{2, said(SpeechAct::kAskToMove, Side::kLeft, 1)},
                                    {1, said(SpeechAct::kThank, Side::kUndefined, 3)}},
                                   false);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].human_id, 1);  // by id
  EXPECT_EQ(out[0].utterance.text, "You on my left, thank you.");
  EXPECT_EQ(out[1].utterance.text,
            "You on my right, it is narrow here. Could you move to your left, please?");
}

TEST(CrowdConversation, AGroupIsToldOncePerRoundAndNeverToPartToBothSides) {
  CrowdConversation conv;
  // 1 and 2 walk abreast (0.8 m apart, same velocity); 3 is alone on the other side.
  const std::vector<CrowdMember> scene{member(1, 8.0, 3.0), member(2, 8.0, 3.8),
                                       member(3, 12.0, -2.0)};
  auto out = conv.coordinate(kRobot, scene,
                             {{1, said(SpeechAct::kInformDirection, Side::kLeft, 1)}}, false);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
  EXPECT_EQ(out[0].group, (std::vector<std::int32_t>{2}));
  EXPECT_EQ(out[0].utterance.text, "You two on my left, I will pass on your left.");
  // A step later 2's own round 1: the same plan (robot on their left) -> already told; asking 2
  // to move to its left (the robot passing on its right) would split the group -> not said.
  out = conv.coordinate(kRobot, scene, {{2, said(SpeechAct::kAskToMove, Side::kRight, 1)}}, false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kToldToGroup);
  out = conv.coordinate(kRobot, scene, {{2, said(SpeechAct::kAskToMove, Side::kLeft, 1)}}, false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kContradicts);
  EXPECT_NE(out[0].reason.find("human 1"), std::string::npos);
  // The same act with the other side parts the group too (the robot's band through it).
  out = conv.coordinate(kRobot, scene, {{2, said(SpeechAct::kInformDirection, Side::kRight, 1)}},
                        false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kContradicts);
  // The lone human 3 is told its own side, whatever the group heard.
  out = conv.coordinate(kRobot, scene, {{3, said(SpeechAct::kInformDirection, Side::kRight, 1)}},
                        false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
  // Round 2 is a new round: the group hears it once more.
  out = conv.coordinate(kRobot, scene, {{2, said(SpeechAct::kRepeatDirection, Side::kLeft, 2)}},
                        false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
  EXPECT_EQ(out[0].group, (std::vector<std::int32_t>{1}));
}

TEST(CrowdConversation, MakingRoomForOneNobodyIsToldTheRobotPasses) {
  CrowdConversation conv;
  const std::vector<CrowdMember> scene{member(1, 4.0, 0.0), member(2, 12.0, 1.5)};
  // The same step: 1's dock and 2's round 1. The dock is judged first and said; 2 is not told
  // that the robot passes it (the robot is about to wait at the wall).
  const auto out = conv.coordinate(kRobot, scene,
                                   {{2, said(SpeechAct::kInformDirection, Side::kRight, 1)},
                                    {1, said(SpeechAct::kInformDocking, Side::kUndefined, 2)}},
                                   true);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].human_id, 1);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
  EXPECT_EQ(out[1].verdict, CrowdVerdict::kContradicts);
  // What does not say the robot passes is still said: a thanks, a dock-if-needed.
  const auto later = conv.coordinate(
      kRobot, scene, {{2, said(SpeechAct::kInformDockIfNeeded, Side::kUndefined, 1)}}, true);
  EXPECT_EQ(later[0].verdict, CrowdVerdict::kSay);
}

TEST(CrowdConversation, AForgottenHumanBindsNobody) {
  CrowdConversation conv;
  const std::vector<CrowdMember> scene{member(1, 8.0, 1.0), member(2, 8.0, 1.8)};
  conv.coordinate(kRobot, scene, {{1, said(SpeechAct::kInformDirection, Side::kLeft, 1)}}, false);
  conv.forget(1);
  conv.forget(2);
  const auto out =
      conv.coordinate(kRobot, scene, {{2, said(SpeechAct::kAskToMove, Side::kLeft, 1)}}, false);
  EXPECT_EQ(out[0].verdict, CrowdVerdict::kSay);
}

// ---- the crossing gate of the decision ----

DecisionInput crossingInput(double t_s, double t_cross_s, double d_hr_m) {
  DecisionInput in;
  in.t_s = t_s;
  in.situation.t_cross_s = t_cross_s;
  in.situation.d_hr_m = d_hr_m;
  in.situation.human_needs_to_contribute = Tristate::kTrue;
  in.situation.robot_is_constrained = Tristate::kFalse;
  in.situation.human_is_constrained = Tristate::kFalse;
  in.situation.dir = Side::kLeft;
  in.situation.d_h_m = 0.5;
  return in;
}

TEST(CrossingGate, NoInteractionWithSomeoneMovingApartOrPassedFarOff) {
  HumanDecision apart;
  // t_CROSS 0: the closest approach is now (walking away, or alongside): never a round.
  for (int i = 0; i < 30; ++i) EXPECT_TRUE(apart.step(crossingInput(0.1 * i, 0.0, 1.0)).empty());
  EXPECT_FALSE(apart.roundFired(1));
  HumanDecision far;
  for (int i = 0; i < 30; ++i) EXPECT_TRUE(far.step(crossingInput(0.1 * i, 6.0, 4.0)).empty());
  EXPECT_FALSE(far.roundFired(1));
  // Coming nearer later: the interaction begins then.
  const auto out = far.step(crossingInput(3.0, 5.5, 2.0));
  EXPECT_TRUE(far.roundFired(1));
  ASSERT_EQ(out.utterances.size(), 1u);
  EXPECT_EQ(out.utterances[0].act, SpeechAct::kInformDirection);
}

TEST(CrossingGate, AnUnknownPassingDistanceDoesNotHoldThePapersRoundBack) {
  HumanDecision d;
  DecisionInput in = crossingInput(0.0, 6.5, 0.0);
  in.situation.d_hr_m.reset();
  d.step(in);
  EXPECT_TRUE(d.roundFired(1));
}

}  // namespace
}  // namespace coopnav::dialogue
