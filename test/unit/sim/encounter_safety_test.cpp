// Who touched whom at a robot-human contact, simulated people near a robot at rest (the body
// check: squeeze past where the body fits, wait where it does not, only oblivious walks in), and
// the standstill that ends an encounter neither side resolves. Analytic corridors (corridor_map).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <ostream>

#include "coopnav/sim/body_check.hpp"
#include "coopnav/sim/simulation.hpp"
#include "corridor_map.hpp"

namespace coopnav::sim {
namespace {

constexpr double kRobotRadius_m = 0.47;

BehaviourConfig config(BehaviourType t) {
  BehaviourConfig c;
  c.type = t;
  return c;
}

/// A human walking +x along y_m from x 0 to x 20 (or standing at x_start when it is its goal).
HumanSpec walker(BehaviourType type, double y_m, double speed_m_s = 1.2, double x_start_m = 0.0,
                 double x_goal_m = 20.0) {
  HumanSpec h;
  h.id = 1;
  h.start = {x_start_m, y_m, 0.0};
  h.goal = {x_goal_m, y_m, 0.0};
  h.speed_m_s = speed_m_s;
  h.behaviour = config(type);
  return h;
}

struct Outcome {
  SimStatus status{SimStatus::kRunning};
  SimSummary summary;
  double end_t_s{0.0};
  std::vector<AgentState> last;
  int human_wall_contacts{0};
  bool waited{false};    ///< the behaviour reported "wait" at some step
  bool squeezed{false};  ///< ... "squeeze"
};

/// Runs until the end with the robot's body-frame command from `command(t_s, robot)`.
Outcome simulate(const WorldSpec& w, const DistanceMap* map,
                 const std::function<Velocity2(double, const AgentState&)>& command) {
  Simulation sim(w, map);
  Outcome run;
  std::vector<AgentState> agents = sim.agents();
  while (sim.status() == SimStatus::kRunning) {
    const StepResult r = sim.step(command(sim.time_s(), agents.front()));
    agents = r.agents;
    for (const SimEvent& e : r.events)
      if (e.kind == SimEvent::Kind::kCollision && e.agent_id >= 1 && e.other_id == kWallId)
        ++run.human_wall_contacts;
    for (const BehaviourStatus& b : sim.behaviourStatus()) {
      run.waited = run.waited || b.mode == "wait";
      run.squeezed = run.squeezed || b.mode == "squeeze";
    }
  }
  run.status = sim.status();
  run.summary = sim.summary();
  run.end_t_s = sim.time_s();
  run.last = agents;
  return run;
}

Velocity2 still(double, const AgentState&) { return {0.0, 0.0, 0.0}; }

WorldSpec world(const Pose2& robot_start, const HumanSpec& human, double time_limit_s = 60.0) {
  WorldSpec w;
  w.seed = 3;
  w.settings.time_limit_s = time_limit_s;
  w.robot.start = robot_start;
  w.robot.goal = robot_start;  // it stays where it is: its goal is reached at once
  w.robot.radius_m = kRobotRadius_m;
  w.humans.push_back(human);
  return w;
}

// ---- who touched whom

TEST(ContactFault, RobotDrivingIntoAStandingHumanIsAtFault) {
  // The human stands at its goal (x 6); the robot drives +x at 0.6 m/s into it.
  HumanSpec h = walker(BehaviourType::kOblivious, 1.0, 1.0, 6.0, 6.0);
  WorldSpec w = world({0.0, 1.0, 0.0}, h);
  w.robot.goal = {20.0, 1.0, 0.0};
  const Outcome run = simulate(w, nullptr, [](double, const AgentState&) {
    return Velocity2{0.6, 0.0, 0.0};
  });
  EXPECT_EQ(run.status, SimStatus::kCollision);
  ASSERT_TRUE(run.summary.first_contact.has_value());
  const RobotHumanContact& c = *run.summary.first_contact;
  EXPECT_EQ(c.human_id, 1);
  EXPECT_TRUE(c.robot_at_fault);
  EXPECT_NEAR(c.robot_speed_towards_m_s, 0.6, 1e-9);
  // Contact when the centre distance falls below 0.77 m: the robot's front at x 6 - 0.77.
  // + the ramp from rest at 0.8 m/s^2: 0.75 s, half of it lost.
  EXPECT_NEAR(c.t_s, (6.0 - 0.77) / 0.6 + 0.375, 0.06);
  EXPECT_LT(run.summary.min_robot_human_clearance_m, 0.0);
  EXPECT_DOUBLE_EQ(run.summary.min_robot_human_clearance_t_s, c.t_s);
}

TEST(ContactFault, HumanWalkingIntoARobotAtRestIsNotTheRobots) {
  const Outcome run =
      simulate(world({8.0, 1.0, 0.0}, walker(BehaviourType::kOblivious, 1.0, 1.0)), nullptr, still);
  EXPECT_EQ(run.status, SimStatus::kCollision);
  ASSERT_TRUE(run.summary.first_contact.has_value());
  EXPECT_FALSE(run.summary.first_contact->robot_at_fault);
  EXPECT_DOUBLE_EQ(run.summary.first_contact->robot_speed_towards_m_s, 0.0);
  EXPECT_NEAR(run.summary.first_contact->t_s, (8.0 - 0.77) / 1.0 + 0.33, 0.1);
}

TEST(ContactFault, RobotBackingAwayAndCaughtIsNotAtFault) {
  // The robot faces the human (theta pi) and backs away from it (+x) at 0.2 m/s; the human
  // walks +x at 1 m/s and catches it.
  const Outcome run = simulate(world({5.0, 1.0, M_PI}, walker(BehaviourType::kOblivious, 1.0, 1.0)),
                               nullptr, [](double, const AgentState&) {
                                 return Velocity2{-0.2, 0.0, 0.0};
                               });
  EXPECT_EQ(run.status, SimStatus::kCollision);
  ASSERT_TRUE(run.summary.first_contact.has_value());
  EXPECT_FALSE(run.summary.first_contact->robot_at_fault);
  EXPECT_NEAR(run.summary.first_contact->robot_speed_towards_m_s, -0.2, 1e-9);
}

TEST(ContactFault, TheThresholdIsTheSetting) {
  // The same slow approach (0.1 m/s into a standing human) with the threshold above and below.
  for (const double threshold_m_s : {0.05, 0.2}) {
    SCOPED_TRACE(threshold_m_s);
    HumanSpec h = walker(BehaviourType::kOblivious, 1.0, 1.0, 1.5, 1.5);
    WorldSpec w = world({0.0, 1.0, 0.0}, h);
    w.robot.goal = {20.0, 1.0, 0.0};
    w.settings.contact_fault_speed_m_s = threshold_m_s;
    const Outcome run = simulate(w, nullptr, [](double, const AgentState&) {
      return Velocity2{0.1, 0.0, 0.0};
    });
    ASSERT_TRUE(run.summary.first_contact.has_value());
    EXPECT_EQ(run.summary.first_contact->robot_at_fault, threshold_m_s < 0.1);
  }
}

TEST(ContactFault, NoContactLeavesItEmptyAndTimesTheMinimumClearance) {
  // The human walks past a robot at rest 1.5 m off its line: closest when abreast.
  const Outcome run =
      simulate(world({8.0, 2.5, 0.0}, walker(BehaviourType::kOblivious, 1.0, 1.0)), nullptr, still);
  EXPECT_FALSE(run.summary.first_contact.has_value());
  EXPECT_NEAR(run.summary.min_robot_human_clearance_m, 1.5 - 0.77, 0.01);
  // Abreast at x 8: 8 m at 1 m/s after the 1/1.5 s ramp (half of it lost: + 1/3 s).
  EXPECT_NEAR(run.summary.min_robot_human_clearance_t_s, 8.0 + 1.0 / 3.0, 0.1);
}

// ---- people near a robot at rest

struct AtWall {
  BehaviourType type;
  double robot_wall_gap_m;  ///< between the robot's body and the wall it stands at
};

void PrintTo(const AtWall& a, std::ostream* os) {
  *os << toString(a.type) << ", robot " << a.robot_wall_gap_m << " m off the wall";
}

class SqueezePast : public ::testing::TestWithParam<AtWall> {};

TEST_P(SqueezePast, ARobotAtTheWallOfA18mCorridor) {
  // 1.8 m corridor; the robot stands at its lower wall; the human walks the centre line. Between
  // the robot's body and the upper wall: 1.8 - 2 x 0.47 - gap = 0.86 - gap >= 0.7 = its body and
  // two squeeze margins, so it fits.
  const AtWall p = GetParam();
  test::CorridorMap map(0.0, 1.8);
  const Outcome run = simulate(
      world({10.0, kRobotRadius_m + p.robot_wall_gap_m, 0.0}, walker(p.type, 0.9)), &map, still);
  EXPECT_EQ(run.status, SimStatus::kGoalsReached);
  EXPECT_FALSE(run.summary.first_contact.has_value());
  // Never closer than half the squeeze margin (the rest absorbs the discrete step).
  EXPECT_GT(run.summary.min_robot_human_clearance_m, 0.5 * BodyCheckParams{}.squeeze_margin_m);
  EXPECT_EQ(run.human_wall_contacts, 0);
  EXPECT_FALSE(run.waited);
  std::printf("%s, robot %.2f m off the wall: min clearance %.3f m at t %.2f s, end %.2f s\n",
              toString(p.type), p.robot_wall_gap_m, run.summary.min_robot_human_clearance_m,
              run.summary.min_robot_human_clearance_t_s, run.end_t_s);
}

INSTANTIATE_TEST_SUITE_P(
    Models, SqueezePast,
    ::testing::Values(
        AtWall{BehaviourType::kMinimal, 0.05}, AtWall{BehaviourType::kMinimal, 0.13},
        AtWall{BehaviourType::kFacilitating, 0.05}, AtWall{BehaviourType::kFacilitating, 0.13},
        AtWall{BehaviourType::kSocialForce, 0.05}, AtWall{BehaviourType::kSocialForce, 0.13},
        AtWall{BehaviourType::kLateFacilitating, 0.05}, AtWall{BehaviourType::kResponsive, 0.05}),
    [](const ::testing::TestParamInfo<AtWall>& i) {
      return std::string(toString(i.param.type)) + "_gap" +
             std::to_string(static_cast<int>(std::lround(i.param.robot_wall_gap_m * 100)));
    });

TEST(BodyCheck, WithoutItTheModelsWalkIntoTheRobot) {
  // The reason for the check: the same encounter with an oblivious human is a contact, the
  // human's fault.
  test::CorridorMap map(0.0, 1.8);
  const Outcome run =
      simulate(world({10.0, kRobotRadius_m + 0.05, 0.0}, walker(BehaviourType::kOblivious, 0.9)),
               &map, still);
  EXPECT_EQ(run.status, SimStatus::kCollision);
  ASSERT_TRUE(run.summary.first_contact.has_value());
  EXPECT_FALSE(run.summary.first_contact->robot_at_fault);
}

TEST(BodyCheck, TooNarrowToPassItStopsAndWaitsThenStandstill) {
  // 1.5 m: beside the robot at the wall 0.48 m are left, less than the human's 0.6 m body.
  for (const BehaviourType type :
       {BehaviourType::kMinimal, BehaviourType::kFacilitating, BehaviourType::kSocialForce}) {
    SCOPED_TRACE(toString(type));
    test::CorridorMap map(0.0, 1.5);
    const Outcome run =
        simulate(world({10.0, kRobotRadius_m + 0.05, 0.0}, walker(type, 0.75)), &map, still);
    EXPECT_EQ(run.status, SimStatus::kStandstill);
    EXPECT_FALSE(run.summary.first_contact.has_value());
    EXPECT_TRUE(run.waited);
    // It stopped about wait_gap_m short of the robot.
    EXPECT_GT(run.summary.min_robot_human_clearance_m, 0.15);
    EXPECT_LT(run.summary.min_robot_human_clearance_m, 0.45);
    // Standing since it stopped (~9 s in), ended 15 s later, well before the time limit.
    EXPECT_GT(run.end_t_s, 15.0);
    EXPECT_LT(run.end_t_s, 35.0);
  }
}

TEST(BodyCheck, WaitingHumanGoesOnOnceTheRobotMakesRoom) {
  // 1.8 m corridor, a holonomic robot at rest in its middle (0.43 m each side: no room). At
  // t 15 s it moves to the wall (-y); the waiting human then squeezes past.
  test::CorridorMap map(0.0, 1.8);
  WorldSpec w = world({10.0, 0.9, 0.0}, walker(BehaviourType::kMinimal, 0.9));
  w.robot.kinematics = Kinematics::kHolonomic;
  const Outcome run = simulate(w, &map, [](double t_s, const AgentState& robot) {
    const bool dock = t_s >= 15.0 && robot.pose.y_m > kRobotRadius_m + 0.06;
    return Velocity2{0.0, dock ? -0.3 : 0.0, 0.0};
  });
  EXPECT_TRUE(run.waited);
  EXPECT_TRUE(run.squeezed);
  EXPECT_EQ(run.status, SimStatus::kGoalsReached);
  EXPECT_FALSE(run.summary.first_contact.has_value());
  EXPECT_GT(run.end_t_s, 15.0 + 10.0 / 1.2);  // it waited: not before the robot moved
}

TEST(BodyCheck, AHumanFollowsARetreatingRobotWithoutCatchingIt) {
  // The robot backs away (+x) at 0.2 m/s in the middle of a 1.5 m corridor: no room to pass.
  test::CorridorMap map(0.0, 1.5);
  const Outcome run =
      simulate(world({5.0, 0.75, M_PI}, walker(BehaviourType::kMinimal, 0.75), 40.0), &map,
               [](double, const AgentState&) {
                 return Velocity2{-0.2, 0.0, 0.0};
               });
  EXPECT_EQ(run.status, SimStatus::kTimeLimit);
  EXPECT_FALSE(run.summary.first_contact.has_value());
  EXPECT_GT(run.summary.min_robot_human_clearance_m, 0.1);
}

TEST(BodyCheck, AnOncomingRobotIsLeftToTheModel) {
  // A robot driving at the human faster than rest_speed_m_s: the check does nothing, so the
  // human's velocity is exactly the model's.
  BehaviourContext ctx;
  AgentState self, robot;
  self.pose = {0.0, 0.0, 0.0};
  self.velocity = {1.0, 0.0, 0.0};
  robot.kind = AgentKind::kRobot;
  robot.radius_m = kRobotRadius_m;
  robot.pose = {1.5, 0.0, M_PI};
  robot.velocity = {-0.5, 0.0, 0.0};
  const Path2 path{{0.0, 0.0}, {10.0, 0.0}};
  ctx.self = &self;
  ctx.robot = &robot;
  ctx.reference_path = &path;
  BodyCheck check{BodyCheckParams{}};
  const Velocity2 want{1.0, 0.0, 0.0};
  const Velocity2 out = check.apply(ctx, want, 0.0);
  EXPECT_EQ(check.mode(), BodyCheckMode::kOff);
  EXPECT_EQ(out.vx_m_s, 1.0);
  EXPECT_EQ(out.vy_m_s, 0.0);
  // The same robot at rest: in the way, no walls: it steers round it (its right, -y).
  robot.velocity = {0.0, 0.0, 0.0};
  const Velocity2 round = check.apply(ctx, want, 0.0);
  EXPECT_EQ(check.mode(), BodyCheckMode::kSqueeze);
  EXPECT_LT(round.vy_m_s, -0.1);
  EXPECT_DOUBLE_EQ(check.side(), -1.0);
}

TEST(RoomBesideRobot, RaysFromTheRobotCentre) {
  test::CorridorMap map(0.0, 1.8);
  AgentState robot;
  robot.radius_m = 0.47;
  robot.pose = {3.0, 0.52, 0.0};
  const RoomBesideRobot room = roomBesideRobot(&map, robot, {0.0, 1.0});
  EXPECT_NEAR(room.left_m, 1.8 - 0.52 - 0.47, 1e-12);
  EXPECT_NEAR(room.right_m, 0.05, 1e-12);
  EXPECT_TRUE(std::isinf(roomBesideRobot(nullptr, robot, {0.0, 1.0}).left_m));
}

// ---- standstill

TEST(Standstill, SettingZeroNeverEndsTheRun) {
  test::CorridorMap map(0.0, 1.5);
  WorldSpec w =
      world({10.0, kRobotRadius_m + 0.05, 0.0}, walker(BehaviourType::kMinimal, 0.75), 40.0);
  w.settings.standstill_time_s = 0.0;
  const Outcome run = simulate(w, &map, still);
  EXPECT_EQ(run.status, SimStatus::kTimeLimit);
  EXPECT_FALSE(run.summary.first_contact.has_value());
}

TEST(Standstill, AgentsAtTheirGoalsAreNotAStandstill) {
  // Everybody at its goal from the start, end_on_goals off: only the time limit ends it.
  WorldSpec w = world({0.0, 0.0, 0.0}, walker(BehaviourType::kMinimal, 5.0, 1.0, 3.0, 3.0), 20.0);
  w.settings.end_on_goals = false;
  const Outcome run = simulate(w, nullptr, still);
  EXPECT_EQ(run.status, SimStatus::kTimeLimit);
}

TEST(Standstill, EndsExactlyTheStatedTimeAfterTheLastMove) {
  // A human standing still away from its goal (speed 0), the robot at its goal.
  WorldSpec w = world({0.0, 0.0, 0.0}, walker(BehaviourType::kMinimal, 5.0, 0.0), 60.0);
  w.settings.standstill_time_s = 7.5;
  const Outcome run = simulate(w, nullptr, still);
  EXPECT_EQ(run.status, SimStatus::kStandstill);
  EXPECT_NEAR(run.end_t_s, 7.5, 1e-9);
  EXPECT_STREQ(toString(SimStatus::kStandstill), "STANDSTILL");
}

}  // namespace
}  // namespace coopnav::sim
