// The viewer's scene model alone (no bus, no HTTP): message time only (a stamp far off the
// scene's time is rejected and moves nothing; a new run, agreed on by a few messages, starts a
// new scene and keeps the daemons' statuses), bands that cannot be drawn are skipped and counted,
// humans not heard of are forgotten, CM history is bounded and a repeated step does not duplicate
// its point, text is cut to limits.max_text_bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "coopnav/channels.hpp"
#include "scene_model.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"
#include "wire/dialogue.hpp"

namespace coopnav::viewer {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

agent_states_t states(double t_s, int humans = 1) {
  AgentStatesSnapshot s;
  s.utime = secondsToUtime(t_s);
  s.robot = {0, AgentKind::kRobot, {1.0 + t_s, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.34};
  for (int i = 1; i <= humans; ++i)
    s.humans.push_back({i, AgentKind::kHuman, {10.0 - t_s, 0.5 * i, M_PI}, {-1.0, 0.0, 0.0}, 0.3});
  return toLcm(s);
}

bands_t bands(double t_s) {
  BandsSnapshot b;
  b.utime = secondsToUtime(t_s);
  for (int i = 0; i < 5; ++i) b.robot.poses.push_back({0.5 * i, {1.0 + t_s + 0.5 * i, 0.0, 0.0}});
  Band h;
  for (int i = 0; i < 5; ++i) h.poses.push_back({0.5 * i, {10.0 - t_s - 0.5 * i, 0.5, M_PI}});
  b.humans.emplace_back(1, h);
  b.room_plans.push_back(bands_t::ROOM_UNKNOWN);
  return toLcm(b);
}

path_assessment_t assessment(double t_s, double cm) {
  PathAssessmentRecord r;
  r.utime = secondsToUtime(t_s);
  r.human_id = 1;
  r.snapshot.state = assessment::RecorderState::kRecording;
  r.window_ca_m = {cm};
  r.snapshot.window_samples = 1;
  r.snapshot.cm_window_m = cm;
  r.snapshot.interaction_samples = 1;
  r.snapshot.cm_interaction_m = cm;
  return toLcm(r);
}

daemon_status_t status(const std::string& name) {
  daemon_status_t s{};
  s.utime = 1'700'000'000'000'000;
  s.name = name;
  s.state = daemon_status_t::STATE_RUNNING;
  s.cycle_p50_ms = kNaN;
  s.cycle_max_ms = kNaN;
  return s;
}

TEST(ViewerSceneModelTest, AStampFarOffIsRejectedAndANewRunStartsANewScene) {
  SceneModel scene;
  scene.apply(states(100.0));
  scene.apply(bands(100.0));
  scene.apply(status("band_source"));
  ASSERT_EQ(scene.utime(), secondsToUtime(100.0));

  // One message from far in the future (or a clock pinned at INT64_MAX): rejected, time kept.
  agent_states_t far = states(100.1);
  far.utime = std::numeric_limits<std::int64_t>::max();
  EXPECT_THROW(scene.apply(far), RejectedMessage);
  bands_t far_bands = bands(100.1);
  far_bands.utime = secondsToUtime(1e6);
  EXPECT_THROW(scene.apply(far_bands), RejectedMessage);
  EXPECT_EQ(scene.utime(), secondsToUtime(100.0));
  EXPECT_EQ(scene.toJson()["bands"]["t"], 100.0);

  // Older than the scene: not drawn (dropped, not an error).
  EXPECT_THROW(scene.apply(states(99.0)), DroppedMessage);

  // A new run from t = 0: after limits.time_resync_messages (3) agreeing messages it is the
  // scene; the old run's bands are gone, the daemons' statuses stay.
  EXPECT_THROW(scene.apply(states(0.0)), RejectedMessage);
  EXPECT_THROW(scene.apply(states(0.1)), RejectedMessage);
  scene.apply(states(0.2));
  EXPECT_EQ(scene.utime(), secondsToUtime(0.2));
  const auto j = scene.toJson();
  EXPECT_TRUE(j["bands"].is_null());
  EXPECT_EQ(j["statuses"].size(), 1u);
  EXPECT_TRUE(j["statuses"][0]["cycle_p50_ms"].is_null());
}

TEST(ViewerSceneModelTest, BandsThatCannotBeDrawnAreSkippedAndCounted) {
  SceneModel scene;
  scene.apply(states(1.0));
  scene.apply(bands(1.0));
  bands_t bad = bands(1.1);
  bad.humans[0].poses[2].y_m = kNaN;
  EXPECT_THROW(scene.apply(bad), RejectedMessage);
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(bad.getEncodedSize()));
  bad.encode(buf.data(), 0, static_cast<int>(buf.size()));
  try {
    scene.applyRaw(channels::kBands, buf.data(), buf.size());
    FAIL() << "a NaN band was taken";
  } catch (const RejectedMessage&) {
    scene.countRejected(channels::kBands);
  }
  EXPECT_EQ(scene.skipped().total(), 1);
  const auto j = scene.toJson();
  EXPECT_EQ(j["bands"]["t"], 1.0);  // the last drawable bands stay
  EXPECT_EQ(j["viewer"]["skipped"][channels::kBands], 1);
  // A channel the viewer does not draw is ignored, not counted.
  EXPECT_FALSE(scene.applyRaw("COOPNAV_SOMETHING_ELSE", buf.data(), buf.size()));
}

TEST(ViewerSceneModelTest, HumansAreForgottenAndHistoriesBounded) {
  SceneOptions options;
  options.cm_history_points = 10;
  options.limits.forget_after_s = 5.0;
  options.limits.max_text_bytes = 16;
  SceneModel scene(options);
  for (int k = 0; k < 30; ++k) {
    scene.apply(states(0.1 * k));
    scene.apply(assessment(0.1 * k, 0.01 * k));
  }
  scene.apply(assessment(2.9, 0.5));  // a step published again: replaces its point
  auto j = scene.toJson();
  ASSERT_EQ(j["assessments"].size(), 1u);
  const auto& cm = j["assessments"][0]["cm_history"];
  EXPECT_EQ(cm.size(), 10u);
  EXPECT_EQ(cm.back()[1], 0.5);
  EXPECT_NEAR(cm.back()[0].get<double>(), 2.9, 1e-9);

  // Human 1 not heard of for more than forget_after_s of message time: its plot goes.
  scene.apply(states(3.0, 0));
  scene.apply(states(9.0, 0));
  j = scene.toJson();
  EXPECT_EQ(j["assessments"].size(), 0u);
  EXPECT_EQ(j["humans"].size(), 0u);

  // Text from the bus is cut to limits.max_text_bytes.
  DialogueStamp stamp{secondsToUtime(9.0), -1, 1};
  dialogue::Utterance u;
  u.act = dialogue::SpeechAct::kThank;
  u.round = 3;
  u.text = "Thank you very much for making room, it was kind.";
  scene.apply(toLcm(stamp, u, std::nullopt, dialogue::SpeechSlot{}));
  j = scene.toJson();
  EXPECT_LE(j["utterances"][0]["text"].get<std::string>().size(), 16u);
  EXPECT_TRUE(j["utterances"][0]["active"].get<bool>());
}

}  // namespace
}  // namespace coopnav::viewer
