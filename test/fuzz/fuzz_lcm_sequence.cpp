// A sequence of messages into the assessment pipeline, in one process over LCM's memq:// (the
// hostile publisher's attacks as fuzz input; docs/bad-inputs.md "Hostile publisher"): the band
// source, situation assessor, path assessor and dialogue manager nodes, with an obstacle distance
// server node so that every distance request is answered, all on one in-process bus. Their
// outputs feed each other as on a robot (bands -> situations -> decisions -> robot actions), so a
// message reaches state that earlier messages of the input built.
//
// Input: records [selector][length: 2 bytes, little endian][payload], at most kMaxRecords; the
// selector (mod 8) picks the channel: 0 COOPNAV_AGENT_STATES, 1 COOPNAV_BANDS,
// 2 COOPNAV_REFERENCE_PATHS, 3 COOPNAV_SITUATION, 4 COOPNAV_PATH_ASSESSMENT,
// 5 COOPNAV_ROBOT_ACTION, 6 COOPNAV_STEP_ACK, 7 COOPNAV_GOALS. A length past the end takes the
// rest. Each payload is published as it is; the bus is drained after each one. Agent states
// beyond kMaxAgentStates are skipped (each may be a planning cycle).
//
// Oracle, besides the sanitizers: time and memory for the whole sequence
// (fuzz_lcm_sequence.options: 3 s per input, 256 MB for one allocation, 1 GB in all: ASan's
// quarantine alone holds 256 MB, and a 4-minute run peaked at 380 MB), and after each message
// what the nodes keep (their "kept" accessors) within the caps of runtime.limits(): per-id state
// within max_ids, steps within max_pending_steps, text from a message within max_text_bytes (set
// low here so that a few messages reach them).
//
// The nodes are built afresh for each input (the stateless distance server once). Their timers
// never run (only the feeder's loop spins) but the band source's free-running planning timer,
// run after each free-running agent-states message, so an input replays the same way.
// COOPNAV_FUZZ_TRACE=1 prints each node's counters after the input.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "band_source_node.hpp"
#include "dialogue_manager_node.hpp"
#include "fuzz_util.hpp"
#include "obstacle_distance_server_node.hpp"
#include "path_assessor_node.hpp"
#include "situation_assessor_node.hpp"

namespace coopnav::fuzz {
namespace {

constexpr const char* kBus = "memq://";
/// Messages of one input that are fed; the rest is ignored.
constexpr std::size_t kMaxRecords = 64;
/// Agent-states messages of one input that are fed (the rest are skipped): each may be a
/// planning cycle of the band source, ~60 ms in this instrumented build, and a legitimate input
/// must stay well within -timeout.
constexpr int kMaxAgentStates = 12;
/// The caps under test, lower than the shipped ones so that short inputs reach them. Per-id
/// state: the wire's most humans in one message (a lower cap would have to forget humans of the
/// message in hand), reached by two messages of new ids.
constexpr int kMaxIds = 64;
constexpr int kMaxPendingSteps = 16;
constexpr int kMaxTextBytes = 64;
/// The band source's planner forgets every agent at once past its max_ids: a low cap of its own
/// is reached within the input's few planning cycles (two new humans planned per cycle).
constexpr int kBandMaxIds = 8;
/// [ms] Wall time after which the band source's 5 ms planning timer is due.
constexpr int kBandTimerDue_ms = 6;

const char* const kChannels[] = {
    channels::kAgentStates, channels::kBands,          channels::kReferencePaths,
    channels::kSituation,   channels::kPathAssessment, channels::kRobotAction,
    channels::kStepAck,     channels::kGoals,
};
constexpr unsigned kNumChannels = sizeof(kChannels) / sizeof(kChannels[0]);

struct Record {
  const char* channel;
  const std::uint8_t* payload;
  std::size_t size;
};

std::vector<Record> splitRecords(const std::uint8_t* data, std::size_t size) {
  std::vector<Record> out;
  std::size_t i = 0;
  while (i < size && out.size() < kMaxRecords) {
    const char* channel = kChannels[data[i] % kNumChannels];
    std::size_t len = 0;
    if (i + 2 < size) len = static_cast<std::size_t>(data[i + 1]) | (std::size_t{data[i + 2]} << 8);
    const std::size_t start = std::min(size, i + 3);
    len = std::min(len, size - start);
    out.push_back({channel, data + start, len});
    i = start + len;
  }
  return out;
}

InputLimits fuzzLimits(int max_ids = kMaxIds) {
  InputLimits l;
  l.max_ids = max_ids;
  l.max_pending_steps = kMaxPendingSteps;
  l.max_text_bytes = kMaxTextBytes;
  return l;
}

/// The band source's and distance server's map: a 28 m x 10 m corridor at 0.1 m (28 000 cells,
/// built in a few milliseconds), where the seeds' agents walk.
MapSource corridorMap() {
  static const std::string kWalls =
      "resolution_m: 0.1\nwalls:\n"
      "  - {x0_m: -2.0, y0_m: 0.0, x1_m: 26.0, y1_m: 0.0, thickness_m: 0.2}\n"
      "  - {x0_m: -2.0, y0_m: 10.0, x1_m: 26.0, y1_m: 10.0, thickness_m: 0.2}\n";
  static const std::string path = scratch().write(
      "corridor.yaml", reinterpret_cast<const std::uint8_t*>(kWalls.data()), kWalls.size());
  MapSource m;
  m.map_file = path;
  return m;
}

Runtime& limited(Runtime& rt, int max_ids = kMaxIds) {
  rt.setLimits(fuzzLimits(max_ids));
  return rt;
}

/// The distance server answers the situation assessor's requests. It keeps no state between
/// requests, and building its octree is most of a pipeline's set-up time, so it is built once and
/// holds the in-process bus for the whole run (the bus is drained empty after every input).
struct DistanceServer {
  static ObstacleDistanceServerNode::Config config() {
    ObstacleDistanceServerNode::Config c;
    c.map = corridorMap();
    c.limits = fuzzLimits();
    return c;
  }
  Runtime rt{"obstacle_distance_server", kBus};
  ObstacleDistanceServerNode node{config(), limited(rt)};
};

DistanceServer& distanceServer() {
  static DistanceServer server;
  return server;
}

/// The stateful nodes of the pipeline on the in-process bus, each with a runtime of its own name
/// (the step gates tell participants apart by it). Members are destroyed in reverse: nodes first.
struct Pipeline {
  static BandSourceNode::Config bandConfig() {
    BandSourceNode::Config c;
    c.map = corridorMap();
    // A few iterations and humans per cycle: the planner's cost is not what this target fuzzes.
    c.max_iterations = 4;
    c.planner.config.max_planned_others = 2;
    c.step_gate_timeout_s = 600.0;
    c.limits = fuzzLimits(kBandMaxIds);
    return c;
  }
  static SituationAssessorNode::Config situationConfig() {
    SituationAssessorNode::Config c;
    // Answers come within the same drain of the bus; no timeout may decide (timers do not run).
    c.distance_timeout_ms = 5000;
    c.distance_attempts = 1;
    c.gate_timeout_ms = 600000;
    c.limits = fuzzLimits();
    return c;
  }
  static PathAssessorNode::Config pathConfig() {
    PathAssessorNode::Config c;
    c.gate_timeout_ms = 600000;
    c.limits = fuzzLimits();
    return c;
  }
  static DialogueManagerNode::Config dialogueConfig() {
    DialogueManagerNode::Config c;
    c.gate_timeout_ms = 600000;
    c.limits = fuzzLimits();
    return c;
  }

  Runtime feeder{"fuzz_feeder", kBus};
  Runtime band_rt{"band_source", kBus};
  BandSourceNode band{bandConfig(), limited(band_rt, kBandMaxIds)};
  Runtime situation_rt{"situation_assessor", kBus};
  SituationAssessorNode situation{situationConfig(), limited(situation_rt)};
  Runtime path_rt{"path_assessor", kBus};
  PathAssessorNode path{pathConfig(), limited(path_rt)};
  Runtime dialogue_rt{"dialogue_manager", kBus};
  DialogueManagerNode dialogue{dialogueConfig(), limited(dialogue_rt)};
};

/// Free-running agent states: the band source plans the newest of them from its loop's 5 ms timer
/// (band_source_node.cpp), the one timer this target lets run.
bool freeRunningAgentStates(const Record& r) {
  if (std::strcmp(r.channel, channels::kAgentStates) != 0) return false;
  agent_states_t m;
  try {
    decodeOrReject(r.payload, r.size, m);
  } catch (const RejectedMessage&) {
    return false;
  }
  return m.step < 0;
}

/// Handles every message on the bus, the nodes' own outputs included, until none is left. A
/// message loop that never ends is a finding (-timeout).
void drain(Pipeline& p) {
  while (p.feeder.spinFor(0) > 0) {
  }
}

/// The per-id state and the text each node keeps, between two messages, within the caps.
void checkCaps(const Pipeline& p) {
  const auto max_ids = static_cast<std::size_t>(kMaxIds);
  const auto max_text = static_cast<std::size_t>(kMaxTextBytes);
  if (p.path.humansKept() > max_ids) fail("path_assessor keeps more humans than limits.max_ids");
  // 16 per human: PathAssessorNode::kReferencesPerHuman.
  if (p.path.referencePathsKept() > 16 * max_ids)
    fail("path_assessor keeps more reference paths than 16 per human");
  if (p.path.controlsWaiting() > max_ids)
    fail("path_assessor keeps more controls waiting than limits.max_ids");
  if (p.situation.referencesKept() > max_ids)
    fail("situation_assessor keeps reference paths of more humans than limits.max_ids");
  if (p.dialogue.idsKept() > max_ids || p.dialogue.humansKept() > max_ids)
    fail("dialogue_manager keeps state of more humans than limits.max_ids");
  if (p.dialogue.longestKeptTextBytes() > max_text)
    fail("dialogue_manager keeps a text longer than limits.max_text_bytes");
  if (p.band.plannerIdsKept() > static_cast<std::size_t>(kBandMaxIds))
    fail("band_source's planner keeps memory of more agents than limits.max_ids");
  if (p.band.stepsKept() > static_cast<std::size_t>(kMaxPendingSteps))
    fail("band_source keeps more steps than limits.max_pending_steps");
  if (p.band.pendingActionReason().size() > max_text)
    fail("band_source keeps a robot action's reason longer than limits.max_text_bytes");
}

/// With COOPNAV_FUZZ_TRACE set (reproducing a finding): what each node received and published.
void traceCounters(Pipeline& p) {
  for (const Runtime* rt : {&p.band_rt, &p.situation_rt, &p.path_rt, &p.dialogue_rt}) {
    const RuntimeCounters& c = rt->counters();
    std::fprintf(stderr, "%-26s received %lld dropped %lld rejected %lld published %lld\n",
                 rt->name().c_str(), static_cast<long long>(c.received),
                 static_cast<long long>(c.dropped), static_cast<long long>(c.rejected),
                 static_cast<long long>(c.published));
  }
}

}  // namespace
}  // namespace coopnav::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  coopnav::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav::fuzz;
  const std::vector<Record> records = splitRecords(data, size);
  if (records.empty()) return 0;
  coopnav::Runtime& bus = distanceServer().rt;
  {
    Pipeline p;
    int agent_states = 0;
    for (const Record& r : records) {
      if (std::strcmp(r.channel, coopnav::channels::kAgentStates) == 0 &&
          ++agent_states > kMaxAgentStates)
        continue;
      p.feeder.lcm().publish(r.channel, r.payload, static_cast<unsigned>(r.size));
      drain(p);
      if (freeRunningAgentStates(r)) {
        p.band_rt.spinFor(kBandTimerDue_ms);
        drain(p);
      }
      checkCaps(p);
    }
    if (std::getenv("COOPNAV_FUZZ_TRACE") != nullptr) traceCounters(p);
  }
  // What the nodes published while going away reaches nobody; the next input starts empty.
  while (bus.spinFor(0) > 0) {
  }
  return 0;
}
