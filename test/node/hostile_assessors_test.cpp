// Hostile inputs of the two assessors (docs/bad-inputs.md), their nodes in-process on this
// executable's udpm port, without a distance server (the inputs here need none; d_OH / d_OR are
// then unknown after the client's bound):
// - bands whose poses span 10^7 s are bad bands at once (their grid would take > 1.9 GB);
// - 3000 reference-path messages of 64 fresh ids each keep every per-id container within
//   limits.max_ids, and ids never seen in agent states age out after limits.forget_after_s of
//   message time;
// - a reference path or agent states stamped INT64_MAX, mid-run or as the very first message,
//   neither stop nor pin the normal traffic that follows.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "coopnav/path_assessment_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "path_assessor_node.hpp"
#include "situation_assessor_node.hpp"
#include "test_util.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;
constexpr std::int64_t kT0_us = 1'000'000'000;  // an ordinary start stamp
constexpr std::int64_t kMaxUtime = std::numeric_limits<std::int64_t>::max();
constexpr int kFloodMessages = 3000;
constexpr int kIdsPerMessage = 64;

/// Straight band from `from` to `to` over duration_s, poses every dt_s, heading along the motion.
Band straightBand(Eigen::Vector2d from, Eigen::Vector2d to, double duration_s, double dt_s) {
  Band b;
  const Eigen::Vector2d d = to - from;
  const double theta = std::atan2(d.y(), d.x());
  const int n = static_cast<int>(std::lround(duration_s / dt_s));
  for (int i = 0; i <= n; ++i) {
    const double t = i * dt_s;
    const Eigen::Vector2d p = from + d * (t / duration_s);
    b.poses.push_back({t, {p.x(), p.y(), theta}});
  }
  return b;
}

/// One message of the flood: kIdsPerMessage ids never used before, from `first_id` on.
ReferencePaths freshIds(std::int64_t utime, std::int32_t first_id) {
  ReferencePaths r;
  r.utime = utime;
  for (std::int32_t i = 0; i < kIdsPerMessage; ++i)
    r.paths.push_back({first_id + i, 1, Path2{{20.0, 2.3}, {12.0, 2.3}}});
  return r;
}

/// Spins `dut` and `probe` until `dut` handled `count` messages in all (or 10 s passed).
bool drain(Runtime& dut, Runtime& probe, std::int64_t count) {
  return test::waitFor([&] { return dut.counters().received >= count; }, 10000ms,
                       [&] {
                         dut.spinFor(1);
                         probe.spinFor(0);
                       });
}

/// Spins `dut` and `probe` until `dut` finds nothing more to handle (loopback delivers a
/// published message before publish() returns).
void flush(Runtime& dut, Runtime& probe) {
  for (int idle = 0; idle < 3;) {
    const int handled = dut.spinFor(2);
    probe.spinFor(0);
    idle = handled == 0 ? idle + 1 : 0;
  }
}

// ---------------------------------------------------------------------------------------------
// situation_assessor

class HostileSituationAssessor : public ::testing::Test {
 protected:
  void SetUp() override {
    dut_rt_ = std::make_unique<Runtime>("situation_assessor", test::testLcmUrl());
    node_ = std::make_unique<SituationAssessorNode>(config_, *dut_rt_);
    probe_ = std::make_unique<Runtime>("probe", test::testLcmUrl());
    probe_->subscribe<situation_t>(channels::kSituation,
                                   [this](const situation_t& m, std::int64_t) {
                                     situations_[{m.step, m.human_id}] = m;
                                   });
    probe_->subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& a, std::int64_t) {
      if (a.participant == "situation_assessor") acks_.push_back(a.step);
    });
  }

  void spin() {
    dut_rt_->spinFor(1);
    probe_->spinFor(1);
  }
  bool waitAck(std::int64_t step, std::chrono::milliseconds timeout = 5000ms) {
    return test::waitFor([&] { return std::find(acks_.begin(), acks_.end(), step) != acks_.end(); },
                         timeout, [&] { spin(); });
  }
  const situation_t* situation(std::int64_t step, std::int32_t human) const {
    const auto it = situations_.find({step, human});
    return it == situations_.end() ? nullptr : &it->second;
  }

  /// Publishes reference paths and lets the node handle them.
  void publishPaths(const ReferencePaths& r) {
    probe_->publish(channels::kReferencePaths, toLcm(r));
    flush(*dut_rt_, *probe_);
  }
  void publishPath(std::int64_t utime, std::int32_t id, std::int32_t revision, double y_m) {
    ReferencePaths r;
    r.utime = utime;
    r.paths.push_back({id, revision, Path2{{20.0, y_m}, {12.0, y_m}}});
    publishPaths(r);
  }
  /// Bands of step k for the given humans against the corridor robot band; waits for the ack.
  void assess(std::int64_t k, std::vector<std::pair<std::int32_t, Band>> humans,
              const Band* robot = nullptr) {
    BandsSnapshot b;
    b.utime = kT0_us + k * 100'000;
    b.step = k;
    b.robot = robot ? *robot : robot_;
    b.humans = std::move(humans);
    probe_->publish(channels::kBands, toLcm(b));
    ASSERT_TRUE(waitAck(k)) << "step " << k << " was not answered";
  }

  // The corridor of test/node/situation_assessor_test.cpp: they meet at t = 4 s, x = 16 m; with
  // the reference path at y the human's d_h is |y - 1.9|.
  Band robot_ = straightBand({12.0, 1.5}, {20.0, 1.5}, 8.0, 0.5);
  Band human_ = straightBand({20.0, 1.9}, {12.0, 1.9}, 8.0, 0.4);

  SituationAssessorConfig config_;
  std::unique_ptr<Runtime> dut_rt_;
  std::unique_ptr<SituationAssessorNode> node_;
  std::unique_ptr<Runtime> probe_;
  std::map<std::pair<std::int64_t, std::int32_t>, situation_t> situations_;
  std::vector<std::int64_t> acks_;
};

TEST_F(HostileSituationAssessor, BandsSpanningTenMillionSecondsAreBadBandsAtOnce) {
  // Unchecked, the common grid of these two 2-pose bands had 2*10^8 points: > 1.9 GB and no
  // answer (10^8 s and more: std::bad_alloc).
  Band robot_long;
  robot_long.poses = {{0.0, {12.0, 1.5, 0.0}}, {1e7, {20.0, 1.5, 0.0}}};
  Band human_long;
  human_long.poses = {{0.0, {20.0, 1.9, M_PI}}, {1e7, {12.0, 1.9, M_PI}}};
  publishPath(kT0_us, 1, 1, 2.3);
  assess(1, {{1, human_long}}, &robot_long);
  const situation_t* s = situation(1, 1);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->crossing_status, situation_t::CROSSING_BAD_BANDS);
  EXPECT_NE(s->reason.find("max_band_span_s"), std::string::npos) << s->reason;
  EXPECT_TRUE(std::isnan(s->t_cross_s));
  EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(s->human_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN);

  // One such human band beside a normal one: that human only.
  assess(2, {{1, human_long}, {2, human_}});
  ASSERT_NE(situation(2, 1), nullptr);
  ASSERT_NE(situation(2, 2), nullptr);
  EXPECT_EQ(situation(2, 1)->crossing_status, situation_t::CROSSING_BAD_BANDS);
  EXPECT_NE(situation(2, 2)->crossing_status, situation_t::CROSSING_BAD_BANDS);
  EXPECT_NEAR(situation(2, 2)->t_cross_s, 4.0, 1e-9);
}

TEST_F(HostileSituationAssessor, AFloodOfFreshIdsInReferencePathsKeepsAtMostMaxIds) {
  const auto max_ids = static_cast<std::size_t>(dut_rt_->limits().max_ids);
  std::int64_t received = dut_rt_->counters().received;
  std::int32_t next_id = 1;
  for (int m = 0; m < kFloodMessages; ++m) {
    // 1 ms of message time apart: nothing ages out, only the count cap holds them.
    probe_->publish(channels::kReferencePaths, toLcm(freshIds(kT0_us + m * 1000, next_id)));
    next_id += kIdsPerMessage;
    ++received;
    if (m % 20 == 19 || m + 1 == kFloodMessages) {
      ASSERT_TRUE(drain(*dut_rt_, *probe_, received)) << "message " << m;
      ASSERT_LE(node_->referencesKept(), max_ids) << "message " << m;
    }
  }
  flush(*dut_rt_, *probe_);
  EXPECT_EQ(node_->referencesKept(), max_ids);
  // The most recently heard are the ones kept: the last id has its path, the first not.
  assess(1, {{next_id - 1, human_}, {1, human_}});
  ASSERT_NE(situation(1, next_id - 1), nullptr);
  ASSERT_NE(situation(1, 1), nullptr);
  EXPECT_NEAR(situation(1, next_id - 1)->d_h_m, 0.4, 1e-9);
  EXPECT_EQ(situation(1, 1)->crossing_status, situation_t::CROSSING_NO_REFERENCE);
}

TEST_F(HostileSituationAssessor, ReferencePathsNotRepublishedAgeOutByMessageTime) {
  ReferencePaths many = freshIds(kT0_us, 1);
  publishPaths(many);
  EXPECT_EQ(node_->referencesKept(), static_cast<std::size_t>(kIdsPerMessage));
  // Message time advances in steps below limits.max_time_jump_s (a bigger one is rejected).
  publishPath(kT0_us + 30'000'000, 500, 1, 2.3);
  EXPECT_EQ(node_->referencesKept(), static_cast<std::size_t>(kIdsPerMessage) + 1);
  publishPath(kT0_us + 61'000'000, 501, 1, 2.3);  // the first 64: 61 s > forget_after_s
  EXPECT_EQ(node_->referencesKept(), 2u);
}

TEST_F(HostileSituationAssessor, AReferencePathStampedInt64MaxMidRunIsRejectedAndPinsNothing) {
  publishPath(kT0_us, 1, 1, 2.3);
  assess(1, {{1, human_}});
  EXPECT_NEAR(situation(1, 1)->d_h_m, 0.4, 1e-9);
  // Far ahead, a high revision, a path 8 m away: taken, it would make every later path "stale".
  const auto rejected = dut_rt_->counters().rejected;
  publishPath(kMaxUtime, 1, 100, 10.0);
  EXPECT_EQ(dut_rt_->counters().rejected, rejected + 1);
  assess(2, {{1, human_}});
  EXPECT_NEAR(situation(2, 1)->d_h_m, 0.4, 1e-9) << "the hostile path was taken";
  publishPath(kT0_us + 1'000'000, 1, 2, 2.5);  // the band source's next revision: followed
  assess(3, {{1, human_}});
  EXPECT_NEAR(situation(3, 1)->d_h_m, 0.6, 1e-9);
}

TEST_F(HostileSituationAssessor, AReferencePathStampedInt64MaxFirstIsLeftAfterAFewNormalOnes) {
  // The very first message sets the time (there is nothing to judge it against) ...
  publishPath(kMaxUtime, 1, 100, 10.0);
  // ... and time_resync_messages normal ones in a row take the time back: a clock that one bad
  // first message had set. Its path (stale revision 100 "newer" than any to come) goes with it.
  const int resync = dut_rt_->limits().time_resync_messages;
  const auto rejected = dut_rt_->counters().rejected;
  for (int i = 0; i < resync; ++i) publishPath(kT0_us + i * 100'000, 1, 1, 2.3);
  EXPECT_EQ(dut_rt_->counters().rejected, rejected + resync - 1);
  assess(1, {{1, human_}});
  ASSERT_NE(situation(1, 1), nullptr);
  EXPECT_NEAR(situation(1, 1)->d_h_m, 0.4, 1e-9);
  EXPECT_EQ(node_->referencesKept(), 1u);
}

// ---------------------------------------------------------------------------------------------
// path_assessor

class HostilePathAssessor : public ::testing::Test {
 protected:
  void SetUp() override {
    dut_rt_ = std::make_unique<Runtime>("path_assessor", test::testLcmUrl());
    node_ = std::make_unique<PathAssessorNode>(config_, *dut_rt_);
    probe_ = std::make_unique<Runtime>("probe", test::testLcmUrl());
    probe_->subscribe<path_assessment_t>(channels::kPathAssessment,
                                         [this](const path_assessment_t& m, std::int64_t) {
                                           published_[{m.step, m.human_id}] = m;
                                         });
    probe_->subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& a, std::int64_t) {
      if (a.participant == "path_assessor") acks_.push_back(a.step);
    });
  }

  void spin() {
    dut_rt_->spinFor(1);
    probe_->spinFor(1);
  }
  bool waitAck(std::int64_t step) {
    return test::waitFor([&] { return std::find(acks_.begin(), acks_.end(), step) != acks_.end(); },
                         5000ms, [&] { spin(); });
  }
  const path_assessment_t* at(std::int64_t step, std::int32_t human) const {
    const auto it = published_.find({step, human});
    return it == published_.end() ? nullptr : &it->second;
  }

  static std::int64_t utimeOf(std::int64_t step) { return kT0_us + step * 100'000; }  // 10 Hz

  /// Agent states of step k stamped `utime`: human 1 walks -x along y = 5 and drifts to -y
  /// from step 3 on, the robot walks +x (path_assessor_test's scene).
  void states(std::int64_t k, std::int64_t utime) {
    AgentStatesSnapshot s;
    s.utime = utime;
    s.step = k;
    s.robot.id = 0;
    s.robot.kind = AgentKind::kRobot;
    const double t = 0.1 * static_cast<double>(k);
    s.robot.pose = {1.0 + 0.8 * t, 5.4, 0.0};
    AgentState h;
    h.id = 1;
    h.kind = AgentKind::kHuman;
    h.pose = {9.0 - 0.8 * t, 5.0 - (k >= 3 ? 0.05 * static_cast<double>(k - 3) : 0.0), M_PI};
    s.humans.push_back(h);
    probe_->publish(channels::kAgentStates, toLcm(s));
    ASSERT_TRUE(waitAck(k)) << "step " << k << " was not acknowledged";
  }
  void states(std::int64_t k) { states(k, utimeOf(k)); }

  void publishPaths(const ReferencePaths& r) {
    probe_->publish(channels::kReferencePaths, toLcm(r));
    flush(*dut_rt_, *probe_);
  }
  void publishPath(std::int64_t utime) {
    ReferencePaths r;
    r.utime = utime;
    r.paths.push_back({1, 1, Path2{{10.0, 5.0}, {0.0, 5.0}}});
    publishPaths(r);
  }
  /// A lockstep control of step k (applied when step k + 1 runs).
  void control(std::int64_t k, dialogue::RecorderCommand c, std::int64_t utime) {
    probe_->publish(channels::kPathAssessorControl,
                    toLcm(RecorderControl{utime, k, 1, c, "hostile_assessors_test", {}, {}}));
    flush(*dut_rt_, *probe_);
  }

  PathAssessorNodeConfig config_;
  std::unique_ptr<Runtime> dut_rt_;
  std::unique_ptr<PathAssessorNode> node_;
  std::unique_ptr<Runtime> probe_;
  std::map<std::pair<std::int64_t, std::int32_t>, path_assessment_t> published_;
  std::vector<std::int64_t> acks_;
};

TEST_F(HostilePathAssessor, AFloodOfFreshIdsInReferencePathsKeepsAtMostMaxIds) {
  states(0);
  const auto max_ids = static_cast<std::size_t>(dut_rt_->limits().max_ids);
  std::int64_t received = dut_rt_->counters().received;
  std::int32_t next_id = 100;
  for (int m = 0; m < kFloodMessages; ++m) {
    probe_->publish(channels::kReferencePaths, toLcm(freshIds(utimeOf(0) + m * 10, next_id)));
    next_id += kIdsPerMessage;
    ++received;
    if (m % 20 == 19 || m + 1 == kFloodMessages) {
      ASSERT_TRUE(drain(*dut_rt_, *probe_, received)) << "message " << m;
      ASSERT_LE(node_->humansKept(), max_ids) << "message " << m;
      ASSERT_LE(node_->referencePathsKept(), node_->humansKept()) << "message " << m;
    }
  }
  flush(*dut_rt_, *probe_);
  EXPECT_EQ(node_->humansKept(), max_ids);
  // The node goes on assessing (human 1, evicted by the flood as the least recently heard,
  // starts afresh).
  states(1);
  ASSERT_NE(at(1, 1), nullptr);
  EXPECT_LE(node_->humansKept(), max_ids);
}

TEST_F(HostilePathAssessor, IdsNeverSeenInAgentStatesAgeOutByMessageTime) {
  states(0);
  publishPaths(freshIds(utimeOf(0), 100));
  EXPECT_EQ(node_->humansKept(), 1u + kIdsPerMessage);
  // Message time advances in steps below limits.max_time_jump_s (a bigger one is rejected).
  states(1, utimeOf(0) + 30'000'000);
  EXPECT_EQ(node_->humansKept(), 1u + kIdsPerMessage);
  states(2, utimeOf(0) + 61'000'000);  // 61 s > forget_after_s: only human 1 is left
  EXPECT_EQ(node_->humansKept(), 1u);
  EXPECT_NE(node_->recorder(1), nullptr);
  EXPECT_EQ(node_->referencePathsKept(), 0u);
}

TEST_F(HostilePathAssessor, AgentStatesStampedInt64MaxMidRunAreRejectedAndRecordingGoesOn) {
  publishPath(utimeOf(0));
  states(0);
  control(0, dialogue::RecorderCommand::kStart, utimeOf(0));
  for (std::int64_t k = 1; k <= 3; ++k) states(k);
  ASSERT_NE(at(3, 1), nullptr);
  ASSERT_EQ(at(3, 1)->recording, path_assessment_t::REC_RECORDING);
  const auto samples = at(3, 1)->interaction_samples;

  const auto rejected = dut_rt_->counters().rejected;
  states(4, kMaxUtime);  // acknowledged (the run goes on), not assessed
  EXPECT_EQ(at(4, 1), nullptr);
  EXPECT_EQ(dut_rt_->counters().rejected, rejected + 1);
  // A STOP stamped INT64_MAX would stop the recorder at a time no observation reaches.
  control(4, dialogue::RecorderCommand::kStop, kMaxUtime);
  for (std::int64_t k = 5; k <= 8; ++k) states(k);
  EXPECT_EQ(dut_rt_->counters().rejected, rejected + 2);
  ASSERT_NE(at(8, 1), nullptr);
  EXPECT_EQ(at(8, 1)->recording, path_assessment_t::REC_RECORDING);
  EXPECT_GT(at(8, 1)->interaction_samples, samples) << "the recorder's time was pinned";
}

TEST_F(HostilePathAssessor, MessagesStampedInt64MaxFirstAreLeftAfterAFewNormalOnes) {
  // The first messages set the time (nothing to judge them against): a reference path, then
  // agent states that agree with it. Kept, that time would make every later observation
  // "before" the last one: no sample ever again.
  ReferencePaths far;
  far.utime = kMaxUtime;
  far.paths.push_back({1, 1, Path2{{10.0, 5.0}, {0.0, 5.0}}});
  publishPaths(far);
  states(0, kMaxUtime);
  // Normal traffic: time_resync_messages agreeing messages in a row take the time back.
  const int resync = dut_rt_->limits().time_resync_messages;
  for (std::int64_t k = 1; k <= resync; ++k) states(k);
  for (std::int64_t k = 1; k < resync; ++k) EXPECT_EQ(at(k, 1), nullptr) << k;
  ASSERT_NE(at(resync, 1), nullptr);
  EXPECT_EQ(at(resync, 1)->utime, utimeOf(resync));
  // Recording works on the new time.
  publishPath(utimeOf(resync));
  control(resync, dialogue::RecorderCommand::kStart, utimeOf(resync));
  for (std::int64_t k = resync + 1; k <= resync + 6; ++k) states(k);
  const path_assessment_t* last = at(resync + 6, 1);
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(last->recording, path_assessment_t::REC_RECORDING);
  EXPECT_GE(last->interaction_samples, 5);
  EXPECT_TRUE(std::isfinite(last->cm_m));
}

}  // namespace
}  // namespace coopnav
