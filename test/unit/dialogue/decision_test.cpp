// Decision logic of paper §II-D (design-readings, "Decision pipeline"): every flowchart branch is a
// row of a table; once-firing under t_CROSS jitter; the precautionary dock of round 2 on an
// unknown (and none without it); crossed detection.
#include "coopnav/dialogue/decision.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace coopnav::dialogue {
namespace {

constexpr Tristate T = Tristate::kTrue;
constexpr Tristate F = Tristate::kFalse;
constexpr Tristate U = Tristate::kUnknown;
constexpr Side L = Side::kLeft;
constexpr Side R = Side::kRight;
constexpr Side X = Side::kUndefined;

using Act = SpeechAct;
using Rec = RecorderCommand;

struct Row {
  const char* name;
  int round;  // the round under test; earlier rounds are run with a neutral situation first
  // Inputs.
  Tristate needs, human_constrained, robot_constrained;
  Side dir;
  std::optional<double> d_h_m, cm_m;
  Tristate contributing;
  // Expected outputs of that round.
  std::vector<Act> acts;
  std::vector<Side> directions;
  std::vector<Rec> recorder;
  std::vector<RobotAction> actions;
  bool silent_with_reason;
};

const std::optional<double> kNone;

// clang-format off
const Row kRows[] = {
  // Round 1 (t_CROSS first <= 7 s): the recorder always starts.
  {"r1 needs, robot free -> inform Dir", 1, T, F, F, L, 0.8, kNone, U,
   {Act::kInformDirection}, {L}, {Rec::kStart}, {}, false},
  {"r1 needs, robot constrained, human free -> ask to move away from Dir", 1, T, F, T, L, 0.8,
   kNone, U, {Act::kAskToMove}, {R}, {Rec::kStart}, {}, false},
  {"r1 needs, both constrained -> dock if needed", 1, T, T, T, R, 0.8, kNone, U,
   {Act::kInformDockIfNeeded}, {X}, {Rec::kStart}, {}, false},
  {"r1 no need, robot constrained -> inform Dir", 1, F, F, T, R, 0.1, kNone, U,
   {Act::kInformDirection}, {R}, {Rec::kStart}, {}, false},
  {"r1 no need, robot free -> silent", 1, F, F, F, R, 0.1, kNone, U,
   {}, {}, {Rec::kStart}, {}, false},
  {"r1 no need, human constrained, robot free -> silent", 1, F, T, F, R, 0.1, kNone, U,
   {}, {}, {Rec::kStart}, {}, false},
  {"r1 needs unknown -> silent", 1, U, F, T, L, kNone, kNone, U,
   {}, {}, {Rec::kStart}, {}, true},
  {"r1 needs, robot unknown -> silent", 1, T, F, U, L, 0.8, kNone, U,
   {}, {}, {Rec::kStart}, {}, true},
  {"r1 needs, robot constrained, human unknown -> silent", 1, T, U, T, L, 0.8, kNone, U,
   {}, {}, {Rec::kStart}, {}, true},
  {"r1 no need, robot unknown -> silent", 1, F, F, U, L, 0.1, kNone, U,
   {}, {}, {Rec::kStart}, {}, true},
  {"r1 needs, robot free, Dir undefined -> silent", 1, T, F, F, X, 0.8, kNone, U,
   {}, {}, {Rec::kStart}, {}, true},
  // Round 2 (t_CROSS first <= 4 s): StillNeedsToContribute = CM < d_h.
  {"r2 still, robot free -> repeat Dir", 2, T, F, F, L, 0.8, 0.1, F,
   {Act::kRepeatDirection}, {L}, {}, {}, false},
  {"r2 still, robot constrained, contributing -> reset, ask to move more", 2, T, F, T, L, 0.8,
   0.5, T, {Act::kAskToMoveMore}, {R}, {Rec::kReset}, {}, false},
  {"r2 still, robot constrained, not contributing -> reset, dock", 2, T, T, T, L, 0.8, 0.1, F,
   {Act::kInformDocking}, {X}, {Rec::kReset}, {RobotAction::kDock}, false},
  {"r2 not still (CM >= d_h) -> silent", 2, T, F, T, L, 0.5, 0.9, T,
   {}, {}, {}, {}, false},
  {"r2 CM == d_h is not still -> silent", 2, T, F, T, L, 0.5, 0.5, T,
   {}, {}, {}, {}, false},
  // Round 2 with an unknown that leaves a dock open: the precautionary dock (degraded).
  {"r2 still, robot constrained, contributing unknown -> reset, precautionary dock", 2, T, T, T,
   L, 0.8, 0.1, U, {Act::kInformDocking}, {X}, {Rec::kReset}, {RobotAction::kDock}, true},
  {"r2 CM unknown -> precautionary dock", 2, T, T, T, L, 0.8, kNone, F,
   {Act::kInformDocking}, {X}, {Rec::kReset}, {RobotAction::kDock}, true},
  {"r2 d_h unknown -> precautionary dock", 2, T, T, T, L, kNone, 0.1, F,
   {Act::kInformDocking}, {X}, {Rec::kReset}, {RobotAction::kDock}, true},
  {"r2 still, robot unknown, not contributing -> precautionary dock", 2, T, T, U, L, 0.8, 0.1,
   F, {Act::kInformDocking}, {X}, {Rec::kReset}, {RobotAction::kDock}, true},
  // ... and with an unknown that a known fact makes harmless: silent, as the flowchart.
  {"r2 still, robot unknown, contributing -> silent", 2, T, T, U, L, 0.8, 0.1, T,
   {}, {}, {}, {}, true},
  {"r2 CM unknown, robot free -> silent", 2, T, F, F, L, 0.8, kNone, U, {}, {}, {}, {}, true},
  {"r2 still, robot free, Dir undefined -> silent", 2, T, F, F, X, 0.8, 0.1, F,
   {}, {}, {}, {}, true},
  // Round 3 (crossed): stop the recorder, thank if the human facilitated.
  {"r3 contributing -> stop, thank", 3, T, F, T, L, 0.8, 0.6, T,
   {Act::kThank}, {X}, {Rec::kStop}, {}, false},
  {"r3 not contributing -> stop, silent", 3, T, F, T, L, 0.8, 0.1, F,
   {}, {}, {Rec::kStop}, {}, false},
  {"r3 contributing unknown -> stop, silent", 3, T, F, T, L, 0.8, kNone, U,
   {}, {}, {Rec::kStop}, {}, true},
};
// clang-format on

DecisionInput inputFor(const Row& row, double t_s, std::optional<double> t_cross_s, bool crossed) {
  DecisionInput in;
  in.t_s = t_s;
  in.situation.t_cross_s = t_cross_s;
  in.situation.human_needs_to_contribute = row.needs;
  in.situation.human_is_constrained = row.human_constrained;
  in.situation.robot_is_constrained = row.robot_constrained;
  in.situation.dir = row.dir;
  in.situation.d_h_m = row.d_h_m;
  in.path.cm_window_m = row.cm_m;
  in.path.is_contributing = row.contributing;
  in.crossed = crossed;
  return in;
}

// A situation in which rounds 1 and 2 stay silent and do nothing but the recorder start.
DecisionInput neutral(double t_s, double t_cross_s) {
  DecisionInput in;
  in.t_s = t_s;
  in.situation.t_cross_s = t_cross_s;
  in.situation.human_needs_to_contribute = F;
  in.situation.human_is_constrained = F;
  in.situation.robot_is_constrained = F;
  in.situation.d_h_m = 0.1;
  in.path.cm_window_m = 0.5;
  in.path.is_contributing = T;
  return in;
}

/// A round-2 step (t_CROSS 3 s) where the human needs to contribute, Dir left, d_h 0.8 m when
/// known, and the given predicates and window CM.
DecisionInput round2Input(Tristate robot_constrained, Tristate contributing,
                          std::optional<double> cm_window_m, bool d_h_known) {
  DecisionInput in = neutral(1.0, 3.0);
  in.situation.human_needs_to_contribute = Tristate::kTrue;
  in.situation.robot_is_constrained = robot_constrained;
  in.situation.dir = Side::kLeft;
  in.situation.d_h_m = d_h_known ? std::optional<double>(0.8) : std::nullopt;
  in.path.cm_window_m = cm_window_m;
  in.path.is_contributing = contributing;
  return in;
}

class DecisionTable : public ::testing::TestWithParam<Row> {};

TEST_P(DecisionTable, BranchGivesItsUtteranceActionAndRecorderCommand) {
  const Row& row = GetParam();
  HumanDecision dut;
  DecisionOutput out;
  if (row.round == 1) {
    out = dut.step(inputFor(row, 10.0, 6.9, false));
  } else if (row.round == 2) {
    dut.step(neutral(10.0, 6.9));
    out = dut.step(inputFor(row, 13.0, 3.9, false));
  } else {
    dut.step(neutral(10.0, 6.9));
    out = dut.step(inputFor(row, 17.0, std::nullopt, true));
  }
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, row.round);
  EXPECT_FALSE(out.rounds[0].branch.empty());
  EXPECT_EQ(!out.rounds[0].reason.empty(), row.silent_with_reason) << out.rounds[0].reason;
  ASSERT_EQ(out.utterances.size(), row.acts.size());
  for (std::size_t i = 0; i < row.acts.size(); ++i) {
    EXPECT_EQ(out.utterances[i].act, row.acts[i]);
    EXPECT_EQ(out.utterances[i].direction, row.directions[i]);
    EXPECT_EQ(out.utterances[i].round, row.round);
    EXPECT_FALSE(out.utterances[i].text.empty());
    EXPECT_EQ(out.utterances[i].text.find("{dir}"), std::string::npos);
  }
  EXPECT_EQ(out.recorder_commands, row.recorder);
  EXPECT_EQ(out.robot_actions, row.actions);
  EXPECT_EQ(dut.docked(), !row.actions.empty());
  // A dock promises to wait only when the flowchart docks: the precautionary one cannot know
  // that a wall is near to wait at (in an open corridor the robot gives way on its band).
  const dialogue::TextTemplates texts;
  for (const auto& u : out.utterances) {
    if (u.act != Act::kInformDocking) continue;
    EXPECT_EQ(u.text,
              out.rounds[0].degraded ? texts.inform_precautionary_docking : texts.inform_docking);
  }
}

INSTANTIATE_TEST_SUITE_P(Flowchart, DecisionTable, ::testing::ValuesIn(kRows),
                         [](const ::testing::TestParamInfo<Row>& p) {
                           std::string n = "row" + std::to_string(p.index) + "_";
                           for (const char* c = p.param.name; *c; ++c) {
                             n += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
                           }
                           return n;
                         });

TEST(Decision, EachRoundFiresOnceWhileTCrossJitters) {
  HumanDecision dut;
  DecisionInput in = neutral(0.0, 9.0);
  in.situation.human_needs_to_contribute = T;  // round 1 informs Dir; round 2 repeats it
  in.situation.dir = L;
  in.situation.d_h_m = 0.8;
  in.path.cm_window_m = 0.1;
  int rounds[4] = {0, 0, 0, 0};
  int utterances = 0;
  int starts = 0;
  const std::optional<double> t_cross[] = {9.0, 7.2, 6.9, 7.1, std::nullopt, 6.95, 7.3, 5.0,
                                           4.1, 3.9, 4.2, 3.8, std::nullopt, 4.05, 2.0, 0.5};
  double t = 0.0;
  for (const auto& tc : t_cross) {
    in.t_s = (t += 0.1);
    in.situation.t_cross_s = tc;
    const DecisionOutput out = dut.step(in);
    for (const auto& r : out.rounds) ++rounds[r.round];
    utterances += static_cast<int>(out.utterances.size());
    for (auto c : out.recorder_commands) starts += c == Rec::kStart;
  }
  in.crossed = true;
  for (int i = 0; i < 3; ++i) {
    const DecisionOutput out = dut.step(in);
    for (const auto& r : out.rounds) ++rounds[r.round];
  }
  EXPECT_EQ(rounds[1], 1);
  EXPECT_EQ(rounds[2], 1);
  EXPECT_EQ(rounds[3], 1);
  EXPECT_EQ(utterances, 2);  // inform Dir, repeat Dir
  EXPECT_EQ(starts, 1);
  EXPECT_TRUE(dut.ended());
}

TEST(Decision, RoundTwoNeverFiresInTheStepOfRoundOne) {
  // t_CROSS first known at 3.5 s (e.g. the human appeared late): round 1 now, round 2 next step.
  HumanDecision dut;
  DecisionOutput out = dut.step(neutral(0.0, 3.5));
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, 1);
  out = dut.step(neutral(0.1, 3.4));
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, 2);
}

// Round 2 judges the response to round 1's words: it waits until they have been heard and
// round2_response_s more, but never beyond round2_latest_t_cross_s.
TEST(Decision, RoundTwoWaitsForTheResponseToRoundOnesWords) {
  const DecisionConfig config;  // response 2 s, latest t_CROSS 3 s
  HumanDecision dut(config);
  ASSERT_EQ(dut.step(neutral(0.0, 7.0)).rounds.size(), 1u);  // round 1 at t = 0
  // Its words ended at t = 3.1 s: round 2 waits until 5.1 s although t_CROSS is below 4 s.
  double t_s = 3.0;
  for (; t_s < 5.05; t_s += 0.1) {
    DecisionInput in = neutral(t_s, 7.0 - t_s * 0.7);  // t_CROSS 4.9 .. 3.5
    in.heard_by_s = 3.1;
    ASSERT_TRUE(dut.step(in).rounds.empty()) << "t " << t_s;
  }
  DecisionInput in = neutral(5.1, 3.4);
  in.heard_by_s = 3.1;
  const DecisionOutput out = dut.step(in);
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, 2);
}

TEST(Decision, RoundTwoWaitsNoLaterThanItsLatestTCross) {
  HumanDecision dut;
  ASSERT_EQ(dut.step(neutral(0.0, 7.0)).rounds.size(), 1u);
  DecisionInput in = neutral(2.0, 3.2);
  in.heard_by_s = 3.5;  // a long sentence, or one that waited for the voice
  EXPECT_TRUE(dut.step(in).rounds.empty());
  in = neutral(2.1, DecisionConfig{}.round2_latest_t_cross_s);
  in.heard_by_s = 3.5;
  const DecisionOutput out = dut.step(in);
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, 2);
}

TEST(Decision, WithNothingSaidOrNoResponseTimeRoundTwoIsAtItsThreshold) {
  HumanDecision silent;  // round 1 said nothing (or the robot is muted): no words to wait for
  ASSERT_EQ(silent.step(neutral(0.0, 7.0)).rounds.size(), 1u);
  EXPECT_EQ(silent.step(neutral(3.0, 4.0)).rounds.size(), 1u);
  DecisionConfig paper;
  paper.round2_response_s = 0.0;
  HumanDecision dut(paper);
  ASSERT_EQ(dut.step(neutral(0.0, 7.0)).rounds.size(), 1u);
  DecisionInput in = neutral(3.0, 4.0);
  in.heard_by_s = 3.0;
  EXPECT_EQ(dut.step(in).rounds.size(), 1u);
}

TEST(Decision, UnknownTCrossFiresNothing) {
  HumanDecision dut;
  DecisionInput in = neutral(0.0, 0.0);
  in.situation.t_cross_s = std::nullopt;
  EXPECT_TRUE(dut.step(in).empty());
  EXPECT_FALSE(dut.roundFired(1));
}

TEST(Decision, WithoutThePrecautionUnknownNeverDocksWhateverElseIsTrue) {
  // The paper's reading (precautionary_dock off): every combination with at least one unknown
  // among the round-2 inputs stays without a dock.
  DecisionConfig paper;
  paper.precautionary_dock = false;
  const Tristate vals[] = {T, F, U};
  for (Tristate robot : vals) {
    for (Tristate contributing : vals) {
      for (int cm_known = 0; cm_known < 2; ++cm_known) {
        for (int dh_known = 0; dh_known < 2; ++dh_known) {
          const bool any_unknown = robot == U || contributing == U || !cm_known || !dh_known;
          if (!any_unknown) continue;
          HumanDecision dut(paper);
          dut.step(neutral(0.0, 6.0));
          const DecisionInput in = round2Input(
              robot, contributing, cm_known ? std::optional<double>(0.1) : std::nullopt, dh_known);
          const DecisionOutput out = dut.step(in);
          EXPECT_TRUE(out.robot_actions.empty());
          EXPECT_FALSE(dut.docked());
        }
      }
    }
  }
}

TEST(Decision, PrecautionaryDockWhenAnUnknownLeavesADockOpenAndSaysItIsDegraded) {
  // Every round-2 combination: a dock exactly when the flowchart docks (all known) or when an
  // input is unknown and nothing known rules the dock out (human moved enough, robot free, human
  // moving aside); the degraded mark exactly on the precautionary ones.
  const Tristate vals[] = {T, F, U};
  const std::optional<double> cms[] = {0.1, 0.9, std::nullopt};  // CM < d_h, >= d_h, unknown
  for (Tristate robot : vals) {
    for (Tristate contributing : vals) {
      for (const auto& cm : cms) {
        for (int dh_known = 0; dh_known < 2; ++dh_known) {
          HumanDecision dut;
          dut.step(neutral(0.0, 6.0));
          DecisionInput in = round2Input(robot, contributing, cm, dh_known);
          in.situation.reason = "distance server: no reply";
          const Tristate still = !cm || !dh_known ? U : (*cm < 0.8 ? T : F);
          const bool flowchart_dock = still == T && robot == T && contributing == F;
          const bool any_unknown =
              still == U || robot == U || (still == T && robot == T && contributing == U);
          const bool precaution = any_unknown && still != F && robot != F && contributing != T;
          const DecisionOutput out = dut.step(in);
          SCOPED_TRACE(::testing::Message() << "robot " << static_cast<int>(robot)
                                            << " contributing " << static_cast<int>(contributing)
                                            << " cm " << (cm ? *cm : -1.0) << " d_h " << dh_known);
          ASSERT_EQ(out.rounds.size(), 1u);
          const RoundOutcome& r = out.rounds[0];
          const bool docks = flowchart_dock || precaution;
          EXPECT_EQ(out.robot_actions, docks ? std::vector<RobotAction>{RobotAction::kDock}
                                             : std::vector<RobotAction>{});
          EXPECT_EQ(dut.docked(), docks);
          EXPECT_EQ(r.degraded, precaution);
          EXPECT_EQ(r.branch.find("degraded: precautionary dock") != std::string::npos, precaution)
              << r.branch;
          if (precaution) {
            // Says what was unknown and why (the assessor's reason), tells the human, restarts
            // the recorder as a dock does.
            EXPECT_NE(r.reason.find("unknown"), std::string::npos) << r.reason;
            EXPECT_NE(r.reason.find("distance server: no reply"), std::string::npos) << r.reason;
            ASSERT_EQ(out.utterances.size(), 1u);
            EXPECT_EQ(out.utterances[0].act, Act::kInformDocking);
            EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kReset});
          }
        }
      }
    }
  }
}

TEST(Decision, PrecautionaryDockOnlyInRoundTwo) {
  // Everything unknown from round 1 on: round 1 stays silent (no dock before the decision point
  // of round 2), round 2 docks as a precaution, round 3 resumes.
  HumanDecision dut;
  DecisionInput in;
  in.situation.human_needs_to_contribute = T;
  in.situation.d_h_m = 0.8;
  in.path.cm_window_m = 0.05;
  in.path.is_contributing = F;
  in.t_s = 0.0;
  in.situation.t_cross_s = 6.9;
  DecisionOutput out = dut.step(in);
  EXPECT_TRUE(out.robot_actions.empty());
  in.t_s = 3.0;
  in.situation.t_cross_s = 4.5;
  EXPECT_TRUE(dut.step(in).empty());
  in.t_s = 3.1;
  in.situation.t_cross_s = 3.9;
  out = dut.step(in);
  EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_TRUE(out.rounds[0].degraded);
  in.crossed = true;
  out = dut.step(in);
  EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
}

// The judgement of cooperation (DecisionConfig::judgement) at rounds 1 and 2: the paper's
// IsContributing (CM > τ) or the forecast p_contributing against forecast_threshold.
DecisionConfig withJudgement(CooperationJudgement j) {
  DecisionConfig c;
  c.judgement = j;
  return c;
}

TEST(DecisionJudgement, RoundOneReadsNoJudgementUnderEither) {
  // Round 1 decides on the situation alone: the same words whatever CM or the forecast say.
  for (const auto j : {CooperationJudgement::kCm, CooperationJudgement::kForecast}) {
    for (const double p : {0.05, 0.95}) {
      HumanDecision dut(withJudgement(j));
      DecisionInput in = round2Input(T, p > 0.5 ? F : T, 0.0, true);
      in.situation.t_cross_s = 6.9;
      in.path.p_contributing = p;
      const DecisionOutput out = dut.step(in);
      ASSERT_EQ(out.rounds.size(), 1u);
      EXPECT_EQ(out.rounds[0].round, 1);
      EXPECT_EQ(out.rounds[0].branch,
                "needs & robot_constrained & !human_constrained -> ask to move away");
      ASSERT_EQ(out.utterances.size(), 1u);
      EXPECT_EQ(out.utterances[0].act, Act::kAskToMove);
      EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kStart});
    }
  }
}

// Round 2, robot constrained, the person still short of d_h: the two judgements disagree in both
// directions, and each decides on its own.
TEST(DecisionJudgement, RoundTwoDecidesOnTheConfiguredJudgement) {
  struct Case {
    CooperationJudgement judgement;
    Tristate is_contributing;  // the paper's, from CM > τ
    std::optional<double> p;   // the forecast
    bool asks_more;            // else docks
    const char* branch;
  };
  const Case cases[] = {
      // Not stepped aside yet (CM below τ), but the track says it will: the paper docks.
      {CooperationJudgement::kCm, F, 0.8, false,
       "still & robot_constrained & !contributing -> dock"},
      {CooperationJudgement::kForecast, F, 0.8, true,
       "still & robot_constrained & forecast contributing (p 0.80 >= 0.50) -> ask to move more"},
      // Stepped a little (CM above τ), but the forecast says it will not make room.
      {CooperationJudgement::kCm, T, 0.2, true,
       "still & robot_constrained & contributing -> ask to move more"},
      {CooperationJudgement::kForecast, T, 0.2, false,
       "still & robot_constrained & forecast !contributing (p 0.20 < 0.50) -> dock"},
      // The threshold itself counts as contributing.
      {CooperationJudgement::kForecast, F, 0.5, true,
       "still & robot_constrained & forecast contributing (p 0.50 >= 0.50) -> ask to move more"},
  };
  for (const Case& c : cases) {
    HumanDecision dut(withJudgement(c.judgement));
    dut.step(neutral(10.0, 6.9));
    DecisionInput in = round2Input(T, c.is_contributing, 0.1, true);
    in.t_s = 13.0;
    in.path.p_contributing = c.p;
    const DecisionOutput out = dut.step(in);
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_EQ(out.rounds[0].round, 2);
    EXPECT_EQ(out.rounds[0].branch, c.branch);
    EXPECT_FALSE(out.rounds[0].degraded);
    EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kReset});
    ASSERT_EQ(out.utterances.size(), 1u) << c.branch;
    if (c.asks_more) {
      EXPECT_EQ(out.utterances[0].act, Act::kAskToMoveMore);
      EXPECT_EQ(out.utterances[0].direction, R);  // away from Dir (left)
      EXPECT_TRUE(out.robot_actions.empty());
    } else {
      EXPECT_EQ(out.utterances[0].act, Act::kInformDocking);
      EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
    }
  }
}

TEST(DecisionJudgement, AnUnknownForecastIsAnUnknownJudgement) {
  for (const std::optional<double> p : {std::optional<double>{}, std::optional<double>{NAN}}) {
    // With the precaution: docks, degraded, naming p_contributing (not IsContributing, known).
    HumanDecision dut(withJudgement(CooperationJudgement::kForecast));
    dut.step(neutral(10.0, 6.9));
    DecisionInput in = round2Input(T, T, 0.1, true);
    in.t_s = 13.0;
    in.path.p_contributing = p;
    DecisionOutput out = dut.step(in);
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_TRUE(out.rounds[0].degraded);
    EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
    EXPECT_NE(out.rounds[0].reason.find("p_contributing"), std::string::npos);
    EXPECT_EQ(out.rounds[0].reason.find("IsContributing"), std::string::npos);
    // Without it: the flowchart's silence on an unknown, said why.
    DecisionConfig silent = withJudgement(CooperationJudgement::kForecast);
    silent.precautionary_dock = false;
    HumanDecision quiet(silent);
    quiet.step(neutral(10.0, 6.9));
    out = quiet.step(in);
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_TRUE(out.utterances.empty());
    EXPECT_TRUE(out.robot_actions.empty());
    EXPECT_EQ(out.rounds[0].reason, "p_contributing unknown: no dock, silent");
  }
  // The paper's judgement ignores the forecast altogether.
  HumanDecision paper;
  paper.step(neutral(10.0, 6.9));
  DecisionInput in = round2Input(T, F, 0.1, true);
  in.t_s = 13.0;
  const DecisionOutput out = paper.step(in);
  EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  EXPECT_FALSE(out.rounds[0].degraded);
}

TEST(DecisionJudgement, RoundThreeThanksOnWhatWasDoneUnderEither) {
  // After the crossing the measure is known: round 3 reads IsContributing under both.
  for (const auto j : {CooperationJudgement::kCm, CooperationJudgement::kForecast}) {
    HumanDecision dut(withJudgement(j));
    dut.step(neutral(10.0, 6.9));
    DecisionInput in = neutral(17.0, 0.0);
    in.crossed = true;
    in.path.is_contributing = T;
    in.path.p_contributing = 0.1;
    const DecisionOutput out = dut.step(in);
    ASSERT_EQ(out.utterances.size(), 1u);
    EXPECT_EQ(out.utterances[0].act, Act::kThank);
  }
}

TEST(DecisionJudgement, NamesParseBack) {
  for (const auto j : {CooperationJudgement::kCm, CooperationJudgement::kForecast}) {
    CooperationJudgement back = j == CooperationJudgement::kCm ? CooperationJudgement::kForecast
                                                               : CooperationJudgement::kCm;
    ASSERT_TRUE(parseCooperationJudgement(toString(j), back));
    EXPECT_EQ(back, j);
  }
  CooperationJudgement out = CooperationJudgement::kCm;
  EXPECT_FALSE(parseCooperationJudgement("CM", out));
  EXPECT_FALSE(parseCooperationJudgement("", out));
  EXPECT_EQ(DecisionConfig{}.judgement, CooperationJudgement::kCm);  // the paper's by default
}

// Making time (MakeTimeConfig, issue 46): round 2 due on the branch that reads the judgement,
// the forecast undecided -> the robot slows and round 2 waits until the forecast is decisive, a
// non-judging input changes the branch, or t_CROSS <= latest_t_cross_s.
DecisionConfig makeTime() {
  DecisionConfig c = withJudgement(CooperationJudgement::kForecast);
  c.make_time.enabled = true;
  return c;  // confidence 0.85, latest 2.0 s
}

/// Round 2 due (robot constrained, CM 0.1 < d_h 0.8) at t_s with this t_CROSS and forecast.
DecisionInput dueAt(double t_s, double t_cross_s, std::optional<double> p) {
  DecisionInput in = round2Input(T, F, 0.1, true);
  in.t_s = t_s;
  in.situation.t_cross_s = t_cross_s;
  in.path.p_contributing = p;
  return in;
}

TEST(DecisionMakeTime, AnUndecidedForecastSlowsOnceAndDecidesWhenDecisive) {
  for (const bool cooperating : {true, false}) {
    HumanDecision dut(makeTime());
    dut.step(neutral(10.0, 6.9));
    // Due at 3.9 s, p 0.55: no branch yet, one SLOW, nothing said, no recorder reset.
    DecisionOutput out = dut.step(dueAt(13.0, 3.9, 0.55));
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_EQ(out.rounds[0].round, 2);
    EXPECT_TRUE(out.rounds[0].deferred);
    EXPECT_EQ(out.rounds[0].branch, "still & robot_constrained & forecast undecided -> slow, wait");
    EXPECT_EQ(out.rounds[0].reason,
              "p_contributing 0.55 within (0.15, 0.85); decided by t_cross 2.0 s");
    EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kSlow});
    EXPECT_TRUE(out.utterances.empty());
    EXPECT_TRUE(out.recorder_commands.empty());
    EXPECT_FALSE(dut.roundFired(2));
    EXPECT_TRUE(dut.slowed());
    // Still undecided, t_CROSS back above 4 s (the robot is slower): nothing more, still slow.
    out = dut.step(dueAt(13.5, 4.3, 0.8));
    EXPECT_TRUE(out.empty());
    EXPECT_TRUE(dut.slowed());
    // Decisive: round 2 on it, and the slowing ends with the decision.
    out = dut.step(dueAt(14.0, 3.2, cooperating ? 0.9 : 0.1));
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_FALSE(out.rounds[0].deferred);
    EXPECT_TRUE(dut.roundFired(2));
    EXPECT_FALSE(dut.slowed());
    EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kReset});
    ASSERT_EQ(out.utterances.size(), 1u);
    if (cooperating) {
      EXPECT_EQ(out.utterances[0].act, Act::kAskToMoveMore);
      EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
    } else {
      EXPECT_EQ(out.utterances[0].act, Act::kInformDocking);
      EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
    }
    EXPECT_TRUE(dut.step(dueAt(14.5, 3.0, 0.5)).empty());  // fired once
  }
}

TEST(DecisionMakeTime, TheLatestTCrossDecidesOnTheThreshold) {
  for (const std::optional<double> p :
       {std::optional<double>{0.6}, std::optional<double>{0.4}, std::optional<double>{}}) {
    HumanDecision dut(makeTime());
    dut.step(neutral(10.0, 6.9));
    EXPECT_EQ(dut.step(dueAt(13.0, 3.9, p)).robot_actions,
              std::vector<RobotAction>{RobotAction::kSlow});
    EXPECT_TRUE(dut.step(dueAt(13.5, 2.1, p)).empty());
    const DecisionOutput out = dut.step(dueAt(14.0, 2.0, p));
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_FALSE(dut.slowed());
    if (p && *p >= 0.5) {  // the forecast profile's own reading, forecast_threshold 0.5
      EXPECT_EQ(out.utterances.at(0).act, Act::kAskToMoveMore);
      EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
    } else {  // !contributing, or unknown: the precautionary dock
      EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
      EXPECT_EQ(out.rounds[0].degraded, !p.has_value());
    }
  }
}

TEST(DecisionMakeTime, OnlyTheBranchThatReadsThePersonWaits) {
  // Decisive at once, robot free, or the person already made the room needed: round 2 as without.
  struct Case {
    Tristate robot;
    double cm_m;
    std::optional<double> p;
  };
  for (const Case& c :
       {Case{T, 0.1, 0.9}, Case{T, 0.1, 0.15}, Case{F, 0.1, 0.5}, Case{T, 0.9, 0.5}}) {
    HumanDecision dut(makeTime());
    dut.step(neutral(10.0, 6.9));
    DecisionInput in = dueAt(13.0, 3.9, c.p);
    in.situation.robot_is_constrained = c.robot;
    in.path.cm_window_m = c.cm_m;
    const DecisionOutput out = dut.step(in);
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_FALSE(out.rounds[0].deferred) << out.rounds[0].branch;
    EXPECT_TRUE(dut.roundFired(2));
    for (const RobotAction a : out.robot_actions) EXPECT_NE(a, RobotAction::kSlow);
  }
  // Waiting, the person makes the room (CM >= d_h): round 2 fires, silent, the robot resumes.
  HumanDecision dut(makeTime());
  dut.step(neutral(10.0, 6.9));
  dut.step(dueAt(13.0, 3.9, 0.5));
  DecisionInput in = dueAt(13.5, 3.5, 0.5);
  in.path.cm_window_m = 0.9;
  const DecisionOutput out = dut.step(in);
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].branch, "!still -> silent");
  EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
}

TEST(DecisionMakeTime, OffOrUnderTheCmJudgementNothingChanges) {
  DecisionConfig off = withJudgement(CooperationJudgement::kForecast);
  DecisionConfig cm = makeTime();
  cm.judgement = CooperationJudgement::kCm;
  for (const DecisionConfig& c : {off, cm, DecisionConfig{}}) {
    HumanDecision dut(c);
    dut.step(neutral(10.0, 6.9));
    const DecisionOutput out = dut.step(dueAt(13.0, 3.9, 0.55));
    ASSERT_EQ(out.rounds.size(), 1u);
    EXPECT_FALSE(out.rounds[0].deferred);
    EXPECT_TRUE(dut.roundFired(2));
  }
}

TEST(DecisionMakeTime, ACrossingOrAnEndWhileSlowedResumes) {
  for (const bool crossed : {true, false}) {
    HumanDecision dut(makeTime());
    dut.step(neutral(10.0, 6.9));
    dut.step(dueAt(13.0, 3.9, 0.5));
    ASSERT_TRUE(dut.slowed());
    DecisionOutput out;
    if (crossed) {
      DecisionInput in = neutral(15.0, 0.0);
      in.crossed = true;
      out = dut.step(in);
    } else {
      out = dut.endInteraction(15.0, "gone");
    }
    EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
    EXPECT_FALSE(dut.slowed());
  }
}

TEST(Decision, CrossingAfterADockResumesAndStops) {
  HumanDecision dut;
  dut.step(neutral(0.0, 6.0));
  DecisionInput in = neutral(1.0, 3.0);
  in.situation.human_needs_to_contribute = T;
  in.situation.robot_is_constrained = T;
  in.situation.d_h_m = 0.8;
  in.path.cm_window_m = 0.1;
  in.path.is_contributing = F;
  ASSERT_EQ(dut.step(in).robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  in.crossed = true;
  const DecisionOutput out = dut.step(in);
  EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
  EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kStop});
  EXPECT_FALSE(dut.docked());
}

// The dock is said as the move the band source will really make for this human.
DecisionInput dockingSituation(double t_s, RoomPlan room) {
  DecisionInput in = neutral(t_s, 3.0);
  in.situation.human_needs_to_contribute = T;
  in.situation.robot_is_constrained = T;
  in.situation.d_h_m = 0.8;
  in.situation.room_plan = room;
  in.path.cm_window_m = 0.1;
  in.path.is_contributing = F;
  return in;
}

TEST(Decision, TheDockIsSaidAsTheMoveTheRobotWillMake) {
  const std::pair<RoomPlan, Act> cases[] = {{RoomPlan::kUnknown, Act::kInformDocking},
                                            {RoomPlan::kDockHere, Act::kInformDocking},
                                            {RoomPlan::kWiderPlace, Act::kInformWiderPlace},
                                            {RoomPlan::kRetreat, Act::kInformRetreat},
                                            {RoomPlan::kNone, Act::kInformStopping}};
  for (const auto& [room, act] : cases) {
    SCOPED_TRACE(toString(room));
    HumanDecision dut;
    dut.step(neutral(0.0, 6.0));
    const DecisionOutput out = dut.step(dockingSituation(1.0, room));
    EXPECT_EQ(out.robot_actions, std::vector<RobotAction>{RobotAction::kDock});
    ASSERT_EQ(out.utterances.size(), 1u);
    EXPECT_EQ(out.utterances[0].act, act);
    EXPECT_EQ(out.utterances[0].text, renderText(TextTemplates{}, act, X));
  }
}

TEST(Decision, ADockThatBecomesARetreatIsSaidOnceAndNotAfterCrossing) {
  HumanDecision dut;
  dut.step(neutral(0.0, 6.0));
  DecisionInput in = dockingSituation(1.0, RoomPlan::kDockHere);
  ASSERT_EQ(dut.step(in).utterances.size(), 1u);
  in.t_s = 1.5;
  EXPECT_TRUE(dut.step(in).utterances.empty()) << "not retreating yet: nothing to say";
  in.t_s = 2.0;
  in.situation.robot_retreating = true;
  const DecisionOutput out = dut.step(in);
  ASSERT_EQ(out.utterances.size(), 1u);
  EXPECT_EQ(out.utterances[0].act, Act::kInformRetreat);
  in.t_s = 2.5;
  EXPECT_TRUE(dut.step(in).utterances.empty()) << "said once";
  // Retreating without a dock for this human (another human's) says nothing to this one.
  HumanDecision other;
  other.step(neutral(0.0, 6.0));
  DecisionInput free_robot = neutral(1.0, 3.0);
  free_robot.situation.robot_retreating = true;
  EXPECT_TRUE(other.step(free_robot).utterances.empty());
  // A retreat announced with the dock is not announced again.
  HumanDecision retreat;
  retreat.step(neutral(0.0, 6.0));
  DecisionInput r = dockingSituation(1.0, RoomPlan::kRetreat);
  ASSERT_EQ(retreat.step(r).utterances.size(), 1u);
  r.t_s = 2.0;
  r.situation.robot_retreating = true;
  EXPECT_TRUE(retreat.step(r).utterances.empty());
}

TEST(Decision, CrossedBeforeRoundOneRecordsWhyAndIssuesNoStop) {
  HumanDecision dut;
  DecisionInput in = neutral(0.0, 9.0);
  in.crossed = true;
  const DecisionOutput out = dut.step(in);
  ASSERT_EQ(out.rounds.size(), 1u);
  EXPECT_EQ(out.rounds[0].round, 3);
  EXPECT_FALSE(out.rounds[0].reason.empty());
  EXPECT_TRUE(out.recorder_commands.empty());
  EXPECT_TRUE(out.utterances.empty());
}

TEST(Decision, HumanLeavingEndsTheInteraction) {
  HumanDecision dut;
  dut.step(neutral(0.0, 6.0));
  const DecisionOutput out = dut.endInteraction(2.0, "human left the scene");
  EXPECT_EQ(out.recorder_commands, std::vector<Rec>{Rec::kStop});
  EXPECT_TRUE(dut.ended());
  EXPECT_TRUE(dut.step(neutral(3.0, 3.0)).empty());
  EXPECT_TRUE(dut.endInteraction(4.0, "again").empty());
}

TEST(RenderText, ReplacesEveryDirPlaceholderWithTheConfiguredWords) {
  TextTemplates t;
  EXPECT_EQ(renderText(t, Act::kInformDirection, L), "I will pass on your left.");
  EXPECT_EQ(renderText(t, Act::kAskToMoveMore, R),
            "Could you move a little more to your right, please?");
  t.inform_direction = "{dir}, {dir}!";
  t.left_word = "links";
  EXPECT_EQ(renderText(t, Act::kInformDirection, L), "links, links!");
  EXPECT_EQ(renderText(t, Act::kThank, X), "Thank you.");
}

TEST(Wordings, MakingRoomSentencesHaveAShorterWordingOfTheSamePromise) {
  const TextTemplates t;
  const auto of = [&](Act act, const std::string& text) {
    return wordings(t, Utterance{act, X, 2, text});
  };
  const struct {
    Act act;
    std::string full, shorter;
  } kWordings[] = {
      {Act::kInformDocking, t.inform_docking, t.inform_docking_short},
      {Act::kInformDocking, t.inform_precautionary_docking, t.inform_precautionary_docking_short},
      {Act::kInformWiderPlace, t.inform_wider_place, t.inform_wider_place_short},
      {Act::kInformRetreat, t.inform_retreat, t.inform_retreat_short},
      {Act::kInformStopping, t.inform_stopping, t.inform_stopping_short},
  };
  for (const auto& row : kWordings) {
    EXPECT_EQ(of(row.act, row.full), (std::vector<std::string>{row.full, row.shorter})) << row.full;
    EXPECT_LT(row.shorter.size(), row.full.size()) << row.full;
  }
  EXPECT_EQ(of(Act::kInformDocking, "I will wait here for you to pass.")[1], "I will wait.");
  // Cues that are not a making-room promise have one wording.
  EXPECT_EQ(of(Act::kThank, t.thank).size(), 1U);
  EXPECT_EQ(of(Act::kInformDirection, renderText(t, Act::kInformDirection, L)).size(), 1U);
  // The crowd's address is kept.
  EXPECT_EQ(of(Act::kInformDocking, "You two ahead, " + t.inform_docking)[1],
            "You two ahead, " + t.inform_docking_short);
  // A text that is not its template keeps its own wording only; so does an empty short form.
  EXPECT_EQ(of(Act::kInformDocking, "Wait.").size(), 1U);
  TextTemplates none = t;
  none.inform_retreat_short.clear();
  EXPECT_EQ(wordings(none, Utterance{Act::kInformRetreat, X, 2, none.inform_retreat}).size(), 1U);
}

TEST(Crossed, RobotBehindHavingBeenAheadWithHysteresis) {
  const Pose2 human{0.0, 0.0, 0.0};  // walking +x
  CrossedTracker s;
  s = updateCrossed(s, human, {-3.0, 1.0});  // behind but never ahead: not crossed
  EXPECT_FALSE(s.crossed);
  EXPECT_FALSE(s.seen_ahead);
  s = updateCrossed(s, human, {5.0, 1.0});
  EXPECT_TRUE(s.seen_ahead);
  s = updateCrossed(s, human, {0.1, 1.0});
  s = updateCrossed(s, human, {-0.15, 1.0});  // inside the 0.2 m band: not yet
  EXPECT_FALSE(s.crossed);
  s = updateCrossed(s, human, {-0.25, 1.0});
  EXPECT_TRUE(s.crossed);
  s = updateCrossed(s, human, {3.0, 1.0});  // latched
  EXPECT_TRUE(s.crossed);
  // Heading matters: a human walking −x has the robot at x = −5 ahead of it.
  EXPECT_NEAR(robotAlongHumanHeading_m({0, 0, M_PI}, {-5.0, 0.0}), 5.0, 1e-12);
  // Non-finite input changes nothing.
  CrossedTracker n;
  n = updateCrossed(n, {0, 0, std::nan("")}, {5.0, 0.0});
  EXPECT_FALSE(n.seen_ahead);
}

TEST(Crossed, AHeadingThatFlipsFarOffIsNoCrossing) {
  // A person 25 m off walking towards the robot (heading −x): the robot is ahead of them.
  CrossedTracker s;
  const Eigen::Vector2d robot{3.0, 0.85};
  s = updateCrossed(s, {28.0, 1.0, M_PI}, robot);
  ASSERT_TRUE(s.seen_ahead);
  // The tracker's heading of someone setting off flips for a step: "behind", 25 m off. No.
  s = updateCrossed(s, {27.9, 1.0, 0.0}, robot);
  EXPECT_FALSE(s.crossed);
  // Passing them, near: crossed.
  s = updateCrossed(s, {2.5, 1.5, M_PI}, robot);
  EXPECT_TRUE(s.crossed);
}

}  // namespace
}  // namespace coopnav::dialogue
