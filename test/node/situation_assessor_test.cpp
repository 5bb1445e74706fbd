// Situation assessor over an isolated udpm port with the REAL obstacle distance server executable
// (map test/data/maps/open.yaml) and hand-made bands: the published numbers equal the library's on
// the same input (distances from the same map loaded in-process); with the server stopped the
// predicates needing it go unknown within the bound and the daemon keeps going, in step order;
// bad bands, a missing reference path and CP_h = CP_r give unknowns with reasons; a message that
// does not convert is rejected but its step acknowledged; SIGTERM exits 0 within 1 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "distance_client/distance_client.hpp"
#include "maps/map_loader.hpp"
#include "situation_assessor_node.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"
#include "wire/conversions.hpp"

namespace coopnav {
namespace {

using namespace std::chrono_literals;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const std::string kMap = ::coopnav::test::testDataDir() + "/maps/open.yaml";

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

/// The library's assessment of one human on the same input, distances from the map in-process.
struct Expected {
  assessment::CrossingInfo crossing;
  assessment::SituationAssessment assessment;
};

class SituationAssessorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<test::ChildProcess>(
        test::daemonPath("obstacle_distance_server"),
        std::vector<std::string>{"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap,
                                 "--log-level", "warn"});
    ASSERT_TRUE(serverAnswers()) << "the obstacle distance server did not come up";
    LoadedMap map = loadMap(kMap);
    field_ = std::make_unique<GridDistanceField>(map.grid, UnknownPolicy::kObstacle);
    dut_rt_ = std::make_unique<Runtime>("situation_assessor", test::testLcmUrl());
    node_ = std::make_unique<SituationAssessorNode>(config_, *dut_rt_);
    probe_ = std::make_unique<Runtime>("probe", test::testLcmUrl());
    probe_->subscribe<situation_t>(
        channels::kSituation,
        [this](const situation_t& m, std::int64_t) { situations_.push_back(m); });
    probe_->subscribe<step_ack_t>(channels::kStepAck, [this](const step_ack_t& a, std::int64_t) {
      if (a.participant == "situation_assessor") acks_.push_back(a.step);
    });
  }

  bool serverAnswers() {
    DistanceClient::Options o;
    o.timeout = 200ms;
    o.attempts = 1;
    DistanceQuery q;
    q.point = {16.0, 1.5};
    for (int i = 0; i < 50; ++i) {
      if (DistanceClient::querySync(test::testLcmUrl(), {q}, o).ok) return true;
    }
    return false;
  }

  void spin() {
    dut_rt_->spinFor(1);
    probe_->spinFor(1);
  }

  /// Publishes bands and reference paths (paths first, as the band source does).
  void publish(const BandsSnapshot& bands, const std::optional<ReferencePaths>& paths = {}) {
    if (paths) probe_->publish(channels::kReferencePaths, toLcm(*paths));
    probe_->publish(channels::kBands, toLcm(bands));
  }

  bool waitAck(std::int64_t step, std::chrono::milliseconds timeout = 3000ms) {
    return test::waitFor([&] { return std::find(acks_.begin(), acks_.end(), step) != acks_.end(); },
                         timeout, [&] { spin(); });
  }

  const situation_t* situation(std::int64_t step, std::int32_t human) const {
    for (const auto& s : situations_)
      if (s.step == step && s.human_id == human) return &s;
    return nullptr;
  }

  Expected expected(const Band& robot, const Band& human, const Path2& ref) const {
    Expected e;
    e.crossing = assessment::computeCrossing(robot, human, config_.crossingConfig());
    const auto thr = config_.thresholds();
    std::optional<double> d_oh;
    std::optional<double> d_or;
    if (const auto q = assessment::halfPlaneQueries(e.crossing, thr)) {
      DistanceQuery dq;
      dq.kind = DistanceQueryKind::kSide;
      dq.max_range_m = config_.query_range_m;
      dq.point = q->human.point;
      dq.vector = q->human.normal;
      d_oh = assessment::obstacleDistanceFrom(answerQuery(*field_, dq), thr.human_radius_m);
      dq.point = q->robot.point;
      dq.vector = q->robot.normal;
      d_or = assessment::obstacleDistanceFrom(answerQuery(*field_, dq), thr.robot_radius_m);
    }
    e.assessment = assessment::assessSituation(e.crossing, ref, d_oh, d_or, thr);
    return e;
  }

  static void expectSame(double published, const std::optional<double>& lib) {
    if (!lib) {
      EXPECT_TRUE(std::isnan(published)) << published;
    } else {
      EXPECT_DOUBLE_EQ(published, *lib);
    }
  }

  static void expectMatches(const situation_t& s, const Expected& e) {
    ASSERT_EQ(e.crossing.status, assessment::CrossingStatus::kOk) << e.crossing.reason;
    EXPECT_EQ(s.i_star, e.crossing.i_star);
    EXPECT_DOUBLE_EQ(s.t_cross_s, *e.crossing.t_cross_s);
    EXPECT_DOUBLE_EQ(s.cp_h_x_m, e.crossing.cp_h.x());
    EXPECT_DOUBLE_EQ(s.cp_h_y_m, e.crossing.cp_h.y());
    EXPECT_DOUBLE_EQ(s.cp_r_x_m, e.crossing.cp_r.x());
    EXPECT_DOUBLE_EQ(s.cp_r_y_m, e.crossing.cp_r.y());
    EXPECT_EQ(s.dir, static_cast<std::int8_t>(e.crossing.dir));
    expectSame(s.d_h_m, e.assessment.d_h_m);
    expectSame(s.d_oh_m, e.assessment.d_oh_m);
    expectSame(s.d_or_m, e.assessment.d_or_m);
    expectSame(s.d_hr_m, e.assessment.d_hr_m);
    EXPECT_EQ(s.human_needs_to_contribute,
              static_cast<std::int8_t>(e.assessment.human_needs_to_contribute));
    EXPECT_EQ(s.human_is_constrained, static_cast<std::int8_t>(e.assessment.human_is_constrained));
    EXPECT_EQ(s.robot_is_constrained, static_cast<std::int8_t>(e.assessment.robot_is_constrained));
  }

  // Bottom corridor of open.pgm: free between the outer wall (y ~ 0.5) and a wall at y ~ 2.8.
  Band robot_ = straightBand({12.0, 1.5}, {20.0, 1.5}, 8.0, 0.5);
  Band human_ = straightBand({20.0, 1.9}, {12.0, 1.9}, 8.0, 0.4);  // unequal ΔT on purpose
  Path2 human_ref_{{20.0, 2.3}, {12.0, 2.3}};

  BandsSnapshot bands(std::int64_t step, std::vector<std::pair<std::int32_t, Band>> humans) {
    BandsSnapshot b;
    b.utime = 1'000'000 + step * 100'000;
    b.step = step;
    b.robot = robot_;
    b.humans = std::move(humans);
    return b;
  }
  ReferencePaths paths(std::vector<std::pair<std::int32_t, Path2>> entries) {
    ReferencePaths r;
    for (auto& [id, p] : entries) r.paths.push_back({id, 1, p});
    return r;
  }

  SituationAssessorConfig config_;
  std::unique_ptr<test::ChildProcess> server_;
  std::unique_ptr<GridDistanceField> field_;
  std::unique_ptr<Runtime> dut_rt_;
  std::unique_ptr<SituationAssessorNode> node_;
  std::unique_ptr<Runtime> probe_;
  std::vector<situation_t> situations_;
  std::vector<std::int64_t> acks_;
};

TEST_F(SituationAssessorTest, PublishedNumbersMatchTheLibraryWithTheRealServer) {
  // Human 2 in the open area above the corridor wall, passing the robot band at 2.2 m.
  const Band open_human = straightBand({19.0, 3.7}, {13.0, 3.7}, 6.0, 0.25);
  const Path2 open_ref{{19.0, 3.5}, {13.0, 3.5}};
  publish(bands(1, {{1, human_}, {2, open_human}}), paths({{1, human_ref_}, {2, open_ref}}));
  ASSERT_TRUE(waitAck(1));
  const situation_t* s1 = situation(1, 1);
  const situation_t* s2 = situation(1, 2);
  ASSERT_NE(s1, nullptr);
  ASSERT_NE(s2, nullptr);
  EXPECT_EQ(s1->utime, 1'100'000);
  EXPECT_EQ(s1->crossing_status, situation_t::CROSSING_OK);
  EXPECT_EQ(s1->reason, "");
  const Expected e1 = expected(robot_, human_, human_ref_);
  expectMatches(*s1, e1);
  expectMatches(*s2, expected(robot_, open_human, open_ref));
  // Hand check of the scene: meeting at t = 4 s, x = 16; the robot (y 1.5) is on the left of the
  // human walking -x; d_h = 0.4 > τ_h; both half-planes find a wall within range.
  EXPECT_NEAR(s1->t_cross_s, 4.0, 1e-9);
  EXPECT_NEAR(s1->cp_h_x_m, 16.0, 1e-9);
  EXPECT_EQ(s1->dir, situation_t::DIR_LEFT);
  EXPECT_NEAR(s1->d_h_m, 0.4, 1e-9);
  EXPECT_NEAR(s1->d_hr_m, 0.4, 1e-9);
  EXPECT_EQ(s1->human_needs_to_contribute, situation_t::PRED_TRUE);
  EXPECT_TRUE(std::isfinite(s1->d_oh_m));
  EXPECT_TRUE(std::isfinite(s1->d_or_m));
  EXPECT_NE(s1->human_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_NE(s1->robot_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_DOUBLE_EQ(s1->tau_h_m, config_.thresholds().tau_h_m);
  EXPECT_DOUBLE_EQ(s1->tau_hr_m, config_.thresholds().tau_hr_m);
}

TEST_F(SituationAssessorTest, ServerStoppedGivesUnknownWithinTheBoundAndKeepsStepOrder) {
  publish(bands(1, {{1, human_}}), paths({{1, human_ref_}}));
  ASSERT_TRUE(waitAck(1));
  server_->signal(SIGTERM);
  ASSERT_EQ(server_->waitExit(2000ms), 0);

  const auto t0 = std::chrono::steady_clock::now();
  for (std::int64_t k = 2; k <= 5; ++k) publish(bands(k, {{1, human_}}));
  ASSERT_TRUE(waitAck(5, 5000ms));
  const double elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // Four messages, each bounded by timeout * attempts (+ the 10 ms client tick); generous slack
  // for a loaded machine: this checks that the wait is bounded, not how fast it is.
  const double bound_ms = config_.distance_timeout_ms * config_.distance_attempts + 10.0;
  EXPECT_LT(elapsed_ms, 4 * bound_ms + 2000.0);
  EXPECT_EQ(acks_, (std::vector<std::int64_t>{1, 2, 3, 4, 5}));
  std::vector<std::int64_t> steps;
  for (const auto& s : situations_) steps.push_back(s.step);
  EXPECT_EQ(steps, (std::vector<std::int64_t>{1, 2, 3, 4, 5}));
  const situation_t* s = situation(5, 1);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->crossing_status, situation_t::CROSSING_OK);
  EXPECT_TRUE(std::isnan(s->d_oh_m));
  EXPECT_TRUE(std::isnan(s->d_or_m));
  EXPECT_EQ(s->human_is_constrained, situation_t::PRED_UNKNOWN);
  // d_HR = 0.4 < τ_HR: the conjunction hinges on the unknown d_OR.
  EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_TRUE);  // needs no server
  EXPECT_NE(s->reason.find("distance server"), std::string::npos) << s->reason;

  // The server comes back: answers again, numbers as the library's.
  server_ = std::make_unique<test::ChildProcess>(
      test::daemonPath("obstacle_distance_server"),
      std::vector<std::string>{"--lcm-url", test::testLcmUrl(), "--set", "map_file=" + kMap,
                               "--log-level", "warn"});
  ASSERT_TRUE(serverAnswers());
  publish(bands(6, {{1, human_}}));
  ASSERT_TRUE(waitAck(6));
  ASSERT_NE(situation(6, 1), nullptr);
  expectMatches(*situation(6, 1), expected(robot_, human_, human_ref_));
}

TEST_F(SituationAssessorTest, BadBandsAreUnknownForThatHumanOnly) {
  Band one_pose;
  one_pose.poses.push_back({0.0, {20.0, 1.9, M_PI}});
  Band with_nan = human_;
  with_nan.poses[3].pose.y_m = kNaN;
  Band not_increasing = human_;
  not_increasing.poses[4].t_s = not_increasing.poses[3].t_s;
  publish(
      bands(1, {{1, human_}, {3, Band{}}, {4, one_pose}, {5, with_nan}, {6, not_increasing}}),
      paths({{1, human_ref_}, {3, human_ref_}, {4, human_ref_}, {5, human_ref_}, {6, human_ref_}}));
  ASSERT_TRUE(waitAck(1));
  ASSERT_NE(situation(1, 1), nullptr);
  expectMatches(*situation(1, 1), expected(robot_, human_, human_ref_));
  for (std::int32_t id : {3, 4, 5, 6}) {
    const situation_t* s = situation(1, id);
    ASSERT_NE(s, nullptr) << id;
    EXPECT_EQ(s->crossing_status, situation_t::CROSSING_BAD_BANDS) << id;
    EXPECT_EQ(s->i_star, -1);
    EXPECT_TRUE(std::isnan(s->t_cross_s));
    EXPECT_TRUE(std::isnan(s->d_h_m));
    EXPECT_TRUE(std::isnan(s->d_hr_m));
    EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_UNKNOWN) << id;
    EXPECT_EQ(s->human_is_constrained, situation_t::PRED_UNKNOWN) << id;
    EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN) << id;
    EXPECT_FALSE(s->reason.empty()) << id;
  }
}

TEST_F(SituationAssessorTest, BadRobotBandOrBandsStatusMakesEveryHumanUnknown) {
  BandsSnapshot b = bands(1, {{1, human_}});
  b.robot.poses.resize(1);
  publish(b, paths({{1, human_ref_}}));
  BandsSnapshot failed = bands(2, {{1, human_}});
  failed.status = bands_t::STATUS_SOLVER_FAILED;
  publish(failed);
  ASSERT_TRUE(waitAck(2));
  for (std::int64_t k : {1, 2}) {
    const situation_t* s = situation(k, 1);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->crossing_status, situation_t::CROSSING_BAD_BANDS);
    EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_UNKNOWN);
    EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN);
  }
  EXPECT_NE(situation(2, 1)->reason.find("SOLVER_FAILED"), std::string::npos);
}

TEST_F(SituationAssessorTest, HumanWithoutReferencePathHasUnknownNeedToContribute) {
  publish(bands(1, {{9, human_}}));
  ASSERT_TRUE(waitAck(1));
  const situation_t* s = situation(1, 9);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->crossing_status, situation_t::CROSSING_NO_REFERENCE);
  EXPECT_NEAR(s->t_cross_s, 4.0, 1e-9);  // the crossing itself is known
  EXPECT_TRUE(std::isnan(s->d_h_m));
  EXPECT_EQ(s->human_needs_to_contribute, situation_t::PRED_UNKNOWN);
  EXPECT_NE(s->human_is_constrained, situation_t::PRED_UNKNOWN);  // the server answered
  EXPECT_NE(s->reason.find("no reference path"), std::string::npos) << s->reason;
}

TEST_F(SituationAssessorTest, CoincidentCrossingPointsWithoutDirAreUnknown) {
  // Dead-on course on the robot's own line: CP_h = CP_r, and the robot band never moves aside.
  const Band dead_on = straightBand({20.0, 1.5}, {12.0, 1.5}, 8.0, 0.5);
  publish(bands(1, {{1, dead_on}}), paths({{1, human_ref_}}));
  ASSERT_TRUE(waitAck(1));
  const situation_t* s = situation(1, 1);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->crossing_status, situation_t::CROSSING_OK);
  EXPECT_EQ(s->dir, situation_t::DIR_UNDEFINED);
  EXPECT_NEAR(s->d_hr_m, 0.0, 1e-9);
  EXPECT_TRUE(std::isnan(s->d_oh_m));
  EXPECT_TRUE(std::isnan(s->d_or_m));
  EXPECT_EQ(s->human_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(s->robot_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_NE(s->reason.find("coincide"), std::string::npos) << s->reason;
}

TEST_F(SituationAssessorTest, UnconvertibleBandsAreRejectedButTheirStepIsAcknowledged) {
  bands_t msg = toLcm(bands(1, {{1, human_}, {1, human_}}));  // duplicate human id
  probe_->publish(channels::kBands, msg);
  ASSERT_TRUE(waitAck(1));
  EXPECT_TRUE(situations_.empty());
  EXPECT_EQ(dut_rt_->counters().rejected, 1);
  publish(bands(2, {{1, human_}}), paths({{1, human_ref_}}));
  ASSERT_TRUE(waitAck(2));
  EXPECT_NE(situation(2, 1), nullptr);
}

TEST(SituationAssessorProcessTest, RunsAloneDegradedAndStopsOnSigtermWithin1s) {
  // No distance server on this port: the executable answers with unknowns and reports DEGRADED.
  Runtime probe("probe", test::testLcmUrl());
  std::vector<daemon_status_t> statuses;
  std::vector<situation_t> situations;
  probe.subscribe<daemon_status_t>(channels::kStatus, [&](const daemon_status_t& s, std::int64_t) {
    if (s.name == "situation_assessor") statuses.push_back(s);
  });
  probe.subscribe<situation_t>(
      channels::kSituation, [&](const situation_t& s, std::int64_t) { situations.push_back(s); });
  test::ChildProcess dut(test::daemonPath("situation_assessor"),
                         {"--lcm-url", test::testLcmUrl(), "--log-level", "error"});
  ASSERT_TRUE(test::waitFor([&] { return !statuses.empty(); }, 5000ms, [&] { probe.spinFor(5); }));
  BandsSnapshot b;
  b.utime = 42;
  b.step = -1;
  b.robot = straightBand({12.0, 1.5}, {20.0, 1.5}, 8.0, 0.5);
  b.humans.emplace_back(1, straightBand({20.0, 1.9}, {12.0, 1.9}, 8.0, 0.4));
  probe.publish(channels::kBands, toLcm(b));
  ASSERT_TRUE(
      test::waitFor([&] { return !situations.empty(); }, 5000ms, [&] { probe.spinFor(5); }));
  EXPECT_EQ(situations[0].human_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(situations[0].utime, 42);
  statuses.clear();
  ASSERT_TRUE(test::waitFor([&] { return !statuses.empty(); }, 3000ms, [&] { probe.spinFor(5); }));
  EXPECT_EQ(statuses.back().state, daemon_status_t::STATE_DEGRADED);
  EXPECT_TRUE(dut.running());
  dut.signal(SIGTERM);
  EXPECT_EQ(dut.waitExit(1000ms), 0);
}

}  // namespace
}  // namespace coopnav
