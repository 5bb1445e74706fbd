// The world's run (lib/sim world_run.hpp): waiting for the lockstep participants, the lockstep
// end held until the last step's acks are in, a silent participant named, and the end-of-run
// sentences world_sim's SIM status carries.
#include "coopnav/sim/world_run.hpp"

#include <gtest/gtest.h>

namespace coopnav::sim {
namespace {

TEST(WorldRun, WaitsForEveryParticipantInScenarioOrder) {
  WorldRun run({"band_source", "dialogue_manager"}, 20.0);
  EXPECT_EQ(run.phase(), WorldRun::Phase::kWaitingReady);
  EXPECT_EQ(run.missing(), "band_source, dialogue_manager");
  EXPECT_TRUE(run.heard("dialogue_manager"));
  EXPECT_FALSE(run.heard("dialogue_manager"));  // heard before: nothing new to check
  EXPECT_TRUE(run.heard("viewer"));             // not a participant: changes nothing missing
  EXPECT_EQ(run.missing(), "band_source");
  const WorldRun::Finish f = run.neverReady(60.0);
  EXPECT_EQ(f.end, RunEnd::kParticipantTimeout);
  EXPECT_EQ(f.detail,
            "participant(s) never sent a status within wait_ready_timeout_s = 60 s: band_source");
  run.heard("band_source");
  EXPECT_EQ(run.missing(), "");
  run.start();
  EXPECT_FALSE(run.heard("path_assessor"));  // statuses after the start are no readiness
  EXPECT_EQ(run.phase(), WorldRun::Phase::kRunning);
}

TEST(WorldRun, FreeRunningHasNobodyToWaitForAndEndsAtOnce) {
  WorldRun run({}, 20.0);
  EXPECT_EQ(run.missing(), "");
  run.start();
  const auto f = run.simulationEnded(RunEnd::kGoalsReached, "done", false);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->end, RunEnd::kGoalsReached);
  EXPECT_FALSE(run.ending());
}

TEST(WorldRun, LockstepEndWaitsForTheLastStepsAcks) {
  WorldRun run({"band_source"}, 20.0);
  run.start();
  EXPECT_FALSE(run.stepAcknowledged(5, false, "").has_value());  // go on with step 6
  EXPECT_FALSE(run.simulationEnded(RunEnd::kCollision, "robot collision", true).has_value());
  EXPECT_TRUE(run.ending());
  const auto f = run.stepAcknowledged(6, false, "");
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->end, RunEnd::kCollision);
  EXPECT_EQ(f->detail, "robot collision");
  EXPECT_FALSE(f->last_step_unacknowledged);
  run.finish();
  EXPECT_TRUE(run.ended());
}

TEST(WorldRun, ASilentParticipantIsNamedEndingOrNot) {
  WorldRun run({"path_assessor"}, 20.0);
  run.start();
  const auto timeout = run.stepAcknowledged(110, true, "path_assessor (step 110)");
  ASSERT_TRUE(timeout.has_value());
  EXPECT_EQ(timeout->end, RunEnd::kParticipantTimeout);
  EXPECT_EQ(timeout->detail,
            "no acknowledgement of step 110 within step_timeout_s = 20 s from: path_assessor "
            "(step 110)");
  WorldRun ending({"path_assessor"}, 2.5);
  ending.start();
  ending.simulationEnded(RunEnd::kGoalsReached, "robot reached its goal", true);
  const auto f = ending.stepAcknowledged(300, true, "path_assessor");
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->end, RunEnd::kGoalsReached);  // how it ended does not depend on the acks
  EXPECT_TRUE(f->last_step_unacknowledged);
  EXPECT_EQ(f->detail,
            "robot reached its goal (its last step 300 was not acknowledged within "
            "step_timeout_s = 2.5 s by: path_assessor)");
}

TEST(WorldRun, RunEndOfEverySimulationEnd) {
  EXPECT_EQ(runEndOf(SimStatus::kGoalsReached), RunEnd::kGoalsReached);
  EXPECT_EQ(runEndOf(SimStatus::kCollision), RunEnd::kCollision);
  EXPECT_EQ(runEndOf(SimStatus::kTimeLimit), RunEnd::kTimeLimit);
  EXPECT_EQ(runEndOf(SimStatus::kStandstill), RunEnd::kStandstill);
}

TEST(WorldRunEnd, ContactSentencesSayWhoIsAtFault) {
  RobotHumanContact c{2, 12.3, 0.32, true};
  EXPECT_EQ(contactDetail(c, 0.05), "the robot drove into human 2 at 0.32 m/s at t 12.30 s");
  c = {1, 23.4, -0.2, false};
  EXPECT_EQ(contactDetail(c, 0.05),
            "human 1 walked into the robot moving away from it at 0.20 m/s at t 23.40 s");
  c = {1, 23.4, 0.01, false};
  EXPECT_EQ(contactDetail(c, 0.05), "human 1 walked into the robot at rest at t 23.40 s");
}

TEST(WorldRunEnd, EndSentencesOfEachEnd) {
  EndContext ctx;
  ctx.time_limit_s = 60.0;
  ctx.standstill_distance_m = 0.05;
  ctx.standstill_time_s = 10.0;
  ctx.contact_fault_speed_m_s = 0.05;
  SimSummary sum;
  StepResult r;
  r.status = SimStatus::kRunning;
  EXPECT_EQ(endDetail(r, sum, ctx), "");
  r.status = SimStatus::kTimeLimit;
  EXPECT_EQ(endDetail(r, sum, ctx), "time limit of 60 s reached before the robot reached its goal");
  sum.robot_goal_time_s = 31.5;
  EXPECT_EQ(endDetail(r, sum, ctx), "time limit of 60 s reached");
  r.status = SimStatus::kGoalsReached;
  EXPECT_EQ(endDetail(r, sum, ctx), "robot reached its goal at t = 31.5 s and every human its own");

  r.status = SimStatus::kStandstill;
  sum.robot_goal_time_s = -1.0;
  EXPECT_EQ(endDetail(r, sum, ctx),
            "standstill: no agent moved more than 0.05 m for 10 s; the robot was never "
            "commanded, had said nothing");
  ctx.robot_mode = "docking";
  ctx.last_said = "\"I will wait here.\" to human 1";
  sum.robot_goal_time_s = 20.0;  // at its goal, though the command does not say so
  EXPECT_EQ(endDetail(r, sum, ctx),
            "standstill: no agent moved more than 0.05 m for 10 s; the robot was docking (at its "
            "goal), last said \"I will wait here.\" to human 1");
  ctx.robot_mode = "at its goal";
  ctx.robot_mode_at_goal = true;
  EXPECT_EQ(endDetail(r, sum, ctx),
            "standstill: no agent moved more than 0.05 m for 10 s; the robot was at its goal, "
            "last said \"I will wait here.\" to human 1");

  r.status = SimStatus::kCollision;
  r.events = {{SimEvent::Kind::kCollision, 4.25, kRobotId, kWallId, -0.01, SimStatus::kRunning}};
  EXPECT_EQ(endDetail(r, sum, ctx), "robot collided with a wall at t = 4.25 s");
  r.events = {{SimEvent::Kind::kCollision, 4.25, kRobotId, 3, -0.01, SimStatus::kRunning}};
  EXPECT_EQ(endDetail(r, sum, ctx), "robot collided with human 3 at t = 4.25 s");
  sum.first_contact = RobotHumanContact{3, 4.2, 0.5, true};
  EXPECT_EQ(endDetail(r, sum, ctx), "the robot drove into human 3 at 0.50 m/s at t 4.20 s");
  r.events.clear();
  EXPECT_EQ(endDetail(r, sum, ctx), "robot collision");
}

}  // namespace
}  // namespace coopnav::sim
