// Each metric of lib/metrics on tracks whose value is worked out by hand (docs/metrics.md).
#include "coopnav/metrics/run_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace coopnav::metrics {
namespace {

AgentSample agent(std::int32_t id, double x, double y, double vx, double vy, double r) {
  AgentSample a;
  a.id = id;
  a.p_m = {x, y};
  a.v_m_s = {vx, vy};
  a.radius_m = r;
  return a;
}

Frame frame(double t, AgentSample robot, std::vector<AgentSample> humans = {}) {
  Frame f;
  f.t_s = t;
  f.robot = robot;
  f.humans = std::move(humans);
  return f;
}

TEST(RunMetrics, SurfaceGapSubtractsBothRadii) {
  EXPECT_DOUBLE_EQ(surfaceGap(agent(0, 0, 0, 0, 0, 0.3), agent(1, 2, 0, 0, 0, 0.5)), 1.2);
}

TEST(RunMetrics, TimeToCollisionIsTheFirstTouchAtConstantVelocity) {
  const AgentSample robot = agent(0, 0, 0, 0, 0, 0.3);
  // Closing at 1 m/s from 5 m, touching at a centre distance of 0.5 m: 4.5 s.
  EXPECT_NEAR(timeToCollision(robot, agent(1, 5, 0, -1, 0, 0.2)), 4.5, 1e-12);
  // Head-on both at 1 m/s: half the time.
  EXPECT_NEAR(timeToCollision(agent(0, 0, 0, 1, 0, 0.3), agent(1, 5, 0, -1, 0, 0.2)), 2.25, 1e-12);
  EXPECT_TRUE(std::isnan(timeToCollision(robot, agent(1, 5, 1, -1, 0, 0.2))));       // passes wide
  EXPECT_TRUE(std::isnan(timeToCollision(robot, agent(1, 5, 0, 1, 0, 0.2))));        // moving away
  EXPECT_TRUE(std::isnan(timeToCollision(robot, agent(1, 5, 0, -1, 0, 0.2), 4.0)));  // horizon
  EXPECT_EQ(timeToCollision(robot, agent(1, 0.4, 0, 0, 0, 0.2)), 0.0);  // already touching
}

TEST(RunMetrics, PathLengthAndCumulativeHeadingChange) {
  EXPECT_DOUBLE_EQ(pathLength({{0, 0}, {3, 4}, {3, 5}}), 6.0);
  // Turns 0.5, 1.0, then 3.5 and 6.0 rad wrapped to 2π-3.5 and 2π-6: 4π-8.
  EXPECT_NEAR(cumulativeHeadingChange({0.0, 0.5, -0.5, 3.0, -3.0}), 4.0 * M_PI - 8.0, 1e-12);
}

TEST(RunMetrics, PathIrregularityIsTurningBeyondTheStraightPath) {
  const Eigen::Vector2d goal{10, 0};
  // A zig-zag facing the goal: 45° left, 90° right, 45° left = π; the straight path needs 0.
  EXPECT_NEAR(pathIrregularity({{0, 0}, {3, 3}, {6, 0}, {10, 0}}, 0.0, goal, 0.01), M_PI, 1e-12);
  // Facing north, driving straight east: the quarter turn is what the goal needs.
  EXPECT_NEAR(pathIrregularity({{0, 0}, {5, 0}, {10, 0}}, M_PI / 2, goal, 0.01), 0.0, 1e-12);
  // Standing still in between (steps below min_motion_m) adds no direction.
  EXPECT_NEAR(pathIrregularity({{0, 0}, {5, 0}, {5.001, 0.004}, {10, 0}}, 0.0, goal, 0.01), 0.0,
              1e-12);
}

TEST(RunMetrics, LongestNoProgressIsTheLongestSpanWithoutGettingHalfAMetreCloser) {
  const std::vector<double> t{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  const std::vector<double> d{10, 9, 8, 8, 8, 8, 8, 7.9, 7.7, 7.4, 5};
  // From t 2 (8 m) the best stays above 7.5 m up to t 8 (7.7 m): 6 s.
  EXPECT_DOUBLE_EQ(longestNoProgress(t, d, 0.5), 6.0);
  // Steady progress of 1 m per second: never 1 s without half a metre.
  EXPECT_DOUBLE_EQ(longestNoProgress({0, 1, 2}, {3, 2, 1}, 0.5), 0.0);
}

TEST(RunMetrics, AccelerationAndJerkAreFiniteDifferencesTimeWeighted) {
  const std::vector<double> t{0, 1, 2, 3};
  const std::vector<Eigen::Vector2d> v{{0, 0}, {1, 0}, {1, 0}, {1, 1}};
  // Accelerations 1, 0, 1 at t 0.5, 1.5, 2.5 standing for 0.5, 1, 0.5 s.
  const Stat3 a = derivativeStats(t, v, 1);
  EXPECT_DOUBLE_EQ(a.min, 0.0);
  EXPECT_DOUBLE_EQ(a.max, 1.0);
  EXPECT_DOUBLE_EQ(a.avg, 0.5);
  // Jerks (-1, 0) and (0, 1): both of norm 1.
  const Stat3 j = derivativeStats(t, v, 2);
  EXPECT_DOUBLE_EQ(j.min, 1.0);
  EXPECT_DOUBLE_EQ(j.avg, 1.0);
  EXPECT_DOUBLE_EQ(j.max, 1.0);
}

TEST(RunMetrics, ConflictIntensityFromTheClosestApproachAndItsTime) {
  const MetricsOptions o;  // σ 0.5 m, τ 2 s, horizon 8 s
  const AgentSample robot = agent(0, 0, 0, 1, 0, 0.3);
  // Head-on 10 m apart closing at 2 m/s: contact predicted at t* 5 s: exp(-5/2).
  EXPECT_NEAR(conflictIntensity(robot, agent(1, 10, 0, -1, 0, 0.3), o), std::exp(-2.5), 1e-12);
  // 1.1 m offset: a 0.5 m gap at t* 5 s: exp(-0.25/0.5) exp(-2.5).
  EXPECT_NEAR(conflictIntensity(robot, agent(1, 10, 1.1, -1, 0, 0.3), o), std::exp(-3.0), 1e-12);
  // Beyond the horizon: the gap at 8 s (closing at 0.5 m/s from 10 m: 6 m apart, 5.4 m gap).
  EXPECT_NEAR(conflictIntensity(agent(0, 0, 0, 0.5, 0, 0.3), agent(1, 10, 0, 0, 0, 0.3), o),
              std::exp(-5.4 * 5.4 / 0.5) * std::exp(-4.0), 1e-15);
}

/// A head-on encounter at 10 Hz: each one walks at 1 m/s and from t 1 s on steps aside at
/// `robot_side` / `person_side` m/s (to its own right).
void encounter(double robot_side, double person_side, std::vector<AgentSample>& robot,
               std::vector<AgentSample>& person) {
  AgentSample r = agent(0, -5, 0, 1, 0, 0.3);
  AgentSample h = agent(1, 5, 0, -1, 0, 0.3);
  for (int k = 0; k <= 60; ++k) {
    robot.push_back(r);
    person.push_back(h);
    if (k == 10) {
      r.v_m_s = {1, -robot_side};
      h.v_m_s = {-1, person_side};
    }
    r.p_m += 0.1 * r.v_m_s;
    h.p_m += 0.1 * h.v_m_s;
  }
}

TEST(RunMetrics, ResponsibilityGoesToWhoeverResolvesTheConflict) {
  const MetricsOptions o;
  std::vector<AgentSample> r;
  std::vector<AgentSample> h;
  encounter(0.0, 0.4, r, h);  // the person steps aside, the robot keeps its line
  ConflictShares s = conflictShares(r, h, o);
  EXPECT_EQ(s.resolved_by_robot, 0.0);
  EXPECT_GT(s.resolved_by_person, 0.0);
  EXPECT_EQ(s.robot_responsibility, 0.0);
  EXPECT_GT(s.max_intensity, 0.0);

  r.clear();
  h.clear();
  encounter(0.4, 0.0, r, h);  // the robot does
  s = conflictShares(r, h, o);
  EXPECT_EQ(s.robot_responsibility, 1.0);

  r.clear();
  h.clear();
  encounter(0.3, 0.3, r, h);  // both alike (the mirror image of each other): half each
  s = conflictShares(r, h, o);
  EXPECT_NEAR(s.robot_responsibility, 0.5, 1e-9);
  EXPECT_NEAR(s.resolved_by_robot, s.resolved_by_person, 1e-12);
}

TEST(RunMetrics, EngagementGoesToWhoeverEscalatesTheConflict) {
  const MetricsOptions o;
  // Passing 2 m apart laterally; at t 1 s the robot turns towards the person's line.
  std::vector<AgentSample> r;
  std::vector<AgentSample> h;
  AgentSample rs = agent(0, -5, 0, 1, 0, 0.3);
  AgentSample hs = agent(1, 5, 2, -1, 0, 0.3);
  for (int k = 0; k <= 30; ++k) {
    r.push_back(rs);
    h.push_back(hs);
    if (k == 10) rs.v_m_s = {1, 0.3};
    rs.p_m += 0.1 * rs.v_m_s;
    hs.p_m += 0.1 * hs.v_m_s;
  }
  const ConflictShares s = conflictShares(r, h, o);
  EXPECT_GT(s.escalated_by_robot, 0.0);
  EXPECT_EQ(s.escalated_by_person, 0.0);
  EXPECT_EQ(s.robot_engagement, 1.0);
  EXPECT_TRUE(std::isnan(s.robot_responsibility));  // nobody resolved anything
}

TEST(RunMetrics, NoConflictNoShares) {
  // Passing 4 m apart laterally, the person drifting further away: the intensity stays far below
  // 0.1, so the drift is nobody's share of resolving anything.
  std::vector<AgentSample> r;
  std::vector<AgentSample> h;
  AgentSample rs = agent(0, -5, 0, 1, 0, 0.3);
  AgentSample hs = agent(1, 5, 4, -1, 0.2, 0.3);
  for (int k = 0; k <= 30; ++k) {
    r.push_back(rs);
    h.push_back(hs);
    hs.v_m_s.y() += 0.01;
    rs.p_m += 0.1 * rs.v_m_s;
    hs.p_m += 0.1 * hs.v_m_s;
  }
  const ConflictShares s = conflictShares(r, h, MetricsOptions{});
  EXPECT_LT(s.max_intensity, 0.1);
  EXPECT_GT(s.resolved_by_person, 0.0);             // the drift is counted ...
  EXPECT_TRUE(std::isnan(s.robot_responsibility));  // ... but shares nothing
  EXPECT_TRUE(std::isnan(s.robot_engagement));
}

TEST(RunMetrics, ZonesComplianceAndDiscomfortFromTheNearestPerson) {
  // Robot (r 0.5) at rest; a person (r 0.3) at gaps 2.2, 1.2, 0.2, 0.1, 2.2 m, one second apart.
  RunInput in;
  const double xs[] = {3.0, 2.0, 1.0, 0.9, 3.0};
  for (int k = 0; k < 5; ++k)
    in.frames.push_back(frame(k, agent(0, 0, 0, 0, 0, 0.5), {agent(7, xs[k], 0, 0, 0, 0.3)}));
  const RunMetrics m = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(m.duration_s, 4.0);
  EXPECT_DOUBLE_EQ(m.intimate_s, 2.0);  // 0.2 and 0.1 m, a second each
  EXPECT_DOUBLE_EQ(m.personal_s, 0.0);
  EXPECT_DOUBLE_EQ(m.social_s, 2.0);  // 2.2 and 1.2 m (1.2 is no longer personal)
  EXPECT_DOUBLE_EQ(m.intimate_share, 0.5);
  EXPECT_DOUBLE_EQ(m.space_compliance, 0.5);      // under 0.5 m for 2 of 4 s
  EXPECT_DOUBLE_EQ(m.discomfort_frequency, 0.2);  // 1 of 5 frames under 0.2 m
  EXPECT_NEAR(m.min_distance_to_person_m, 0.1, 1e-12);
  EXPECT_NEAR(m.closest_person_distance_m.avg, 3.7 / 4.0, 1e-12);
  EXPECT_NEAR(m.closest_person_distance_m.max, 2.2, 1e-12);
  EXPECT_DOUBLE_EQ(m.stalled_s, 4.0);
  EXPECT_FALSE(m.success);  // no goal, no outcome
  ASSERT_EQ(m.persons.size(), 1u);
  EXPECT_EQ(m.persons[0].id, 7);
  EXPECT_DOUBLE_EQ(m.persons[0].intimate_s, 2.0);
  EXPECT_EQ(m.person_collisions, 0);
}

TEST(RunMetrics, SeveralPeopleEachOnTheirOwnAndTheNearestForTheRun) {
  // Robot (r 0.5) at rest. Person 1 (r 0.3) at a 1.0 m gap then 3.0 m; person 2 at 2.0 m then
  // 0.3 m. The nearest gap: 1.0 m (person 1), then 0.3 m (person 2).
  RunInput in;
  in.frames.push_back(frame(0, agent(0, 0, 0, 0, 0, 0.5),
                            {agent(2, 0, 2.8, 0, 0, 0.3), agent(1, 1.8, 0, 0, 0, 0.3)}));
  in.frames.push_back(frame(1, agent(0, 0, 0, 0, 0, 0.5),
                            {agent(1, 3.8, 0, 0, 0, 0.3), agent(2, 0, 1.1, 0, 0, 0.3)}));
  in.frames.push_back(frame(2, agent(0, 0, 0, 0, 0, 0.5), {agent(1, 3.8, 0, 0, 0, 0.3)}));
  const RunMetrics m = computeRunMetrics(in);
  EXPECT_NEAR(m.min_distance_to_person_m, 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(m.personal_s, 1.0);  // 1.0 m for the first second
  EXPECT_DOUBLE_EQ(m.intimate_s, 1.0);  // 0.3 m for the second
  ASSERT_EQ(m.persons.size(), 2u);
  EXPECT_EQ(m.persons[0].id, 1);  // ascending ids
  EXPECT_NEAR(m.persons[0].min_distance_m, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.persons[0].personal_s, 1.0);
  EXPECT_DOUBLE_EQ(m.persons[0].social_s, 1.0);  // 3.0 m in the second second
  EXPECT_EQ(m.persons[1].id, 2);
  EXPECT_NEAR(m.persons[1].min_distance_m, 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(m.persons[1].social_s, 1.0);
  EXPECT_DOUBLE_EQ(m.persons[1].intimate_s, 1.0);
  EXPECT_NEAR(m.closest_person_distance_m.avg, 0.65, 1e-12);  // 1.0 and 0.3, a second each
}

TEST(RunMetrics, PathRatioSplAndTimeToGoal) {
  RunInput in;
  in.robot_goal = Eigen::Vector2d{10, 0};
  in.outcome = Outcome::kGoalReached;
  in.goal_time_s = 3.0;
  const double ps[][2] = {{0, 0}, {3, 4}, {6, 0}, {10, 0}, {10, 0}};
  for (int k = 0; k < 5; ++k)
    in.frames.push_back(frame(k, agent(0, ps[k][0], ps[k][1], 2, 0, 0.3)));
  RunMetrics m = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(m.time_to_goal_s, 3.0);
  EXPECT_DOUBLE_EQ(m.duration_s, 3.0);  // the frame after the goal is not the robot's run
  EXPECT_DOUBLE_EQ(m.path_length_m, 14.0);
  EXPECT_DOUBLE_EQ(m.shortest_path_m, 10.0);
  EXPECT_DOUBLE_EQ(m.path_length_ratio, 1.4);
  EXPECT_DOUBLE_EQ(m.spl, 10.0 / 14.0);
  EXPECT_TRUE(m.success);
  EXPECT_DOUBLE_EQ(m.final_distance_to_goal_m, 0.0);
  EXPECT_DOUBLE_EQ(m.motion_energy_m2_s, 12.0);  // 2 m/s for 3 s: 4 × 3
  EXPECT_DOUBLE_EQ(m.speed_m_s.avg, 2.0);
  EXPECT_DOUBLE_EQ(m.goal_traversal_ratio, 0.0);
  // Turned atan(4/3) left, twice that right, atan(4/3) left again, over 14 m.
  EXPECT_NEAR(m.path_irregularity_rad_per_m, 4.0 * std::atan2(4.0, 3.0) / 14.0,
              1e-12);         // 45° + 90° + 45° turned
  in.shortest_path_m = 12.0;  // the map's geodesic, given: SPL's, not the ratio's (straight)
  m = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(m.spl, 12.0 / 14.0);
  EXPECT_DOUBLE_EQ(m.path_length_ratio, 1.4);
  in.outcome = Outcome::kTimeLimit;  // not reached: no SPL, a timeout
  in.goal_time_s = kNaN;
  m = computeRunMetrics(in);
  EXPECT_FALSE(m.success);
  EXPECT_TRUE(m.timeout);
  EXPECT_EQ(m.spl, 0.0);
  // Without the simulator's word the goal counts as reached within the tolerance.
  in.outcome = Outcome::kUnknown;
  m = computeRunMetrics(in);
  EXPECT_TRUE(m.success);
  EXPECT_DOUBLE_EQ(m.time_to_goal_s, 3.0);
}

TEST(RunMetrics, CollisionsSayWhoRanIntoWhom) {
  RunInput in;  // the robot (r 0.3) drives at 1 m/s into a person (r 0.3) standing at x 1.4
  for (int k = 0; k < 4; ++k)
    in.frames.push_back(
        frame(0.3 * k, agent(0, 0.3 * k, 0, 1, 0, 0.3), {agent(1, 1.4, 0, 0, 0, 0.3)}));
  RunMetrics m = computeRunMetrics(in);  // gaps 0.8, 0.5, 0.2, -0.1
  EXPECT_TRUE(m.collision);
  EXPECT_EQ(m.person_collisions, 1);
  EXPECT_EQ(m.robot_on_person_collisions, 1);
  EXPECT_EQ(m.person_on_robot_collisions, 0);
  EXPECT_NEAR(m.min_ttc_s, 0.0, 1e-12);  // touching at the last frame

  RunInput walked;  // a person walks into the robot at rest
  for (int k = 0; k < 4; ++k)
    walked.frames.push_back(
        frame(0.3 * k, agent(0, 0, 0, 0, 0, 0.3), {agent(1, 1.4 - 0.3 * k, 0, -1, 0, 0.3)}));
  m = computeRunMetrics(walked);
  EXPECT_EQ(m.robot_on_person_collisions, 0);
  EXPECT_EQ(m.person_on_robot_collisions, 1);
  EXPECT_NEAR(m.persons[0].min_ttc_s, 0.0, 1e-12);
}

TEST(RunMetrics, WallClearanceGivesClearingDistanceAndWallCollisions) {
  RunInput in;
  for (int k = 0; k < 4; ++k) in.frames.push_back(frame(k, agent(0, k, 0, 1, 0, 0.3)));
  in.wall_clearance_m = {1.0, 0.5, 0.0, 0.3};
  const RunMetrics m = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(m.clearing_distance_m.min, 0.0);
  EXPECT_DOUBLE_EQ(m.clearing_distance_m.avg, 0.5);  // 1, 0.5, 0 a second each
  EXPECT_DOUBLE_EQ(m.clearing_distance_m.max, 1.0);
  EXPECT_EQ(m.wall_collisions, 1);
  EXPECT_TRUE(m.collision);
  // The wall force 10 exp(-c / 0.2) over the three seconds held (1, 0.5 and 0 m).
  EXPECT_NEAR(m.obstacle_work, 10.0 * (std::exp(-5.0) + std::exp(-2.5) + 1.0), 1e-12);
  EXPECT_DOUBLE_EQ(m.social_work, m.obstacle_work);  // nobody else there

  in.wall_clearance_m = {1.0, kNaN, 0.5, 0.5};  // off the map at t 1 s: left out
  const RunMetrics unknown = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(unknown.clearing_distance_m.min, 0.5);
  EXPECT_DOUBLE_EQ(unknown.clearing_distance_m.avg, 0.75);
  EXPECT_EQ(unknown.wall_collisions, 0);
  EXPECT_NEAR(unknown.obstacle_work, 10.0 * (std::exp(-5.0) + std::exp(-2.5)), 1e-12);
}

TEST(RunMetrics, SocialWorkAndPersonalSpaceCost) {
  RunInput in;  // 0.5 m gap held for one second, the person walking at the robot at 1 m/s
  for (int k = 0; k < 2; ++k)
    in.frames.push_back(frame(k, agent(0, 0, 0, 0, 0, 0.5), {agent(1, 1.3, 0, -1, 0, 0.3)}));
  const RunMetrics m = computeRunMetrics(in);
  // The robot's force on the person and the person's on the robot: 2 × 2.1 exp(-0.5/0.3).
  EXPECT_NEAR(m.social_work, 4.2 * std::exp(-0.5 / 0.3), 1e-12);
  // 1.3 m ahead of a person at 1 m/s: σ = 2 m: exp(-1.3² / 8).
  EXPECT_NEAR(m.personal_space_cost_s, std::exp(-1.69 / 8.0), 1e-12);
}

TEST(RunMetrics, PersonalSpaceIsLongerAheadThanBehindAndNarrowAside) {
  const MetricsOptions o;
  const AgentSample walker = agent(1, 0, 0, 1, 0, 0.3);  // 1 m/s along +x: σ 2, 2/3, 0.5 m
  EXPECT_NEAR(personalSpaceCost(agent(0, 1, 0, 0, 0, 0.3), walker, o), std::exp(-1.0 / 8.0), 1e-12);
  EXPECT_NEAR(personalSpaceCost(agent(0, -1, 0, 0, 0, 0.3), walker, o),
              std::exp(-1.0 / (2.0 * 4.0 / 9.0)), 1e-12);
  EXPECT_NEAR(personalSpaceCost(agent(0, 0, 1, 0, 0, 0.3), walker, o), std::exp(-2.0), 1e-12);
  // Standing still facing +y: σ 0.5 m ahead (along +y), 0.125 m aside.
  AgentSample still = agent(1, 0, 0, 0, 0, 0.3);
  still.theta_rad = M_PI / 2;
  EXPECT_NEAR(personalSpaceCost(agent(0, 0, 0.5, 0, 0, 0.3), still, o), std::exp(-0.5), 1e-12);
  EXPECT_NEAR(personalSpaceCost(agent(0, 0.25, 0, 0, 0, 0.3), still, o), std::exp(-2.0), 1e-12);
}

TEST(RunMetrics, FailureToProgressIsAStandstillOrTenSecondsWithoutProgress) {
  RunInput in;
  in.robot_goal = Eigen::Vector2d{20, 0};
  for (int k = 0; k <= 12; ++k) in.frames.push_back(frame(k, agent(0, 0.01 * k, 0, 0.01, 0, 0.3)));
  RunMetrics m = computeRunMetrics(in);
  EXPECT_DOUBLE_EQ(m.longest_no_progress_s, 12.0);
  EXPECT_TRUE(m.failure_to_progress);
  EXPECT_DOUBLE_EQ(m.stalled_s, 12.0);  // 0.01 m/s is stalled
  in.frames.resize(6);                  // 5 s only: not yet a failure
  in.outcome = Outcome::kStandstill;    // ... unless the simulator called a standstill
  m = computeRunMetrics(in);
  EXPECT_TRUE(m.failure_to_progress);
  in.outcome = Outcome::kUnknown;
  EXPECT_FALSE(computeRunMetrics(in).failure_to_progress);
}

}  // namespace
}  // namespace coopnav::metrics
