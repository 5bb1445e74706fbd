// A sequence of hostile decoded messages into the viewer's scene (daemons/viewer/scene_model):
// every channel the viewer draws, as the node and the replay feed it (applyRaw, a
// RejectedMessage counted, a DroppedMessage ignored), with a receive clock that moves 0.1 s per
// message.
//
// Input: records [selector][length: 2 bytes, little endian][payload], at most kMaxRecords; the
// selector (mod 13) picks the channel, 0-7 numbered as fuzz_lcm_sequence's (so its seeds are
// this target's too): 0 COOPNAV_AGENT_STATES, 1 COOPNAV_BANDS, 2 COOPNAV_REFERENCE_PATHS,
// 3 COOPNAV_SITUATION, 4 COOPNAV_PATH_ASSESSMENT, 5 COOPNAV_ROBOT_ACTION, 6 COOPNAV_STEP_ACK
// (not drawn: ignored), 7 COOPNAV_GOALS, 8 COOPNAV_UTTERANCE, 9 COOPNAV_PATH_ASSESSOR_CONTROL,
// 10 COOPNAV_STATUS, 11 COOPNAV_SIM_STATUS, 12 COOPNAV_ROBOT_CMD.
//
// Oracle, besides the sanitizers: after each message the scene's JSON serialises (strict UTF-8:
// nlohmann throws on anything else, which froze the live page) and holds what the caps allow:
// at most max_ids daemons, reference paths, situations and plots; polylines of at most
// max_polyline_points; at most max_utterances utterances and actions; text within
// max_text_bytes.
#include <cstdint>
#include <string>
#include <vector>

#include "coopnav/channels.hpp"
#include "fuzz_util.hpp"
#include "scene_model.hpp"

namespace coopnav::fuzz {
namespace {

constexpr std::size_t kMaxRecords = 64;
constexpr int kMaxIds = 8;
constexpr int kMaxPoints = 16;
constexpr int kMaxUtterances = 8;
constexpr int kMaxTextBytes = 64;
constexpr std::int64_t kReceiveStart = 1'700'000'000'000'000;  // [µs] wall clock

const char* const kChannels[] = {
    channels::kAgentStates,    channels::kBands,
    channels::kReferencePaths, channels::kSituation,
    channels::kPathAssessment, channels::kRobotAction,
    channels::kStepAck,        channels::kGoals,
    channels::kUtterance,      channels::kPathAssessorControl,
    channels::kStatus,         channels::kSimStatus,
    channels::kRobotCmd,
};
constexpr unsigned kNumChannels = sizeof(kChannels) / sizeof(kChannels[0]);

void checkCaps(const nlohmann::json& j) {
  const auto atMost = [](const nlohmann::json& a, int n, const char* what) {
    if (!a.is_array() || a.size() > static_cast<std::size_t>(n)) fail(what);
  };
  atMost(j["statuses"], kMaxIds, "more daemons than max_ids");
  atMost(j["reference_paths"], kMaxIds, "more reference paths than max_ids");
  atMost(j["situations"], kMaxIds, "more situations than max_ids");
  atMost(j["assessments"], kMaxIds, "more plots than max_ids");
  atMost(j["utterances"], kMaxUtterances, "more utterances than max_utterances");
  atMost(j["actions"], kMaxUtterances, "more actions than max_utterances");
  for (const auto& r : j["reference_paths"])
    atMost(r["points"], kMaxPoints, "a reference path over max_polyline_points");
  for (const auto& a : j["assessments"]) atMost(a["ca"], kMaxPoints, "a CA window over the cap");
  if (j["bands"].is_object()) {
    atMost(j["bands"]["robot"], kMaxPoints, "the robot band over the cap");
    for (const auto& h : j["bands"]["humans"])
      atMost(h["poses"], kMaxPoints, "a human band over the cap");
  }
  for (const auto& u : j["utterances"])
    if (u["text"].get<std::string>().size() > static_cast<std::size_t>(kMaxTextBytes))
      fail("utterance text over max_text_bytes");
  for (const auto& s : j["statuses"])
    if (s["detail"].get<std::string>().size() > static_cast<std::size_t>(kMaxTextBytes))
      fail("status detail over max_text_bytes");
}

}  // namespace
}  // namespace coopnav::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  using namespace coopnav::fuzz;
  viewer::SceneOptions options;
  options.max_utterances = kMaxUtterances;
  options.max_polyline_points = kMaxPoints;
  options.limits.max_ids = kMaxIds;
  options.limits.max_text_bytes = kMaxTextBytes;
  viewer::SceneModel scene(options);
  std::size_t i = 0;
  std::int64_t received = kReceiveStart;
  for (std::size_t n = 0; i < size && n < kMaxRecords; ++n) {
    const char* channel = kChannels[data[i] % kNumChannels];
    std::size_t len = 0;
    if (i + 2 < size) len = static_cast<std::size_t>(data[i + 1]) | (std::size_t{data[i + 2]} << 8);
    const std::size_t start = std::min(size, i + 3);
    len = std::min(len, size - start);
    try {
      scene.applyRaw(channel, data + start, len, received);
    } catch (const RejectedMessage&) {
      scene.countRejected(channel);
    } catch (const DroppedMessage&) {
    }
    received += 100'000;
    i = start + len;
    const nlohmann::json j = scene.toJson();
    try {
      (void)j.dump();  // strict: throws on text that is not UTF-8
    } catch (const nlohmann::json::exception&) {
      fail("the scene's JSON does not serialise");
    }
    checkCaps(j);
  }
  return 0;
}
