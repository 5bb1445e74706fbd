// dialogue_manager as a real process on this executable's udpm port. The test plays
// situation_assessor and path_assessor: it publishes situations, path assessments, agent states
// and their step acks by hand, and reads the utterances, robot actions, recorder controls and
// step acks the daemon publishes (docs/lockstep.md row 4).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "runtime/runtime.hpp"
#include "speech_output.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::int8_t T = situation_t::PRED_TRUE;
constexpr std::int8_t F = situation_t::PRED_FALSE;
constexpr std::int8_t U = situation_t::PRED_UNKNOWN;

struct Sit {
  std::int32_t id{1};
  double t_cross_s{10.0};
  std::int8_t needs{T};
  std::int8_t human_constrained{F};
  std::int8_t robot_constrained{F};
  std::int8_t dir{situation_t::DIR_LEFT};
  double d_h_m{0.6};
  std::int8_t crossing_status{situation_t::CROSSING_OK};
  std::string reason{};
};

struct Path {
  std::int32_t id{1};
  double cm_m{0.0};
  std::int8_t contributing{F};
  std::int8_t recording{path_assessment_t::REC_RECORDING};
  double p_contributing{std::numeric_limits<double>::quiet_NaN()};  ///< the forecast; NaN unknown
};

struct Human {
  std::int32_t id;
  double x_m, y_m, theta_rad;
};

std::int64_t utimeOf(std::int64_t step) { return 1'000'000 + step * 100'000; }

class DialogueManagerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    probe_.subscribe<utterance_t>(channels::kUtterance, [this](const utterance_t& m, std::int64_t) {
      utterances_.push_back(m);
      events_ += 'U';
    });
    probe_.subscribe<robot_action_t>(channels::kRobotAction,
                                     [this](const robot_action_t& m, std::int64_t) {
                                       actions_.push_back(m);
                                       events_ += 'A';
                                     });
    probe_.subscribe<path_assessor_control_t>(
        channels::kPathAssessorControl, [this](const path_assessor_control_t& m, std::int64_t) {
          controls_.push_back(m);
          events_ += 'C';
        });
    probe_.subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& m, std::int64_t) {
      if (m.participant != "dialogue_manager") return;
      acks_.push_back(m.step);
      events_ += 'K';
    });
    probe_.subscribe<daemon_status_t>(channels::kStatus,
                                      [this](const daemon_status_t& m, std::int64_t) {
                                        if (m.name == "dialogue_manager") status_ = m;
                                      });
  }

  /// The flowchart tests run round 2 at its t_CROSS threshold only, as the paper does
  /// (round2_response_s 0); the wait for a response to round 1's words has tests of its own.
  void start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"--lcm-url", test::testLcmUrl(),   "--log-level", "warn",
                                  "--set",     "round2_response_s=0"};
    args.insert(args.end(), extra.begin(), extra.end());
    dut_ = std::make_unique<test::ChildProcess>(test::daemonPath("dialogue_manager"), args);
    ASSERT_TRUE(spinUntil([&] { return status_ && status_->pid == dut_->pid(); }, seconds(5)))
        << "no status from this dialogue_manager";
  }

  bool spinUntil(const std::function<bool()>& pred, milliseconds timeout) {
    return test::waitFor(pred, timeout, [&] { probe_.spinFor(5); });
  }
  void settle(milliseconds d = milliseconds(150)) { probe_.spinFor(static_cast<int>(d.count())); }

  /// `utime`: the message time when not the step's (free-running messages carry their own).
  void situation(std::int64_t step, const Sit& s, std::optional<std::int64_t> utime = {}) {
    situation_t m{};
    m.utime = utime.value_or(utimeOf(step));
    m.step = step;
    m.human_id = s.id;
    m.crossing_status = s.crossing_status;
    const bool ok = s.crossing_status == situation_t::CROSSING_OK;
    m.i_star = ok ? 10 : -1;
    m.t_cross_s = s.t_cross_s;
    m.cp_h_x_m = ok ? 5.0 : kNaN;
    m.cp_h_y_m = ok ? 0.0 : kNaN;
    m.cp_r_x_m = ok ? 5.0 : kNaN;
    m.cp_r_y_m = ok ? 0.7 : kNaN;
    m.dir = s.dir;
    m.d_h_m = s.d_h_m;
    m.d_oh_m = 1.0;
    m.d_or_m = 1.0;
    m.d_hr_m = 0.7;
    m.human_needs_to_contribute = s.needs;
    m.human_is_constrained = s.human_constrained;
    m.robot_is_constrained = s.robot_constrained;
    m.tau_h_m = 0.3;
    m.tau_oh_m = 0.5;
    m.tau_or_m = 0.5;
    m.tau_hr_m = 1.0;
    m.reason = s.reason;
    probe_.publish(channels::kSituation, m);
  }

  void path(std::int64_t step, const Path& p, std::optional<std::int64_t> utime = {}) {
    path_assessment_t m{};
    m.utime = utime.value_or(utimeOf(step));
    m.step = step;
    m.human_id = p.id;
    m.recording = p.recording;
    m.num_samples = 0;
    m.window_samples = 10;
    m.cm_m = p.cm_m;
    m.is_contributing = p.contributing;
    m.interaction_samples = 10;
    m.cm_interaction_m = p.cm_m;
    m.is_contributing_interaction = p.contributing;
    m.gamma = 0.98;
    m.profile = "paper";
    m.tau_m = 0.4;
    m.p_contributing = p.p_contributing;
    probe_.publish(channels::kPathAssessment, m);
  }

  void agents(std::int64_t step, double robot_x_m, double robot_y_m,
              const std::vector<Human>& humans) {
    agent_states_t m{};
    m.utime = utimeOf(step);
    m.step = step;
    m.robot.id = 0;
    m.robot.kind = agent_state_t::KIND_ROBOT;
    m.robot.x_m = robot_x_m;
    m.robot.y_m = robot_y_m;
    m.robot.theta_rad = M_PI;
    m.robot.radius_m = 0.3;
    for (const auto& h : humans) {
      agent_state_t a{};
      a.id = h.id;
      a.kind = agent_state_t::KIND_HUMAN;
      a.x_m = h.x_m;
      a.y_m = h.y_m;
      a.theta_rad = h.theta_rad;
      a.radius_m = 0.3;
      m.humans.push_back(a);
    }
    m.num_humans = static_cast<std::int16_t>(m.humans.size());
    probe_.publish(channels::kAgentStates, m);
  }

  void ack(const std::string& participant, std::int64_t step) {
    step_ack_t a{};
    a.utime = utimeOf(step);
    a.step = step;
    a.participant = participant;
    probe_.publish(channels::kStepAck, a);
  }
  void ackBoth(std::int64_t step) {
    ack("path_assessor", step);
    ack("situation_assessor", step);
  }
  bool acked(std::int64_t step) const {
    return std::find(acks_.begin(), acks_.end(), step) != acks_.end();
  }
  bool waitAck(std::int64_t step) {
    return spinUntil([&] { return acked(step); }, seconds(3));
  }
  /// One lockstep step as the real pipeline orders it: paths, situations, then both acks.
  void fullStep(std::int64_t step, const std::vector<Sit>& sits, const std::vector<Path>& paths) {
    for (const auto& p : paths) path(step, p);
    for (const auto& s : sits) situation(step, s);
    ackBoth(step);
    ASSERT_TRUE(waitAck(step)) << "dialogue_manager did not acknowledge step " << step;
  }
  /// Makes both assessors "seen" so that the gate waits for them from now on.
  void primePeers() {
    ackBoth(0);
    ASSERT_TRUE(waitAck(0));
  }

  std::vector<utterance_t> utterancesOf(std::int32_t id) const {
    std::vector<utterance_t> r;
    for (const auto& u : utterances_)
      if (u.human_id == id) r.push_back(u);
    return r;
  }

  Runtime probe_{"probe", test::testLcmUrl()};
  std::unique_ptr<test::ChildProcess> dut_;
  std::vector<utterance_t> utterances_;
  std::vector<robot_action_t> actions_;
  std::vector<path_assessor_control_t> controls_;
  std::vector<std::int64_t> acks_;
  std::string events_;
  std::optional<daemon_status_t> status_;
};

TEST_F(DialogueManagerTest, RoundOneAtSevenSecondsSpeaksDirAndStartsTheRecorder) {
  start();
  primePeers();
  fullStep(1, {{1, 9.0}}, {});
  EXPECT_TRUE(utterances_.empty());
  EXPECT_TRUE(controls_.empty());
  events_.clear();
  fullStep(2, {{1, 6.9, T, F, F, situation_t::DIR_LEFT}}, {});
  ASSERT_EQ(utterances_.size(), 1u);
  const utterance_t& u = utterances_[0];
  EXPECT_EQ(u.speech_act, utterance_t::ACT_INFORM_DIRECTION);
  EXPECT_EQ(u.direction, situation_t::DIR_LEFT);
  EXPECT_EQ(u.human_id, 1);
  EXPECT_EQ(u.round, 1);
  EXPECT_EQ(u.step, 2);
  EXPECT_EQ(u.utime, utimeOf(2));
  EXPECT_DOUBLE_EQ(u.t_cross_s, 6.9);
  EXPECT_EQ(u.text, "I will pass on your left.");
  ASSERT_EQ(controls_.size(), 1u);
  EXPECT_EQ(controls_[0].command, path_assessor_control_t::COMMAND_START);
  EXPECT_EQ(controls_[0].human_id, 1);
  EXPECT_EQ(controls_[0].step, 2);
  EXPECT_EQ(controls_[0].utime, utimeOf(2));
  // The START carries the situation it was decided on (the path assessor's room, tau_mode).
  EXPECT_DOUBLE_EQ(controls_[0].d_oh_m, 1.0);
  EXPECT_DOUBLE_EQ(controls_[0].d_h_m, 0.6);
  EXPECT_TRUE(actions_.empty());
  EXPECT_EQ(events_, "UCK") << "utterance, control, then the ack";
  // t_CROSS keeps falling (and jitters back over 7 s): round 1 does not fire again.
  fullStep(3, {{1, 7.2, T, F, F, situation_t::DIR_LEFT}}, {});
  fullStep(4, {{1, 6.5, T, F, F, situation_t::DIR_LEFT}}, {});
  EXPECT_EQ(utterances_.size(), 1u);
  EXPECT_EQ(controls_.size(), 1u);
}

TEST_F(DialogueManagerTest, RoundTwoDocksAConstrainedRobotWhenCmStaysBelowDh) {
  start({"--set", "templates.ask_to_move=Please step to your {dir}."});
  primePeers();
  // Round 1: robot constrained, human not: ask the human to move away from the robot's side.
  fullStep(1, {{1, 6.8, T, F, T, situation_t::DIR_LEFT}}, {});
  ASSERT_EQ(utterances_.size(), 1u);
  EXPECT_EQ(utterances_[0].speech_act, utterance_t::ACT_ASK_TO_MOVE);
  EXPECT_EQ(utterances_[0].direction, situation_t::DIR_RIGHT);
  EXPECT_EQ(utterances_[0].text, "Please step to your right.");
  fullStep(2, {{1, 5.0, T, F, T, situation_t::DIR_LEFT}}, {{1, 0.02, F}});
  events_.clear();
  // Round 2: CM 0.05 < d_h 0.6, robot constrained, not contributing -> dock.
  fullStep(3, {{1, 3.9, T, F, T, situation_t::DIR_LEFT, 0.6}}, {{1, 0.05, F}});
  ASSERT_EQ(actions_.size(), 1u);
  EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
  EXPECT_EQ(actions_[0].human_id, 1);
  EXPECT_EQ(actions_[0].step, 3);
  EXPECT_EQ(actions_[0].utime, utimeOf(3));
  ASSERT_EQ(utterances_.size(), 2u);
  EXPECT_EQ(utterances_[1].speech_act, utterance_t::ACT_INFORM_DOCKING);
  EXPECT_EQ(utterances_[1].round, 2);
  ASSERT_EQ(controls_.size(), 2u);
  EXPECT_EQ(controls_[1].command, path_assessor_control_t::COMMAND_RESET);
  EXPECT_EQ(events_, "UACK");
  // Round 2 once only.
  fullStep(4, {{1, 3.5, T, F, T, situation_t::DIR_LEFT, 0.6}}, {{1, 0.05, F}});
  EXPECT_EQ(actions_.size(), 1u);
}

TEST_F(DialogueManagerTest, UnknownPredicatesNearTheCrossingDockAsAPrecautionSaidDegraded) {
  start();
  primePeers();
  // The distance server is down: d_OH / d_OR unknown, so HumanIsConstrained and
  // RobotIsConstrained are unknown (d_HR below tau_HR). Human 1 does not move aside (CM 0.05 m
  // below d_h 0.6 m, not contributing): as narrow_minimal without the server. Human 2: same,
  // but the robot is known to be free (d_HR above tau_HR). Human 3: unknown robot constraint,
  // but the human is moving aside (contributing).
  const std::string why = "distance server: no reply from the distance server after 3 attempts";
  const auto sits = [&](double t) {
    return std::vector<Sit>{
        {1, t, T, U, U, situation_t::DIR_LEFT, 0.6, situation_t::CROSSING_OK, why},
        {2, t, T, U, F, situation_t::DIR_LEFT, 0.6, situation_t::CROSSING_OK, why},
        {3, t, T, U, U, situation_t::DIR_LEFT, 0.6, situation_t::CROSSING_OK, why}};
  };
  fullStep(1, sits(6.9), {});
  EXPECT_TRUE(actions_.empty()) << "no dock before round 2";
  EXPECT_TRUE(utterancesOf(1).empty()) << "round 1 stays silent on an unknown";
  fullStep(2, sits(5.0), {{1, 0.02, F}, {2, 0.02, F}, {3, 0.3, T}});
  EXPECT_TRUE(actions_.empty()) << "no dock before round 2";
  fullStep(3, sits(3.9), {{1, 0.05, F}, {2, 0.05, F}, {3, 0.45, T}});
  settle();
  ASSERT_EQ(actions_.size(), 1u) << "only human 1 leaves a dock open";
  EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
  EXPECT_EQ(actions_[0].human_id, 1);
  EXPECT_EQ(actions_[0].step, 3);
  // The reason the transcript prints says it is degraded, what was unknown and why.
  const std::string reason = actions_[0].reason;
  EXPECT_NE(reason.find("degraded: precautionary dock"), std::string::npos) << reason;
  EXPECT_NE(reason.find("RobotIsConstrained"), std::string::npos) << reason;
  EXPECT_NE(reason.find(why), std::string::npos) << reason;
  const auto u1 = utterancesOf(1);
  ASSERT_EQ(u1.size(), 1u);
  EXPECT_EQ(u1[0].speech_act, utterance_t::ACT_INFORM_DOCKING);
  EXPECT_EQ(u1[0].round, 2);
  bool reset1 = false;
  for (const auto& c : controls_)
    reset1 |= c.human_id == 1 && c.command == path_assessor_control_t::COMMAND_RESET;
  EXPECT_TRUE(reset1) << "the recorder restarts at a precautionary dock as at any dock";
  // Human 2: robot free -> Dir told and repeated as the flowchart says; human 3: no dock,
  // nothing said.
  const auto u2 = utterancesOf(2);
  ASSERT_EQ(u2.size(), 2u);
  EXPECT_EQ(u2[0].speech_act, utterance_t::ACT_INFORM_DIRECTION);
  EXPECT_EQ(u2[1].speech_act, utterance_t::ACT_REPEAT_DIRECTION);
  EXPECT_TRUE(utterancesOf(3).empty());
}

// judgement: forecast (config/dialogue_manager_forecast.yaml): round 2 reads p_contributing off
// the wire, not IsContributing. Human 1 has not stepped aside yet (IsContributing false) but is
// forecast to; human 2 stepped a little (true) and is forecast not to make room.
TEST_F(DialogueManagerTest, TheForecastProfileDecidesRoundTwoOnPContributing) {
  for (const bool forecast : {false, true}) {
    utterances_.clear();
    actions_.clear();
    controls_.clear();
    acks_.clear();
    events_.clear();
    if (forecast)
      start({"-c", ::coopnav::test::sourceDir() + "/config/dialogue_manager_forecast.yaml"});
    else
      start();
    primePeers();
    const auto sits = [](double t) {
      return std::vector<Sit>{{1, t, T, F, T, situation_t::DIR_LEFT, 0.6},
                              {2, t, T, F, T, situation_t::DIR_LEFT, 0.6}};
    };
    const std::vector<Path> paths{{1, 0.05, F, path_assessment_t::REC_RECORDING, 0.8},
                                  {2, 0.45, T, path_assessment_t::REC_RECORDING, 0.2}};
    fullStep(1, sits(6.9), {});
    fullStep(2, sits(3.9), paths);
    settle();
    const auto u1 = utterancesOf(1);
    const auto u2 = utterancesOf(2);
    ASSERT_EQ(u1.size(), 2u);
    ASSERT_EQ(u2.size(), 2u);
    // The paper docks for human 1 and asks human 2 for more; the forecast the other way round.
    EXPECT_EQ(u1[1].speech_act,
              forecast ? utterance_t::ACT_ASK_TO_MOVE_MORE : utterance_t::ACT_INFORM_DOCKING);
    EXPECT_EQ(u2[1].speech_act,
              forecast ? utterance_t::ACT_INFORM_DOCKING : utterance_t::ACT_ASK_TO_MOVE_MORE);
    ASSERT_EQ(actions_.size(), 1u);
    EXPECT_EQ(actions_[0].human_id, forecast ? 2 : 1);
    EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
    dut_.reset();
  }
}

// make_time (config/dialogue_manager_make_time.yaml): round 2 due with the forecast undecided ->
// ACTION_SLOW, nothing said; decided later: human 1 once its forecast is decisive (asked for more,
// the robot resumes its speed), human 2 at make_time.latest_t_cross_s on the threshold (dock).
TEST_F(DialogueManagerTest, TheMakeTimeProfileSlowsAndDecidesRoundTwoLater) {
  start({"-c", ::coopnav::test::sourceDir() + "/config/dialogue_manager_make_time.yaml"});
  primePeers();
  const auto sits = [](double t1, double t2) {
    return std::vector<Sit>{{1, t1, T, F, T, situation_t::DIR_LEFT, 0.6},
                            {2, t2, T, F, T, situation_t::DIR_LEFT, 0.6}};
  };
  const auto paths = [](double p1, double p2) {
    return std::vector<Path>{{1, 0.05, F, path_assessment_t::REC_RECORDING, p1},
                             {2, 0.05, F, path_assessment_t::REC_RECORDING, p2}};
  };
  fullStep(1, sits(6.9, 6.9), {});
  fullStep(2, sits(3.9, 3.9), paths(0.5, 0.3));
  settle();
  // Both undecided (0.5, 0.3 within (0.15, 0.85)): one SLOW each, no round-2 words yet.
  ASSERT_EQ(actions_.size(), 2u);
  for (const auto& a : actions_) {
    EXPECT_EQ(a.action, robot_action_t::ACTION_SLOW);
    EXPECT_NE(a.reason.find("round 2 deferred: "), std::string::npos) << a.reason;
  }
  EXPECT_EQ(utterancesOf(1).size(), 1u);
  EXPECT_EQ(utterancesOf(2).size(), 1u);
  // Human 1 decisive at 3.5 s, human 2 still undecided above 2 s: only human 1 decides.
  fullStep(3, sits(3.5, 2.5), paths(0.9, 0.3));
  settle();
  ASSERT_EQ(utterancesOf(1).size(), 2u);
  EXPECT_EQ(utterancesOf(1)[1].speech_act, utterance_t::ACT_ASK_TO_MOVE_MORE);
  EXPECT_EQ(utterancesOf(2).size(), 1u);
  ASSERT_EQ(actions_.size(), 3u);
  EXPECT_EQ(actions_[2].human_id, 1);
  EXPECT_EQ(actions_[2].action, robot_action_t::ACTION_RESUME);
  // Human 2 at the latest t_CROSS (2 s): decided on p 0.3 < 0.5 -> dock, said.
  fullStep(4, sits(3.4, 2.0), paths(0.9, 0.3));
  settle();
  ASSERT_EQ(utterancesOf(2).size(), 2u);
  EXPECT_EQ(utterancesOf(2)[1].speech_act, utterance_t::ACT_INFORM_DOCKING);
  ASSERT_EQ(actions_.size(), 4u);
  EXPECT_EQ(actions_[3].human_id, 2);
  EXPECT_EQ(actions_[3].action, robot_action_t::ACTION_DOCK);
}

TEST_F(DialogueManagerTest, WithoutThePrecautionUnknownPredicatesNeverLeadToADock) {
  start({"--set", "precautionary_dock=false"});
  primePeers();
  // Human 1: IsContributing unknown; human 2: RobotIsConstrained unknown at round 2;
  // human 3: CM unknown (no samples). All with CM below d_h where CM is known.
  const auto sits = [](double t) {
    return std::vector<Sit>{{1, t, T, F, T, situation_t::DIR_LEFT},
                            {2, t, T, F, U, situation_t::DIR_LEFT},
                            {3, t, T, F, T, situation_t::DIR_RIGHT}};
  };
  fullStep(1, sits(6.9), {});
  fullStep(2, sits(3.9), {{1, 0.05, U}, {2, 0.05, F}, {3, kNaN, U, path_assessment_t::REC_IDLE}});
  fullStep(3, sits(3.0), {{1, 0.05, U}, {2, 0.05, F}});
  settle();
  EXPECT_TRUE(actions_.empty()) << "an unknown predicate led to robot action "
                                << static_cast<int>(actions_.front().action);
  // Round 1 still started every recorder once; only human 1 and 3 were talked to in round 1
  // (human 2's RobotIsConstrained is unknown: silent).
  int starts = 0;
  for (const auto& c : controls_) starts += c.command == path_assessor_control_t::COMMAND_START;
  EXPECT_EQ(starts, 3);
  EXPECT_TRUE(utterancesOf(2).empty());
  for (const auto& u : utterances_) EXPECT_NE(u.speech_act, utterance_t::ACT_INFORM_DOCKING);
}

TEST_F(DialogueManagerTest, FacilitatingHumanIsThankedAfterCrossing) {
  start();
  primePeers();
  const std::vector<Human> at_origin{{1, 0.0, 0.0, 0.0}};  // walking along +x
  agents(1, 6.0, 0.7, at_origin);                          // robot ahead of the human
  fullStep(1, {{1, 6.9, T, F, F, situation_t::DIR_LEFT}}, {});
  agents(2, 3.0, 0.7, at_origin);
  fullStep(2, {{1, 3.9, T, F, F, situation_t::DIR_LEFT, 0.6}}, {{1, 0.9, T}});
  EXPECT_EQ(utterances_.size(), 1u) << "CM 0.9 >= d_h 0.6: round 2 is silent";
  events_.clear();
  agents(3, -1.0, 0.7, at_origin);  // robot now behind the human: crossed
  fullStep(3, {}, {{1, 0.9, T}});   // no situation needed for round 3
  ASSERT_EQ(utterances_.size(), 2u);
  const utterance_t& thanks = utterances_[1];
  EXPECT_EQ(thanks.speech_act, utterance_t::ACT_THANK);
  EXPECT_EQ(thanks.round, 3);
  EXPECT_EQ(thanks.human_id, 1);
  EXPECT_EQ(thanks.step, 3);
  EXPECT_TRUE(std::isnan(thanks.t_cross_s));
  EXPECT_EQ(thanks.text, "Thank you.");
  ASSERT_FALSE(controls_.empty());
  EXPECT_EQ(controls_.back().command, path_assessor_control_t::COMMAND_STOP);
  EXPECT_TRUE(actions_.empty());
  EXPECT_EQ(events_, "UCK");
  // Once only.
  agents(4, -2.0, 0.7, at_origin);
  fullStep(4, {{1, 0.0}}, {{1, 0.9, T}});
  EXPECT_EQ(utterances_.size(), 2u);
}

TEST_F(DialogueManagerTest, MinimalHumanIsNotThankedAndADockedRobotResumesAfterCrossing) {
  start();
  primePeers();
  const std::vector<Human> h{{1, 0.0, 0.0, 0.0}};
  agents(1, 6.0, 0.7, h);
  fullStep(1, {{1, 6.9, T, F, T, situation_t::DIR_LEFT}}, {});
  agents(2, 3.0, 0.7, h);
  fullStep(2, {{1, 3.9, T, F, T, situation_t::DIR_LEFT}}, {{1, 0.05, F}});
  ASSERT_EQ(actions_.size(), 1u);
  agents(3, -1.0, 0.7, h);
  fullStep(3, {{1, 0.0}}, {{1, 0.05, F}});
  ASSERT_EQ(actions_.size(), 2u);
  EXPECT_EQ(actions_[1].action, robot_action_t::ACTION_RESUME);
  for (const auto& u : utterances_) EXPECT_NE(u.speech_act, utterance_t::ACT_THANK);
}

TEST_F(DialogueManagerTest, DoesNotActOnAStepBeforeBothAcksArrive) {
  start();
  primePeers();
  situation(1, {1, 6.9});
  ack("situation_assessor", 1);
  settle(milliseconds(300));
  EXPECT_TRUE(utterances_.empty()) << "acted without path_assessor's ack";
  EXPECT_FALSE(acked(1));
  ack("path_assessor", 1);
  ASSERT_TRUE(waitAck(1));
  EXPECT_EQ(utterances_.size(), 1u);
  // The other way round, and the path assessment of the step is read before deciding.
  situation(2, {1, 3.9, T, F, T, situation_t::DIR_LEFT});
  ack("situation_assessor", 2);
  settle(milliseconds(200));
  path(2, {1, 0.05, F});
  settle(milliseconds(200));
  EXPECT_FALSE(acked(2));
  EXPECT_TRUE(actions_.empty());
  ack("path_assessor", 2);
  ASSERT_TRUE(waitAck(2));
  ASSERT_EQ(actions_.size(), 1u) << "round 2 must read the path assessment of its step";
  EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
}

TEST_F(DialogueManagerTest, WaitsForTheAssessorsFromTheFirstStepEvenBeforeHearingFromThem) {
  start();
  situation(0, {1, 6.9});
  path(0, {1, 0.0, F});
  ack("path_assessor", 0);
  settle(milliseconds(300));
  EXPECT_TRUE(utterances_.empty());
  EXPECT_FALSE(acked(0));
  ack("situation_assessor", 0);
  ASSERT_TRUE(waitAck(0));
  EXPECT_EQ(utterances_.size(), 1u);
}

TEST_F(DialogueManagerTest, WithoutWaitingForUnseenPeersAStepRunsAtOnce) {
  start({"--set", "gate_wait_for_unseen=false"});
  situation(0, {1, 6.9});
  ASSERT_TRUE(waitAck(0));
  EXPECT_EQ(utterances_.size(), 1u);
}

TEST_F(DialogueManagerTest, AcknowledgesAStepWithoutAnyHuman) {
  start();
  primePeers();
  ackBoth(1);
  ASSERT_TRUE(waitAck(1));
  EXPECT_TRUE(utterances_.empty());
}

TEST_F(DialogueManagerTest, ProceedsDegradedAfterTheGateTimeoutWhenAcksNeverCome) {
  start({"--set", "gate_timeout_ms=300"});
  primePeers();
  situation(1, {1, 6.9});
  ASSERT_TRUE(waitAck(1)) << "the step never ran although its gate timed out";
  EXPECT_EQ(utterances_.size(), 1u);
  ASSERT_TRUE(spinUntil(
      [&] { return status_ && status_->state == daemon_status_t::STATE_DEGRADED; }, seconds(3)));
  EXPECT_NE(status_->detail.find("situation_assessor"), std::string::npos) << status_->detail;
  // Both peers are now absent: the next step runs on its input alone.
  situation(2, {1, 3.9, T, F, F, situation_t::DIR_LEFT});
  path(2, {1, 0.0, F});
  ASSERT_TRUE(waitAck(2));
}

TEST_F(DialogueManagerTest, BadInputsAreRejectedNeverCrashAndTheStepIsStillAcked) {
  start();
  primePeers();
  Sit nan_t{1, kNaN};  // crossing OK with NaN t_CROSS
  Sit bad_dir{2, 6.9};
  bad_dir.dir = 5;
  Sit bad_pred{3, 6.9};
  bad_pred.needs = 7;
  Sit bad_status{6, 6.9};
  bad_status.crossing_status = 9;
  Sit unknown_t{7, kNaN};  // legitimately unknown: beyond the horizon -> not rejected
  unknown_t.crossing_status = situation_t::CROSSING_BEYOND_HORIZON;
  path(1, {4, 0.1, F, 9});  // unknown recording value
  for (const auto& s : {nan_t, bad_dir, bad_pred, bad_status, unknown_t}) situation(1, s);
  const std::uint8_t garbage[5] = {1, 2, 3, 4, 5};
  probe_.lcm().publish(channels::kSituation, garbage, sizeof garbage);
  ackBoth(1);
  ASSERT_TRUE(waitAck(1)) << "a step with only bad inputs must still be acknowledged";
  EXPECT_TRUE(utterances_.empty());
  EXPECT_TRUE(controls_.empty());
  // A good input afterwards works.
  fullStep(2, {{1, 6.9}}, {});
  EXPECT_EQ(utterancesOf(1).size(), 1u);
  // Step backwards: rejected, nothing decided on it.
  situation(1, {5, 6.9});
  fullStep(3, {{8, 6.5}}, {});
  EXPECT_TRUE(utterancesOf(5).empty());
  EXPECT_EQ(utterancesOf(8).size(), 1u);
  ASSERT_TRUE(spinUntil([&] { return status_ && status_->rejected >= 7; }, seconds(3)));
  settle(milliseconds(1100));
  EXPECT_EQ(status_->rejected, 7) << "5 bad messages, 1 undecodable, 1 step backwards";
  EXPECT_TRUE(dut_->running());
}

TEST_F(DialogueManagerTest, EachHumanIsDecidedOnItsOwn) {
  start();
  primePeers();
  fullStep(1, {{2, 9.0}, {1, 6.9}}, {});
  ASSERT_EQ(utterances_.size(), 1u);
  EXPECT_EQ(utterances_[0].human_id, 1);
  fullStep(2, {{2, 6.5, T, F, F, situation_t::DIR_RIGHT}, {1, 6.0}}, {});
  ASSERT_EQ(utterances_.size(), 2u);
  EXPECT_EQ(utterances_[1].human_id, 2);
  EXPECT_EQ(utterances_[1].direction, situation_t::DIR_RIGHT);
  // Same step, two rounds 1: published in human id order.
  fullStep(3, {{4, 6.0}, {3, 6.0}}, {});
  ASSERT_EQ(utterances_.size(), 4u);
  EXPECT_EQ(utterances_[2].human_id, 3);
  EXPECT_EQ(utterances_[3].human_id, 4);
}

TEST_F(DialogueManagerTest, FreeRunningActsOnEachSituationWithTheLatestPathAssessment) {
  start();  // the assessors are waited for in lockstep only: step -1 runs at once
  situation(-1, {1, 6.9, T, F, T, situation_t::DIR_RIGHT});
  ASSERT_TRUE(spinUntil([&] { return utterances_.size() == 1; }, seconds(3)));
  EXPECT_EQ(utterances_[0].step, -1);
  EXPECT_EQ(utterances_[0].direction, situation_t::DIR_LEFT);  // ask: away from the robot
  path(-1, {1, 0.05, F});
  settle(milliseconds(100));
  situation(-1, {1, 3.8, T, F, T, situation_t::DIR_RIGHT});
  ASSERT_TRUE(spinUntil([&] { return actions_.size() == 1; }, seconds(3)));
  EXPECT_EQ(actions_[0].action, robot_action_t::ACTION_DOCK);
  EXPECT_EQ(actions_[0].step, -1);
  settle();
  EXPECT_TRUE(acks_.empty()) << "free-running steps are not acknowledged";
}

TEST_F(DialogueManagerTest, FreeRunningNeverDecidesOnAStalePathAssessment) {
  // The path assessor (or its host) is gone: its last assessment, 3 s old when round 2 comes,
  // is not acted on (path_max_age_s 0.5 s): CM unknown, so no dock on it (the paper's silence,
  // precautionary_dock off); the same assessment 0.1 s old docks (the test above).
  start({"--set", "precautionary_dock=false"});
  const std::int64_t t0 = 5'000'000;
  situation(-1, {1, 6.9, T, F, T, situation_t::DIR_RIGHT}, t0);
  ASSERT_TRUE(spinUntil([&] { return utterances_.size() == 1; }, seconds(3)));
  path(-1, {1, 0.05, F}, t0 + 100'000);
  settle(milliseconds(100));
  situation(-1, {1, 3.8, T, F, T, situation_t::DIR_RIGHT}, t0 + 3'100'000);
  settle(milliseconds(300));
  EXPECT_TRUE(actions_.empty()) << "docked on a CM assessed 3 s before";
  EXPECT_EQ(utterances_.size(), 1u);
}

TEST_F(DialogueManagerTest, AGroupIsToldOnceAddressedToAllOfIt) {
  start();
  primePeers();
  // Two people side by side 0.8 m apart ahead of the robot (facing -x), both at round 1.
  agents(1, 10.0, 0.0, {{1, 5.0, 0.4, 0.0}, {2, 5.0, -0.4, 0.0}});
  fullStep(1, {{1, 6.9}, {2, 6.9}}, {});
  ASSERT_EQ(utterances_.size(), 2u);
  EXPECT_EQ(utterances_[0].human_id, 1);
  EXPECT_EQ(utterances_[0].delivery, utterance_t::DELIVERY_SAID);
  EXPECT_EQ(utterances_[0].text, "You two ahead, I will pass on your left.");
  EXPECT_EQ(utterances_[0].group_ids, (std::vector<std::int32_t>{2}));
  EXPECT_EQ(utterances_[1].human_id, 2);
  EXPECT_EQ(utterances_[1].delivery, utterance_t::DELIVERY_TOLD_TO_GROUP);
}

TEST_F(DialogueManagerTest, AHumanWhoLeavesTheSceneEndsItsInteraction) {
  start({"--set", "human_gone_s=0.5"});
  primePeers();
  agents(1, 6.0, 0.7, {{1, 0.0, 0.0, 0.0}});
  fullStep(1, {{1, 6.9, T, F, T}}, {});
  agents(2, 5.0, 0.7, {{1, 0.0, 0.0, 0.0}});
  fullStep(2, {{1, 3.9, T, F, T}}, {{1, 0.0, F}});
  ASSERT_EQ(actions_.size(), 1u);
  for (std::int64_t k = 3; k <= 9; ++k) {  // 0.7 s of agent states without human 1
    agents(k, 5.0, 0.7, {});
    fullStep(k, {}, {});
  }
  ASSERT_EQ(actions_.size(), 2u);
  EXPECT_EQ(actions_[1].action, robot_action_t::ACTION_RESUME);
  EXPECT_EQ(controls_.back().command, path_assessor_control_t::COMMAND_STOP);
}

TEST_F(DialogueManagerTest, ANewTrackerIdForTheSamePersonContinuesItsInteraction) {
  start();
  primePeers();
  agents(1, 6.0, 0.7, {{1, 0.0, 0.0, 0.0}});
  fullStep(1, {{1, 6.9, T, F, F}}, {});
  ASSERT_EQ(utterancesOf(1).size(), 1u);
  // The tracker switches 1 to 1001 where 1 stood; someone else (2) appears 3 m away.
  agents(2, 5.9, 0.7, {{1001, 0.1, 0.0, 0.0}, {2, 0.0, 3.0, 0.0}});
  fullStep(2, {{1001, 6.5, T, F, F}, {2, 6.5, T, F, F}}, {});
  EXPECT_TRUE(utterancesOf(1001).empty()) << "round 1 is not said again to the same person";
  ASSERT_EQ(utterancesOf(2).size(), 1u) << "someone new gets round 1";
  EXPECT_EQ(utterancesOf(2)[0].round, 1);
  // Round 2 comes, to the new id, as the person's second round.
  agents(3, 5.8, 0.7, {{1001, 0.2, 0.0, 0.0}, {2, 0.0, 3.0, 0.0}});
  fullStep(3, {{1001, 3.9, T, F, F}}, {{1001, 0.0, F}});
  ASSERT_EQ(utterancesOf(1001).size(), 1u);
  EXPECT_EQ(utterancesOf(1001)[0].round, 2);
}

TEST_F(DialogueManagerTest, AssessmentsOfAnotherProfileAreRejected) {
  start({"--set", "assessment_profile=calibrated"});
  primePeers();
  const std::int64_t rejected_before = status_->rejected;
  path(1, {1, 0.9, T});  // a "paper" assessment
  ackBoth(1);
  ASSERT_TRUE(waitAck(1));
  ASSERT_TRUE(spinUntil([&] { return status_->rejected > rejected_before; }, seconds(3)))
      << "an assessment of the paper profile was acted on by a calibrated dialogue manager";
}

TEST_F(DialogueManagerTest, AHumanGoneForAMinuteIsForgottenAndItsIdStartsAfresh) {
  // Given human 1 told round 1, then out of the agent states.
  start({"--set", "human_gone_s=0.5"});
  primePeers();
  // Over 700 steps: the world acknowledges its steps as in a run (a step gate keeps the inputs of
  // a peer that never acknowledges for 320 steps only, limits.max_pending_steps + 64).
  auto worldStep = [&](std::int64_t step, const std::vector<Human>& humans) {
    agents(step, 6.0, 0.7, humans);
    step_ack_t a{};
    a.utime = utimeOf(step);
    a.step = step;
    a.participant = "world_sim";
    a.output_channels = {channels::kAgentStates};
    a.output_counts = {1};
    a.num_outputs = 1;
    probe_.publish(channels::kStepAck, a);
  };
  worldStep(1, {{1, 0.0, 0.0, 0.0}});
  fullStep(1, {{1, 6.9, T, F, F}}, {});
  ASSERT_EQ(utterancesOf(1).size(), 1u);
  std::int64_t k = 2;
  auto absentUntil = [&](std::int64_t last) {
    for (; k <= last; ++k) {
      worldStep(k, {});
      fullStep(k, {}, {});
    }
  };
  // When the id comes back 10 s later: the same interaction, ended; nothing is said again.
  absentUntil(100);
  worldStep(k, {{1, 0.0, 0.0, 0.0}});
  fullStep(k++, {{1, 6.8, T, F, F}}, {});
  EXPECT_EQ(utterancesOf(1).size(), 1u);
  // When it comes back after more than a minute away: someone new to the dialogue manager
  // (its state was forgotten, as the assessors forget theirs), whose round 1 is said.
  absentUntil(k + 610);
  worldStep(k, {{1, 0.0, 0.0, 0.0}});
  fullStep(k++, {{1, 6.8, T, F, F}}, {});
  ASSERT_EQ(utterancesOf(1).size(), 2u);
  EXPECT_EQ(utterancesOf(1)[1].round, 1);
}

TEST_F(DialogueManagerTest, SigtermExitsZeroWithinOneSecond) {
  start();
  dut_->signal(SIGTERM);
  EXPECT_EQ(dut_->waitExit(milliseconds(1000)), 0);
}

TEST_F(DialogueManagerTest, BadConfigExitsTwo) {
  test::ChildProcess p(test::daemonPath("dialogue_manager"),
                       {"--lcm-url", test::testLcmUrl(), "--set", "round2_t_cross_s=8"});
  EXPECT_EQ(p.waitExit(seconds(5)), 2);
}

// ---- speech (no LCM): argument vector, never a shell; missing program ----

std::string tempDir() {
  std::string tmpl = (test::scratchDir() / "speech_XXXXXX").string();
  return ::mkdtemp(tmpl.data());
}

TEST(SpeechOutputTest, RunsTheProgramWithAnArgumentVectorNeverAShell) {
  const std::string dir = tempDir();
  const std::string fake = dir + "/fake_espeak.sh";
  {
    std::ofstream f(fake);
    // Writes each argument on its own line, as received.
    f << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > " << dir << "/args.txt\n";
  }
  ::chmod(fake.c_str(), 0755);
  SpeechConfig c;
  c.enabled = true;
  c.program = fake;
  c.voice = "en+f3";
  c.wav_dir = dir + "/wav";
  SpeechOutput speech(c);
  ASSERT_TRUE(speech.usable());
  const std::string text = "-x; touch " + dir + "/PWNED $(touch " + dir + "/PWNED2) `id`";
  speech.say(text, "u1_h1_r1_thank");
  ASSERT_TRUE(test::waitFor(
      [&] {
        speech.poll();
        return !speech.busy();
      },
      seconds(5)));
  std::ifstream in(dir + "/args.txt");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  const std::vector<std::string> expected{
      "-v", "en+f3", "-s", "175", "-w", dir + "/wav/u1_h1_r1_thank.wav", "--", text};
  EXPECT_EQ(lines, expected);
  struct stat st {};
  EXPECT_NE(::stat((dir + "/PWNED").c_str(), &st), 0);
  EXPECT_NE(::stat((dir + "/PWNED2").c_str(), &st), 0);
  EXPECT_EQ(speech.started(), 1);
  EXPECT_EQ(speech.failed(), 0);
}

TEST(SpeechOutputTest, OneChildAtATimeAndABoundedQueue) {
  const std::string dir = tempDir();
  const std::string fake = dir + "/slow.sh";
  {
    std::ofstream f(fake);
    f << "#!/bin/sh\nsleep 0.2\n";
  }
  ::chmod(fake.c_str(), 0755);
  SpeechConfig c;
  c.enabled = true;
  c.program = fake;
  c.max_queue = 2;
  SpeechOutput speech(c);
  ASSERT_TRUE(speech.usable());
  for (int i = 0; i < 4; ++i) speech.say("utterance " + std::to_string(i), "x");
  EXPECT_EQ(speech.started(), 1);  // the first one runs, two wait, one was dropped
  EXPECT_EQ(speech.droppedFromQueue(), 1);
  ASSERT_TRUE(test::waitFor(
      [&] {
        speech.poll();
        return speech.started() == 3 && !speech.busy();
      },
      seconds(10)));
}

TEST(SpeechOutputTest, AMissingProgramDisablesSpeechAndNothingElse) {
  SpeechConfig c;
  c.enabled = true;
  c.program = "coopnav-no-such-tts-program";
  SpeechOutput speech(c);
  EXPECT_FALSE(speech.usable());
  speech.say("hello", "x");
  speech.poll();
  EXPECT_EQ(speech.started(), 0);
}

TEST(SpeechOutputTest, RealEspeakNgWritesAWavFile) {
  if (findExecutable("espeak-ng").empty()) GTEST_SKIP() << "espeak-ng not installed";
  const std::string dir = tempDir();
  SpeechConfig c;
  c.enabled = true;
  c.wav_dir = dir;
  SpeechOutput speech(c);
  ASSERT_TRUE(speech.usable());
  speech.say("-I will pass on your left.", "u1_h1_r1_inform_direction");
  ASSERT_TRUE(test::waitFor(
      [&] {
        speech.poll();
        return !speech.busy();
      },
      seconds(20)));
  EXPECT_EQ(speech.failed(), 0);
  struct stat st {};
  ASSERT_EQ(::stat((dir + "/u1_h1_r1_inform_direction.wav").c_str(), &st), 0);
  EXPECT_GT(st.st_size, 10000) << "about a second of audio at least";
}

TEST(SpeechOutputTest, DisabledByDefault) {
  SpeechOutput speech(SpeechConfig{});
  EXPECT_FALSE(speech.usable());
}

TEST_F(DialogueManagerTest, SpeechWithAMissingProgramDoesNotChangeWhatIsPublished) {
  start({"--set", "speech.enabled=true", "--set", "speech.program=coopnav-no-such-tts-program"});
  primePeers();
  fullStep(1, {{1, 6.9}}, {});
  EXPECT_EQ(utterances_.size(), 1u);
  EXPECT_TRUE(dut_->running());
}

TEST_F(DialogueManagerTest, SpeaksIntoWavFilesWhenEspeakNgIsInstalled) {
  if (findExecutable("espeak-ng").empty()) GTEST_SKIP() << "espeak-ng not installed";
  const std::string dir = tempDir();
  start({"--set", "speech.enabled=true", "--set", "speech.wav_dir=" + dir});
  primePeers();
  fullStep(1, {{1, 6.9}}, {});
  ASSERT_EQ(utterances_.size(), 1u);
  const std::string wav = dir + "/u" + std::to_string(utimeOf(1)) + "_h1_r1_inform_direction.wav";
  struct stat st {};
  EXPECT_TRUE(test::waitFor([&] { return ::stat(wav.c_str(), &st) == 0 && st.st_size > 10000; },
                            seconds(20)))
      << wav;
}

}  // namespace
}  // namespace coopnav
