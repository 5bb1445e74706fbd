// Head-on encounters in analytic corridors: a robot drives straight at constant speed (it never
// avoids) towards a human walking the corridor's centre line the other way. Measures each
// behaviour's lateral deviation from its path and how long before the crossing it starts.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "coopnav/sim/simulation.hpp"
#include "corridor_map.hpp"

namespace coopnav::sim {
namespace {

constexpr double kOnsetThreshold_m = 0.05;  ///< deviation that counts as "started avoiding"

struct HeadOn {
  double corridor_width_m{6.0};
  double robot_lane_m{0.0};  ///< robot's lateral offset from the centre line (+y)
  double robot_speed_m_s{0.6};
  double human_speed_m_s{1.0};
  BehaviourConfig behaviour;
  std::vector<Cue> cues;
  std::uint64_t seed{1};
  double speed_stddev_m_s{0.0};
  double velocity_noise_m_s{0.0};
  AvoidanceTiming timing{AvoidanceTiming::kTrigger};
};

struct Trace {
  std::vector<double> t_s, x_m, dev_m;  ///< human samples; dev: signed, +y > 0
  double crossing_t_s{-1.0};            ///< first time the human is not ahead of the robot
  SimStatus status{SimStatus::kRunning};
  double min_clearance_m{0.0};
  std::vector<AgentState> last;
  int human_wall_collisions{0};
  std::vector<CueOutcome> cues;
  std::optional<double> onset_s;  ///< the human's realistic onset (Simulation::onsets)

  double maxAbsDev() const {
    double m = 0.0;
    for (double d : dev_m) m = std::max(m, std::abs(d));
    return m;
  }
  double maxAbsDevBefore(double t) const {
    double m = 0.0;
    for (std::size_t i = 0; i < t_s.size(); ++i)
      if (t_s[i] < t) m = std::max(m, std::abs(dev_m[i]));
    return m;
  }
  /// Seconds between the first deviation above threshold and the crossing (< 0: never).
  double onsetLead() const {
    for (std::size_t i = 0; i < t_s.size(); ++i)
      if (std::abs(dev_m[i]) > kOnsetThreshold_m) return crossing_t_s - t_s[i];
    return -1.0;
  }
};

Trace runHeadOn(const HeadOn& h) {
  const double yc = h.corridor_width_m / 2.0;
  test::CorridorMap map(0.0, h.corridor_width_m);
  WorldSpec w;
  w.seed = h.seed;
  w.avoidance_timing = h.timing;
  w.settings.time_limit_s = 30.0;
  w.robot.start = {0.0, yc + h.robot_lane_m, 0.0};
  w.robot.goal = {24.0, yc + h.robot_lane_m, 0.0};
  HumanSpec hs;
  hs.id = 1;
  hs.start = {24.0, yc, M_PI};
  hs.goal = {0.0, yc, M_PI};
  hs.speed_m_s = h.human_speed_m_s;
  hs.speed_stddev_m_s = h.speed_stddev_m_s;
  hs.velocity_noise_m_s = h.velocity_noise_m_s;
  hs.behaviour = h.behaviour;
  w.humans.push_back(hs);
  Simulation sim(w, &map);
  for (const Cue& c : h.cues) sim.addCue(c);
  Trace tr;
  while (sim.status() == SimStatus::kRunning) {
    const StepResult r = sim.step({h.robot_speed_m_s, 0.0, 0.0});
    const AgentState& robot = r.agents[0];
    const AgentState& human = r.agents[1];
    tr.t_s.push_back(r.t_s);
    tr.x_m.push_back(human.pose.x_m);
    tr.dev_m.push_back(human.pose.y_m - yc);
    if (tr.crossing_t_s < 0.0 && human.pose.x_m <= robot.pose.x_m) tr.crossing_t_s = r.t_s;
    for (const SimEvent& e : r.events)
      if (e.kind == SimEvent::Kind::kCollision && e.agent_id == 1 && e.other_id == kWallId)
        ++tr.human_wall_collisions;
    tr.last = r.agents;
    tr.cues.insert(tr.cues.end(), r.cues.begin(), r.cues.end());
    if (tr.crossing_t_s > 0.0 && r.t_s > tr.crossing_t_s + 6.0) break;
  }
  tr.status = sim.status();
  tr.min_clearance_m = sim.summary().min_robot_human_clearance_m;
  tr.onset_s = sim.onsets().at(0);
  return tr;
}

BehaviourConfig config(BehaviourType t) {
  BehaviourConfig c;
  c.type = t;
  return c;
}

TEST(FacilitatingHuman, WideCorridorYieldsEarlyAndFar) {
  HeadOn h;
  h.behaviour = config(BehaviourType::kFacilitating);
  const Trace tr = runHeadOn(h);
  ASSERT_GT(tr.crossing_t_s, 0.0);
  EXPECT_GE(tr.maxAbsDev(), 0.5);
  EXPECT_NEAR(tr.maxAbsDev(), 0.9, 0.1);  // paper Table I: CM 0.94 m in the open corridor
  EXPECT_GE(tr.onsetLead(), 3.0);
  EXPECT_GT(tr.min_clearance_m, 0.0);
  EXPECT_NE(tr.status, SimStatus::kCollision);
  // Dead-on robot: the human keeps to its right (+y when walking towards -x).
  EXPECT_GT(tr.maxAbsDevBefore(tr.crossing_t_s), 0.5);
  EXPECT_GT(tr.dev_m[static_cast<std::size_t>(tr.crossing_t_s / 0.1) - 1], 0.5);
}

TEST(FacilitatingHuman, NarrowCorridorYieldIsLimitedByWalls) {
  HeadOn h;
  h.corridor_width_m = 2.25;
  h.robot_lane_m = -0.3;  // in 2.25 m the robot must take its share too (on the human's left)
  h.behaviour = config(BehaviourType::kFacilitating);
  const Trace tr = runHeadOn(h);
  // 2.25 / 2 - 0.3 (radius) - 0.3 (wall margin) = 0.525 m: paper Table I's CM 0.49 m (narrow).
  EXPECT_GE(tr.maxAbsDev(), 0.45);
  EXPECT_LE(tr.maxAbsDev(), 0.55);
  EXPECT_GE(tr.onsetLead(), 3.0);
  EXPECT_EQ(tr.human_wall_collisions, 0);
}

TEST(FacilitatingHuman, YieldsAwayFromAnOffsetRobotAndReturnsAfterPassing) {
  HeadOn h;
  h.robot_lane_m = 0.6;  // robot on the human's right (+y)
  h.behaviour = config(BehaviourType::kFacilitating);
  const Trace tr = runHeadOn(h);
  EXPECT_LT(*std::min_element(tr.dev_m.begin(), tr.dev_m.end()), -0.5);  // moved to -y
  EXPECT_LT(std::abs(tr.dev_m.back()), 0.1);  // back on its path 6 s after crossing
}

TEST(FacilitatingHuman, PlannerModeWithoutAdapterIsAClearError) {
  BehaviourConfig c = config(BehaviourType::kFacilitating);
  c.facilitating.planner = "band";
  EXPECT_THROW(makeBehaviour(c), std::invalid_argument);
}

TEST(FacilitatingHuman, PlannerAdapterIsUsedWhenItHasAPlan) {
  struct Fixed : HumanPlannerAdapter {
    std::optional<Velocity2> plan(const BehaviourContext&) override {
      return Velocity2{0.0, 0.7, 0.0};
    }
  };
  BehaviourConfig c = config(BehaviourType::kFacilitating);
  c.facilitating.planner = "band";
  auto b = makeBehaviour(c, [](const FacilitatingParams&) { return std::make_unique<Fixed>(); });
  AgentState self;
  Path2 path{{0, 0}, {10, 0}};
  BehaviourContext ctx;
  ctx.self = &self;
  ctx.goal = {10, 0, 0};
  ctx.reference_path = &path;
  EXPECT_EQ(b->desiredVelocity(ctx), (Velocity2{0.0, 0.7, 0.0}));
}

TEST(MinimalHuman, WideCorridorSidestepsLateAndLittle) {
  for (double width : {6.0, 2.25}) {
    SCOPED_TRACE(width);
    HeadOn h;
    h.corridor_width_m = width;
    h.robot_lane_m = 0.6;  // the robot took its share; the human completes the clearance
    h.behaviour = config(BehaviourType::kMinimal);
    const Trace tr = runHeadOn(h);
    EXPECT_LT(tr.maxAbsDev(), 0.4);
    EXPECT_GT(tr.maxAbsDev(), 0.1);  // it does avoid
    EXPECT_GT(tr.onsetLead(), 0.0);
    // Real head-on pedestrians (ETH / UCY datasets) start avoiding a median 1.2-1.6 s before
    // the closest approach.
    EXPECT_LT(tr.onsetLead(), 1.5);
    EXPECT_NE(tr.status, SimStatus::kCollision);
  }
}

TEST(ObliviousHuman, CollidesWithARobotThatDoesNotAvoid) {
  HeadOn h;
  h.behaviour = config(BehaviourType::kOblivious);
  const Trace tr = runHeadOn(h);
  EXPECT_EQ(tr.status, SimStatus::kCollision);
  EXPECT_LT(tr.maxAbsDev(), 1e-9);
}

// The head-on layout: 24 m apart, closing at up to 1.6 m/s; at 9.5 s the robot is about 9.6 m
// away, within the default hearing range (10 m), and they cross at about 15 s. The human walks
// -x: its left is -y.
constexpr double kHeard_s = 9.5;

BehaviourConfig responsive(double compliance = 1.0) {
  BehaviourConfig c = config(BehaviourType::kResponsive);
  c.responsive.compliance_request = compliance;
  c.responsive.compliance_statement = compliance;
  return c;
}

Cue cue(CueKind kind, Side side, double t_s, bool repeat = false, std::int32_t id = 1) {
  Cue c;
  c.human_id = id;
  c.kind = kind;
  c.side = side;
  c.repeat = repeat;
  c.t_s = t_s;
  return c;
}

double minDev(const Trace& tr) { return *std::min_element(tr.dev_m.begin(), tr.dev_m.end()); }
double maxDev(const Trace& tr) { return *std::max_element(tr.dev_m.begin(), tr.dev_m.end()); }

TEST(ResponsiveHuman, AskedToMoveGoesToTheAskedSideAfterItsReactionTime) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s));
  const Trace tr = runHeadOn(h);
  ASSERT_EQ(tr.cues.size(), 1u);
  const CueOutcome& o = tr.cues[0];
  EXPECT_TRUE(o.responds && o.heard && o.complies);
  EXPECT_NEAR(o.distance_m, 9.6, 0.3);
  // Reaction time: a log-normal draw around 1 s, cut at reaction_time_max_s.
  EXPECT_GT(o.act_s - kHeard_s, 0.2);
  EXPECT_LE(o.act_s - kHeard_s, h.behaviour.responsive.reaction_time_max_s);
  EXPECT_LT(tr.maxAbsDevBefore(o.act_s), 1e-6);
  EXPECT_LT(minDev(tr), -0.6);
  EXPECT_NE(tr.status, SimStatus::kCollision);
}

TEST(ResponsiveHuman, ToldTheRobotsSideKeepsToTheOtherByAModestAmount) {
  HeadOn h;
  h.robot_lane_m = -0.6;  // the robot passes on the human's left (-y)...
  h.behaviour = responsive();
  // ... and says so: "I will pass on your left" -> the human keeps to its right (+y).
  h.cues.push_back(cue(CueKind::kKeepSide, Side::kRight, kHeard_s));
  const Trace told = runHeadOn(h);
  EXPECT_NEAR(maxDev(told), h.behaviour.responsive.inform_offset_m, 0.05);
  h.cues = {cue(CueKind::kMoveToSide, Side::kRight, kHeard_s)};
  const Trace asked = runHeadOn(h);
  EXPECT_GT(maxDev(asked), maxDev(told) + 0.2);  // a request moves it further than a statement
}

TEST(ResponsiveHuman, WithoutASideKeepsAwayFromTheRobot) {
  HeadOn h;
  h.robot_lane_m = 0.6;  // robot on +y: away is -y
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kKeepSide, Side::kUndefined, kHeard_s));  // "... if needed."
  EXPECT_LT(minDev(runHeadOn(h)), -0.3);
}

TEST(ResponsiveHuman, EachRepeatMovesItFurther) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s));
  const double once = -minDev(runHeadOn(h));
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s + 1.5, /*repeat=*/true));
  const double more = -minDev(runHeadOn(h));
  EXPECT_NEAR(more - once, h.behaviour.responsive.repeat_increment_m, 0.05);
}

TEST(ResponsiveHuman, GoesOnWhenTheRobotSaysItWillWait) {
  HeadOn h;
  h.robot_lane_m = 1.5;  // clear of the human's line: no sidestep needed
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s));
  const Trace asked = runHeadOn(h);
  h.cues.push_back(cue(CueKind::kRobotMakesRoom, Side::kUndefined, kHeard_s + 0.1));
  const Trace waited = runHeadOn(h);
  EXPECT_LT(minDev(asked), -0.5);
  EXPECT_GT(minDev(waited), -0.25);  // it had barely begun to move aside, and walks on
}

TEST(ResponsiveHuman, DoesNotHearBeyondItsHearingRange) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, 3.0));  // 19 m away
  const Trace tr = runHeadOn(h);
  ASSERT_EQ(tr.cues.size(), 1u);
  EXPECT_FALSE(tr.cues[0].heard);
  h.cues.clear();
  EXPECT_EQ(tr.dev_m, runHeadOn(h).dev_m);  // as if nothing was said
}

TEST(ResponsiveHuman, ANonCompliantPersonHearsAndDoesNothing) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = responsive(/*compliance=*/0.0);
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s));
  const Trace tr = runHeadOn(h);
  ASSERT_EQ(tr.cues.size(), 1u);
  EXPECT_TRUE(tr.cues[0].heard);
  EXPECT_FALSE(tr.cues[0].complies);
  h.cues.clear();
  EXPECT_EQ(tr.dev_m, runHeadOn(h).dev_m);
}

// The draws follow their stated distributions over seeds, and what a person hears never changes
// the other draws of the run: a speaking and a muted run walk the same until the words act.
TEST(ResponsiveHuman, DrawsFollowTheModelAndLeaveTheWalkingNoiseAlone) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.velocity_noise_m_s = 0.05;
  h.behaviour = config(BehaviourType::kResponsive);  // default compliance
  std::vector<double> reaction_s;
  int complied = 0;
  constexpr int kSeeds = 200;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    h.seed = static_cast<std::uint64_t>(seed);
    h.cues = {cue(CueKind::kKeepSide, Side::kRight, kHeard_s)};
    const Trace spoken = runHeadOn(h);
    ASSERT_EQ(spoken.cues.size(), 1u);
    reaction_s.push_back(spoken.cues[0].act_s - kHeard_s);
    complied += spoken.cues[0].complies ? 1 : 0;
    if (seed <= 5) {
      h.cues.clear();
      const Trace muted = runHeadOn(h);
      const double acts_s = spoken.cues[0].act_s;
      for (std::size_t i = 0; i < muted.t_s.size() && muted.t_s[i] < acts_s; ++i)
        ASSERT_EQ(spoken.dev_m[i], muted.dev_m[i]) << "seed " << seed << " t " << muted.t_s[i];
    }
  }
  std::sort(reaction_s.begin(), reaction_s.end());
  const ResponsiveParams& p = h.behaviour.responsive;
  EXPECT_NEAR(reaction_s[kSeeds / 2], p.reaction_time_median_s, 0.1);
  // 5 % and 95 % quantiles of the log-normal: median ×/÷ exp(1.645 σ).
  EXPECT_NEAR(reaction_s[kSeeds / 20], p.reaction_time_median_s * std::exp(-1.645 * 0.3), 0.12);
  EXPECT_NEAR(reaction_s[kSeeds * 19 / 20], p.reaction_time_median_s * std::exp(1.645 * 0.3), 0.2);
  // Statements are followed with compliance_statement (binomial sd ≈ 0.035 for 200 draws).
  EXPECT_NEAR(static_cast<double>(complied) / kSeeds, p.compliance_statement, 0.1);
}

TEST(ResponsiveHuman, WithoutCueBehavesMinimally) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = config(BehaviourType::kResponsive);
  const Trace responsive = runHeadOn(h);
  h.behaviour = config(BehaviourType::kMinimal);
  const Trace minimal = runHeadOn(h);
  EXPECT_EQ(responsive.dev_m, minimal.dev_m);
}

TEST(ResponsiveHuman, CueForAnotherHumanIsIgnored) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = responsive();
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s, false, 7));
  const Trace tr = runHeadOn(h);
  EXPECT_TRUE(tr.cues.empty());
  EXPECT_LT(tr.maxAbsDev(), 0.4);
}

TEST(MinimalHuman, HearsNothing) {
  HeadOn h;
  h.robot_lane_m = 0.6;
  h.behaviour = config(BehaviourType::kMinimal);
  const Trace silent = runHeadOn(h);
  h.cues.push_back(cue(CueKind::kMoveToSide, Side::kLeft, kHeard_s));
  const Trace told = runHeadOn(h);
  ASSERT_EQ(told.cues.size(), 1u);
  EXPECT_FALSE(told.cues[0].responds);
  EXPECT_EQ(told.dev_m, silent.dev_m);
}

TEST(LateFacilitatingHuman, StartsYieldingAboutThreeSecondsBefore) {
  HeadOn h;
  h.robot_lane_m = 0.3;
  h.behaviour = config(BehaviourType::kLateFacilitating);
  const Trace tr = runHeadOn(h);
  EXPECT_GT(tr.onsetLead(), 1.8);
  EXPECT_LT(tr.onsetLead(), 3.0);
  EXPECT_GE(tr.maxAbsDev(), 0.4);
  EXPECT_NE(tr.status, SimStatus::kCollision);
}

// Realistic avoidance timing (AvoidanceTiming::kRealistic): an onset drawn per person from the
// real walkers' (RealisticOnsetParams) replaces the fixed triggers.
TEST(RealisticTiming, FacilitatingYieldsAtItsOnsetNotFiveSecondsBefore) {
  HeadOn h;
  h.robot_lane_m = 0.3;  // this robot never avoids: dead on, a yield begun late cannot clear it
  h.behaviour = config(BehaviourType::kFacilitating);
  EXPECT_GE(runHeadOn(h).onsetLead(), 3.0);  // the fixed trigger: t_ca < 5 s or within 7 m
  h.behaviour.onset_s = 2.0;
  const Trace tr = runHeadOn(h);
  // It starts when t_ca falls below 2 s; the first 5 cm of the shift take a few tenths.
  EXPECT_LE(tr.onsetLead(), 2.0);
  EXPECT_GE(tr.onsetLead(), 1.4);
  EXPECT_NE(tr.status, SimStatus::kCollision);
}

TEST(RealisticTiming, LateFacilitatingYieldsAtItsOnset) {
  HeadOn h;
  h.robot_lane_m = 0.3;
  h.behaviour = config(BehaviourType::kLateFacilitating);
  h.behaviour.onset_s = 2.5;
  const Trace late = runHeadOn(h);
  h.behaviour.onset_s = 1.0;
  const Trace later = runHeadOn(h);
  EXPECT_LE(late.onsetLead(), 2.5);
  EXPECT_GE(late.onsetLead(), 1.9);
  EXPECT_LT(later.onsetLead(), late.onsetLead() - 1.0);
}

TEST(RealisticTiming, ToldTheRobotsSideAResponsivePersonKeepsToTheOtherFromItsOnset) {
  HeadOn h;
  h.robot_lane_m = -0.6;  // the robot passes on the human's left (-y) and says so
  h.behaviour = responsive();
  h.behaviour.onset_s = 1.5;
  h.cues.push_back(cue(CueKind::kKeepSide, Side::kRight, kHeard_s));
  const Trace told = runHeadOn(h);
  ASSERT_EQ(told.cues.size(), 1u);
  ASSERT_TRUE(told.cues[0].complies);
  // Heard at ~9.6 m: under the trigger it would shift a second later; here only at its onset.
  EXPECT_LT(told.maxAbsDevBefore(told.crossing_t_s - 2.0), 0.05);
  EXPECT_LE(told.onsetLead(), 1.5);
  // Begun late, the shift to inform_offset_m (0.4 m) is not complete when the robot passes.
  EXPECT_GT(maxDev(told), 0.25);
  EXPECT_LE(maxDev(told), h.behaviour.responsive.inform_offset_m + 0.05);
  // A request is acted on after the reaction time, as under the trigger.
  h.cues = {cue(CueKind::kMoveToSide, Side::kRight, kHeard_s)};
  const Trace asked = runHeadOn(h);
  EXPECT_GT(asked.onsetLead(), 3.0);
}

TEST(RealisticTiming, OnsetDrawsFollowTheFittedLogNormal) {
  const RealisticOnsetParams p;
  Rng rng = Rng::forStream(46, 1);
  std::vector<double> d;
  for (int i = 0; i < 4000; ++i) d.push_back(drawOnset(p, rng));
  std::sort(d.begin(), d.end());
  EXPECT_NEAR(d[2000], p.median_s, 0.08);
  // Quartiles of the log-normal: median ×/÷ exp(0.674 σ) = 1.11, 2.64 s (the real walkers'
  // empirical quartiles, at 2.5 Hz: 1.2, 2.4 s).
  EXPECT_NEAR(d[1000], p.median_s * std::exp(-0.674 * p.log_sd), 0.08);
  EXPECT_NEAR(d[3000], p.median_s * std::exp(0.674 * p.log_sd), 0.15);
  EXPECT_LE(d.back(), p.max_s);
  EXPECT_GT(d.front(), 0.0);
}

TEST(RealisticTiming, EachPersonDrawsItsOwnOnsetAndNothingElseChanges) {
  HeadOn h;
  h.velocity_noise_m_s = 0.05;
  h.timing = AvoidanceTiming::kRealistic;
  h.behaviour = config(BehaviourType::kFacilitating);
  const Trace a = runHeadOn(h);
  ASSERT_TRUE(a.onset_s.has_value());
  EXPECT_EQ(runHeadOn(h).dev_m, a.dev_m);  // same seed, same person
  EXPECT_LE(a.onsetLead(), *a.onset_s + 0.1);
  h.seed = 2;
  const Trace b = runHeadOn(h);
  ASSERT_TRUE(b.onset_s.has_value());
  EXPECT_NE(*a.onset_s, *b.onset_s);
  // A minimal person has no onset to draw, and its walk (noise included) is the trigger run's.
  h.behaviour = config(BehaviourType::kMinimal);
  const Trace minimal = runHeadOn(h);
  EXPECT_FALSE(minimal.onset_s.has_value());
  h.timing = AvoidanceTiming::kTrigger;
  EXPECT_EQ(runHeadOn(h).dev_m, minimal.dev_m);
}

TEST(RealisticTiming, NamesParseBack) {
  for (const auto t : {AvoidanceTiming::kTrigger, AvoidanceTiming::kRealistic}) {
    AvoidanceTiming back = AvoidanceTiming::kTrigger;
    ASSERT_TRUE(parseAvoidanceTiming(toString(t), back));
    EXPECT_EQ(back, t);
  }
  AvoidanceTiming out = AvoidanceTiming::kTrigger;
  EXPECT_FALSE(parseAvoidanceTiming("fixed", out));
}

TEST(SocialForceHuman, AvoidsTheRobot) {
  HeadOn h;
  h.robot_lane_m = 0.4;  // 0.4 m < 0.77 m sum of radii: walking straight collides
  h.behaviour = config(BehaviourType::kOblivious);
  ASSERT_EQ(runHeadOn(h).status, SimStatus::kCollision);
  h.behaviour = config(BehaviourType::kSocialForce);
  const Trace tr = runHeadOn(h);
  EXPECT_GT(tr.maxAbsDev(), 0.1);
  EXPECT_GT(tr.min_clearance_m, 0.0);
  EXPECT_NE(tr.status, SimStatus::kCollision);
  EXPECT_EQ(tr.human_wall_collisions, 0);
}

TEST(SocialForceHuman, KeepsOffTheWallsInANarrowCorridor) {
  HeadOn h;
  h.corridor_width_m = 2.25;
  h.robot_lane_m = 0.4;
  h.behaviour = config(BehaviourType::kSocialForce);
  const Trace tr = runHeadOn(h);
  EXPECT_EQ(tr.human_wall_collisions, 0);
  EXPECT_GT(tr.maxAbsDev(), 0.1);
}

TEST(Determinism, SameSeedGivesBitEqualTrajectories) {
  for (BehaviourType t : {BehaviourType::kFacilitating, BehaviourType::kSocialForce}) {
    HeadOn h;
    h.behaviour = config(t);
    h.speed_stddev_m_s = 0.15;
    h.velocity_noise_m_s = 0.05;
    h.seed = 42;
    const Trace a = runHeadOn(h), b = runHeadOn(h);
    EXPECT_EQ(a.x_m, b.x_m);  // exact equality of doubles: bit-identical
    EXPECT_EQ(a.dev_m, b.dev_m);
    h.seed = 43;
    const Trace c = runHeadOn(h);
    EXPECT_NE(a.x_m, c.x_m);
  }
}

TEST(Determinism, NoNoiseMeansSeedDoesNotMatter) {
  HeadOn h;
  h.behaviour = config(BehaviourType::kMinimal);
  h.robot_lane_m = 0.6;
  const Trace a = runHeadOn(h);
  h.seed = 99;
  EXPECT_EQ(a.dev_m, runHeadOn(h).dev_m);
}

}  // namespace
}  // namespace coopnav::sim

#include "coopnav/geometry/geometry.hpp"
#include "coopnav/sim/band_human_adapter.hpp"

namespace coopnav::sim {
namespace {

// Smoke test of the planner-backed facilitating mode: the adapter builds a request for the human
// with the robot as the other agent and returns a finite world-frame velocity or nothing.
TEST(FacilitatingHuman, DualBandAdapterPlansForTheHuman) {
  auto map = std::make_shared<test::CorridorMap>(0.0, 6.0);
  WorldSpec w;
  w.robot.start = {0.0, 3.0, 0.0};
  w.robot.goal = {20.0, 3.0, 0.0};
  HumanSpec h;
  h.start = {12.0, 3.0, M_PI};
  h.goal = {0.5, 3.0, M_PI};
  h.behaviour.type = BehaviourType::kFacilitating;
  h.behaviour.facilitating.planner = "band";
  w.humans.push_back(h);
  Simulation sim(w, map.get(), dualBandAdapterFactory(BandPlannerConfig{}, map));
  const StepResult r = sim.step({0.5, 0.0, 0.0});
  const AgentState& human = r.agents[1];
  EXPECT_TRUE(std::isfinite(human.velocity.vx_m_s));
  EXPECT_TRUE(std::isfinite(human.velocity.vy_m_s));
  EXPECT_LE(std::hypot(human.velocity.vx_m_s, human.velocity.vy_m_s), 2.0);
  std::printf("band adapter: mode %s, v = (%.3f, %.3f)\n", sim.behaviourStatus()[0].mode.c_str(),
              human.velocity.vx_m_s, human.velocity.vy_m_s);
}

// A person stepping back slowly keeps facing the way they walked; one who walks back turns. At
// 0.05 m/s a stopping human's one-step creep backwards turned it round, and the dialogue's
// crossing test (robot behind the human along its heading) read that as the agents having
// crossed, 3.6 m apart.
TEST(HumanHeading, FollowsWalkingNotAShuffleBackwards) {
  struct Scripted : HumanPlannerAdapter {
    std::optional<Velocity2> plan(const BehaviourContext& ctx) override {
      if (ctx.t_s < 2.0) return Velocity2{-1.0, 0.0, 0.0};  // walking towards −x
      if (ctx.t_s < 4.0) return Velocity2{0.2, 0.05, 0.0};  // shuffling back
      return Velocity2{1.0, 0.0, 0.0};                      // walking back to +x
    }
  };
  test::CorridorMap map(0.0, 6.0);
  WorldSpec w;
  w.settings.time_limit_s = 10.0;
  w.robot.start = {0.5, 1.0, 0.0};
  w.robot.goal = {20.0, 1.0, 0.0};
  HumanSpec h;
  h.id = 1;
  h.start = {12.0, 3.0, M_PI};
  h.goal = {0.5, 3.0, M_PI};
  h.behaviour.type = BehaviourType::kFacilitating;
  h.behaviour.facilitating.planner = "band";
  w.humans.push_back(h);
  Simulation sim(w, &map, [](const FacilitatingParams&) { return std::make_unique<Scripted>(); });
  double heading_at_3_9_s = 0.0, heading_at_6_s = 0.0, speed_at_3_9_s = 0.0;
  while (sim.status() == SimStatus::kRunning) {
    const StepResult r = sim.step({0.0, 0.0, 0.0});
    const AgentState& human = r.agents[1];
    if (std::abs(r.t_s - 3.9) < 1e-6) {
      heading_at_3_9_s = human.pose.theta_rad;
      speed_at_3_9_s = std::hypot(human.velocity.vx_m_s, human.velocity.vy_m_s);
    }
    if (std::abs(r.t_s - 6.0) < 1e-6) {
      heading_at_6_s = human.pose.theta_rad;
      break;
    }
  }
  EXPECT_GT(speed_at_3_9_s, 0.15);  // it did move backwards, slowly
  // Still facing −x (within the few degrees the slowing walk turned it), not the shuffle's way.
  EXPECT_GT(std::abs(wrapAngle(heading_at_3_9_s)), 0.95 * M_PI);
  EXPECT_NEAR(wrapAngle(heading_at_6_s), 0.0, 1e-9);
}

}  // namespace
}  // namespace coopnav::sim
