// Round trips and rejections of the lcmtypes <-> lib conversions (daemons/common/conversions).
#include "wire/conversions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace coopnav {
namespace {

template <class Msg>
Msg reencode(const Msg& m) {
  std::vector<uint8_t> buf(m.getEncodedSize());
  EXPECT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  Msg out;
  EXPECT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return out;
}

AgentStatesSnapshot sampleStates() {
  AgentStatesSnapshot s;
  s.utime = 1234567;
  s.step = 12;
  s.robot.id = 0;
  s.robot.kind = AgentKind::kRobot;
  s.robot.pose = {1.0, 2.0, 0.5};
  s.robot.velocity = {0.7, 0.0, 0.1};
  s.robot.radius_m = 0.34;
  for (int i = 1; i <= 3; ++i) {
    AgentState h;
    h.id = i;
    h.kind = AgentKind::kHuman;
    h.pose = {10.0 + i, 6.5, M_PI};
    h.velocity = {-1.2, 0.0, 0.0};
    h.radius_m = 0.3;
    s.humans.push_back(h);
  }
  return s;
}

TEST(ConversionsTest, AgentStatesRoundTripThroughTheWire) {
  const auto s = sampleStates();
  const auto back = fromLcm(reencode(toLcm(s)));
  EXPECT_EQ(back.utime, s.utime);
  EXPECT_EQ(back.step, s.step);
  EXPECT_EQ(back.robot.pose, s.robot.pose);
  EXPECT_EQ(back.robot.velocity, s.robot.velocity);
  ASSERT_EQ(back.humans.size(), 3u);
  EXPECT_EQ(back.humans[2].pose, s.humans[2].pose);
  EXPECT_EQ(back.human(2)->id, 2);
  EXPECT_EQ(back.human(7), nullptr);
}

TEST(ConversionsTest, AgentStatesRejectNaNDuplicateIdsAndOverBound) {
  auto m = toLcm(sampleStates());
  m.humans[1].x_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fromLcm(m), RejectedMessage);
  m = toLcm(sampleStates());
  m.humans[1].id = m.humans[0].id;
  EXPECT_THROW(fromLcm(m), RejectedMessage);
  m = toLcm(sampleStates());
  m.robot.radius_m = 0.0;
  EXPECT_THROW(fromLcm(m), RejectedMessage);
  m = toLcm(sampleStates());
  m.humans.resize(agent_states_t::MAX_HUMANS + 1, m.humans[0]);
  for (std::size_t i = 0; i < m.humans.size(); ++i) m.humans[i].id = static_cast<int>(i + 1);
  m.num_humans = static_cast<int16_t>(m.humans.size());
  EXPECT_THROW(fromLcm(m), RejectedMessage);
}

TEST(ConversionsTest, BandsRoundTripKeepsPerPoseTimes) {
  BandsSnapshot b;
  b.utime = 42;
  b.step = 3;
  b.robot_id = 0;
  for (int i = 0; i < 5; ++i) b.robot.poses.push_back({0.125 * i, {0.1 * i, 0.0, 0.0}});
  Band h;
  for (int i = 0; i < 4; ++i) h.poses.push_back({0.2 * i, {5.0 - 0.2 * i, 0.1, M_PI}});
  b.humans.emplace_back(7, h);
  b.room_plans = {bands_t::ROOM_RETREAT};
  const auto back = fromLcm(reencode(toLcm(b)));
  EXPECT_EQ(back.robot, b.robot);
  ASSERT_NE(back.humanBand(7), nullptr);
  EXPECT_EQ(*back.humanBand(7), h);
  EXPECT_EQ(back.step, 3);
  EXPECT_EQ(back.roomPlan(7), bands_t::ROOM_RETREAT);
  EXPECT_EQ(back.roomPlan(8), bands_t::ROOM_UNKNOWN) << "no band, no plan";
}

TEST(ConversionsTest, BandsRoomPlansAreFilledOnTheWayOutAndCheckedOnTheWayIn) {
  BandsSnapshot b;
  b.humans.emplace_back(1, Band{});
  b.humans.emplace_back(2, Band{});
  bands_t m = toLcm(b);  // no plans given: one ROOM_UNKNOWN per human
  ASSERT_EQ(m.room_plans.size(), 2u);
  EXPECT_EQ(m.room_plans[1], bands_t::ROOM_UNKNOWN);
  m.room_plans[0] = bands_t::ROOM_NONE + 1;
  EXPECT_THROW(fromLcm(m), RejectedMessage);
  m.room_plans.pop_back();
  m.room_plans[0] = bands_t::ROOM_DOCK_HERE;
  EXPECT_THROW(fromLcm(m), RejectedMessage) << "fewer plans than humans";
}

TEST(ConversionsTest, VelocityCommandKeepsModeAndGuard) {
  VelocityCommand c;
  c.body = {0.1, 0.0, 0.2};
  c.mode = velocity_command_t::MODE_RETREATING;
  c.guard = velocity_command_t::GUARD_EVADING;
  const VelocityCommand back = fromLcm(reencode(toLcm(c)));
  EXPECT_EQ(back.mode, velocity_command_t::MODE_RETREATING);
  EXPECT_EQ(back.guard, velocity_command_t::GUARD_EVADING);
}

TEST(ConversionsTest, BandsKeepDegenerateBandsForTheAssessorToJudge) {
  BandsSnapshot b;
  b.humans.emplace_back(1, Band{});  // length 0: kept, reported unknown downstream
  Band nan_band;
  nan_band.poses.push_back({0.0, {std::nan(""), 0.0, 0.0}});
  b.humans.emplace_back(2, nan_band);
  const auto back = fromLcm(reencode(toLcm(b)));
  EXPECT_TRUE(back.humanBand(1)->poses.empty());
  EXPECT_TRUE(std::isnan(back.humanBand(2)->poses[0].pose.x_m));
}

TEST(ConversionsTest, ReferencePathsRoundTripAndRejectMismatchedArrays) {
  ReferencePaths r;
  r.utime = 5;
  r.paths.push_back({3, 2, {{0.0, 0.0}, {1.0, 0.5}, {2.0, 1.0}}});
  const auto back = fromLcm(reencode(toLcm(r)));
  ASSERT_EQ(back.paths.size(), 1u);
  EXPECT_EQ(back.paths[0].agent_id, 3);
  EXPECT_EQ(back.paths[0].revision, 2);
  EXPECT_EQ(back.paths[0].path[2], Eigen::Vector2d(2.0, 1.0));
  auto m = toLcm(r);
  m.paths[0].y_m.pop_back();
  EXPECT_THROW(fromLcm(m), RejectedMessage);
}

TEST(ConversionsTest, DistanceRequestAndReplyRoundTrip) {
  std::vector<DistanceQuery> qs(3);
  qs[0] = {DistanceQueryKind::kNearest, {1.0, 2.0}, {0.0, 0.0}, 5.0};
  qs[1] = {DistanceQueryKind::kSide, {1.0, 2.0}, {0.0, 1.0}, 5.0};
  qs[2] = {DistanceQueryKind::kRay, {1.0, 2.0}, {1.0, 0.0}, 8.0};
  const auto req = reencode(toLcm(9, 77, "COOPNAV_DIST_REP_x", qs));
  EXPECT_EQ(req.request_id, 77);
  const auto back = queriesFromLcm(req);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[1].kind, DistanceQueryKind::kSide);
  EXPECT_EQ(back[2].vector, Eigen::Vector2d(1.0, 0.0));

  std::vector<DistanceResult> rs(2);
  rs[0] = {DistanceStatus::kOk, 1.5, {3.0, 4.0}};
  rs[1] = {DistanceStatus::kOutsideMap, 0.0, {0.0, 0.0}};
  const auto rep = reencode(toLcm(9, 77, rs));
  const auto rback = resultsFromLcm(rep);
  EXPECT_EQ(rback[0].status, DistanceStatus::kOk);
  EXPECT_EQ(rback[0].distance_m, 1.5);
  EXPECT_EQ(rback[1].status, DistanceStatus::kOutsideMap);
  EXPECT_TRUE(std::isnan(rep.results[1].distance_m));  // no number for a status
}

TEST(ConversionsTest, EmptyOrOversizedDistanceRequestIsRejected) {
  auto req = toLcm(0, 1, "R", {});
  EXPECT_THROW(queriesFromLcm(req), RejectedMessage);
}

TEST(ConversionsTest, TimeConversionIsExactOnMicroseconds) {
  EXPECT_EQ(secondsToUtime(utimeToSeconds(1234567890123)), 1234567890123);
  EXPECT_EQ(secondsToUtime(0.1), 100000);
}

}  // namespace
}  // namespace coopnav

namespace coopnav {
namespace {

GoalEstimates sampleEstimates() {
  GoalEstimates e;
  e.utime = 42;
  e.step = 7;
  e.goals = {{1.0, 2.0}, {-3.0, 4.5}};
  GoalEstimates::Human h;
  h.agent_id = 3;
  h.most_likely = 1;
  h.walked_m = 2.5;
  h.observations = 20;
  h.probability = {0.25, 0.75};
  e.humans.push_back(h);
  return e;
}

TEST(ConversionsTest, GoalEstimatesRoundTrip) {
  const goal_estimates_t m = reencode(toLcm(sampleEstimates()));
  EXPECT_EQ(m.num_goals, 2);
  ASSERT_EQ(m.num_humans, 1);
  const GoalEstimates b = fromLcm(m);
  EXPECT_EQ(b.utime, 42);
  EXPECT_EQ(b.step, 7);
  ASSERT_EQ(b.goals.size(), 2U);
  EXPECT_EQ(b.goals[1], Eigen::Vector2d(-3.0, 4.5));
  ASSERT_EQ(b.humans.size(), 1U);
  EXPECT_EQ(b.humans[0].agent_id, 3);
  EXPECT_EQ(b.humans[0].most_likely, 1);
  EXPECT_EQ(b.humans[0].observations, 20);
  EXPECT_DOUBLE_EQ(b.humans[0].walked_m, 2.5);
  EXPECT_EQ(b.humans[0].probability, (std::vector<double>{0.25, 0.75}));
}

TEST(ConversionsTest, GarbageGoalEstimatesAreRejected) {
  const goal_estimates_t m = toLcm(sampleEstimates());
  auto bad = m;
  bad.num_goals = 3;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.goal_x_m[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.humans[0].most_likely = 2;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.humans[0].probability[0] = 1.5F;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.humans[0].probability.pop_back();
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.humans.push_back(bad.humans[0]);
  bad.num_humans = 2;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
}

TEST(ConversionsTest, GoalEstimatesKeepAMostLikelyGoalOnlyWhenItIsSent) {
  GoalEstimates e = sampleEstimates();
  e.goals.resize(goal_estimates_t::MAX_GOALS + 1, Eigen::Vector2d(0.0, 0.0));
  e.humans[0].most_likely = goal_estimates_t::MAX_GOALS;  // beyond the kept candidates
  const goal_estimates_t m = toLcm(e);
  EXPECT_EQ(m.num_goals, goal_estimates_t::MAX_GOALS);
  EXPECT_EQ(m.humans[0].most_likely, -1);
  EXPECT_NO_THROW(fromLcm(m));
}

}  // namespace
}  // namespace coopnav
