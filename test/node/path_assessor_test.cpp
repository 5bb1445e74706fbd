// Path assessor over an isolated udpm port: published CA / CM / IsContributing equal a library
// PathRecorder fed the same input; recorder controls of step k-1 are applied before step k
// (StepGate on the dialogue manager's ack); unknown ids and bad commands are dropped / rejected
// and counted; a rejected agent-states message is still acknowledged; SIGTERM exits 0 within 1 s;
// p_contributing is published from the forecast profile, equal to a library forecaster fed the
// same input, and rises as the human steps aside (NaN without a profile; a bad one stops it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "path_assessor_node.hpp"
#include "profiles/forecast_profile.hpp"
#include "runtime/daemon_main.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;

class PathAssessorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dut_rt_ = std::make_unique<Runtime>("path_assessor", test::testLcmUrl());
    node_ = std::make_unique<PathAssessorNode>(config_, *dut_rt_);
    probe_ = std::make_unique<Runtime>("probe", test::testLcmUrl());
    probe_->subscribe<path_assessment_t>(
        channels::kPathAssessment,
        [this](const path_assessment_t& m, std::int64_t) { published_.push_back(m); });
    probe_->subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& a, std::int64_t) {
      if (a.participant == "path_assessor") acks_.push_back(a.step);
    });
  }

  void spin() {
    dut_rt_->spinFor(1);
    probe_->spinFor(1);
  }

  bool waitAck(std::int64_t step, std::chrono::milliseconds timeout = 3000ms) {
    return test::waitFor([&] { return std::find(acks_.begin(), acks_.end(), step) != acks_.end(); },
                         timeout, [&] { spin(); });
  }

  const path_assessment_t* latest(std::int64_t step, std::int32_t human) const {
    for (auto it = published_.rbegin(); it != published_.rend(); ++it)
      if (it->step == step && it->human_id == human) return &*it;
    return nullptr;
  }

  static std::int64_t utimeOf(std::int64_t step) { return 5'000'000 + step * 50'000; }  // 20 Hz

  /// Scene at step k: human 1 walks -x along y = 5 and drifts to -y (its left) from step 6 on;
  /// the robot walks +x and swerves to +y (the human's right) from step 4 on.
  AgentStatesSnapshot scene(std::int64_t k) const {
    AgentStatesSnapshot s;
    s.utime = utimeOf(k);
    s.step = k;
    s.robot.id = 0;
    s.robot.kind = AgentKind::kRobot;
    const double t = 0.05 * static_cast<double>(k);
    s.robot.pose = {1.0 + 0.8 * t, 5.0 + (k >= 4 ? 0.4 : 0.0), 0.0};
    AgentState h;
    h.id = 1;
    h.kind = AgentKind::kHuman;
    h.pose = {9.0 - 0.8 * t, 5.0 - (k >= 6 ? 0.03 * static_cast<double>(k - 6) : 0.0), M_PI};
    s.humans.push_back(h);
    return s;
  }

  void publishStates(std::int64_t k) { probe_->publish(channels::kAgentStates, toLcm(scene(k))); }

  void publishControl(std::int64_t step, std::int32_t id, dialogue::RecorderCommand c,
                      std::optional<double> d_oh_m = std::nullopt,
                      std::optional<double> d_h_m = std::nullopt) {
    RecorderControl rc;
    rc.utime = utimeOf(step);
    rc.step = step;
    rc.human_id = id;
    rc.command = c;
    rc.reason = "test";
    rc.d_oh_m = d_oh_m;
    rc.d_h_m = d_h_m;
    probe_->publish(channels::kPathAssessorControl, toLcm(rc));
  }

  void publishReference() {
    ReferencePaths r;
    r.utime = utimeOf(0);
    r.paths.push_back({1, 1, Path2{{10.0, 5.0}, {0.0, 5.0}}});
    probe_->publish(channels::kReferencePaths, toLcm(r));
  }

  void dmAck(std::int64_t step) {
    step_ack_t a{};
    a.utime = utimeOf(step);
    a.step = step;
    a.participant = "dialogue_manager";
    probe_->publish(channels::kStepAck, a);
  }

  PathAssessorNodeConfig config_;
  std::unique_ptr<Runtime> dut_rt_;
  std::unique_ptr<PathAssessorNode> node_;
  std::unique_ptr<Runtime> probe_;
  std::vector<path_assessment_t> published_;
  std::vector<std::int64_t> acks_;
};

TEST_F(PathAssessorTest, PublishedNumbersMatchALibraryRecorderFedTheSameInput) {
  publishReference();
  // The dialogue manager is never heard from here: the gate does not wait for it.
  for (std::int64_t k = 0; k <= 2; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(2));
  ASSERT_NE(latest(2, 1), nullptr);
  EXPECT_EQ(latest(2, 1)->recording, path_assessment_t::REC_IDLE);
  EXPECT_EQ(latest(2, 1)->num_samples, 0);
  EXPECT_TRUE(std::isnan(latest(2, 1)->cm_m));
  EXPECT_EQ(latest(2, 1)->is_contributing, situation_t::PRED_UNKNOWN);

  publishControl(2, 1, dialogue::RecorderCommand::kStart);
  for (std::int64_t k = 3; k <= 20; ++k) {
    if (k == 14) {
      ASSERT_TRUE(waitAck(13));
      publishControl(13, 1, dialogue::RecorderCommand::kReset);
    }
    publishStates(k);
  }
  ASSERT_TRUE(waitAck(20));

  // The same through the library; time base = the first message's utime, as the node's.
  assessment::PathRecorder lib(config_.recorderConfig());
  auto t = [](std::int64_t k) { return utimeToSeconds(utimeOf(k) - utimeOf(0)); };
  for (std::int64_t k = 0; k <= 20; ++k) {
    if (k == 3) {
      ASSERT_TRUE(lib.start(t(2), Path2{{10.0, 5.0}, {0.0, 5.0}}));
    }
    if (k == 14) lib.reset(t(13));
    const auto s = scene(k);
    lib.observe(t(k), s.humans[0].pose.position(), s.robot.pose.position());
  }
  const auto snap = lib.snapshot();
  const path_assessment_t* m = latest(20, 1);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->utime, utimeOf(20));
  EXPECT_EQ(m->recording, path_assessment_t::REC_RECORDING);
  EXPECT_EQ(m->ca_m, lib.windowCa());
  EXPECT_EQ(static_cast<std::size_t>(m->window_samples), snap.window_samples);
  EXPECT_EQ(static_cast<std::size_t>(m->interaction_samples), snap.interaction_samples);
  EXPECT_DOUBLE_EQ(m->cm_m, *snap.cm_window_m);
  EXPECT_DOUBLE_EQ(m->cm_interaction_m, *snap.cm_interaction_m);
  EXPECT_EQ(m->is_contributing, static_cast<std::int8_t>(snap.is_contributing_window));
  EXPECT_EQ(m->is_contributing_interaction,
            static_cast<std::int8_t>(snap.is_contributing_interaction));
  EXPECT_DOUBLE_EQ(m->gamma, config_.recorder.gamma);
  EXPECT_DOUBLE_EQ(m->tau_m, config_.recorder.tau_m);
  // Hand check: 10 Hz from t(2) = 0.1 s to t(20) = 1.0 s -> 10 samples; the reset at t(13) =
  // 0.65 s leaves the 4 samples at 0.7 .. 1.0 s in the window. The human drifts away from the
  // robot's side, so its CA grows positive.
  EXPECT_EQ(m->interaction_samples, 10);
  EXPECT_EQ(m->window_samples, 4);
  EXPECT_GT(m->ca_m.back(), 0.3);
  // The pure CM-for-another-γ function agrees with the published CM, and γ = 1 is the mean.
  EXPECT_NEAR(*cmForGamma(*m, m->gamma), m->cm_m, 1e-12);
  double mean = 0.0;
  for (double ca : m->ca_m) mean += ca / static_cast<double>(m->ca_m.size());
  EXPECT_NEAR(*cmForGamma(*m, 1.0), mean, 1e-12);
}

TEST_F(PathAssessorTest, ControlsOfStepKMinus1AreAppliedBeforeStepK) {
  publishReference();
  dmAck(0);  // the dialogue manager is now a known participant: step k waits for its ack k-1
  publishStates(0);
  publishStates(1);
  ASSERT_TRUE(waitAck(1));
  publishStates(2);  // needs the dialogue manager's ack of step 1
  test::waitFor([] { return false; }, 200ms, [&] { spin(); });
  EXPECT_EQ(latest(2, 1), nullptr) << "step 2 ran before the dialogue manager finished step 1";
  publishControl(1, 1, dialogue::RecorderCommand::kStart);
  dmAck(1);
  ASSERT_TRUE(waitAck(2));
  ASSERT_NE(latest(2, 1), nullptr);
  EXPECT_EQ(latest(2, 1)->recording, path_assessment_t::REC_RECORDING);
  EXPECT_EQ(acks_, (std::vector<std::int64_t>{0, 1, 2}));
}

TEST_F(PathAssessorTest, BadControlsAreDroppedOrRejectedAndCounted) {
  publishStates(0);
  ASSERT_TRUE(waitAck(0));
  const auto before = dut_rt_->counters();
  publishControl(0, 77, dialogue::RecorderCommand::kStart);  // unknown id
  publishControl(0, 1, dialogue::RecorderCommand::kStart);   // no reference path yet
  path_assessor_control_t bad =
      toLcm(RecorderControl{utimeOf(0), 0, 1, dialogue::RecorderCommand::kStop, "", {}, {}});
  bad.command = 9;
  probe_->publish(channels::kPathAssessorControl, bad);
  // Lockstep controls of step 0 take effect at the start of step 1 (docs/lockstep.md "Loss and
  // restarts"): the unknown command is rejected on arrival, the other two dropped then.
  publishStates(1);
  ASSERT_TRUE(waitAck(1));
  ASSERT_TRUE(test::waitFor(
      [&] {
        return dut_rt_->counters().dropped >= before.dropped + 2 &&
               dut_rt_->counters().rejected >= before.rejected + 1;
      },
      3000ms, [&] { spin(); }));
  test::waitFor([] { return false; }, 100ms, [&] { spin(); });  // nothing else may follow
  EXPECT_EQ(dut_rt_->counters().dropped, before.dropped + 2);
  EXPECT_EQ(dut_rt_->counters().rejected, before.rejected + 1);
  EXPECT_EQ(latest(1, 1)->recording, path_assessment_t::REC_IDLE);
}

TEST_F(PathAssessorTest, RejectedAgentStatesAreStillAcknowledgedInOrder) {
  publishStates(0);
  agent_states_t nan_states = toLcm(scene(1));
  nan_states.humans[0].x_m = std::nan("");
  probe_->publish(channels::kAgentStates, nan_states);
  publishStates(2);
  ASSERT_TRUE(waitAck(2));
  EXPECT_EQ(acks_, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(latest(1, 1), nullptr);
  EXPECT_EQ(dut_rt_->counters().rejected, 1);
}

TEST(PathAssessorProcessTest, StopsOnSigtermWithin1s) {
  Runtime probe("probe", test::testLcmUrl());
  bool up = false;
  probe.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.name == "path_assessor") up = true;
  });
  test::ChildProcess dut(test::daemonPath("path_assessor"),
                         {"--lcm-url", test::testLcmUrl(), "--log-level", "error"});
  ASSERT_TRUE(test::waitFor([&] { return up; }, 5000ms, [&] { probe.spinFor(5); }));
  dut.signal(SIGTERM);
  EXPECT_EQ(dut.waitExit(1000ms), 0);
}

/// tau_mode: room, from the config key the daemon reads.
class PathAssessorRoomTest : public PathAssessorTest {
 protected:
  void SetUp() override {
    config_.tau_mode = "room";
    PathAssessorTest::SetUp();
  }
};

TEST_F(PathAssessorRoomTest, TheStartsSituationSetsTheThresholdAndBothAreReported) {
  publishReference();
  for (std::int64_t k = 0; k <= 2; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(2));
  // Round 1 saw d_OH 0.3 m and d_h 0.1 m: 0.4 m of room, half of it is the threshold.
  publishControl(2, 1, dialogue::RecorderCommand::kStart, 0.3, 0.1);
  for (std::int64_t k = 3; k <= 10; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(10));
  const path_assessment_t* m = latest(10, 1);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->tau_mode, path_assessment_t::TAU_ROOM);
  EXPECT_NEAR(m->room_m, 0.4, 1e-12);
  EXPECT_NEAR(m->tau_room_m, 0.2, 1e-12);
  EXPECT_NEAR(m->tau_m, 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(m->tau_fixed_m, config_.recorder.tau_m);
  EXPECT_EQ(m->is_contributing, m->cm_m > 0.2 ? situation_t::PRED_TRUE : situation_t::PRED_FALSE);

  // A new START without a known situation: the paper's τ.
  publishControl(10, 1, dialogue::RecorderCommand::kStart);
  for (std::int64_t k = 11; k <= 12; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(12));
  m = latest(12, 1);
  ASSERT_NE(m, nullptr);
  EXPECT_TRUE(std::isnan(m->room_m));
  EXPECT_DOUBLE_EQ(m->tau_m, config_.recorder.tau_m);
}

TEST_F(PathAssessorTest, WithoutAForecastProfilePContributingIsNaN) {
  publishReference();
  for (std::int64_t k = 0; k <= 2; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(2));
  publishControl(2, 1, dialogue::RecorderCommand::kStart);
  for (std::int64_t k = 3; k <= 20; ++k) publishStates(k);
  ASSERT_TRUE(waitAck(20));
  ASSERT_NE(latest(20, 1), nullptr);
  EXPECT_EQ(latest(20, 1)->recording, path_assessment_t::REC_RECORDING);
  EXPECT_TRUE(std::isnan(latest(20, 1)->p_contributing));
  EXPECT_EQ(node_->forecaster(1), nullptr);
}

TEST_F(PathAssessorTest, ABadForecastProfileStopsTheStartNamingTheKey) {
  PathAssessorNodeConfig c = config_;
  c.forecast_profile = "/nonexistent/forecast.yaml";
  try {
    PathAssessorNode bad(c, *dut_rt_);
    ADD_FAILURE() << "a missing forecast profile was accepted";
  } catch (const StartupError& e) {
    EXPECT_NE(std::string(e.what()).find("forecast_profile"), std::string::npos) << e.what();
  }
}

/// The shipped forecast profile (config/path_assessor_forecast.yaml), as the shipped configs name.
class PathAssessorForecastTest : public PathAssessorTest {
 protected:
  void SetUp() override {
    config_.forecast_profile = ::coopnav::test::sourceDir() + "/config/path_assessor_forecast.yaml";
    PathAssessorTest::SetUp();
  }

  /// Human 1 walks -x along y = 5 at 0.8 m/s, then steps to -y (away from the robot) at 0.5 m/s
  /// from step kAside on; the robot walks +x along y = 5.4 (on the human's right).
  static constexpr std::int64_t kAside = 20;
  static AgentStatesSnapshot asideScene(std::int64_t k) {
    AgentStatesSnapshot s;
    s.utime = utimeOf(k);
    s.step = k;
    s.robot.id = 0;
    s.robot.kind = AgentKind::kRobot;
    const double t = 0.05 * static_cast<double>(k);
    s.robot.pose = {1.0 + 0.8 * t, 5.4, 0.0};
    AgentState h;
    h.id = 1;
    h.kind = AgentKind::kHuman;
    const double aside_s = 0.05 * static_cast<double>(std::max<std::int64_t>(k - kAside, 0));
    h.pose = {9.0 - 0.8 * t, 5.0 - 0.5 * aside_s, M_PI};
    s.humans.push_back(h);
    return s;
  }
};

TEST_F(PathAssessorForecastTest, PContributingIsPublishedAndRisesAsTheHumanStepsAside) {
  publishReference();
  for (std::int64_t k = 0; k <= 2; ++k)
    probe_->publish(channels::kAgentStates, toLcm(asideScene(k)));
  ASSERT_TRUE(waitAck(2));
  EXPECT_TRUE(std::isnan(latest(2, 1)->p_contributing)) << "no interaction yet";
  publishControl(2, 1, dialogue::RecorderCommand::kStart);
  for (std::int64_t k = 3; k <= 40; ++k) {
    if (k == 40) {
      ASSERT_TRUE(waitAck(39));
      publishControl(39, 1, dialogue::RecorderCommand::kStop);
    }
    probe_->publish(channels::kAgentStates, toLcm(asideScene(k)));
  }
  ASSERT_TRUE(waitAck(40));
  for (std::int64_t k = 41; k <= 44; ++k)
    probe_->publish(channels::kAgentStates, toLcm(asideScene(k)));
  ASSERT_TRUE(waitAck(44));

  // The same through the library: started with the reference path's start and direction, fed
  // the observations of steps 3 .. 39 (the START of step 2 applies from step 3, the STOP of 39
  // before step 40's observation).
  assessment::CooperationForecaster lib(
      loadForecastProfile(::coopnav::test::sourceDir() + "/config/path_assessor_forecast.yaml"));
  lib.start({10.0, 5.0}, {-1.0, 0.0});
  auto t = [](std::int64_t k) { return utimeToSeconds(utimeOf(k) - utimeOf(0)); };
  std::map<std::int64_t, double> expected;
  for (std::int64_t k = 3; k <= 39; ++k) {
    const auto s = asideScene(k);
    lib.observe(t(k), s.humans[0].pose.position(), s.robot.pose.position());
    expected[k] = lib.pContributing();
  }
  std::size_t known = 0;
  for (std::int64_t k = 3; k <= 39; ++k) {
    const path_assessment_t* m = latest(k, 1);
    ASSERT_NE(m, nullptr) << k;
    if (std::isnan(expected[k])) {
      EXPECT_TRUE(std::isnan(m->p_contributing)) << k;
      continue;
    }
    ++known;
    EXPECT_DOUBLE_EQ(m->p_contributing, expected[k]) << k;
    EXPECT_TRUE(m->p_contributing >= 0.0 && m->p_contributing <= 1.0) << k;
  }
  // Known after half a velocity span (0.4 s = 8 steps) of track, long before the step aside.
  EXPECT_GE(known, 25U);
  ASSERT_FALSE(std::isnan(latest(kAside, 1)->p_contributing));
  // Walking straight, 0.4 m off the robot's line: about even (the model's hand value ~0.5); after
  // a second of stepping away (0.475 m, at 0.5 m/s): ~0.77 by hand, clearly contributing.
  const double before = latest(kAside, 1)->p_contributing;
  const double after = latest(39, 1)->p_contributing;
  EXPECT_GT(after, 0.65);
  EXPECT_GT(after, before + 0.15);
  // STOP ends the interaction: the last forecast stays while the human walks on.
  for (std::int64_t k = 40; k <= 44; ++k) EXPECT_EQ(latest(k, 1)->p_contributing, after) << k;
}

}  // namespace
}  // namespace coopnav
