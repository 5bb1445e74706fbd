// Stand-offs (lib/dialogue/stand_off.hpp) and how the decision resolves them (decision.hpp,
// HumanDecision::resolveStandOff): a mutual wait and a dock the person does not come to pass
// end within a bounded time, in words and an action chosen by the cooperation assessment.
#include "coopnav/dialogue/stand_off.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "coopnav/dialogue/decision.hpp"

namespace coopnav::dialogue {
namespace {

constexpr Tristate T = Tristate::kTrue;
constexpr Tristate F = Tristate::kFalse;

/// Robot and person both still, 1.2 m apart (0.56 m between bodies), t_CROSS as given.
StandOffInput still(double t_s, double t_cross_s = 3.5, double distance_m = 1.2) {
  StandOffInput in;
  in.t_s = t_s;
  in.robot_speed_m_s = 0.0;
  in.human_speed_m_s = 0.05;
  in.centre_distance_m = distance_m;
  in.gap_m = distance_m - 0.34 - 0.3;
  in.t_cross_s = t_cross_s;
  return in;
}

/// Steps the watch at 4 Hz (times exact in binary) from t0_s up to and including t1_s; returns
/// the first stand-off seen and when (t = NaN when none).
std::pair<StandOff, double> run(StandOffWatch& w, double t0_s, double t1_s, bool docked,
                                StandOffInput (*make)(double)) {
  for (int i = 0; t0_s + 0.25 * i <= t1_s; ++i) {
    const double t = t0_s + 0.25 * i;
    const StandOff s = w.update(make(t), docked);
    if (s != StandOff::kNone) return {s, t};
  }
  return {StandOff::kNone, std::numeric_limits<double>::quiet_NaN()};
}

TEST(StandOffWatch, BothStillAndNearWithTheCrossingNoCloserIsAMutualWaitAfterItsTime) {
  StandOffWatch w;
  // t_CROSS creeps down 0.1 s a second (bands shifting, nobody moving): no progress.
  const auto [s, t] = run(w, 0.0, 10.0, false, [](double u) { return still(u, 3.5 - 0.1 * u); });
  EXPECT_EQ(s, StandOff::kMutualWait);
  EXPECT_NEAR(t, StandOffConfig{}.mutual_wait_s, 1e-9);
  EXPECT_NEAR(w.mutualWait_s(), StandOffConfig{}.mutual_wait_s, 1e-9);
  // Reported at every step until restarted; then timed afresh.
  EXPECT_EQ(w.update(still(3.1), false), StandOff::kMutualWait);
  w.restart();
  EXPECT_EQ(w.update(still(3.2), false), StandOff::kNone);
  EXPECT_EQ(w.mutualWait_s(), 0.0);
}

// A robot whose planner and guard take turns in front of the person dithers in place: steps of
// 0.00-0.10 m/s, 0.03 m/s on average. Still waiting; a robot that sets off is not.
TEST(StandOffWatch, ARobotDitheringInPlaceIsStillWaitingOneSettingOffIsNot) {
  StandOffWatch w;
  auto dither = [](double u) {
    StandOffInput in = still(u);
    const int k = static_cast<int>(std::lround(u * 4.0)) % 4;
    in.robot_speed_m_s = k == 1 ? 0.10 : (k == 3 ? 0.02 : 0.0);
    return in;
  };
  const auto [s, t] = run(w, 0.0, 10.0, false, dither);
  EXPECT_EQ(s, StandOff::kMutualWait);
  EXPECT_NEAR(t, StandOffConfig{}.mutual_wait_s, 0.25 + 1e-9);
  // Dithering faster on average than robot_still_m_s is moving.
  StandOffWatch busy;
  EXPECT_EQ(run(busy, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = still(u);
                  in.robot_speed_m_s = static_cast<int>(std::lround(u * 4.0)) % 2 ? 0.12 : 0.0;
                  return in;
                })
                .first,
            StandOff::kNone);
  // Setting off (one step above robot_dither_m_s) ends the wait at once.
  StandOffWatch off;
  EXPECT_EQ(run(off, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = still(u);
                  if (static_cast<int>(std::lround(u * 4.0)) % 8 == 7) in.robot_speed_m_s = 0.2;
                  return in;
                })
                .first,
            StandOff::kNone);
}

TEST(StandOffWatch, TheCrossingGettingCloserIsNoMutualWait) {
  StandOffWatch w;
  // t_CROSS falls 0.3 s a second: every 0.5 s of it restarts the wait, which never lasts 3 s.
  const auto [s, t] = run(w, 0.0, 10.0, false, [](double u) { return still(u, 6.0 - 0.3 * u); });
  EXPECT_EQ(s, StandOff::kNone) << t;
}

TEST(StandOffWatch, SomeoneMovingOrFarIsNoMutualWait) {
  StandOffWatch robot_moves, human_walks, far;
  EXPECT_EQ(run(robot_moves, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = still(u);
                  in.robot_speed_m_s = 0.3;
                  return in;
                })
                .first,
            StandOff::kNone);
  EXPECT_EQ(run(human_walks, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = still(u);
                  in.human_speed_m_s = 0.8;
                  return in;
                })
                .first,
            StandOff::kNone);
  EXPECT_EQ(run(far, 0.0, 10.0, false, [](double u) { return still(u, 3.5, 6.0); }).first,
            StandOff::kNone);
  // A wait interrupted by a step of walking starts again.
  StandOffWatch w;
  for (double t = 0.0; t < 2.5; t += 0.1) EXPECT_EQ(w.update(still(t), false), StandOff::kNone);
  StandOffInput walk = still(2.5);
  walk.human_speed_m_s = 1.0;
  EXPECT_EQ(w.update(walk, false), StandOff::kNone);
  EXPECT_EQ(w.update(still(4.0), false), StandOff::kNone);
  EXPECT_EQ(w.update(still(6.9), false), StandOff::kNone);
  EXPECT_EQ(w.update(still(7.0), false), StandOff::kMutualWait);
}

TEST(StandOffWatch, ADockThePersonDoesNotComeToPassEndsAfterItsWait) {
  // The person walks about (never still: no mutual wait) but comes no nearer.
  StandOffWatch w;
  const auto [s, t] = run(w, 0.0, 20.0, true, [](double u) {
    StandOffInput in = still(u, 3.5, 4.0 + 0.1 * std::sin(u));
    in.human_speed_m_s = 0.5;
    return in;
  });
  EXPECT_EQ(s, StandOff::kDockNoShow);
  EXPECT_NEAR(t, StandOffConfig{}.dock_wait_s, 1e-9);
  // Not docked: never.
  StandOffWatch free;
  EXPECT_EQ(run(free, 0.0, 20.0, false,
                [](double u) {
                  StandOffInput in = still(u, 3.5, 4.0);
                  in.human_speed_m_s = 0.5;
                  return in;
                })
                .first,
            StandOff::kNone);
}

TEST(StandOffWatch, APersonComingToPassTheDockIsProgressEvenWhenCreeping) {
  StandOffWatch w;
  // 0.05 m/s nearer, walking: 0.3 m every 6 s, within the 8 s wait each time.
  const auto [s, t] = run(w, 0.0, 40.0, true, [](double u) {
    StandOffInput in = still(u, 3.5, 6.0 - 0.05 * u);
    in.human_speed_m_s = 0.5;
    return in;
  });
  EXPECT_EQ(s, StandOff::kNone) << t;
}

TEST(StandOffWatch, NonFiniteInputIsNoEvidence) {
  StandOffWatch w;
  for (double t = 0.0; t < 2.9; t += 0.1) w.update(still(t), false);
  StandOffInput bad = still(2.9);
  bad.human_speed_m_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(w.update(bad, false), StandOff::kNone);
  EXPECT_EQ(w.mutualWait_s(), 0.0);
  EXPECT_EQ(w.update(still(3.5), false), StandOff::kNone);  // timed afresh from 3.5 s
  StandOffInput no_t_cross = still(6.5);
  no_t_cross.t_cross_s.reset();  // unknown t_CROSS: the stillness alone counts
  EXPECT_EQ(w.update(no_t_cross, false), StandOff::kMutualWait);
}

/// The robot backing off at 0.3 m/s before a person 1.0 m away who follows at 0.3 m/s, in front
/// of it (the robot faces its goal and backs).
StandOffInput backing(double t_s) {
  StandOffInput in = still(t_s, 3.5, 1.0);
  in.t_cross_s.reset();  // the bands yield ground: no crossing ahead
  in.robot_speed_m_s = 0.3;
  in.human_speed_m_s = 0.3;
  in.robot_receding_m_s = 0.3;
  in.human_closing_m_s = 0.3;
  in.human_ahead = true;
  return in;
}

TEST(StandOffWatch, BackingOffBeforeAPersonWhoFollowsIsAStandOffAfterItsTime) {
  StandOffWatch w;
  const auto [s, t] = run(w, 0.0, 10.0, false, backing);
  EXPECT_EQ(s, StandOff::kBackingOff);
  EXPECT_NEAR(t, StandOffConfig{}.backing_off_s, 1e-9);
  EXPECT_NEAR(w.backingOff_s(), StandOffConfig{}.backing_off_s, 1e-9);
  // Not while docked (a retreat the robot announced: watched as a dock), not with the person
  // behind the robot (the robot drives on and is followed), not when the person stops following.
  StandOffWatch docked;
  EXPECT_EQ(run(docked, 0.0, 5.0, true, backing).first, StandOff::kNone);
  StandOffWatch behind;
  EXPECT_EQ(run(behind, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = backing(u);
                  in.human_ahead = false;
                  return in;
                })
                .first,
            StandOff::kNone);
  StandOffWatch stands;
  EXPECT_EQ(run(stands, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = backing(u);
                  in.human_closing_m_s = 0.0;  // the person does not come after it
                  return in;
                })
                .first,
            StandOff::kNone);
  StandOffWatch stops;
  EXPECT_EQ(run(stops, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = backing(u);
                  if (u >= 0.5) in.robot_receding_m_s = 0.0;  // a step back, then it stays
                  return in;
                })
                .first,
            StandOff::kNone);
  // Judged on means: a chase whose speeds flicker round the person's standing threshold, step
  // by step (a tracked person's velocity noise), is still one.
  StandOffWatch noisy;
  EXPECT_EQ(run(noisy, 0.0, 10.0, false,
                [](double u) {
                  StandOffInput in = backing(u);
                  const bool odd = static_cast<int>(u * 4.0) % 2 == 1;
                  in.robot_receding_m_s = odd ? 0.0 : 0.4;
                  in.human_closing_m_s = odd ? -0.1 : 0.5;
                  return in;
                })
                .first,
            StandOff::kBackingOff);
}

// ---- decisions ----

/// Round 1 fired (silent), the person needs to contribute, the robot is constrained.
DecisionInput narrow(double t_s, double t_cross_s) {
  DecisionInput in;
  in.t_s = t_s;
  in.situation.t_cross_s = t_cross_s;
  in.situation.human_needs_to_contribute = T;
  in.situation.human_is_constrained = T;
  in.situation.robot_is_constrained = T;
  in.situation.d_h_m = 0.8;
  in.situation.room_plan = RoomPlan::kDockHere;
  in.path.cm_window_m = 0.1;
  in.path.is_contributing = F;
  return in;
}

DecisionInput withMotion(DecisionInput in, double distance_m = 1.2) {
  in.motion = still(in.t_s, *in.situation.t_cross_s, distance_m);
  return in;
}

/// Steps `dut` at 4 Hz from t0_s to t1_s with `make`; returns the outputs that are not empty.
std::vector<DecisionOutput> steps(HumanDecision& dut, double t0_s, double t1_s,
                                  DecisionInput (*make)(double)) {
  std::vector<DecisionOutput> out;
  for (int i = 0; t0_s + 0.25 * i <= t1_s; ++i) {
    DecisionOutput o = dut.step(make(t0_s + 0.25 * i));
    if (!o.empty()) out.push_back(std::move(o));
  }
  return out;
}

TEST(StandOffDecision, ADockThePersonDoesNotComeToPassEndsWithWordsAndAResume) {
  HumanDecision dut;
  dut.step(narrow(0.0, 6.5));  // round 1: "I will wait at the side if needed."
  // Round 2 docks at 1 s; the person stays 4 m away, walking about: no mutual wait, no progress.
  const auto outs = steps(dut, 1.0, 20.0, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.5), 4.0);
    in.motion->human_speed_m_s = 0.5;
    return in;
  });
  ASSERT_EQ(outs.size(), 2u);
  EXPECT_EQ(outs[0].robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  const DecisionOutput& end = outs[1];
  EXPECT_EQ(end.robot_actions, std::vector<RobotAction>{RobotAction::kResume});
  ASSERT_EQ(end.utterances.size(), 1u);
  EXPECT_EQ(end.utterances[0].act, SpeechAct::kInformResuming);
  EXPECT_EQ(end.utterances[0].text, "I will go now.");
  ASSERT_EQ(end.rounds.size(), 1u);
  EXPECT_NEAR(end.rounds[0].t_s, 1.0 + StandOffConfig{}.dock_wait_s, 1e-9);
  EXPECT_NE(end.rounds[0].branch.find("dock_no_show"), std::string::npos) << end.rounds[0].branch;
  EXPECT_FALSE(dut.docked());
}

TEST(StandOffDecision, DockedInAMutualWaitWithAPersonWhoMadeRoomTheRobotGoesFirst) {
  HumanDecision dut;
  dut.step(narrow(0.0, 6.5));
  ASSERT_EQ(dut.step(withMotion(narrow(1.0, 3.5))).robot_actions,
            std::vector<RobotAction>{RobotAction::kDock});
  // Both wait at 1.2 m; the person has made room: CM 0.9 m >= d_h 0.8 m.
  const auto outs = steps(dut, 1.25, 6.5, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.4));
    in.path.cm_window_m = 0.9;
    return in;
  });
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].robot_actions, std::vector<RobotAction>{RobotAction::kResume});
  ASSERT_EQ(outs[0].utterances.size(), 1u);
  EXPECT_EQ(outs[0].utterances[0].act, SpeechAct::kInformGoingFirst);
  EXPECT_EQ(outs[0].utterances[0].text, "Thank you, I will go first.");
  // Bounded: decided once the wait has lasted mutual_wait_s (timed from the dock's step).
  EXPECT_NEAR(outs[0].rounds[0].t_s, 1.0 + StandOffConfig{}.mutual_wait_s, 1e-9);
  // The person's plan needing nothing of them any more (the passage fits) counts as well.
  HumanDecision other;
  other.step(narrow(0.0, 6.5));
  other.step(withMotion(narrow(1.0, 3.5)));
  const auto fits = steps(other, 1.25, 6.5, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.4));
    in.situation.human_needs_to_contribute = F;
    return in;
  });
  ASSERT_EQ(fits.size(), 1u);
  EXPECT_EQ(fits[0].utterances.at(0).act, SpeechAct::kInformGoingFirst);
}

TEST(StandOffDecision, NotDockedAPersonWhoDidNotMakeRoomIsGivenWayWithWordsAtEveryStandOff) {
  HumanDecision dut;
  // Round 2 silent (the person moved enough then: CM 0.9 >= d_h), then both stand.
  dut.step(narrow(0.0, 6.5));
  const auto outs = steps(dut, 1.0, 40.0, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.5));
    // The person has since stepped back into the way: its plan needs it to move (CM reset).
    in.path.cm_window_m = u < 1.05 ? 0.9 : 0.1;
    // Near the crossing, the words of a stand-off are still said (they have no deadline).
    in.situation.t_cross_s = 0.4;
    return in;
  });
  ASSERT_GE(outs.size(), 5u);
  // Round 2 at 1 s is silent; the mutual wait at 4 s docks with words ...
  EXPECT_TRUE(outs[0].robot_actions.empty());
  EXPECT_EQ(outs[1].robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  ASSERT_EQ(outs[1].utterances.size(), 1u);
  EXPECT_EQ(outs[1].utterances[0].act, SpeechAct::kInformDocking);
  EXPECT_TRUE(outs[1].utterances[0].resolves_stand_off);
  EXPECT_NEAR(outs[1].rounds[0].t_s, 1.0 + StandOffConfig{}.mutual_wait_s, 1e-9);
  // ... the person still stands: the dock ends with words after its bounded wait ...
  EXPECT_EQ(outs[2].robot_actions, std::vector<RobotAction>{RobotAction::kResume});
  EXPECT_EQ(outs[2].utterances.at(0).act, SpeechAct::kInformResuming);
  // ... and every later stand-off is resolved the same way, within the same bounds, never in
  // silence: a dock with its words, ended with words after its wait.
  double last_t_s = outs[2].rounds.at(0).t_s;
  for (std::size_t i = 3; i < outs.size(); ++i) {
    ASSERT_EQ(outs[i].rounds.size(), 1u);
    ASSERT_EQ(outs[i].robot_actions.size(), 1u);
    ASSERT_EQ(outs[i].utterances.size(), 1u);
    EXPECT_TRUE(outs[i].rounds[0].reason.empty()) << outs[i].rounds[0].reason;
    const bool docks = i % 2 == 1;
    EXPECT_EQ(outs[i].robot_actions[0], docks ? RobotAction::kDock : RobotAction::kResume);
    EXPECT_EQ(outs[i].utterances[0].act,
              docks ? SpeechAct::kInformDocking : SpeechAct::kInformResuming);
    if (docks) {
      EXPECT_NE(outs[i].rounds[0].branch.find("docked before -> dock again"), std::string::npos)
          << outs[i].rounds[0].branch;
    }
    const double bound_s = docks ? StandOffConfig{}.mutual_wait_s : StandOffConfig{}.dock_wait_s;
    EXPECT_LE(outs[i].rounds[0].t_s - last_t_s, bound_s + 0.25 + 1e-9);
    last_t_s = outs[i].rounds[0].t_s;
  }
}

// A later dock escalated to a retreat by the band source is announced again: each dock is its
// own promise.
TEST(StandOffDecision, ALaterDockThatBecomesARetreatIsAnnounced) {
  HumanDecision dut;
  dut.step(narrow(0.0, 6.5));
  // Round 2 docks as a retreat: "I will back up to let you pass." said at once.
  DecisionInput first = withMotion(narrow(1.0, 3.5));
  first.situation.room_plan = RoomPlan::kRetreat;
  ASSERT_EQ(dut.step(first).utterances.at(0).act, SpeechAct::kInformRetreat);
  // The person never comes: the dock ends, the two meet again, the robot docks again (here) ...
  auto outs = steps(dut, 1.25, 14.0, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.5), 4.0);
    in.motion->human_speed_m_s = 0.5;
    return in;
  });
  ASSERT_EQ(outs.size(), 1u);  // the dock's end
  outs = steps(dut, 14.25, 18.0, [](double u) { return withMotion(narrow(u, 3.5)); });
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].utterances.at(0).act, SpeechAct::kInformDocking);
  // ... and then backs away as the person closes: said, though a retreat was said before.
  DecisionInput retreating = withMotion(narrow(18.25, 3.5));
  retreating.situation.robot_retreating = true;
  const DecisionOutput told = dut.step(retreating);
  ASSERT_EQ(told.utterances.size(), 1u);
  EXPECT_EQ(told.utterances[0].act, SpeechAct::kInformRetreat);
  EXPECT_TRUE(told.utterances[0].resolves_stand_off);  // said even at the crossing's door
}

// Not docked, a person who made room waits for the robot, which waits too: the robot goes
// first, said and done in the same step (GO_FIRST with "Thank you, I will go first."), once; if
// the wait goes on (the guard kept the robot back), it makes room instead, with its words.
TEST(StandOffDecision, NotDockedAPersonWhoMadeRoomIsPassedWithWords) {
  HumanDecision dut;
  dut.step(narrow(0.0, 6.5));
  const auto outs = steps(dut, 1.0, 12.0, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.5));
    in.path.cm_window_m = 0.9;  // made room: round 2 silent, no dock
    return in;
  });
  ASSERT_GE(outs.size(), 3u);  // round 2, the stand-off, the stand-off again
  EXPECT_TRUE(outs[0].robot_actions.empty());
  EXPECT_EQ(outs[1].robot_actions, std::vector<RobotAction>{RobotAction::kGoFirst});
  ASSERT_EQ(outs[1].utterances.size(), 1u);
  EXPECT_EQ(outs[1].utterances[0].act, SpeechAct::kInformGoingFirst);
  EXPECT_NE(outs[1].rounds.at(0).branch.find("made room -> go first"), std::string::npos);
  EXPECT_EQ(outs[2].robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  ASSERT_EQ(outs[2].utterances.size(), 1u);
  EXPECT_EQ(outs[2].utterances[0].act, SpeechAct::kInformDocking);
  EXPECT_NE(outs[2].rounds.at(0).branch.find("went first -> dock"), std::string::npos);
}

TEST(StandOffDecision, GoingFirstOffLeavesTheWaitToTheRoundsReason) {
  DecisionConfig c;
  c.go_first_when_not_docked = false;
  HumanDecision dut(c);
  dut.step(narrow(0.0, 6.5));
  const auto outs = steps(dut, 1.0, 6.0, [](double u) {
    DecisionInput in = withMotion(narrow(u, 3.5));
    in.path.cm_window_m = 0.9;
    return in;
  });
  ASSERT_EQ(outs.size(), 2u);
  EXPECT_TRUE(outs[1].utterances.empty());
  EXPECT_TRUE(outs[1].robot_actions.empty());
  EXPECT_FALSE(outs[1].rounds.at(0).reason.empty());
}

TEST(StandOffDecision, NoStandOffBeforeRoundOneAfterTheCrossingOrWhenNotResolving) {
  // Before round 1 (t_CROSS above 7 s): nothing.
  HumanDecision early;
  EXPECT_TRUE(steps(early, 0.0, 20.0, [](double u) { return withMotion(narrow(u, 9.0)); }).empty());
  // The paper's reading: the dock waits for the person.
  DecisionConfig paper;
  paper.resolve_stand_offs = false;
  HumanDecision waits(paper);
  waits.step(narrow(0.0, 6.5));
  const auto outs =
      steps(waits, 1.0, 30.0, [](double u) { return withMotion(narrow(u, 3.5), 4.0); });
  ASSERT_EQ(outs.size(), 1u);  // the dock only
  EXPECT_TRUE(waits.docked());
}

TEST(StandOffDecision, BackingOffBeforeRoundOneEndsInADockSaidAndTakesTheRoundsPlace) {
  // Given no crossing ahead (the planner backs the robot off before the person: t_CROSS
  // unknown, so round 1 never comes) ...
  HumanDecision dut;
  const auto outs = steps(dut, 0.0, 10.0, [](double u) {
    DecisionInput in = narrow(u, 9.0);
    in.situation.t_cross_s.reset();
    in.motion = backing(u);
    return in;
  });
  // ... the robot makes room, and says so, once it has backed off backing_off_s.
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0].robot_actions, std::vector<RobotAction>{RobotAction::kDock});
  ASSERT_EQ(outs[0].utterances.size(), 1u);
  EXPECT_EQ(outs[0].utterances[0].act, SpeechAct::kInformDocking);
  EXPECT_TRUE(outs[0].utterances[0].resolves_stand_off);
  ASSERT_EQ(outs[0].rounds.size(), 1u);
  EXPECT_NEAR(outs[0].rounds[0].t_s, StandOffConfig{}.backing_off_s, 1e-9);
  EXPECT_EQ(outs[0].rounds[0].branch.rfind("before round 1: stand-off: backing_off", 0), 0u)
      << outs[0].rounds[0].branch;
  EXPECT_TRUE(dut.docked());
  // Rounds 1 and 2 do not speak after it: their words would contradict the dock.
  EXPECT_TRUE(dut.roundFired(1));
  EXPECT_TRUE(dut.roundFired(2));
  EXPECT_TRUE(dut.step(narrow(10.25, 6.5)).utterances.empty());
}

}  // namespace
}  // namespace coopnav::dialogue
