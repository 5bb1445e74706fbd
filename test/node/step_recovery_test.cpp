// Loss and restarts in lockstep (docs/lockstep.md "Loss and restarts"): a step gate holds a step
// until every message an ack counts is here and applies a repeat once; a step's outputs are sent
// again byte for byte, ack included; a daemon's journal rebuilds its state with publishing muted;
// a path assessor handed a step again answers with what it said the first time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "path_assessor_node.hpp"
#include "runtime/journal.hpp"
#include "runtime/step_gate.hpp"
#include "runtime/step_outputs.hpp"
#include "test_util.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

std::vector<std::uint8_t> encode(const path_assessment_t& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

TEST(StepGateCounts, AStepWaitsForEveryMessageTheAckCountsAndARepeatIsNotedOnce) {
  Runtime rt("gate_dut", test::testLcmUrl());
  StepGateOptions o;
  o.requirements = {{"dialogue_manager", -1, {channels::kRobotAction}}};
  o.timeout = 5000ms;
  StepGate gate(rt, o);
  std::vector<std::int64_t> ran;
  // Given the dialogue manager acknowledged step 4 with two robot actions,
  gate.onAck("dialogue_manager", 4, {{channels::kRobotAction, 2}});
  gate.submit(5, [&](bool, const std::string&) { ran.push_back(5); });
  // when only one has arrived, step 5 waits and says what it misses;
  EXPECT_TRUE(gate.noteReceived("dialogue_manager", channels::kRobotAction, 4, "dock/1"));
  gate.poke();
  EXPECT_TRUE(ran.empty());
  EXPECT_NE(gate.missing(5).find("1/2"), std::string::npos) << gate.missing(5);
  // a repeat of the same one is not counted again;
  EXPECT_FALSE(gate.noteReceived("dialogue_manager", channels::kRobotAction, 4, "dock/1"));
  gate.poke();
  EXPECT_TRUE(ran.empty());
  // the second one lets the step run.
  EXPECT_TRUE(gate.noteReceived("dialogue_manager", channels::kRobotAction, 4, "resume/1"));
  gate.poke();
  EXPECT_EQ(ran, std::vector<std::int64_t>{5});
}

TEST(StepGateCounts, AnOptionalPeerIsNotWaitedForBeforeItWasHeardFrom) {
  Runtime rt("gate_dut", test::testLcmUrl());
  StepGateOptions o;
  o.requirements = {{"world_sim", 0, {channels::kAgentStates}, true}};
  o.wait_for_unseen = true;
  StepGate gate(rt, o);
  int ran = 0;
  gate.submit(0, [&](bool, const std::string&) { ++ran; });
  EXPECT_EQ(ran, 1);            // never heard from: a replay without the world runs on
  gate.onAck("world_sim", -1);  // "here" before a run: from now on waited for
  gate.submit(1, [&](bool, const std::string&) { ++ran; });
  EXPECT_EQ(ran, 1);
  gate.onAck("world_sim", 1, {{channels::kAgentStates, 1}});
  EXPECT_EQ(ran, 1);  // acknowledged, but its agent states of step 1 are not here
  gate.noteReceived("world_sim", channels::kAgentStates, 1, "");
  gate.poke();
  EXPECT_EQ(ran, 2);
}

TEST(StepOutputsTest, AStepIsPublishedAgainByteForByteWithTheSameCountingAck) {
  Runtime dut("outputs_dut", test::testLcmUrl());
  Runtime probe("probe", test::testLcmUrl());
  std::vector<std::vector<std::uint8_t>> got;
  std::vector<step_ack_t> acks;
  probe.subscribe<path_assessment_t>(
      channels::kPathAssessment,
      [&](const path_assessment_t& m, std::int64_t) { got.push_back(encode(m)); });
  probe.subscribe<step_ack_t>(channels::kStepAck, [&](const step_ack_t& a, std::int64_t) {
    if (a.participant == "outputs_dut") acks.push_back(a);
  });
  StepOutputs out(dut);
  path_assessment_t m{};
  m.step = 0;
  m.gamma = 0.98;
  m.profile = "paper";
  for (int id : {1, 2}) {
    m.human_id = id;
    out.publish(0, channels::kPathAssessment, m);
  }
  out.ack(1234, 0);
  ASSERT_TRUE(test::waitFor([&] { return acks.size() == 1 && got.size() == 2; }, 2000ms,
                            [&] { probe.spinFor(5); }));
  ASSERT_EQ(acks[0].num_outputs, 1);
  EXPECT_EQ(acks[0].output_channels[0], channels::kPathAssessment);
  EXPECT_EQ(acks[0].output_counts[0], 2);
  EXPECT_EQ(acks[0].restart, step_ack_t::RESTART_NONE);

  EXPECT_FALSE(out.republish(1));  // never done: nothing to repeat
  out.republishRecent(1);          // repeats step 0 (what step 1's consumers may miss)
  ASSERT_TRUE(test::waitFor([&] { return acks.size() == 2 && got.size() == 4; }, 2000ms,
                            [&] { probe.spinFor(5); }));
  EXPECT_EQ(got[2], got[0]);
  EXPECT_EQ(got[3], got[1]);
  EXPECT_EQ(acks[1].output_counts, acks[0].output_counts);
  EXPECT_EQ(acks[1].utime, 1234);
}

TEST(JournalTest, ARestartedProcessGetsItsRecordedMessagesAgainMutedAndSaysSo) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("coopnav_journal_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  Runtime probe("probe", test::testLcmUrl());
  std::vector<std::int64_t> first;
  {
    Runtime rt("journal_dut", test::testLcmUrl());
    rt.subscribe<agent_states_t>(
        channels::kAgentStates,
        [&](const agent_states_t& m, std::int64_t) { first.push_back(m.step); });
    Journal journal(rt, dir.string());
    EXPECT_EQ(journal.replayAndRecord(), 0u);  // a fresh start
    for (std::int64_t k = 0; k < 3; ++k) {
      agent_states_t s{};
      s.step = k;
      s.robot.radius_m = 0.3;
      probe.publish(channels::kAgentStates, s);
    }
    ASSERT_TRUE(test::waitFor([&] { return first.size() == 3; }, 2000ms, [&] { rt.spinFor(5); }));
  }  // killed: nothing but the journal survives
  Runtime rt("journal_dut", test::testLcmUrl());
  std::vector<std::int64_t> again;
  bool muted_while_replayed = true;
  rt.subscribe<agent_states_t>(channels::kAgentStates, [&](const agent_states_t& m, std::int64_t) {
    again.push_back(m.step);
    muted_while_replayed = muted_while_replayed && rt.muted();
  });
  Journal journal(rt, dir.string());
  EXPECT_EQ(journal.replayAndRecord(), 3u);
  EXPECT_EQ(again, first);
  EXPECT_TRUE(muted_while_replayed);
  EXPECT_FALSE(rt.muted());
  // Its next acknowledgement says it restarted and recovered, from which step.
  step_ack_t a{};
  a.step = 7;
  rt.fillRestart(a);
  EXPECT_EQ(a.restart, step_ack_t::RESTART_RECOVERED);
  EXPECT_EQ(a.restart_step, 7);
  EXPECT_NE(a.restart_note.find("3 messages"), std::string::npos) << a.restart_note;
  std::filesystem::remove_all(dir);
}

TEST(RestartTest, AProcessJoiningMidRunWithoutItsStateMarksItselfDegraded) {
  Runtime rt("late_dut", test::testLcmUrl());
  rt.setLostStateNote("its CA history");
  step_ack_t a{};
  a.step = 41;
  rt.fillRestart(a);  // no world heard yet: a test or a replay, not a restart
  EXPECT_EQ(a.restart, step_ack_t::RESTART_NONE);
  rt.noteWorldAck(41);  // the first world step it hears is not the run's start
  a.step = 42;
  rt.fillRestart(a);
  EXPECT_EQ(a.restart, step_ack_t::RESTART_STATE_LOST);
  EXPECT_EQ(a.restart_step, 42);
  EXPECT_NE(a.restart_note.find("its CA history"), std::string::npos) << a.restart_note;
}

TEST(PathAssessorRepeat, AStepHandedAgainIsAnsweredWithTheSameBytesNotAssessedTwice) {
  Runtime dut("path_assessor", test::testLcmUrl());
  PathAssessorNode node(PathAssessorNode::Config{}, dut);
  Runtime probe("probe", test::testLcmUrl());
  std::map<std::int64_t, std::vector<std::vector<std::uint8_t>>> by_step;
  std::vector<std::int64_t> acks;
  probe.subscribe<path_assessment_t>(
      channels::kPathAssessment,
      [&](const path_assessment_t& m, std::int64_t) { by_step[m.step].push_back(encode(m)); });
  probe.subscribe<step_ack_t>(channels::kStepAck, [&](const step_ack_t& a, std::int64_t) {
    if (a.participant == "path_assessor") acks.push_back(a.step);
  });
  auto states = [](std::int64_t k) {
    AgentStatesSnapshot s;
    s.utime = 1'000'000 + k * 100'000;
    s.step = k;
    s.robot.id = 0;
    s.robot.kind = AgentKind::kRobot;
    s.robot.pose = {1.0 + 0.1 * static_cast<double>(k), 5.0, 0.0};
    s.robot.radius_m = 0.3;
    AgentState h;
    h.id = 1;
    h.kind = AgentKind::kHuman;
    h.pose = {9.0 - 0.1 * static_cast<double>(k), 5.0, 3.14159};
    h.radius_m = 0.3;
    s.humans.push_back(h);
    return toLcm(s);
  };
  auto spin = [&] {
    dut.spinFor(1);
    probe.spinFor(1);
  };
  for (std::int64_t k = 0; k < 3; ++k) {
    probe.publish(channels::kAgentStates, states(k));
    ASSERT_TRUE(test::waitFor([&] { return acks.size() == static_cast<std::size_t>(k + 1); },
                              2000ms, spin));
  }
  // The world publishes step 2 again (an ack was lost): steps 1 and 2 are answered again.
  probe.publish(channels::kAgentStates, states(2));
  ASSERT_TRUE(test::waitFor([&] { return acks.size() == 5; }, 2000ms, spin));
  ASSERT_EQ(by_step[1].size(), 2u);
  ASSERT_EQ(by_step[2].size(), 2u);
  EXPECT_EQ(by_step[1][1], by_step[1][0]);
  EXPECT_EQ(by_step[2][1], by_step[2][0]);
  EXPECT_EQ(by_step[0].size(), 1u);
}

}  // namespace
}  // namespace coopnav
