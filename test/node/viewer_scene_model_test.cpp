// The viewer's scene model alone (no bus, no HTTP): message time only (a stamp far off the
// scene's time is rejected and moves nothing; a new run, agreed on by a few messages, starts a
// new scene and keeps the daemons' statuses), bands that cannot be drawn are skipped and counted,
// humans not heard of are forgotten, CM history is bounded and a repeated step does not duplicate
// its point, text is cut to limits.max_text_bytes. Hostile messages: text that is not UTF-8 is
// made valid where it enters (every frame serialises); reference paths, bands and CA windows of
// the maximum sizes are decimated and age out; the daemon table judges stamps against the
// viewer's receive clock (an INT64_MAX stamp neither hides the real daemons nor stays) and a
// full table evicts its stalest entry, never the newcomer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
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

path_assessment_t assessment(double t_s, double cm,
                             std::optional<double> p_contributing = std::nullopt) {
  PathAssessmentRecord r;
  r.p_contributing = p_contributing;
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

constexpr std::int64_t kWall = 1'700'000'000'000'000;  // the receive clock of these tests

daemon_status_t status(const std::string& name, std::int64_t utime = kWall) {
  daemon_status_t s{};
  s.utime = utime;
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
  scene.apply(status("band_source"), kWall);
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
    scene.applyRaw(channels::kBands, buf.data(), buf.size(), kWall);
    FAIL() << "a NaN band was taken";
  } catch (const RejectedMessage&) {
    scene.countRejected(channels::kBands);
  }
  EXPECT_EQ(scene.skipped().total(), 1);
  const auto j = scene.toJson();
  EXPECT_EQ(j["bands"]["t"], 1.0);  // the last drawable bands stay
  EXPECT_EQ(j["viewer"]["skipped"][channels::kBands], 1);
  // A channel the viewer does not draw is ignored, not counted.
  EXPECT_FALSE(scene.applyRaw("COOPNAV_SOMETHING_ELSE", buf.data(), buf.size(), kWall));
}

TEST(ViewerSceneModelTest, HumansAreForgottenAndHistoriesBounded) {
  SceneOptions options;
  options.cm_history_points = 10;
  options.limits.forget_after_s = 5.0;
  options.limits.max_text_bytes = 16;
  SceneModel scene(options);
  for (int k = 0; k < 30; ++k) {
    scene.apply(states(0.1 * k));
    // The forecast: unknown for the first 5, then 0.02 k.
    scene.apply(
        assessment(0.1 * k, 0.01 * k, k >= 5 ? std::optional<double>(0.02 * k) : std::nullopt));
  }
  scene.apply(assessment(2.9, 0.5, 0.9));  // a step published again: replaces its point
  auto j = scene.toJson();
  ASSERT_EQ(j["assessments"].size(), 1u);
  const auto& cm = j["assessments"][0]["cm_history"];
  EXPECT_EQ(cm.size(), 10u);
  EXPECT_EQ(cm.back()[1], 0.5);
  EXPECT_NEAR(cm.back()[0].get<double>(), 2.9, 1e-9);
  // p_contributing beside it: bounded the same way, replaced the same way, known values only.
  EXPECT_EQ(j["assessments"][0]["p_contributing"], 0.9);
  const auto& pc = j["assessments"][0]["p_contributing_history"];
  EXPECT_EQ(pc.size(), 10u);
  EXPECT_EQ(pc.back()[1], 0.9);
  EXPECT_NEAR(pc.front()[0].get<double>(), 2.0, 1e-9);
  // Unknown again (a new interaction): the latest is null, the history keeps what was known.
  scene.apply(states(2.95));
  scene.apply(assessment(2.95, 0.5));
  j = scene.toJson();
  EXPECT_TRUE(j["assessments"][0]["p_contributing"].is_null());
  EXPECT_EQ(j["assessments"][0]["p_contributing_history"].size(), 10u);

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

TEST(ViewerSceneModelTest, TextThatIsNotUtf8IsMadeValidAndEveryFrameSerialises) {
  EXPECT_EQ(validUtf8("ok \xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"),
            "ok \xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
  // A lone continuation byte, a cut sequence, an overlong '/', a surrogate, beyond U+10FFFF.
  EXPECT_EQ(validUtf8("a\x80"
                      "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(validUtf8("\xE2\x82"), "\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("\xF4\x90\x80\x80").size(), 12u);

  SceneModel scene;
  scene.apply(states(1.0));
  DialogueStamp stamp{secondsToUtime(1.0), -1, 1};
  dialogue::Utterance u;
  u.act = dialogue::SpeechAct::kThank;
  u.round = 1;
  u.text = "Thank \xFF\xFE you";
  scene.apply(toLcm(stamp, u, std::nullopt, dialogue::SpeechSlot{}));
  daemon_status_t st = status("band\xC3");
  st.detail = "\xC0\x80 detail";
  scene.apply(st, kWall);
  sim_status_t sim{};
  sim.utime = secondsToUtime(1.0);
  sim.state = sim_status_t::STATE_RUNNING;
  sim.scenario = "\x80";
  sim.detail = "\xF8";
  scene.apply(sim);
  std::string dumped;
  ASSERT_NO_THROW(dumped = scene.toJson().dump());
  const auto j = nlohmann::json::parse(dumped);
  EXPECT_EQ(j["utterances"][0]["text"], "Thank \xEF\xBF\xBD\xEF\xBF\xBD you");
  EXPECT_EQ(j["statuses"][0]["name"], "band\xEF\xBF\xBD");
  EXPECT_EQ(j["sim"]["scenario"], "\xEF\xBF\xBD");
}

TEST(ViewerSceneModelTest, PolylinesOfTheMaximumSizesAreDecimatedAndReferencePathsAgeOut) {
  SceneOptions options;
  options.max_polyline_points = 50;
  options.limits.forget_after_s = 5.0;
  SceneModel scene(options);
  scene.apply(states(1.0));
  ReferencePaths r;
  r.utime = secondsToUtime(1.0);
  ReferencePaths::Entry e;
  e.agent_id = 1;
  for (int i = 0; i < 5000; ++i) e.path.emplace_back(0.001 * i, 0.0);
  r.paths.push_back(e);
  scene.apply(toLcm(r));
  PathAssessmentRecord a;
  a.utime = secondsToUtime(1.0);
  a.human_id = 1;
  a.window_ca_m.assign(5000, 0.25);
  a.snapshot.window_samples = 5000;
  a.snapshot.interaction_samples = 5000;
  a.snapshot.state = assessment::RecorderState::kRecording;
  a.snapshot.cm_window_m = 0.25;
  a.snapshot.cm_interaction_m = 0.25;
  scene.apply(toLcm(a));
  BandsSnapshot b;
  b.utime = secondsToUtime(1.0);
  for (int i = 0; i < 3000; ++i) b.robot.poses.push_back({0.01 * i, {0.001 * i, 0.0, 0.0}});
  scene.apply(toLcm(b));

  auto j = scene.toJson();
  const auto& pts = j["reference_paths"][0]["points"];
  ASSERT_EQ(pts.size(), 50u);
  EXPECT_EQ(pts.front()[0], 0.0);  // the ends are kept
  EXPECT_NEAR(pts.back()[0].get<double>(), 4.999, 1e-9);
  const auto& ca = j["assessments"][0]["ca"];
  ASSERT_EQ(ca.size(), 50u);
  EXPECT_NEAR(ca.back()[0].get<double>(), 1.0, 1e-9);   // the newest sample at the message time
  EXPECT_LT(ca.front()[0].get<double>(), 1.0 - 300.0);  // the oldest kept, 0.1 s per sample
  EXPECT_EQ(j["bands"]["robot"].size(), 50u);

  // No new reference for more than forget_after_s of message time: it goes.
  scene.apply(states(4.0));
  EXPECT_EQ(scene.toJson()["reference_paths"].size(), 1u);
  scene.apply(states(7.0));
  EXPECT_EQ(scene.toJson()["reference_paths"].size(), 0u);
}

TEST(ViewerSceneModelTest, TheDaemonTableCannotBeFakedByAStampOrByForgedNames) {
  SceneOptions options;
  options.limits.max_ids = 8;
  SceneModel scene(options);
  scene.apply(status("band_source"), kWall);
  scene.apply(status("path_assessor", kWall - 1'000'000), kWall);
  // INT64_MAX: counts as received now (nobody looks older for it); far in the past: rejected.
  scene.apply(status("forged", std::numeric_limits<std::int64_t>::max()), kWall);
  EXPECT_THROW(scene.apply(status("old", std::numeric_limits<std::int64_t>::min()), kWall),
               RejectedMessage);
  auto j = scene.toJson();
  ASSERT_EQ(j["statuses"].size(), 3u);
  for (const auto& s : j["statuses"]) EXPECT_FALSE(s["silent"].get<bool>()) << s["name"];
  EXPECT_EQ(j["statuses"][2]["name"], "path_assessor");
  EXPECT_NEAR(j["statuses"][2]["age_s"].get<double>(), 1.0, 1e-9);

  // The table full of forged names: a daemon appearing later takes the stalest one's place.
  for (int i = 0; i < 20; ++i)
    scene.apply(status("forged" + std::to_string(i), kWall + i * 100'000), kWall + i * 100'000);
  scene.apply(status("band_source", kWall + 3'000'000), kWall + 3'000'000);
  scene.apply(status("dialogue_manager", kWall + 3'000'000), kWall + 3'000'000);
  j = scene.toJson();
  EXPECT_EQ(j["statuses"].size(), 8u);
  bool band = false;
  bool dialogue = false;
  for (const auto& s : j["statuses"]) {
    band |= s["name"] == "band_source";
    dialogue |= s["name"] == "dialogue_manager";
  }
  EXPECT_TRUE(band);
  EXPECT_TRUE(dialogue);
}

// fuzz_viewer_scene's first finding: before any agent states (no scene time yet) reference
// paths of new ids were kept without the max_ids cap.
TEST(ViewerSceneModelTest, CapsHoldBeforeTheFirstAgentStates) {
  SceneOptions options;
  options.limits.max_ids = 8;
  SceneModel scene(options);
  for (int id = 1; id <= 20; ++id) {
    ReferencePaths r;
    r.utime = secondsToUtime(1.0);
    r.paths.push_back({id, 1, {{0.0, 0.0}, {1.0, 0.0}}});
    scene.apply(toLcm(r));
  }
  EXPECT_EQ(scene.toJson()["reference_paths"].size(), 8u);
}

}  // namespace
}  // namespace coopnav::viewer
