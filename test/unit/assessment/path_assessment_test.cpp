// Human path assessment of paper §II-C: CA sign, CM, IsContributing and the fixed-rate recorder.
#include "coopnav/assessment/path_assessment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numeric>

namespace coopnav::assessment {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(DiscountedMean, ConstantCaGivesThatConstant) {
  EXPECT_NEAR(*discountedMean(std::vector<double>(57, 0.37), 0.98), 0.37, 1e-12);
}

TEST(DiscountedMean, MatchesTheGeometricSeriesClosedForm) {
  // M samples of a followed by K samples of b:
  // CM = (a γ^K (1 − γ^M) + b (1 − γ^K)) / (1 − γ^(M+K)).
  const double a = 0.1, b = 0.9, g = 0.98;
  const int M = 40, K = 25;
  std::vector<double> ca(M, a);
  ca.insert(ca.end(), K, b);
  const double expected = (a * std::pow(g, K) * (1 - std::pow(g, M)) + b * (1 - std::pow(g, K))) /
                          (1 - std::pow(g, M + K));
  EXPECT_NEAR(*discountedMean(ca, g), expected, 1e-12);
  // Two samples by hand: (γ a + b) / (γ + 1).
  EXPECT_NEAR(*discountedMean({a, b}, g), (g * a + b) / (g + 1), 1e-15);
}

TEST(DiscountedMean, GammaToOneIsThePlainMean) {
  std::vector<double> ca;
  for (int i = 0; i < 200; ++i) ca.push_back(std::sin(0.1 * i) + 0.01 * i);
  const double mean = std::accumulate(ca.begin(), ca.end(), 0.0) / ca.size();
  EXPECT_NEAR(*discountedMean(ca, 1.0), mean, 1e-12);
  EXPECT_NEAR(*discountedMean(ca, 1.0 - 1e-9), mean, 1e-6);
  EXPECT_NEAR(*discountedMean(ca, 1.0 + 1e-9), mean, 1e-6);
}

TEST(DiscountedMean, IsSafeForLargeNAndAnyGamma) {
  std::vector<double> ca(1000000, 0.2);
  ca.back() = 1.2;
  // γ < 1: the newest sample weighs 1 / Σγ^k ≈ 1 − γ.
  EXPECT_NEAR(*discountedMean(ca, 0.98), 0.2 + 1.0 * 0.02, 1e-9);
  // γ > 1 (early samples weigh more): finite, and the newest weighs ≈ γ^-(N−1) ≈ 0.
  const auto cm = discountedMean(ca, 1.02);
  ASSERT_TRUE(cm.has_value());
  EXPECT_TRUE(std::isfinite(*cm));
  EXPECT_NEAR(*cm, 0.2, 1e-9);
  EXPECT_FALSE(discountedMean({}, 0.98).has_value());
  EXPECT_FALSE(discountedMean({1.0}, 0.0).has_value());
  EXPECT_FALSE(discountedMean({1.0}, kNaN).has_value());
}

TEST(IsContributing, StrictlyAboveTau) {
  EXPECT_EQ(isContributing(0.41, 0.4), Tristate::kTrue);
  EXPECT_EQ(isContributing(0.4, 0.4), Tristate::kFalse);
  EXPECT_EQ(isContributing(0.39, 0.4), Tristate::kFalse);
  EXPECT_EQ(isContributing(std::nullopt, 0.4), Tristate::kUnknown);
  EXPECT_EQ(isContributing(kNaN, 0.4), Tristate::kUnknown);
}

// Reference path along +x: its left is +y.
const Path2 kPath{{0, 0}, {20, 0}};

TEST(ContributionAt, PositiveAwayFromTheRobotOnBothSides) {
  // Robot on the left (+y): a human on the right is contributing, on the left is not.
  EXPECT_NEAR(contributionAt(kPath, {3, -0.5}, {5, 1}, Side::kUndefined, 0.1)->ca_m, 0.5, 1e-12);
  EXPECT_NEAR(contributionAt(kPath, {3, 0.5}, {5, 1}, Side::kUndefined, 0.1)->ca_m, -0.5, 1e-12);
  // Robot on the right (−y): mirrored.
  EXPECT_NEAR(contributionAt(kPath, {3, -0.5}, {5, -1}, Side::kUndefined, 0.1)->ca_m, -0.5, 1e-12);
  EXPECT_NEAR(contributionAt(kPath, {3, 0.5}, {5, -1}, Side::kUndefined, 0.1)->ca_m, 0.5, 1e-12);
  EXPECT_EQ(contributionAt(kPath, {3, 0.5}, {5, -1}, Side::kUndefined, 0.1)->robot_side,
            Side::kRight);
}

TEST(ContributionAt, RobotOnThePathKeepsItsLastSideOrUsesTheHumanRelativeSide) {
  // Within the deadband: the remembered side wins.
  auto c = contributionAt(kPath, {3, 0.5}, {5, 0.05}, Side::kRight, 0.1);
  EXPECT_EQ(c->robot_side, Side::kRight);
  EXPECT_NEAR(c->ca_m, 0.5, 1e-12);
  // No memory: the robot is left of a human who stepped right -> contributing.
  c = contributionAt(kPath, {3, -0.5}, {5, 0.0}, Side::kUndefined, 0.1);
  EXPECT_EQ(c->robot_side, Side::kLeft);
  EXPECT_FALSE(c->side_from_path);
  EXPECT_NEAR(c->ca_m, 0.5, 1e-12);
  // Both on the path: no side, no evidence.
  c = contributionAt(kPath, {3, 0.02}, {5, 0.0}, Side::kUndefined, 0.1);
  EXPECT_EQ(c->robot_side, Side::kUndefined);
  EXPECT_EQ(c->ca_m, 0.0);
  EXPECT_FALSE(contributionAt(Path2{}, {3, 0}, {5, 1}, Side::kUndefined, 0.1).has_value());
  EXPECT_FALSE(contributionAt(kPath, {kNaN, 0}, {5, 1}, Side::kUndefined, 0.1).has_value());
}

// Scene for the recorder: human h(t) = (t, −0.1 t) drifting right, robot r(t) = (10 − t, 1) on
// the left of the path, so CA(t) = 0.1 t exactly (linear motion: interpolation is exact).
TEST(ContributionAt, HumanSideRuleSignsAwayFromTheRobotAsSeenFromTheHuman) {
  // Open space: the robot is already right of the human's path (y = -0.5) and the human has
  // stepped further right (y = -0.8), away from it.
  const auto path_side = contributionAt(kPath, {3, -0.8}, {5, -0.5}, Side::kUndefined, 0.1);
  const auto human_side =
      contributionAt(kPath, {3, -0.8}, {5, -0.5}, Side::kUndefined, 0.1, SideRule::kHumanSide);
  // The robot is right of the path: under the paper's reading the human's right step is towards
  // it; seen from the human the robot is on its LEFT, so the same step is away from it.
  EXPECT_NEAR(path_side->ca_m, -0.8, 1e-12);
  EXPECT_NEAR(human_side->ca_m, 0.8, 1e-12);
  EXPECT_EQ(human_side->robot_side, Side::kLeft);
  // Level with the human (within the deadband): the last side is kept, or none.
  const auto level =
      contributionAt(kPath, {3, -0.8}, {5, -0.75}, Side::kLeft, 0.1, SideRule::kHumanSide);
  EXPECT_NEAR(level->ca_m, 0.8, 1e-12);
  EXPECT_FALSE(level->side_from_path);
  const auto none =
      contributionAt(kPath, {3, -0.8}, {5, -0.75}, Side::kUndefined, 0.1, SideRule::kHumanSide);
  EXPECT_EQ(none->ca_m, 0.0);
}

Eigen::Vector2d humanAt(double t) { return {t, -0.1 * t}; }
Eigen::Vector2d robotAt(double t) { return {10 - t, 1}; }

PathRecorder recordAtRate(int messages_per_s, double until_s) {
  PathRecorder rec;
  EXPECT_TRUE(rec.start(0.0, kPath));
  const int n = static_cast<int>(std::round(until_s * messages_per_s));
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / messages_per_s;
    EXPECT_TRUE(rec.observe(t, humanAt(t), robotAt(t)));
  }
  return rec;
}

TEST(PathRecorder, SamplesAtAFixedRateWhateverTheMessageRate) {
  for (int rate : {2, 7, 10, 50}) {
    const PathRecorder rec = recordAtRate(rate, 3.0);
    const auto& s = rec.interactionSamples();
    ASSERT_EQ(s.size(), 31u) << rate << " Hz";  // 0.0, 0.1, ..., 3.0
    for (std::size_t k = 0; k < s.size(); ++k) {
      EXPECT_NEAR(s[k].t_s, 0.1 * k, 1e-9);
      EXPECT_NEAR(s[k].ca_m, 0.01 * k, 1e-9) << rate << " Hz, k " << k;
    }
    EXPECT_NEAR(*rec.snapshot().cm_window_m, *recordAtRate(10, 3.0).snapshot().cm_window_m, 1e-12);
  }
}

TEST(PathRecorder, ResetStartsANewDecisionWindowButNotANewInteraction) {
  PathRecorder rec;
  ASSERT_TRUE(rec.start(0.0, kPath));
  // CA 0.2 up to 1.0 s, then 0.6 (human steps further right).
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * i;
    const double y = t <= 1.0 + 1e-9 ? -0.2 : -0.6;
    rec.observe(t, {t, y}, {10 - t, 1});
    if (i == 10) rec.reset(t);
  }
  PathAssessmentSnapshot snap = rec.snapshot();
  EXPECT_EQ(snap.state, RecorderState::kRecording);
  EXPECT_EQ(snap.window_samples, 10u);  // 1.1 .. 2.0
  EXPECT_NEAR(*snap.cm_window_m, 0.6, 1e-12);
  EXPECT_EQ(snap.is_contributing_window, Tristate::kTrue);
  EXPECT_EQ(snap.interaction_samples, 21u);
  const double g = 0.98;
  const double whole =
      (0.2 * std::pow(g, 10) * (1 - std::pow(g, 11)) + 0.6 * (1 - std::pow(g, 10))) /
      (1 - std::pow(g, 21));
  EXPECT_NEAR(*snap.cm_interaction_m, whole, 1e-12);

  // Stop at 2.0 s: later observations add nothing, data stay readable.
  rec.stop(2.0);
  rec.observe(2.5, {2.5, -0.6}, {7.5, 1});
  snap = rec.snapshot();
  EXPECT_EQ(snap.state, RecorderState::kStopped);
  EXPECT_EQ(snap.interaction_samples, 21u);

  // A new start clears both windows.
  ASSERT_TRUE(rec.start(3.0, kPath));
  EXPECT_EQ(rec.snapshot().interaction_samples, 0u);
  EXPECT_FALSE(rec.snapshot().cm_window_m.has_value());
  EXPECT_EQ(rec.snapshot().is_contributing_window, Tristate::kUnknown);
}

TEST(PathRecorder, CommandsStampedInThePastTakeEffectFromTheirTime) {
  PathRecorder rec;
  for (int i = 0; i <= 10; ++i) rec.observe(0.1 * i, humanAt(0.1 * i), robotAt(0.1 * i));
  EXPECT_EQ(rec.state(), RecorderState::kIdle);
  ASSERT_TRUE(rec.start(0.5, kPath));  // the control message arrives after the data
  const auto& s = rec.interactionSamples();
  ASSERT_EQ(s.size(), 6u);  // 0.5 .. 1.0
  EXPECT_NEAR(s.front().ca_m, 0.05, 1e-9);
  rec.stop(0.75);  // drops 0.8 .. 1.0
  EXPECT_EQ(rec.interactionSamples().size(), 3u);
}

TEST(PathRecorder, RejectsBadInput) {
  PathRecorder rec;
  EXPECT_FALSE(rec.start(0.0, Path2{}));
  EXPECT_FALSE(rec.start(0.0, Path2{{0, 0}, {kNaN, 1}}));
  EXPECT_EQ(rec.state(), RecorderState::kIdle);
  ASSERT_TRUE(rec.start(0.0, kPath));
  EXPECT_TRUE(rec.observe(0.0, {0, 0}, {5, 1}));
  EXPECT_FALSE(rec.observe(0.0, {0, 0}, {5, 1}));  // not after the previous
  EXPECT_FALSE(rec.observe(-1.0, {0, 0}, {5, 1}));
  EXPECT_FALSE(rec.observe(0.1, {kNaN, 0}, {5, 1}));
  EXPECT_FALSE(rec.observe(kNaN, {0, 0}, {5, 1}));
  EXPECT_EQ(rec.interactionSamples().size(), 1u);
}

TEST(PathRecorder, AGapOrAClockJumpIsSkippedInOneStepNotInterpolatedOver) {
  PathRecorder rec;
  ASSERT_TRUE(rec.start(0.0, kPath));
  const Eigen::Vector2d human{5.0, -0.3}, robot{8.0, 0.5};
  for (int k = 0; k <= 10; ++k) ASSERT_TRUE(rec.observe(0.1 * k, human, robot));
  ASSERT_EQ(rec.interactionSamples().size(), 11u);
  // The tracker loses the human for 20 s (more than max_gap_s): no samples inside the gap.
  ASSERT_TRUE(rec.observe(21.0, human, robot));
  ASSERT_EQ(rec.interactionSamples().size(), 12u);
  EXPECT_NEAR(rec.interactionSamples().back().t_s, 21.0, 1e-9);
  // A clock jumping 32 years ahead costs one step, not 10^10 samples (a hostile input must not
  // hang the path assessor); observations of the old clock after it are ignored.
  ASSERT_TRUE(rec.observe(1e9, human, robot));
  EXPECT_LE(rec.interactionSamples().size(), 13u);  // 13 if 1e9 falls on the grid to the ulp
  EXPECT_FALSE(rec.observe(21.1, human, robot));
  EXPECT_TRUE(std::isfinite(*rec.snapshot().cm_window_m));
}

TEST(LateralRoom, IsDohPlusDhAndUnknownWhenEitherIs) {
  EXPECT_NEAR(*lateralRoom(0.3, 0.3), 0.6, 1e-15);
  EXPECT_NEAR(*lateralRoom(0.8, 0.0), 0.8, 1e-15);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(*lateralRoom(inf, 0.2), inf);  // nothing within range on that side
  EXPECT_FALSE(lateralRoom(std::nullopt, 0.2));
  EXPECT_FALSE(lateralRoom(0.2, std::nullopt));
  EXPECT_FALSE(lateralRoom(kNaN, 0.2));
  EXPECT_FALSE(lateralRoom(-0.1, 0.2));
  EXPECT_FALSE(lateralRoom(0.2, inf));
}

TEST(RoomTau, KeepsThePapersTauWhereThereIsRoomAndShrinksItWhereThereIsNot) {
  const double inf = std::numeric_limits<double>::infinity();
  // The paper's corridors: 6 m (unbounded for this purpose) and 2.25 m (room ~0.825 m).
  EXPECT_EQ(roomTau(0.4, inf, 0.5, 0.1), 0.4);
  EXPECT_EQ(roomTau(0.4, 0.825, 0.5, 0.1), 0.4);
  // A 1.8 m corridor, human in the middle: 0.6 m of room -> half of it.
  EXPECT_NEAR(roomTau(0.4, 0.6, 0.5, 0.1), 0.3, 1e-15);
  // No room at all: the floor, never below it.
  EXPECT_EQ(roomTau(0.4, 0.0, 0.5, 0.1), 0.1);
  // Unknown room: the paper's τ.
  EXPECT_EQ(roomTau(0.4, std::nullopt, 0.5, 0.1), 0.4);
  EXPECT_EQ(roomTau(0.4, kNaN, 0.5, 0.1), 0.4);
  // A floor above τ never raises it.
  EXPECT_EQ(roomTau(0.4, 0.0, 0.5, 0.7), 0.4);
}

TEST(AssessmentNames, RoundTripAndUnknownNames) {
  for (const TauMode m : {TauMode::kFixed, TauMode::kRoom})
    EXPECT_EQ(*tauModeFromString(toString(m)), m);
  for (const SideRule r : {SideRule::kPathSide, SideRule::kHumanSide})
    EXPECT_EQ(*sideRuleFromString(toString(r)), r);
  EXPECT_FALSE(tauModeFromString("Room"));
  EXPECT_FALSE(sideRuleFromString(""));
}

TEST(PathRecorder, RoomModeJudgesCmAgainstTheRoomGivenAtStart) {
  // CA 0.25 throughout: below the paper's τ, above half of a 0.4 m room.
  auto run = [](TauMode mode, std::optional<double> room_m) {
    PathAssessorConfig config;
    config.tau_mode = mode;
    PathRecorder rec(config);
    EXPECT_TRUE(rec.start(0.0, kPath, room_m));
    for (int i = 0; i <= 20; ++i) {
      const double t = 0.1 * i;
      rec.observe(t, {t, -0.25}, {10 - t, 1});
    }
    return rec.snapshot();
  };
  const PathAssessmentSnapshot fixed = run(TauMode::kFixed, 0.4);
  EXPECT_EQ(fixed.tau_m, 0.4);
  EXPECT_NEAR(fixed.tau_room_m, 0.2, 1e-15);  // reported in both modes
  EXPECT_EQ(fixed.is_contributing_window, Tristate::kFalse);
  EXPECT_EQ(fixed.is_contributing_interaction, Tristate::kFalse);

  const PathAssessmentSnapshot room = run(TauMode::kRoom, 0.4);
  EXPECT_NEAR(room.tau_m, 0.2, 1e-15);
  EXPECT_EQ(room.tau_fixed_m, 0.4);
  EXPECT_NEAR(*room.room_m, 0.4, 1e-15);
  EXPECT_EQ(room.is_contributing_window, Tristate::kTrue);
  EXPECT_EQ(room.is_contributing_interaction, Tristate::kTrue);

  // Without a room the room mode is the paper's.
  const PathAssessmentSnapshot unknown = run(TauMode::kRoom, std::nullopt);
  EXPECT_FALSE(unknown.room_m);
  EXPECT_EQ(unknown.tau_m, 0.4);
  EXPECT_EQ(unknown.is_contributing_window, Tristate::kFalse);
}

}  // namespace
}  // namespace coopnav::assessment
