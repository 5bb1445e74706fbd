// The dialogue with several people (lib/dialogue/session.hpp), without a bus: each person decided
// on its own in id order, one who leaves has its interaction ended, one who reappears under a new
// tracker id goes on, an id reused after it was forgotten starts afresh, a late join decides
// nothing, and the ids kept stay within max_ids.
#include "coopnav/dialogue/session.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace coopnav::dialogue {
namespace {

constexpr std::int64_t kStepUs = 100'000;  // 10 Hz

/// A human walking towards the robot (at the origin, facing +x) along -x.
AgentState walker(std::int32_t id, double x_m, double y_m, double vx_m_s = -1.0) {
  AgentState h;
  h.id = id;
  h.pose = {x_m, y_m, vx_m_s < 0.0 ? 3.14159265358979 : 0.0};
  h.velocity = {vx_m_s, 0.0, 0.0};
  return h;
}

/// A situation that fires round 1 with "I will pass on your left." (the robot free, the human
/// needing to contribute).
SituationSnapshot approaching(double t_cross_s) {
  SituationSnapshot s;
  s.t_cross_s = t_cross_s;
  s.human_needs_to_contribute = Tristate::kTrue;
  s.human_is_constrained = Tristate::kFalse;
  s.robot_is_constrained = Tristate::kFalse;
  s.dir = Side::kLeft;
  s.d_h_m = 0.8;
  s.d_oh_m = 1.0;
  s.d_hr_m = 1.0;
  return s;
}

class SessionTest : public ::testing::Test {
 protected:
  explicit SessionTest(double forget_after_s = 60.0, std::size_t max_ids = 256)
      : session_(SessionConfig{}, forget_after_s, max_ids) {}

  /// Step k at utime k · 100 ms with these humans in the agent states and these situations.
  SessionInput input(std::int64_t k, const std::vector<AgentState>& humans,
                     const std::map<std::int32_t, SituationSnapshot>& situations = {}) {
    SessionInput in;
    in.step = k;
    in.utime = k * kStepUs;
    in.clock_utime = in.utime;
    SceneSnapshot scene;
    scene.utime = in.utime;
    scene.robot.id = 0;
    scene.robot.kind = AgentKind::kRobot;
    scene.humans = humans;
    in.agents = scene;
    for (const auto& [id, s] : situations) in.situations[id] = {{in.utime, k, id}, s};
    return in;
  }

  Session session_;
};

std::vector<UtteranceOut> utterances(const SessionOutput& out) {
  std::vector<UtteranceOut> u;
  for (const auto& m : out.messages)
    if (const auto* x = std::get_if<UtteranceOut>(&m)) u.push_back(*x);
  return u;
}

std::vector<RecorderOut> recorders(const SessionOutput& out) {
  std::vector<RecorderOut> r;
  for (const auto& m : out.messages)
    if (const auto* x = std::get_if<RecorderOut>(&m)) r.push_back(*x);
  return r;
}

bool noted(const SessionOutput& out, const std::string& text) {
  for (const auto& n : out.notes)
    if (n.text.find(text) != std::string::npos) return true;
  return false;
}

TEST_F(SessionTest, SeveralPeopleAreEachDecidedInIdOrderAndShareOneVoice) {
  // Two people 3 m apart (not a group): each is told on its own, in id order, the second after
  // the first one's words.
  const SessionOutput out = session_.step(input(0, {walker(7, 6.0, 1.5), walker(3, 6.0, -1.5)},
                                                {{7, approaching(6.5)}, {3, approaching(6.5)}}));
  const auto said = utterances(out);
  ASSERT_EQ(said.size(), 2U);
  EXPECT_EQ(said[0].stamp.human_id, 3);
  EXPECT_EQ(said[1].stamp.human_id, 7);
  for (const auto& u : said) {
    EXPECT_EQ(u.utterance.act, SpeechAct::kInformDirection);
    EXPECT_EQ(u.slot.delivery, Delivery::kSaid);
    EXPECT_TRUE(u.group.empty());
  }
  EXPECT_DOUBLE_EQ(said[0].slot.start_s, 0.0);
  EXPECT_DOUBLE_EQ(said[1].slot.start_s, said[0].slot.duration_s);  // one voice
  // Several people: each sentence says whom it is for.
  EXPECT_NE(said[0].utterance.text, "I will pass on your left.");
  // Per decision: its utterance, then its recorder start.
  ASSERT_EQ(out.messages.size(), 4U);
  EXPECT_TRUE(std::holds_alternative<UtteranceOut>(out.messages[0]));
  EXPECT_TRUE(std::holds_alternative<RecorderOut>(out.messages[1]));
  EXPECT_EQ(std::get<RecorderOut>(out.messages[1]).stamp.human_id, 3);
  EXPECT_EQ(std::get<RecorderOut>(out.messages[3]).stamp.human_id, 7);
  ASSERT_EQ(out.speak.size(), 2U);
  EXPECT_EQ(session_.humansKept(), 2U);
  EXPECT_EQ(session_.idsKept(), 2U);
  ASSERT_NE(session_.decision(3), nullptr);
  EXPECT_TRUE(session_.decision(3)->roundFired(1));
}

TEST_F(SessionTest, OneWhoLeavesHasItsInteractionEndedAndTheOtherGoesOn) {
  session_.step(input(0, {walker(3, 6.0, -1.5), walker(7, 6.0, 1.5)},
                      {{3, approaching(6.5)}, {7, approaching(6.5)}}));
  // Human 7 is lost from step 1 on; human 3 stays.
  std::vector<RecorderOut> stops;
  std::int64_t ended_at = -1;
  for (std::int64_t k = 1; k <= 30; ++k) {
    const SessionOutput out = session_.step(input(k, {walker(3, 6.0 - 0.1 * k, -1.5)}));
    for (const auto& r : recorders(out)) {
      stops.push_back(r);
      if (ended_at < 0) ended_at = k;
    }
  }
  ASSERT_EQ(stops.size(), 1U);
  EXPECT_EQ(stops[0].stamp.human_id, 7);
  EXPECT_EQ(stops[0].command, RecorderCommand::kStop);
  EXPECT_NE(stops[0].why.find("absent from the agent states"), std::string::npos) << stops[0].why;
  // Absent for more than human_gone_s (2 s) of message time: 20 steps after it was last seen.
  EXPECT_EQ(ended_at, 21);
  EXPECT_TRUE(session_.decision(7)->ended());
  EXPECT_FALSE(session_.decision(3)->ended());
}

TEST_F(SessionTest, OneWhoReappearsUnderANewIdGoesOnWithoutARoundRepeated) {
  session_.step(input(0, {walker(7, 6.0, 0.0)}, {{7, approaching(6.5)}}));
  session_.step(input(1, {walker(7, 5.9, 0.0)}));
  // Lost at step 1 at x 5.9 walking at -1 m/s; at step 4 a new id where it was heading.
  session_.step(input(2, {}));
  session_.step(input(3, {}));
  const SessionOutput switched = session_.step(input(4, {walker(9, 5.6, 0.0)}));
  EXPECT_TRUE(noted(switched, "human 9 continues human 7")) << switched.notes.size();
  EXPECT_EQ(session_.decision(7), nullptr);
  ASSERT_NE(session_.decision(9), nullptr);
  EXPECT_TRUE(session_.decision(9)->roundFired(1));
  EXPECT_EQ(session_.idsKept(), 1U);
  // Its situation as id 9: round 1 is not said again.
  const SessionOutput next =
      session_.step(input(5, {walker(9, 5.5, 0.0)}, {{9, approaching(5.5)}}));
  EXPECT_TRUE(utterances(next).empty());
  EXPECT_TRUE(recorders(next).empty());
}

class SessionForgetTest : public SessionTest {
 protected:
  SessionForgetTest() : SessionTest(/*forget_after_s=*/5.0, /*max_ids=*/3) {}
};

TEST_F(SessionForgetTest, AnIdReusedAfterItWasForgottenStartsAfresh) {
  session_.step(input(0, {walker(3, 6.0, 0.0)}, {{3, approaching(6.5)}}));
  // Gone: ended after human_gone_s, forgotten after forget_after_s (message time).
  bool forgotten = false;
  for (std::int64_t k = 1; k <= 60 && !forgotten; ++k) {
    const SessionOutput out = session_.step(input(k, {}));
    forgotten = noted(out, "forgot 1 humans not heard of for 5 s (3)");
    EXPECT_EQ(forgotten, k == 51) << k;
  }
  ASSERT_TRUE(forgotten);
  EXPECT_EQ(session_.decision(3), nullptr);
  EXPECT_EQ(session_.idsKept(), 0U);
  // The tracker reuses id 3 for someone new: round 1 again.
  const SessionOutput again =
      session_.step(input(70, {walker(3, 6.0, 0.0)}, {{3, approaching(6.5)}}));
  ASSERT_EQ(utterances(again).size(), 1U);
  EXPECT_EQ(utterances(again)[0].utterance.act, SpeechAct::kInformDirection);
  ASSERT_EQ(recorders(again).size(), 1U);
  EXPECT_EQ(recorders(again)[0].command, RecorderCommand::kStart);
}

TEST_F(SessionForgetTest, BeyondMaxIdsTheLeastRecentIsForgottenItsInteractionEndedFirst) {
  session_.step(input(0, {walker(1, 6.0, -3.0)}, {{1, approaching(6.5)}}));
  session_.step(input(1, {walker(1, 5.9, -3.0), walker(2, 6.0, 0.0), walker(3, 6.0, 3.0)}));
  EXPECT_EQ(session_.idsKept(), 3U);
  // A fourth id: the least recently heard of goes. All three were heard of at step 1; ids heard
  // of at the same time keep the order they were heard in, so 1 (the first) is forgotten.
  const SessionOutput out =
      session_.step(input(2, {walker(2, 5.9, 0.0), walker(3, 5.9, 3.0), walker(4, 6.0, 6.0)}));
  EXPECT_EQ(session_.idsKept(), 3U);
  EXPECT_EQ(session_.decision(1), nullptr);
  const auto r = recorders(out);
  ASSERT_EQ(r.size(), 1U);  // its open interaction was ended before it went
  EXPECT_EQ(r[0].stamp.human_id, 1);
  EXPECT_EQ(r[0].command, RecorderCommand::kStop);
  EXPECT_TRUE(noted(out, "1 beyond limits.max_ids 3 (1); interactions ended: 1"));
}

TEST_F(SessionTest, AJoinedLateSessionDecidesNothingForThoseAlreadyThere) {
  const SessionInput first = input(40, {walker(3, 6.0, 0.0)}, {{3, approaching(6.5)}});
  const SessionNote note = session_.joinLate(first);
  EXPECT_EQ(note.level, SessionNote::Level::kWarn);
  EXPECT_NE(note.text.find("no decisions for humans 3"), std::string::npos) << note.text;
  const SessionOutput out = session_.step(first);
  EXPECT_TRUE(out.messages.empty());
  EXPECT_EQ(session_.decision(3), nullptr);
  // Someone new is decided as usual.
  const SessionOutput next =
      session_.step(input(41, {walker(3, 5.9, 0.0), walker(8, 6.0, 4.0)}, {{8, approaching(6.5)}}));
  ASSERT_EQ(utterances(next).size(), 1U);
  EXPECT_EQ(utterances(next)[0].stamp.human_id, 8);
}

TEST_F(SessionTest, AResyncedClockRestartsTheAgesOfWhatIsKept) {
  session_.step(input(0, {walker(3, 6.0, 0.0)}, {{3, approaching(6.5)}}));
  // The message clock went on from a new time line far behind: the times kept are re-based on
  // it, so human 3, absent from then on, is judged gone after human_gone_s of the new time (on
  // the old times it would never be: its last sighting would stay in the future).
  constexpr std::int64_t kBase = -1'000'000'000;
  session_.restamp(kBase);
  std::int64_t ended_at = -1;
  for (std::int64_t k = 1; k <= 30 && ended_at < 0; ++k) {
    SessionInput in = input(k, {});
    in.utime = kBase + k * kStepUs;
    in.clock_utime = in.utime;
    in.agents->utime = in.utime;
    if (!recorders(session_.step(in)).empty()) ended_at = k;
  }
  EXPECT_EQ(ended_at, 21);
  EXPECT_TRUE(session_.decision(3)->ended());
}

}  // namespace
}  // namespace coopnav::dialogue
