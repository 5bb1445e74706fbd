// What a flood of hostile messages can make band_source and dialogue_manager hold
// (docs/bad-inputs.md "Caps"): each node in this process on LCM's in-process bus (memq://), so
// that the test can read the sizes of its per-id and per-step state and of the text it keeps.
// Per-id state stays within limits.max_ids, is forgotten after limits.forget_after_s of message
// time (ids never seen in the agent states too), and text from a message is kept no longer than
// limits.max_text_bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "band_source_node.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "dialogue_manager_node.hpp"
#include "messages.hpp"
#include "runtime/log.hpp"
#include "runtime/runtime.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

/// Every runtime of this process opened on it shares one bus (runtime.hpp).
constexpr const char* kBus = "memq://";
constexpr std::int64_t kStart_us = 1'000'000'000;
constexpr std::int64_t kStep_us = 100'000;
/// The flood of the issue: 5000 situations of new humans with 60 kB reasons.
constexpr int kFloodMessages = 5000;
const std::string kLongReason = "hostile " + std::string(60'000, 'r');

/// Spins the node's runtime (memq: it handles every runtime's messages) until `pred`.
bool spinUntil(Runtime& rt, const std::function<bool()>& pred,
               std::chrono::milliseconds timeout = 10s) {
  return test::waitFor(pred, timeout, [&] { rt.spinFor(5); });
}

class QuietLog : public ::testing::Test {
 protected:
  void SetUp() override { setLogLevel("error"); }
  void TearDown() override { setLogLevel("info"); }
};

// ---------------------------------------------------------------------------------------------
// dialogue_manager

/// Robot constrained, human not: round 1 asks the human to move, round 2 docks if it did not.
situation_t situation(std::int64_t utime, std::int32_t id, double t_cross_s,
                      const std::string& reason = "") {
  return hostile::situation(utime, -1, id, t_cross_s, reason);
}

path_assessment_t notContributing(std::int64_t utime, std::int32_t id) {
  path_assessment_t m{};
  m.utime = utime;
  m.step = -1;
  m.human_id = id;
  m.recording = path_assessment_t::REC_RECORDING;
  m.window_samples = 10;
  m.cm_m = 0.0;
  m.is_contributing = situation_t::PRED_FALSE;
  m.interaction_samples = 10;
  m.cm_interaction_m = 0.0;
  m.is_contributing_interaction = situation_t::PRED_FALSE;
  m.gamma = 0.98;
  m.profile = "paper";
  m.tau_m = 0.4;
  return m;
}

class HostileDialogue : public QuietLog {
 protected:
  void start(const InputLimits& limits = {}) {
    config_.limits = limits;
    config_.round2_response_s = 0.0;  // round 2 at its t_CROSS threshold, as the paper has it
    rt_.setLimits(limits);
    node_ = std::make_unique<DialogueManagerNode>(config_, rt_);
  }
  /// Publishes and has the node handle it.
  template <class Msg>
  void send(const std::string& channel, const Msg& m) {
    probe_.publish(channel, m);
    rt_.spinFor(0);
  }

  DialogueManagerConfig config_;
  Runtime rt_{"dialogue_manager", kBus};
  Runtime probe_{"hostile_probe", kBus};
  std::unique_ptr<DialogueManagerNode> node_;
};

TEST_F(HostileDialogue, FiveThousandNewIdsWithLongReasonsKeepAtMostMaxIdsAndCutTheText) {
  start();
  const InputLimits limits;
  std::size_t most_ids = 0;
  std::size_t longest_text = 0;
  for (int i = 0; i < kFloodMessages; ++i) {
    send(channels::kSituation, situation(kStart_us + i * 10'000, 1000 + i, 9.0, kLongReason));
    most_ids = std::max(most_ids, node_->idsKept());
    longest_text = std::max(longest_text, node_->longestKeptTextBytes());
  }
  EXPECT_GE(rt_.counters().received, kFloodMessages);
  EXPECT_EQ(rt_.counters().rejected, 0);
  EXPECT_EQ(node_->idsKept(), static_cast<std::size_t>(limits.max_ids));
  EXPECT_LE(most_ids, static_cast<std::size_t>(limits.max_ids));
  EXPECT_LE(node_->humansKept(), static_cast<std::size_t>(limits.max_ids));
  EXPECT_GT(longest_text, 0u);
  EXPECT_LE(longest_text, static_cast<std::size_t>(limits.max_text_bytes));
  // The newest ids are the ones kept: the last one is still decided on.
  EXPECT_NE(node_->decision(1000 + kFloodMessages - 1), nullptr);
  EXPECT_EQ(node_->decision(1000), nullptr);
}

TEST_F(HostileDialogue, IdsNeverSeenInTheAgentStatesAreForgottenAfterForgetAfterS) {
  start();
  const double forget_after_s = InputLimits{}.forget_after_s;
  for (int id = 1; id <= 10; ++id) send(channels::kSituation, situation(kStart_us, id, 9.0));
  ASSERT_EQ(node_->idsKept(), 10u);
  // Someone else is heard of every 10 s of message time (no jump the clock would refuse).
  std::int64_t t_us = kStart_us;
  while (t_us - kStart_us < static_cast<std::int64_t>(forget_after_s * 1e6)) {
    t_us += 10'000'000;
    send(channels::kSituation, situation(t_us, 100, 9.0));
    EXPECT_EQ(node_->idsKept(), 11u) << "forgotten before forget_after_s at t " << t_us;
  }
  t_us += 10'000'000;
  send(channels::kSituation, situation(t_us, 100, 9.0));
  EXPECT_EQ(node_->idsKept(), 1u);
  EXPECT_EQ(node_->decision(1), nullptr);
  ASSERT_NE(node_->decision(100), nullptr);
}

TEST_F(HostileDialogue, AHumanForgottenMidInteractionHasItsDockResumedAndRecorderStopped) {
  InputLimits limits;
  limits.max_ids = 16;
  start(limits);
  std::vector<robot_action_t> actions;
  std::vector<path_assessor_control_t> controls;
  probe_.subscribe<robot_action_t>(
      channels::kRobotAction, [&](const robot_action_t& m, std::int64_t) { actions.push_back(m); });
  probe_.subscribe<path_assessor_control_t>(
      channels::kPathAssessorControl,
      [&](const path_assessor_control_t& m, std::int64_t) { controls.push_back(m); });
  // Human 1: round 1 (recorder started), then round 2 docks for it (it did not move).
  std::int64_t t_us = kStart_us;
  send(channels::kPathAssessment, notContributing(t_us, 1));
  send(channels::kSituation, situation(t_us, 1, 6.9));
  t_us += kStep_us;
  send(channels::kSituation, situation(t_us, 1, 3.9));
  // Recorder START (round 1) and RESET (round 2), then the DOCK.
  ASSERT_TRUE(spinUntil(rt_, [&] { return actions.size() == 1u && controls.size() == 2u; }));
  ASSERT_EQ(actions[0].action, robot_action_t::ACTION_DOCK);
  // A flood of new ids pushes human 1 out of the max_ids kept: its dock must not stay behind.
  for (int i = 0; i < limits.max_ids; ++i) {
    t_us += 1'000;
    send(channels::kSituation, situation(t_us, 1000 + i, 9.0, kLongReason));
  }
  ASSERT_TRUE(spinUntil(rt_, [&] { return actions.size() == 2u && controls.size() == 3u; }));
  EXPECT_EQ(actions[1].action, robot_action_t::ACTION_RESUME);
  EXPECT_EQ(actions[1].human_id, 1);
  EXPECT_EQ(controls.back().command, path_assessor_control_t::COMMAND_STOP);
  EXPECT_EQ(controls.back().human_id, 1);
  EXPECT_EQ(node_->decision(1), nullptr);
  EXPECT_LE(node_->idsKept(), static_cast<std::size_t>(limits.max_ids));
  for (const auto& a : actions)
    EXPECT_LE(a.reason.size(), static_cast<std::size_t>(limits.max_text_bytes));
}

TEST_F(HostileDialogue, ReasonsPublishedOnAreCutToMaxTextBytes) {
  start();
  std::vector<robot_action_t> actions;
  probe_.subscribe<robot_action_t>(
      channels::kRobotAction, [&](const robot_action_t& m, std::int64_t) { actions.push_back(m); });
  // Round 2 with RobotIsConstrained unknown: the precautionary dock, whose reason quotes the
  // situation's (here 60 kB).
  send(channels::kPathAssessment, notContributing(kStart_us, 1));
  send(channels::kSituation, situation(kStart_us, 1, 6.9));
  auto unknown = situation(kStart_us + kStep_us, 1, 3.9, kLongReason);
  unknown.robot_is_constrained = situation_t::PRED_UNKNOWN;
  send(channels::kSituation, unknown);
  ASSERT_TRUE(spinUntil(rt_, [&] { return !actions.empty(); }));
  EXPECT_LE(actions[0].reason.size(), static_cast<std::size_t>(InputLimits{}.max_text_bytes));
  EXPECT_NE(actions[0].reason.find("..."), std::string::npos) << actions[0].reason.substr(0, 200);
}

// ---------------------------------------------------------------------------------------------
// band_source

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double th, double vx) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = th;
  a.vx_m_s = vx;
  a.radius_m = kind == agent_state_t::KIND_ROBOT ? 0.34 : 0.3;
  return a;
}

/// The robot in the 6 m corridor of open.pgm with `humans` walking towards it (ids from
/// `first_id`), lockstep step `step` at `utime`.
agent_states_t states(std::int64_t step, std::int64_t utime, int humans = 1,
                      std::int32_t first_id = 1) {
  agent_states_t m{};
  m.utime = utime;
  m.step = step;
  m.robot = agent(0, agent_state_t::KIND_ROBOT, 6.5, 6.5, 0.0, 0.5);
  for (int k = 0; k < humans; ++k)
    m.humans.push_back(
        agent(first_id + k, agent_state_t::KIND_HUMAN, 14.0 + k, 5.5 + k, M_PI, -1.0));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  return m;
}

goals_t robotGoal() {
  goals_t g{};
  g.utime = kStart_us;
  goal_t r{};
  r.agent_id = 0;
  r.kind = agent_state_t::KIND_ROBOT;
  r.x_m = 20.5;
  r.y_m = 6.5;
  g.goals = {r};
  g.num_goals = 1;
  return g;
}

class HostileBand : public QuietLog {
 protected:
  void start(const InputLimits& limits = {}) {
    config_.map.map_file = ::coopnav::test::testDataDir() + "/maps/open.yaml";
    config_.step_gate_timeout_s = 0.5;
    config_.limits = limits;
    rt_.setLimits(limits);
    node_ = std::make_unique<BandSourceNode>(config_, rt_);
    probe_.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& m, std::int64_t) {
      if (m.participant == "band_source") last_ack_ = std::max(last_ack_, m.step);
    });
    probe_.publish(channels::kGoals, robotGoal());
    rt_.spinFor(0);
  }
  /// Publishes a lockstep step and waits for its ack.
  bool step(const agent_states_t& m) {
    probe_.publish(channels::kAgentStates, m);
    return spinUntil(rt_, [&] { return last_ack_ >= m.step; });
  }

  BandSourceConfig config_;
  Runtime rt_{"band_source", kBus};
  Runtime probe_{"hostile_probe", kBus};
  std::unique_ptr<BandSourceNode> node_;
  std::int64_t last_ack_{-1};
};

TEST_F(HostileBand, ThousandsOfActionsWithLongReasonsKeepOneCutReason) {
  start();
  ASSERT_TRUE(step(states(0, kStart_us)));
  for (int i = 0; i < 3000; ++i) {
    robot_action_t a{};
    a.utime = kStart_us;
    a.step = -1;
    a.action = robot_action_t::ACTION_RESUME;
    a.human_id = i;
    a.reason = "hostile\n\x1b[31m[critical] FORGED " + kLongReason;
    probe_.publish(channels::kRobotAction, a);
    rt_.spinFor(0);
  }
  EXPECT_EQ(rt_.counters().rejected, 0);
  EXPECT_GT(node_->pendingActionReason().size(), 0u);
  EXPECT_LE(node_->pendingActionReason().size(),
            static_cast<std::size_t>(InputLimits{}.max_text_bytes));
  ASSERT_TRUE(step(states(1, kStart_us + kStep_us)));
  EXPECT_TRUE(node_->pendingActionReason().empty()) << "applied at the next cycle";
}

TEST_F(HostileBand, DroppedAndRejectedStepsLeaveNoStepTimeBehind) {
  start();
  ASSERT_TRUE(step(states(0, kStart_us)));
  // 150 steps stamped before step 0 (dropped), then 150 stamped ever farther off either way
  // (rejected; never agreeing, so never followed). Fewer than the 320 steps a step gate keeps of
  // a world that never acknowledges (this test's).
  for (std::int64_t k = 1; k <= 150; ++k) ASSERT_TRUE(step(states(k, kStart_us - k)));
  for (std::int64_t k = 151; k <= 300; ++k) {
    const std::int64_t off_us = (k % 2 ? 1 : -1) * 1'000'000'000'000LL * k;
    ASSERT_TRUE(step(states(k, kStart_us + off_us))) << "step " << k;
  }
  EXPECT_EQ(node_->stepsKept(), 0u);
  EXPECT_EQ(node_->cycles(), 1);
  EXPECT_EQ(rt_.counters().dropped, 150);
  EXPECT_EQ(rt_.counters().rejected, 150);
  ASSERT_TRUE(step(states(301, kStart_us + kStep_us)));
  EXPECT_EQ(node_->cycles(), 2);
  EXPECT_EQ(node_->stepsKept(), 0u);
}

TEST_F(HostileBand, NewHumanIdsEveryStepKeepThePlannerMemoryWithinMaxIds) {
  InputLimits limits;
  limits.max_ids = 8;
  start(limits);
  for (std::int64_t k = 0; k < 30; ++k) {
    ASSERT_TRUE(step(states(k, kStart_us + k * kStep_us, 2, 100 + 2 * static_cast<int>(k))));
    EXPECT_LE(node_->plannerIdsKept(), 8u) << "step " << k;
  }
  EXPECT_EQ(node_->cycles(), 30);
}

TEST_F(HostileBand, ThePlannerForgetsAgentsGoneForForgetAfterS) {
  InputLimits limits;
  limits.forget_after_s = 1.0;
  start(limits);
  std::int64_t k = 0;
  for (; k < 5; ++k) ASSERT_TRUE(step(states(k, kStart_us + k * kStep_us, 1, 7)));
  EXPECT_EQ(node_->plannerIdsKept(), 2u);  // the robot and human 7
  // Human 7 gone: within about twice forget_after_s its memory is cleared.
  for (; k < 5 + 25; ++k) ASSERT_TRUE(step(states(k, kStart_us + k * kStep_us, 0)));
  EXPECT_EQ(node_->plannerIdsKept(), 1u);  // the robot only
}

}  // namespace
}  // namespace coopnav
