// conversions_dialogue: utterance_t / robot_action_t <-> lib/dialogue, and the DIR / PRED codes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "wire/dialogue.hpp"

namespace coopnav {
namespace {

using dialogue::RobotAction;
using dialogue::SpeechAct;

TEST(ConversionsDialogue, SideAndPredicateCodesRoundTripAndMatchTheWire) {
  for (Side s : {Side::kLeft, Side::kRight, Side::kUndefined})
    EXPECT_EQ(sideFromLcmDir(lcmDirFromSide(s)), s);
  EXPECT_EQ(lcmDirFromSide(Side::kLeft), situation_t::DIR_LEFT);
  EXPECT_EQ(lcmDirFromSide(Side::kRight), situation_t::DIR_RIGHT);
  for (Tristate t : {Tristate::kTrue, Tristate::kFalse, Tristate::kUnknown})
    EXPECT_EQ(tristateFromLcmPred(lcmPredFromTristate(t), "p"), t);
  EXPECT_EQ(lcmPredFromTristate(Tristate::kUnknown), situation_t::PRED_UNKNOWN);
  EXPECT_THROW(sideFromLcmDir(2), RejectedMessage);
  EXPECT_THROW(sideFromLcmDir(-2), RejectedMessage);
  EXPECT_THROW(tristateFromLcmPred(2, "p"), RejectedMessage);
  EXPECT_THROW(tristateFromLcmPred(-2, "p"), RejectedMessage);
}

TEST(ConversionsDialogue, LibEnumValuesMirrorTheWireConstants) {
  EXPECT_EQ(static_cast<int>(SpeechAct::kInformDirection), utterance_t::ACT_INFORM_DIRECTION);
  EXPECT_EQ(static_cast<int>(SpeechAct::kAskToMove), utterance_t::ACT_ASK_TO_MOVE);
  EXPECT_EQ(static_cast<int>(SpeechAct::kInformDockIfNeeded),
            utterance_t::ACT_INFORM_DOCK_IF_NEEDED);
  EXPECT_EQ(static_cast<int>(SpeechAct::kRepeatDirection), utterance_t::ACT_REPEAT_DIRECTION);
  EXPECT_EQ(static_cast<int>(SpeechAct::kAskToMoveMore), utterance_t::ACT_ASK_TO_MOVE_MORE);
  EXPECT_EQ(static_cast<int>(SpeechAct::kInformDocking), utterance_t::ACT_INFORM_DOCKING);
  EXPECT_EQ(static_cast<int>(SpeechAct::kThank), utterance_t::ACT_THANK);
  EXPECT_EQ(static_cast<int>(RobotAction::kDock), robot_action_t::ACTION_DOCK);
  EXPECT_EQ(static_cast<int>(RobotAction::kResume), robot_action_t::ACTION_RESUME);
  EXPECT_EQ(static_cast<int>(Side::kLeft), situation_t::DIR_LEFT);
  EXPECT_EQ(static_cast<int>(Side::kRight), situation_t::DIR_RIGHT);
}

TEST(ConversionsDialogue, UtteranceRoundTrip) {
  const DialogueStamp stamp{12'500'000, 125, 3};
  const dialogue::Utterance u{SpeechAct::kAskToMove, Side::kRight, 1,
                              "It is narrow here. Could you move to your right, please?"};
  const dialogue::SpeechSlot slot{dialogue::Delivery::kSaid, 0.4, 3.3};
  const utterance_t m = toLcm(stamp, u, 6.9, slot);
  EXPECT_EQ(m.utime, 12'500'000);
  EXPECT_EQ(m.step, 125);
  EXPECT_EQ(m.human_id, 3);
  EXPECT_EQ(m.speech_act, utterance_t::ACT_ASK_TO_MOVE);
  EXPECT_EQ(m.direction, situation_t::DIR_RIGHT);
  EXPECT_EQ(m.round, 1);
  EXPECT_DOUBLE_EQ(m.t_cross_s, 6.9);
  EXPECT_EQ(m.delivery, utterance_t::DELIVERY_SAID);
  EXPECT_DOUBLE_EQ(m.speech_start_s, 0.4);
  EXPECT_DOUBLE_EQ(m.speech_duration_s, 3.3);
  const UtteranceMsg back = fromLcm(m);
  EXPECT_EQ(back.slot.delivery, dialogue::Delivery::kSaid);
  EXPECT_DOUBLE_EQ(back.slot.start_s, 0.4);
  EXPECT_DOUBLE_EQ(back.slot.duration_s, 3.3);
  EXPECT_EQ(back.stamp.utime, stamp.utime);
  EXPECT_EQ(back.stamp.step, stamp.step);
  EXPECT_EQ(back.stamp.human_id, stamp.human_id);
  EXPECT_EQ(back.utterance.act, u.act);
  EXPECT_EQ(back.utterance.direction, u.direction);
  EXPECT_EQ(back.utterance.round, 1);
  EXPECT_EQ(back.utterance.text, u.text);
  ASSERT_TRUE(back.t_cross_s.has_value());
  EXPECT_DOUBLE_EQ(*back.t_cross_s, 6.9);
}

TEST(ConversionsDialogue, GroupAndCrowdDeliveriesRoundTrip) {
  const utterance_t m =
      toLcm({5, 9, 2}, {SpeechAct::kInformDirection, Side::kRight, 1, "You two ahead, x"}, 6.0,
            {dialogue::Delivery::kSaid, 0.0, 1.5}, {3});
  EXPECT_EQ(m.n_group, 1);
  EXPECT_EQ(fromLcm(m).group, (std::vector<std::int32_t>{3}));
  for (const auto d : {dialogue::Delivery::kToldToGroup, dialogue::Delivery::kContradicts}) {
    const utterance_t n =
        toLcm({5, 9, 3}, {SpeechAct::kAskToMove, Side::kLeft, 1, "x"}, 6.0, {d, 0.0, 0.0}, {2});
    EXPECT_EQ(fromLcm(n).slot.delivery, d);
  }
}

TEST(ConversionsDialogue, RoundThreeHasNoTCrossOnTheWire) {
  const utterance_t m =
      toLcm({1, -1, 1}, {SpeechAct::kThank, Side::kUndefined, 3, "Thank you."}, std::nullopt, {});
  EXPECT_TRUE(std::isnan(m.t_cross_s));
  EXPECT_EQ(m.direction, situation_t::DIR_UNDEFINED);
  EXPECT_FALSE(fromLcm(m).t_cross_s.has_value());
}

TEST(ConversionsDialogue, BadUtterancesAreRejected) {
  const utterance_t good = toLcm({1, 4, 1}, {SpeechAct::kInformDirection, Side::kLeft, 1, "x"}, 7.0,
                                 {dialogue::Delivery::kTooLate, 0.0, 1.2});
  EXPECT_NO_THROW(fromLcm(good));
  auto bad = [&](auto mutate) {
    utterance_t m = good;
    mutate(m);
    return m;
  };
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.speech_act = 0; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.speech_act = 13; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.direction = 3; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.round = 0; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.round = 4; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.step = -2; })), RejectedMessage);
  EXPECT_THROW(
      fromLcm(bad([](utterance_t& m) { m.t_cross_s = std::numeric_limits<double>::infinity(); })),
      RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.delivery = 0; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.delivery = 6; })), RejectedMessage);
  // group_ids: the count must match, ids sorted and unique, never the human itself.
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.n_group = -1; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) {
                 m.group_ids = {2, 3};
                 m.n_group = 1;
               })),
               RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) {
                 m.group_ids = {3, 2};
                 m.n_group = 2;
               })),
               RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) {
                 m.group_ids = {1};  // human_id is 1
                 m.n_group = 1;
               })),
               RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) {
                 m.group_ids.assign(65, 0);
                 for (int i = 0; i < 65; ++i) m.group_ids[static_cast<std::size_t>(i)] = i + 2;
                 m.n_group = 65;
               })),
               RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.speech_duration_s = -0.1; })), RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.speech_start_s = std::nan(""); })),
               RejectedMessage);
  EXPECT_THROW(fromLcm(bad([](utterance_t& m) { m.speech_start_s = 1e9; })), RejectedMessage);
}

TEST(ConversionsDialogue, RobotActionRoundTripAndRejection) {
  const robot_action_t m = toLcm({4'000'000, 40, 2}, RobotAction::kDock, "round 2: dock");
  EXPECT_EQ(m.action, robot_action_t::ACTION_DOCK);
  EXPECT_EQ(m.human_id, 2);
  EXPECT_EQ(m.step, 40);
  const RobotActionMsg back = fromLcm(m);
  EXPECT_EQ(back.action, RobotAction::kDock);
  EXPECT_EQ(back.stamp.utime, 4'000'000);
  EXPECT_EQ(back.reason, "round 2: dock");
  const robot_action_t go = toLcm({4'000'000, 40, 2}, RobotAction::kGoFirst, "stand-off");
  EXPECT_EQ(go.action, robot_action_t::ACTION_GO_FIRST);
  EXPECT_EQ(fromLcm(go).action, RobotAction::kGoFirst);
  const robot_action_t slow = toLcm({4'000'000, 40, 2}, RobotAction::kSlow, "round 2 deferred");
  EXPECT_EQ(slow.action, robot_action_t::ACTION_SLOW);
  EXPECT_EQ(fromLcm(slow).action, RobotAction::kSlow);
  robot_action_t bad = m;
  bad.action = 5;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.step = -7;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
}

}  // namespace
}  // namespace coopnav
