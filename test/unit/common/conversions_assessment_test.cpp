// situation_t / path_assessment_t / path_assessor_control_t <-> lib types: round trips, the
// wire encodings of unknown (NaN, PRED_UNKNOWN), validation of garbage, and cmForGamma.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "wire/assessment.hpp"

namespace coopnav {
namespace {

using assessment::CrossingStatus;
constexpr double kInf = std::numeric_limits<double>::infinity();

SituationRecord okRecord() {
  SituationRecord r;
  r.utime = 1'500'000;
  r.step = 15;
  r.human_id = 3;
  r.crossing.status = CrossingStatus::kOk;
  r.crossing.i_star = 42;
  r.crossing.t_cross_s = 2.1;
  r.crossing.cp_h = {4.0, 1.5};
  r.crossing.cp_r = {4.0, 0.9};
  r.crossing.dir = Side::kRight;
  r.assessment.d_h_m = 0.45;
  r.assessment.d_oh_m = kInf;
  r.assessment.d_or_m = std::nullopt;
  r.assessment.d_hr_m = 0.6;
  r.assessment.human_needs_to_contribute = Tristate::kTrue;
  r.assessment.human_is_constrained = Tristate::kFalse;
  r.assessment.robot_is_constrained = Tristate::kUnknown;
  r.assessment.reason = "d_OR unknown (no distance answer)";
  r.room_plan = bands_t::ROOM_WIDER_PLACE;
  r.robot_mode = velocity_command_t::MODE_RETREATING;
  return r;
}

TEST(ConversionsAssessmentTest, SituationRoundTripKeepsEveryField) {
  const SituationRecord r = okRecord();
  const situation_t m = toLcm(r);
  EXPECT_EQ(m.crossing_status, situation_t::CROSSING_OK);
  EXPECT_EQ(m.dir, situation_t::DIR_RIGHT);
  EXPECT_TRUE(std::isnan(m.d_or_m));
  EXPECT_TRUE(std::isinf(m.d_oh_m));
  EXPECT_EQ(m.robot_is_constrained, situation_t::PRED_UNKNOWN);
  EXPECT_DOUBLE_EQ(m.tau_h_m, 0.3);
  const SituationRecord b = fromLcm(m);
  EXPECT_EQ(b.utime, r.utime);
  EXPECT_EQ(b.step, r.step);
  EXPECT_EQ(b.human_id, 3);
  EXPECT_EQ(b.crossing.status, CrossingStatus::kOk);
  EXPECT_EQ(b.crossing.i_star, 42);
  EXPECT_DOUBLE_EQ(*b.crossing.t_cross_s, 2.1);
  EXPECT_EQ(b.crossing.cp_h, r.crossing.cp_h);
  EXPECT_EQ(b.crossing.cp_r, r.crossing.cp_r);
  EXPECT_EQ(b.crossing.dir, Side::kRight);
  EXPECT_TRUE(b.has_reference);
  EXPECT_DOUBLE_EQ(*b.assessment.d_h_m, 0.45);
  EXPECT_TRUE(std::isinf(*b.assessment.d_oh_m));
  EXPECT_FALSE(b.assessment.d_or_m.has_value());
  EXPECT_EQ(b.assessment.human_needs_to_contribute, Tristate::kTrue);
  EXPECT_EQ(b.assessment.human_is_constrained, Tristate::kFalse);
  EXPECT_EQ(b.assessment.robot_is_constrained, Tristate::kUnknown);
  EXPECT_EQ(b.assessment.reason, r.assessment.reason);
  EXPECT_EQ(b.room_plan, bands_t::ROOM_WIDER_PLACE);
  EXPECT_EQ(b.robot_mode, velocity_command_t::MODE_RETREATING);
  const dialogue::SituationSnapshot s = situationSnapshotFromLcm(m);
  EXPECT_EQ(s.room_plan, dialogue::RoomPlan::kWiderPlace);
  EXPECT_TRUE(s.robot_retreating);
}

TEST(ConversionsAssessmentTest, OkCrossingWithoutReferenceIsNoReferenceOnTheWire) {
  SituationRecord r = okRecord();
  r.has_reference = false;
  r.assessment.d_h_m.reset();
  const situation_t m = toLcm(r);
  EXPECT_EQ(m.crossing_status, situation_t::CROSSING_NO_REFERENCE);
  EXPECT_FALSE(std::isnan(m.t_cross_s));  // the crossing itself is still known
  const SituationRecord b = fromLcm(m);
  EXPECT_FALSE(b.has_reference);
  EXPECT_EQ(b.crossing.status, CrossingStatus::kOk);
  EXPECT_DOUBLE_EQ(*situationSnapshotFromLcm(m).t_cross_s, 2.1);
}

TEST(ConversionsAssessmentTest, BadCrossingPublishesNaNAndUnknown) {
  SituationRecord r;
  r.crossing.status = CrossingStatus::kBadBands;
  r.crossing.reason = "human band: 1 pose";
  const situation_t m = toLcm(r);
  EXPECT_EQ(m.crossing_status, situation_t::CROSSING_BAD_BANDS);
  EXPECT_EQ(m.i_star, -1);
  EXPECT_TRUE(std::isnan(m.t_cross_s));
  EXPECT_TRUE(std::isnan(m.cp_h_x_m));
  EXPECT_TRUE(std::isnan(m.d_hr_m));
  EXPECT_EQ(m.dir, situation_t::DIR_UNDEFINED);
  EXPECT_EQ(m.human_needs_to_contribute, situation_t::PRED_UNKNOWN);
  const auto snap = situationSnapshotFromLcm(m);
  EXPECT_FALSE(snap.t_cross_s.has_value());
  EXPECT_EQ(snap.robot_is_constrained, Tristate::kUnknown);
}

TEST(ConversionsAssessmentTest, GarbageSituationsAreRejected) {
  situation_t m = toLcm(okRecord());
  auto bad = m;
  bad.crossing_status = 9;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.dir = 2;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.human_is_constrained = 5;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.cp_h_x_m = std::nan("");
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.t_cross_s = -1.0;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.d_h_m = -0.1;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.room_plan = bands_t::ROOM_NONE + 1;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.robot_mode = -1;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
}

PathAssessmentRecord pathRecord(std::vector<double> ca) {
  PathAssessmentRecord r;
  r.utime = 2'000'000;
  r.step = 20;
  r.human_id = 7;
  r.snapshot.state = assessment::RecorderState::kRecording;
  r.snapshot.window_samples = ca.size();
  r.snapshot.cm_window_m = assessment::discountedMean(ca, 0.98);
  r.snapshot.is_contributing_window = assessment::isContributing(r.snapshot.cm_window_m, 0.4);
  r.snapshot.interaction_samples = ca.size() + 2;
  r.snapshot.cm_interaction_m = 0.2;
  r.snapshot.is_contributing_interaction = Tristate::kFalse;
  r.snapshot.tau_mode = assessment::TauMode::kRoom;
  r.snapshot.room_m = 0.5;
  r.snapshot.tau_room_m = 0.25;
  r.snapshot.tau_m = 0.25;
  r.profile = "calibrated";
  r.side_rule = assessment::SideRule::kHumanSide;
  r.window_ca_m = std::move(ca);
  return r;
}

TEST(ConversionsAssessmentTest, PathAssessmentRoundTrip) {
  const auto r = pathRecord({0.1, 0.5, 0.9});
  const path_assessment_t m = toLcm(r);
  EXPECT_EQ(m.num_samples, 3);
  EXPECT_EQ(m.recording, path_assessment_t::REC_RECORDING);
  EXPECT_EQ(m.window_samples, 3);
  EXPECT_EQ(m.interaction_samples, 5);
  const auto b = fromLcm(m);
  EXPECT_EQ(b.window_ca_m, r.window_ca_m);
  EXPECT_DOUBLE_EQ(*b.snapshot.cm_window_m, *r.snapshot.cm_window_m);
  EXPECT_EQ(b.snapshot.is_contributing_window, r.snapshot.is_contributing_window);
  EXPECT_DOUBLE_EQ(*b.snapshot.cm_interaction_m, 0.2);
  EXPECT_EQ(b.snapshot.state, assessment::RecorderState::kRecording);
  EXPECT_EQ(b.snapshot.tau_mode, r.snapshot.tau_mode);
  EXPECT_EQ(b.snapshot.tau_m, r.snapshot.tau_m);
  EXPECT_EQ(b.snapshot.tau_fixed_m, r.snapshot.tau_fixed_m);
  EXPECT_EQ(b.snapshot.tau_room_m, r.snapshot.tau_room_m);
  EXPECT_EQ(b.snapshot.room_m, r.snapshot.room_m);
  EXPECT_EQ(b.profile, "calibrated");
  EXPECT_EQ(b.side_rule, assessment::SideRule::kHumanSide);
  const auto snap = pathSnapshotFromLcm(m);
  EXPECT_DOUBLE_EQ(*snap.cm_window_m, *r.snapshot.cm_window_m);
}

TEST(ConversionsAssessmentTest, PContributingTravelsAsAProbabilityOrNaN) {
  auto r = pathRecord({0.1, 0.2});
  EXPECT_TRUE(std::isnan(toLcm(r).p_contributing));  // unknown
  EXPECT_FALSE(fromLcm(toLcm(r)).p_contributing.has_value());
  EXPECT_FALSE(pathSnapshotFromLcm(toLcm(r)).p_contributing.has_value());
  for (const double p : {0.0, 0.37, 1.0}) {
    r.p_contributing = p;
    const path_assessment_t m = toLcm(r);
    EXPECT_EQ(m.p_contributing, p);
    ASSERT_TRUE(fromLcm(m).p_contributing.has_value());
    EXPECT_EQ(*fromLcm(m).p_contributing, p);
    // ... and reaches the decision logic (dialogue::PathSnapshot, the forecast judgement).
    ASSERT_TRUE(pathSnapshotFromLcm(m).p_contributing.has_value());
    EXPECT_EQ(*pathSnapshotFromLcm(m).p_contributing, p);
  }
  path_assessment_t bad = toLcm(r);
  for (const double p : {-1e-9, 1.0 + 1e-9, 2.0, -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::infinity()}) {
    bad.p_contributing = p;
    EXPECT_THROW(fromLcm(bad), RejectedMessage) << p;
  }
}

TEST(ConversionsAssessmentTest, NoSamplesIsNaNAndUnknown) {
  PathAssessmentRecord r;
  const path_assessment_t m = toLcm(r);
  EXPECT_EQ(m.num_samples, 0);
  EXPECT_TRUE(std::isnan(m.cm_m));
  EXPECT_EQ(m.is_contributing, situation_t::PRED_UNKNOWN);
  EXPECT_EQ(m.recording, path_assessment_t::REC_IDLE);
  EXPECT_FALSE(pathSnapshotFromLcm(m).cm_window_m.has_value());
  EXPECT_FALSE(cmForGamma(m, 0.9).has_value());
}

TEST(ConversionsAssessmentTest, LongWindowsKeepTheNewestMaxSamples) {
  std::vector<double> ca(path_assessment_t::MAX_SAMPLES + 10);
  for (std::size_t i = 0; i < ca.size(); ++i) ca[i] = static_cast<double>(i);
  const path_assessment_t m = toLcm(pathRecord(ca));
  ASSERT_EQ(m.num_samples, path_assessment_t::MAX_SAMPLES);
  EXPECT_EQ(m.window_samples, path_assessment_t::MAX_SAMPLES + 10);
  EXPECT_DOUBLE_EQ(m.ca_m.front(), 10.0);
  EXPECT_DOUBLE_EQ(m.ca_m.back(), static_cast<double>(ca.size() - 1));
}

TEST(ConversionsAssessmentTest, CmForGammaMatchesThePublishedCmAndTheClosedForm) {
  const path_assessment_t m = toLcm(pathRecord({0.2, 0.4, 1.0}));
  EXPECT_NEAR(*cmForGamma(m, m.gamma), m.cm_m, 1e-12);
  // gamma = 0.5: weights 0.25, 0.5, 1 -> (0.05 + 0.2 + 1.0) / 1.75.
  EXPECT_NEAR(*cmForGamma(m, 0.5), 1.25 / 1.75, 1e-12);
  // gamma = 1: the plain mean.
  EXPECT_NEAR(*cmForGamma(m, 1.0), 1.6 / 3.0, 1e-12);
  EXPECT_FALSE(cmForGamma(m, 0.0).has_value());
}

TEST(ConversionsAssessmentTest, GarbagePathAssessmentsAreRejected) {
  const path_assessment_t m = toLcm(pathRecord({0.1, 0.2}));
  auto bad = m;
  bad.num_samples = 3;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.recording = 7;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  for (const char* name : {"", "pa per", "paper\n", "a-name-of-more-than-thirty-two-bytes"}) {
    bad = m;
    bad.profile = name;
    EXPECT_THROW(fromLcm(bad), RejectedMessage) << name;
  }
  bad = m;
  bad.side_rule = 2;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.ca_m[0] = std::nan("");
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.gamma = 0.0;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.cm_m = std::nan("");
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.window_samples = 1;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.tau_mode = 2;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.tau_room_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = m;
  bad.room_m = -0.5;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  auto unbounded = m;  // +inf room: nothing within range on that side, a known value
  unbounded.room_m = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isinf(*fromLcm(unbounded).snapshot.room_m));
}

TEST(ConversionsAssessmentTest, ControlRoundTripAndUnknownCommand) {
  RecorderControl c;
  c.utime = 5;
  c.step = 4;
  c.human_id = 2;
  c.command = dialogue::RecorderCommand::kReset;
  c.reason = "round 2";
  const auto m = toLcm(c);
  EXPECT_EQ(m.command, path_assessor_control_t::COMMAND_RESET);
  const auto b = fromLcm(m);
  EXPECT_EQ(b.command, dialogue::RecorderCommand::kReset);
  EXPECT_EQ(b.human_id, 2);
  EXPECT_EQ(b.step, 4);
  EXPECT_EQ(b.reason, "round 2");
  EXPECT_TRUE(std::isnan(m.d_oh_m));  // unknown travels as NaN
  EXPECT_FALSE(b.d_oh_m);
  EXPECT_FALSE(b.d_h_m);
  auto bad = m;
  bad.command = 0;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);

  c.command = dialogue::RecorderCommand::kStart;
  c.d_oh_m = std::numeric_limits<double>::infinity();
  c.d_h_m = 0.25;
  const auto start = fromLcm(toLcm(c));
  EXPECT_TRUE(std::isinf(*start.d_oh_m));
  EXPECT_EQ(*start.d_h_m, 0.25);
  bad = toLcm(c);
  bad.d_h_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
  bad = toLcm(c);
  bad.d_oh_m = -1.0;
  EXPECT_THROW(fromLcm(bad), RejectedMessage);
}

}  // namespace
}  // namespace coopnav
