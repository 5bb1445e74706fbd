#include "coopnav/band/dual_band_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "analytic_map.hpp"
#include "band_test_util.hpp"

namespace coopnav {
namespace {

using test::BoxMap;

constexpr double kRobotRadius_m = 0.34;
constexpr double kHumanRadius_m = 0.30;
/// Tolerance on distances judged from bands (soft penalties stop a little inside the bound).
constexpr double kDistTol_m = 0.05;

/// Clearance of every pose from the walls minus the radius.
double minWallClearance(const DistanceMap& map, const Band& b, double radius_m) {
  double m = 1e9;
  for (const auto& p : b.poses)
    m = std::min(m, map.nearest(p.pose.position()).distance_m - radius_m);
  return m;
}

class HeadOnOpenCorridor : public ::testing::Test {
 protected:
  void SetUp() override {
    // Given a 6 m wide corridor, a robot driving +x at 0.7 m/s and a human walking −x at
    // 1 m/s on the same centre line, 8 m apart, each going to the other's start.
    map_ = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
    DualBandPlanner dut(BandPlannerConfig{}, map_);
    auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
    req.agent.velocity.vx_m_s = 0.7;
    // When one cycle is planned with CoHAN's budget (8 inner x 4 outer).
    result_ = dut.plan(req);
  }
  std::shared_ptr<BoxMap> map_;
  PlanResult result_;
};

TEST_F(HeadOnOpenCorridor, BandsPassWithSafetyDistancePairedByTime) {
  ASSERT_EQ(result_.status, PlanStatus::kOk);
  ASSERT_EQ(result_.others.size(), 1u);
  const double d = test::minPairedDistance(result_.agent_band, result_.others[0].band);
  EXPECT_GE(
      d, kRobotRadius_m + kHumanRadius_m + BandPlannerConfig{}.min_agent_robot_dist_m - kDistTol_m);
}

TEST_F(HeadOnOpenCorridor, BandsAreKinematicallyFeasible) {
  const BandPlannerConfig cfg;
  const auto kr = test::measure(result_.agent_band);
  const auto kh = test::measure(result_.others[0].band);
  // Speeds: within 5 % of the limits.
  EXPECT_LE(kr.max_vx, cfg.robot.max_vel_x_m_s * 1.05);
  EXPECT_GE(kr.min_vx, -cfg.robot.max_vel_x_backwards_m_s * 1.05);
  EXPECT_LE(kr.max_abs_vy, cfg.robot.max_vel_y_m_s * 1.05);
  EXPECT_LE(kr.max_abs_omega, cfg.robot.max_vel_theta_rad_s * 1.05);
  EXPECT_LE(kh.max_vx, cfg.human.max_vel_x_m_s * 1.05);
  EXPECT_LE(kh.max_abs_vy, cfg.human.max_vel_y_m_s * 1.05);
  // Accelerations are soft penalties (TEB) solved with 32 LM iterations: allow 2x, plus one
  // segment at the human's goal stop.
  EXPECT_LE(kr.max_abs_ax, cfg.robot.acc_lim_x_m_s2 * 2.0);
  EXPECT_LE(kr.max_abs_ay, cfg.robot.acc_lim_y_m_s2 * 2.0);
  EXPECT_LE(kh.max_abs_ay, cfg.human.acc_lim_y_m_s2 * 2.0);
  EXPECT_LE(kh.max_abs_ax, cfg.human.acc_lim_x_m_s2 * 4.0);
}

TEST_F(HeadOnOpenCorridor, BandsStayClearOfWalls) {
  const double min_obst = BandPlannerConfig{}.min_obstacle_dist_m;
  EXPECT_GE(minWallClearance(*map_, result_.agent_band, kRobotRadius_m), min_obst - kDistTol_m);
  EXPECT_GE(minWallClearance(*map_, result_.others[0].band, kHumanRadius_m), min_obst - kDistTol_m);
}

TEST_F(HeadOnOpenCorridor, HumanDeviatesLessThanRobot) {
  const double dev_r = test::maxDeviation(result_.agent_band, result_.agent_path);
  const double dev_h = test::maxDeviation(result_.others[0].band, result_.others[0].reference_path);
  EXPECT_LT(dev_h, dev_r);
  EXPECT_LT(dev_h, 0.4);  // "minimal contribution"
}

TEST_F(HeadOnOpenCorridor, ReportsCommandAndCosts) {
  EXPECT_GT(result_.command_body.vx_m_s, 0.3);
  EXPECT_LE(result_.command_body.vx_m_s, BandPlannerConfig{}.robot.max_vel_x_m_s + 1e-9);
  EXPECT_GT(result_.iterations, 0);
  EXPECT_LE(result_.iterations, 32);
  EXPECT_EQ(result_.term_costs.size(), 9u);
  EXPECT_FALSE(result_.others[0].reference_path.empty());
  EXPECT_TRUE(result_.others[0].reference_changed);
}

TEST(DualBandPlannerTest, NarrowCorridorRobotBandMovesToOneSide) {
  // Given the 2.25 m corridor and a head-on human 8 m away.
  auto map = BoxMap::corridor(0.0, 20.0, 0.45, 2.70);
  const double centre_y = 1.575;
  DualBandPlanner dut(BandPlannerConfig{}, map);
  auto req = test::headOn(3.0, 11.0, centre_y, 17.0);
  req.agent.velocity.vx_m_s = 0.7;
  const PlanResult r = dut.plan(req);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  // Then the robot band leaves the centre line towards one wall and stays clear of it.
  double max_off = 0.0;
  for (const auto& p : r.agent_band.poses)
    max_off = std::max(max_off, std::abs(p.pose.y_m - centre_y));
  EXPECT_GT(max_off, 0.25);
  // Clear of the walls: at least 0.1 m from the disc edge (the 0.2 m clearance is a soft
  // penalty the safety term pushes against in 2.25 m).
  EXPECT_GE(minWallClearance(*map, r.agent_band, kRobotRadius_m), 0.1);
}

TEST(DualBandPlannerTest, FarHeadOnHumanDoesNotSlowTheRobotBand) {
  // Given a head-on human who stays > 14 m away over the whole robot band (6.75 m ahead),
  auto map = BoxMap::corridor(0.0, 40.0, 0.0, 6.0);
  auto req = test::headOn(3.0, 35.0, 3.0, 20.0);
  req.agent.velocity.vx_m_s = 0.7;
  auto duration = [&](BandPlannerConfig cfg, bool with_human) {
    DualBandPlanner dut(cfg, map);
    auto r0 = req;
    if (!with_human) r0.others.clear();
    const PlanResult r = dut.plan(r0);
    EXPECT_EQ(r.status, PlanStatus::kOk);
    return r.agent_band.poses.back().t_s;
  };
  const double alone_s = duration({}, false);
  // then the robot band is as fast as without the human: CoHAN's relative-velocity cost
  // (closing speed + (|v_r| + 1)/|d| > 1.5 head-on at any range) acts only near the meeting.
  EXPECT_NEAR(duration({}, true), alone_s, 0.05 * alone_s);
  // The bug this guards against: ungated, the same term slows the robot band from afar.
  BandPlannerConfig ungated;
  ungated.rel_vel_activation_dist_m = 0.0;
  EXPECT_GT(duration(ungated, true), 1.2 * alone_s);
}

TEST(DualBandPlannerTest, WarmStartKeepsPlanningAsAgentsMove) {
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  DualBandPlanner dut(BandPlannerConfig{}, map);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.agent.velocity.vx_m_s = 0.7;
  PlanResult r = dut.plan(req);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  EXPECT_FALSE(r.warm_started);
  for (int k = 0; k < 3; ++k) {
    // Agents advance along their bands by 0.1 s.
    req.stamp_s += 0.1;
    const Eigen::Vector2d pr = test::positionAt(r.agent_band, 0.1);
    const Eigen::Vector2d ph = test::positionAt(r.others[0].band, 0.1);
    req.agent.pose.x_m = pr.x(), req.agent.pose.y_m = pr.y();
    req.others[0].state.pose.x_m = ph.x(), req.others[0].state.pose.y_m = ph.y();
    r = dut.plan(req);
    ASSERT_EQ(r.status, PlanStatus::kOk);
    // Last cycle's bands are optimised beside fresh ones; the cheaper are kept.
    EXPECT_TRUE(r.warm_candidate);
    EXPECT_FALSE(r.others[0].reference_changed);
  }
  EXPECT_GE(test::minPairedDistance(r.agent_band, r.others[0].band),
            kRobotRadius_m + kHumanRadius_m + 0.6 - 2 * kDistTol_m);
}

TEST(DualBandPlannerTest, ColdBandStartsWhereTheRobotIsAcrossItsPathAndKeepsItsLateralSpeed) {
  // Given a cold-started robot that planned its path on the corridor's centre line, then drifted
  // 0.4 m to its right (less than the re-plan distance: the path is kept) and still moves right,
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  BandPlannerConfig cfg;
  cfg.warm_start = false;
  DualBandPlanner dut(cfg, map);
  PlanRequest req;
  req.stamp_s = 10.0;
  req.agent = test::makeAgent(0, AgentKind::kRobot, 3.0, 3.0, 0.0, 0.0, kRobotRadius_m);
  req.goal = {17.0, 3.0, 0.0};
  ASSERT_EQ(dut.plan(req).status, PlanStatus::kOk);
  const double vy_m_s = -0.2;
  req.stamp_s = 11.0;
  req.agent.pose = {4.0, 2.6, 0.0};
  req.agent.velocity = {0.7, vy_m_s, 0.0};
  // when it plans again,
  const PlanResult r = dut.plan(req);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  EXPECT_LT(std::abs(r.agent_path.front().y() - 3.0), 0.05) << "the path was re-planned";
  // then the band's first segment (the command) carries on from the robot's lateral speed within
  // the acceleration limit, at cruising speed, instead of jumping back to the path (a band laid
  // on the path from a robot beside it did: its first segment pointed at the path and the
  // optimiser slowed the band to keep that within the limits).
  const auto& p = r.agent_band.poses;
  ASSERT_GE(p.size(), 3u);
  const double dt = p[1].t_s - p[0].t_s;
  const double vx1 = (p[1].pose.x_m - p[0].pose.x_m) / dt;
  const double vy1 = (p[1].pose.y_m - p[0].pose.y_m) / dt;
  EXPECT_NEAR(vy1, vy_m_s, cfg.robot.acc_lim_y_m_s2 * dt + 0.05);
  EXPECT_GT(vx1, 0.6);
  // And it returns to the path within the lateral speed limit.
  const auto k = test::measure(r.agent_band);
  EXPECT_LE(k.max_abs_vy, cfg.robot.max_vel_y_m_s * 1.05);
  EXPECT_LT(std::abs(test::positionAt(r.agent_band, 6.0).y() - 3.0), 0.1);
}

TEST(DualBandPlannerTest, IterationBudgetIsRespected) {
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  DualBandPlanner dut(BandPlannerConfig{}, map);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.max_iterations = 3;
  const PlanResult r = dut.plan(req);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  EXPECT_LE(r.iterations, 3);
}

TEST(DualBandPlannerTest, ScaleAwareDampingStartTakesMoreStepsOfTheSameBudget) {
  // Given the head-on case planned with the damping started at 1 (the default) and at 1e-2 of
  // the problem's largest JᵀJ diagonal entry, the same 32-solve budget each.
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.agent.velocity.vx_m_s = 0.7;
  BandPlannerConfig from_one, from_scale;
  from_scale.initial_damping_scale = 1e-2;
  const PlanResult a = DualBandPlanner(from_one, map).plan(req);
  const PlanResult b = DualBandPlanner(from_scale, map).plan(req);
  ASSERT_EQ(a.status, PlanStatus::kOk);
  ASSERT_EQ(b.status, PlanStatus::kOk);
  // Then both spend the budget, the scale-aware start wastes fewer solves on rejected steps and
  // its bands still keep the safety distance.
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_GT(b.accepted_steps, a.accepted_steps);
  EXPECT_GE(
      test::minPairedDistance(b.agent_band, b.others[0].band) - kRobotRadius_m - kHumanRadius_m,
      from_scale.min_agent_robot_dist_m - kDistTol_m);
  if (std::getenv("COOPNAV_TEST_VERBOSE")) {
    std::printf("steps taken %d -> %d of %d, final cost %.4f -> %.4f\n", a.accepted_steps,
                b.accepted_steps, a.iterations, a.final_cost, b.final_cost);
  }
}

TEST(DualBandPlannerTest, BothSolversReachComparableBandsOnTheSameProblem) {
  // Given the head-on case planned once with our sparse LM and once with Ceres.
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.agent.velocity.vx_m_s = 0.7;
  BandPlannerConfig ours_cfg, ceres_cfg;
  ours_cfg.solver = "sparse_lm";
  ceres_cfg.solver = "ceres";
  const PlanResult ours = DualBandPlanner(ours_cfg, map).plan(req);
  const PlanResult ceres = DualBandPlanner(ceres_cfg, map).plan(req);
  ASSERT_EQ(ours.status, PlanStatus::kOk);
  ASSERT_EQ(ceres.status, PlanStatus::kOk);
  // Then both use the whole budget and end within 10 % of each other's cost (same residual
  // blocks, same damping rule; rounding differs), with bands of the same length in time.
  EXPECT_EQ(ours.iterations, ceres.iterations);
  EXPECT_NEAR(ours.final_cost, ceres.final_cost, 0.1 * ceres.final_cost);
  EXPECT_NEAR(ours.agent_band.poses.back().t_s, ceres.agent_band.poses.back().t_s, 0.5);
  EXPECT_GE(test::minPairedDistance(ours.agent_band, ours.others[0].band) - kRobotRadius_m -
                kHumanRadius_m,
            BandPlannerConfig{}.min_agent_robot_dist_m - kDistTol_m);
}

TEST(DualBandPlannerTest, TimeBudgetUsesTheCallersClock) {
  // Given a fake clock that advances 10 ms per reading and a 25 ms budget.
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  for (const char* solver : {"sparse_lm", "ceres"}) {
    BandPlannerConfig cfg;
    cfg.solver = solver;
    DualBandPlanner dut(cfg, map);
    auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
    double now_s = 0.0;
    req.clock_s = [&now_s] { return now_s += 0.01; };
    req.time_budget_s = 0.025;
    const PlanResult r = dut.plan(req);
    // Then the solve stops early, says so, and reports the clock's elapsed time.
    ASSERT_EQ(r.status, PlanStatus::kOk) << solver;
    EXPECT_TRUE(r.budget_exhausted) << solver;
    EXPECT_LT(r.iterations, 32) << solver;
    EXPECT_GT(r.solver_time_s, 0.02) << solver;
  }
}

TEST(DualBandPlannerTest, HumanAsPlanningAgentYieldsToAnticipatedRobot) {
  // Given the facilitating-human set-up of world_sim: the human plans, the robot is "other".
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  DualBandPlanner dut(BandPlannerConfig{}, map);
  PlanRequest req;
  req.stamp_s = 5.0;
  req.agent = test::makeAgent(7, AgentKind::kHuman, 11.0, 3.0, M_PI, 1.0, kHumanRadius_m);
  req.goal = {3.0, 3.0, M_PI};
  OtherAgentInput robot;
  robot.state = test::makeAgent(0, AgentKind::kRobot, 3.0, 3.0, 0.0, 0.7, kRobotRadius_m);
  robot.goal = {17.0, 3.0, 0.0};
  req.others.push_back(robot);
  const PlanResult r = dut.plan(req);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  const double dev_h = test::maxDeviation(r.agent_band, r.agent_path);
  const double dev_r = test::maxDeviation(r.others[0].band, r.others[0].reference_path);
  EXPECT_GT(dev_h, dev_r);
  EXPECT_GT(dev_h, 0.5);
  // Human limits apply to the planning human: lateral speed near 0.4 m/s, not the robot's 0.7
  // (soft limit: the planning band carries the whole avoidance here).
  EXPECT_LE(test::measure(r.agent_band).max_abs_vy, BandPlannerConfig{}.human.max_vel_y_m_s * 1.4);
}

// --- degenerate inputs: defined statuses, never a crash ---

class Degenerate : public ::testing::Test {
 protected:
  void SetUp() override {
    map_ = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
    map_->addBox({Eigen::Vector2d(14.0, 2.0), Eigen::Vector2d(15.0, 3.0)});
    dut_ = std::make_unique<DualBandPlanner>(BandPlannerConfig{}, map_);
    req_ = test::headOn(3.0, 11.0, 3.0, 17.0);
  }
  std::shared_ptr<BoxMap> map_;
  std::unique_ptr<DualBandPlanner> dut_;
  PlanRequest req_;
};

TEST_F(Degenerate, StartEqualsGoalIsGoalReachedWithZeroCommand) {
  req_.goal = req_.agent.pose;
  const PlanResult r = dut_->plan(req_);
  EXPECT_EQ(r.status, PlanStatus::kGoalReached);
  EXPECT_EQ(r.command_body, Velocity2{});
  EXPECT_EQ(r.agent_band.poses.size(), 1u);
  ASSERT_EQ(r.others.size(), 1u);
  EXPECT_GE(r.others[0].band.poses.size(), 2u);
}

TEST_F(Degenerate, GoalInsideObstacle) {
  req_.goal = {14.5, 2.5, 0.0};
  EXPECT_EQ(dut_->plan(req_).status, PlanStatus::kGoalInObstacle);
}

TEST_F(Degenerate, StartInsideObstacle) {
  req_.agent.pose = {14.5, 2.5, 0.0};
  EXPECT_EQ(dut_->plan(req_).status, PlanStatus::kStartInObstacle);
}

TEST_F(Degenerate, GoalOutsideMap) {
  req_.goal = {100.0, 2.5, 0.0};
  EXPECT_EQ(dut_->plan(req_).status, PlanStatus::kOutsideMap);
}

TEST_F(Degenerate, NoPath) {
  // A wall across the corridor.
  map_->addBox({Eigen::Vector2d(8.0, 0.0), Eigen::Vector2d(8.5, 6.0)});
  DualBandPlanner dut(BandPlannerConfig{}, map_);
  const PlanResult r = dut.plan(req_);
  EXPECT_EQ(r.status, PlanStatus::kNoPath);
  EXPECT_EQ(r.command_body, Velocity2{});
}

TEST_F(Degenerate, NanPose) {
  req_.agent.pose.x_m = std::nan("");
  EXPECT_EQ(dut_->plan(req_).status, PlanStatus::kInvalidInput);
  req_.agent.pose.x_m = 3.0;
  req_.goal.y_m = std::nan("");
  EXPECT_EQ(dut_->plan(req_).status, PlanStatus::kInvalidInput);
}

TEST_F(Degenerate, NanHumanIsSkipped) {
  req_.others[0].state.pose.y_m = std::nan("");
  const PlanResult r = dut_->plan(req_);
  EXPECT_EQ(r.status, PlanStatus::kOk);
  EXPECT_TRUE(r.others.empty());
  ASSERT_EQ(r.skipped_ids.size(), 1u);
  EXPECT_EQ(r.skipped_ids[0], 1);
}

TEST_F(Degenerate, EmptyHumanListPlansAlone) {
  req_.others.clear();
  const PlanResult r = dut_->plan(req_);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  EXPECT_TRUE(r.others.empty());
  EXPECT_GE(r.agent_band.poses.size(), 3u);
  EXPECT_NEAR(r.agent_band.poses.back().pose.x_m, 3.0 + BandPlannerConfig{}.max_plan_length_m, 0.3);
}

TEST_F(Degenerate, HumanWithUnknownGoalUsesConstantVelocity) {
  req_.others[0].goal = {std::nan(""), std::nan(""), 0.0};
  const PlanResult r = dut_->plan(req_);
  ASSERT_EQ(r.status, PlanStatus::kOk);
  ASSERT_EQ(r.others.size(), 1u);
  EXPECT_LT(r.others[0].reference_path.back().x(), 11.0);
}

/// A crowd: the 64 humans (the band source's bound) on a grid ahead of the robot, ids in an
/// order unrelated to their distance.
PlanRequest crowd(std::size_t n) {
  PlanRequest r = test::headOn(3.0, 11.0, 3.0, 17.0);
  r.others.clear();
  for (std::size_t k = 0; k < n; ++k) {
    OtherAgentInput h;
    const double x = 19.0 - 0.9 * static_cast<double>(k % 8);
    const double y = 0.8 + 0.6 * static_cast<double>(k / 8);
    h.state = test::makeAgent(static_cast<std::int32_t>(100 + (k * 37) % n), AgentKind::kHuman, x,
                              y, M_PI, 1.0, 0.30);
    h.goal = {1.0, y, M_PI};
    r.others.push_back(h);
  }
  return r;
}

TEST_F(Degenerate, CrowdBeyondTheCapPlansOnlyTheNearest) {
  // Given 64 humans and a planner that plans at most 3 of them jointly.
  BandPlannerConfig cfg;
  cfg.max_planned_others = 3;
  DualBandPlanner dut(cfg, map_);
  const PlanRequest req = crowd(64);
  // When one cycle is planned.
  const PlanResult r = dut.plan(req);
  // Then the three nearest are planned, the others reported unplanned, in request order, with
  // a predicted band each (after the planned ones, in the same order).
  ASSERT_EQ(r.status, PlanStatus::kOk);
  ASSERT_EQ(r.others.size(), 64u);
  ASSERT_EQ(r.unplanned_ids.size(), 61u);
  for (std::size_t i = 0; i < r.others.size(); ++i) {
    EXPECT_EQ(r.others[i].predicted, i >= 3) << i;
    EXPECT_GE(r.others[i].band.poses.size(), 2u) << i;
    if (i >= 3) {
      EXPECT_EQ(r.others[i].id, r.unplanned_ids[i - 3]);
    }
  }
  std::vector<std::pair<double, std::int32_t>> by_distance;
  for (const auto& o : req.others)
    by_distance.push_back(
        {(o.state.pose.position() - req.agent.pose.position()).norm(), o.state.id});
  std::sort(by_distance.begin(), by_distance.end());
  std::set<std::int32_t> planned;
  for (const auto& o : r.others)
    if (!o.predicted) planned.insert(o.id);
  EXPECT_EQ(planned, (std::set<std::int32_t>{by_distance[0].second, by_distance[1].second,
                                             by_distance[2].second}));
  std::size_t u = 0;
  for (const auto& o : req.others) {
    if (planned.count(o.state.id)) continue;
    ASSERT_LT(u, r.unplanned_ids.size());
    EXPECT_EQ(r.unplanned_ids[u++], o.state.id);
  }
  EXPECT_TRUE(r.skipped_ids.empty());
}

TEST_F(Degenerate, WhichHumansArePlannedDoesNotDependOnTheirOrder) {
  BandPlannerConfig cfg;
  cfg.max_planned_others = 4;
  PlanRequest req = crowd(16);
  std::set<std::int32_t> first, second;
  {
    DualBandPlanner dut(cfg, map_);
    for (const auto& o : dut.plan(req).others)
      if (!o.predicted) first.insert(o.id);
  }
  std::reverse(req.others.begin(), req.others.end());
  {
    DualBandPlanner dut(cfg, map_);
    for (const auto& o : dut.plan(req).others)
      if (!o.predicted) second.insert(o.id);
  }
  EXPECT_EQ(first.size(), 4u);
  EXPECT_EQ(first, second);
}

TEST_F(Degenerate, DefaultCapPlansACrowdOfTheBandSourcesBound) {
  // 64 humans (band_source's bound) with the default cap: one cycle completes with that many
  // bands (before the cap, one such cycle took minutes; docs/bad-inputs.md).
  DualBandPlanner dut(BandPlannerConfig{}, map_);
  const PlanResult r = dut.plan(crowd(64));
  ASSERT_EQ(r.status, PlanStatus::kOk);
  const auto planned = std::count_if(r.others.begin(), r.others.end(),
                                     [](const OtherAgentResult& o) { return !o.predicted; });
  EXPECT_EQ(planned, BandPlannerConfig{}.max_planned_others);
  EXPECT_EQ(r.others.size(), 64u);
  EXPECT_EQ(static_cast<std::size_t>(planned) + r.unplanned_ids.size(), 64u);
}

// Obstacles of the moment (a box on the corridor's centre line that the map does not hold, as
// laser returns around its outline), against the same request without them.
std::vector<Eigen::Vector2d> boxOutline(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  std::vector<Eigen::Vector2d> pts;
  constexpr double kStep_m = 0.05;
  for (double x = lo.x(); x <= hi.x() + 1e-9; x += kStep_m) {
    pts.emplace_back(x, lo.y());
    pts.emplace_back(x, hi.y());
  }
  for (double y = lo.y() + kStep_m; y < hi.y() - 1e-9; y += kStep_m) {
    pts.emplace_back(lo.x(), y);
    pts.emplace_back(hi.x(), y);
  }
  return pts;
}

double minDistanceToPoints(const Band& b, const std::vector<Eigen::Vector2d>& pts) {
  double m = 1e9;
  for (const auto& p : b.poses)
    for (const auto& o : pts) m = std::min(m, (p.pose.position() - o).norm());
  return m;
}

TEST(DualBandPlannerTest, ObstaclePointsReachTheObstacleTermAndPushTheBandOffABox) {
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 6.0);
  auto req = test::headOn(3.0, 11.0, 3.0, 17.0);
  req.others.clear();
  req.agent.velocity.vx_m_s = 0.5;
  // 0.6 m x 0.8 m, 3 m ahead, the centre line 0.2 m above its lower edge.
  const auto box = boxOutline({6.0, 2.8}, {6.6, 3.6});
  const PlanResult blind = DualBandPlanner(BandPlannerConfig{}, map).plan(req);
  ASSERT_EQ(blind.status, PlanStatus::kOk);
  EXPECT_LT(minDistanceToPoints(blind.agent_band, box), kRobotRadius_m);

  req.obstacle_points = box;
  const PlanResult seen = DualBandPlanner(BandPlannerConfig{}, map).plan(req);
  ASSERT_EQ(seen.status, PlanStatus::kOk);
  // One cycle: the global path goes round the box, and the band laid on it and optimised with
  // the obstacle term keeps the robot's radius from every return.
  EXPECT_GT(minDistanceToPoints(seen.agent_band, box), minDistanceToPoints(blind.agent_band, box));
  EXPECT_GE(minDistanceToPoints(seen.agent_band, box), kRobotRadius_m - kDistTol_m);
  double path_min = 1e9;
  for (const auto& p : seen.agent_path)
    for (const auto& o : box) path_min = std::min(path_min, (p - o).norm());
  EXPECT_GE(path_min, kRobotRadius_m - BandPlannerConfig{}.global_resolution_m);
  EXPECT_FALSE(seen.path_blocked);
  EXPECT_GE(minWallClearance(*map, seen.agent_band, kRobotRadius_m),
            BandPlannerConfig{}.min_obstacle_dist_m - kDistTol_m);
}

TEST(DualBandPlannerTest, ObstaclePointsTheRobotCannotPassHoldItOnTheStaticPath) {
  // A 2 m corridor and a row of returns across it leaving 0.3 m: no way round.
  auto map = BoxMap::corridor(0.0, 20.0, 0.0, 2.0);
  auto req = test::headOn(3.0, 11.0, 1.0, 17.0);
  req.others.clear();
  std::vector<Eigen::Vector2d> wall;
  for (double y = 0.0; y <= 1.7 + 1e-9; y += 0.05) wall.emplace_back(6.0, y);
  req.obstacle_points = wall;
  DualBandPlanner dut(BandPlannerConfig{}, map);
  const PlanResult r = dut.plan(req);
  // The static map's path, marked blocked; the band stops short of the returns.
  ASSERT_EQ(r.status, PlanStatus::kOk);
  EXPECT_TRUE(r.path_blocked);
  EXPECT_GT(minDistanceToPoints(r.agent_band, wall), 0.0);
  // Once the returns are gone (a door opened), a path without them.
  req.obstacle_points.clear();
  req.stamp_s += 0.1;
  const PlanResult open = dut.plan(req);
  ASSERT_EQ(open.status, PlanStatus::kOk);
  EXPECT_FALSE(open.path_blocked);
}

TEST(DualBandPlannerConfigTest, InvalidConfigIsReported) {
  BandPlannerConfig cfg;
  cfg.dt_ref_s = -1.0;
  cfg.robot.max_vel_x_m_s = 0.0;
  DualBandPlanner dut(cfg, BoxMap::corridor(0.0, 5.0, 0.0, 2.0));
  ASSERT_GE(dut.configErrors().size(), 2u);
  EXPECT_EQ(dut.configErrors()[0].key, "dt_ref_s");
  EXPECT_EQ(dut.plan(test::headOn(1.0, 4.0, 1.0, 4.0)).status, PlanStatus::kInvalidConfig);
}

}  // namespace
}  // namespace coopnav
