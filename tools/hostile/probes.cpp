#include "probes.hpp"

#include <lcm/lcm.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include "coopnav/distance_reply_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "messages.hpp"

namespace coopnav::hostile {
namespace {

constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();
constexpr double kMiB = 1024.0 * 1024.0;
/// [s] CPU one daemon may spend on 20 000 far-future step messages: ~250 us each, 20x what a
/// bounded gate needs on the loaded 2-core CI machine; a gate scanning every kept step per
/// message takes minutes.
constexpr double kFutureStepFloodCpuCap_s = 5.0;
/// After a message stamped INT64_MAX, the first of the normal messages answered: at most
/// limits.time_resync_messages (3) go unanswered while the daemon resyncs, plus 3 for a loaded
/// machine (the free-running band source plans only the newest of the states waiting).
constexpr int kFirstAfterJump = 6;

/// printf into a std::string (arguments: numbers and C strings).
template <class... A>
std::string fmt(const char* f, A... a) {
  char buf[512];
  std::snprintf(buf, sizeof buf, f, a...);
  return buf;
}

/// Text of a daemon's message cut for an answer line, control characters shown as '?'.
std::string shortText(const std::string& s, std::size_t n = 70) {
  std::string out = s.substr(0, n);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  return s.size() > n ? out + "..." : out;
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The status of `name` before an attack, and a fresh one after it: counter deltas.
struct Before {
  Watched* w{nullptr};
  daemon_status_t status;
};
Before before(Bus& bus, const std::string& name) {
  Before b;
  b.w = bus.find(name);
  if (b.w && b.w->status) b.status = *b.w->status;
  return b;
}
std::optional<daemon_status_t> after(Bus& bus, const Before& b, double timeout_s = 5.0) {
  if (!b.w) return std::nullopt;
  return bus.statusAfter(*b.w, wallUtime(), timeout_s);
}

// ---- 1. a band whose poses span 10^7 s -------------------------------------------------------

Outcome bandsTimeSpan(Bus& bus) {
  struct State {
    std::optional<situation_t> situation;
  };
  auto st = std::make_shared<State>();
  const std::int64_t utime = kEpoch_us + kPeriod_us;
  bus.runtime().subscribe<situation_t>(channels::kSituation,
                                       [st, utime](const situation_t& m, std::int64_t) {
                                         if (m.human_id == 1 && m.utime == utime) st->situation = m;
                                       });
  bus.publish(channels::kReferencePaths, referencePaths(kEpoch_us, -1, 1, 1, 2));
  bus.spin(100);
  bands_t b = corridorBands(utime, -1, 1, 2);
  b.robot.poses[1].t_s = 1e7;
  b.humans[0].poses[1].t_s = 1e7;
  const auto t0 = Clock::now();
  bus.publish(channels::kBands, b);
  bus.spinUntil([&] { return st->situation.has_value(); }, 3.0);
  if (!st->situation)
    return {false, "no situation for human 1 within 3 s (resampling the whole 10^7 s?)"};
  const double ms = msSince(t0);
  if (st->situation->crossing_status != situation_t::CROSSING_BAD_BANDS)
    return {false, fmt("situation with crossing status %d, not BAD_BANDS",
                       static_cast<int>(st->situation->crossing_status))};
  return {true, fmt("BAD_BANDS situation after %.0f ms", ms) + " (" +
                    shortText(st->situation->reason) + ")"};
}

// ---- 2. a message stamped INT64_MAX, then normal traffic ----------------------------------------

/// Sends `hostile(bus)` (stamped near INT64_MAX), then 20 normal messages 0.1 s of message time
/// apart (`normal(bus, i, utime)`), and checks that the daemon's output `Out` goes on for them:
/// the jump is rejected, or the daemon follows the normal time after time_resync_messages. With
/// `max_first` >= 0, the first output must answer one of the first max_first + 1 normal messages.
template <class Out>
Outcome afterTimeJump(Bus& bus, const std::string& daemon, const char* output,
                      void (*hostile)(Bus&), void (*normal)(Bus&, int, std::int64_t),
                      int max_first) {
  constexpr int kNormal = 20;
  struct State {
    std::vector<std::int64_t> utimes;  ///< of the outputs of normal messages
  };
  auto st = std::make_shared<State>();
  bus.runtime().subscribe<Out>(output, [st](const Out& m, std::int64_t) {
    if (m.utime >= kEpoch_us && m.utime < kEpoch_us + kNormal * kPeriod_us)
      st->utimes.push_back(m.utime);
  });
  const Before b = before(bus, daemon);
  hostile(bus);
  bus.spin(300);
  for (int i = 0; i < kNormal; ++i) {
    normal(bus, i, kEpoch_us + i * kPeriod_us);
    bus.spin(50);
  }
  bus.spinUntil([&] { return !st->utimes.empty(); }, 5.0);
  const auto a = after(bus, b);
  const std::string counts = a ? fmt("rejected +%lld dropped +%lld",
                                     static_cast<long long>(a->rejected - b.status.rejected),
                                     static_cast<long long>(a->dropped - b.status.dropped))
                               : std::string("no status");
  if (st->utimes.empty())
    return {false,
            std::string("no ") + output + " for the 20 normal messages after it (" + counts + ")"};
  const auto first = *std::min_element(st->utimes.begin(), st->utimes.end());
  const auto first_index = (first - kEpoch_us) / kPeriod_us;
  const bool in_time = max_first < 0 || first_index <= max_first;
  return {in_time, std::string(output) +
                       fmt(" goes on: first for normal message %lld of 20, %zu in all (",
                           static_cast<long long>(first_index), st->utimes.size()) +
                       counts + ")" + (in_time ? "" : fmt(", later than message %d", max_first))};
}

Outcome agentStatesInt64Max(Bus& bus) {
  bus.publish(channels::kGoals, corridorGoals(kEpoch_us, 1));
  bus.spin(100);
  return afterTimeJump<velocity_command_t>(
      bus, "band_source", channels::kRobotCmd,
      [](Bus& b) { b.publish(channels::kAgentStates, corridorStates(kInt64Max, -1, 1, 0)); },
      [](Bus& b, int i, std::int64_t utime) {
        b.publish(channels::kAgentStates, corridorStates(utime, -1, 1, i));
      },
      kFirstAfterJump);
}

Outcome referencePathsInt64Max(Bus& bus) {
  return afterTimeJump<path_assessment_t>(
      bus, "path_assessor", channels::kPathAssessment,
      [](Bus& b) {
        b.publish(channels::kReferencePaths, referencePaths(kInt64Max - 1, -1, 1, 1, 2));
      },
      [](Bus& b, int i, std::int64_t utime) {
        if (i % 5 == 0) b.publish(channels::kReferencePaths, referencePaths(utime, -1, 1, 1, 2));
        b.publish(channels::kAgentStates, corridorStates(utime, -1, 1, i));
      },
      kFirstAfterJump);
}

Outcome situationInt64Max(Bus& bus) {
  // t_CROSS 9 s at the jump (no round fires on it), then from 9 s down: round 1 (7 s) speaks.
  return afterTimeJump<utterance_t>(
      bus, "dialogue_manager", channels::kUtterance,
      [](Bus& b) {
        b.publish(channels::kSituation, situation(kInt64Max - 1, -1, 1, 9.0, "hostile"));
      },
      [](Bus& b, int i, std::int64_t utime) {
        b.publish(channels::kAgentStates, corridorStates(utime, -1, 1, i));
        b.publish(channels::kSituation, situation(utime, -1, 1, 9.0 - 0.2 * i, ""));
      },
      -1);  // round 1 comes at message 10 (t_CROSS 7 s) by design
}

// ---- 3. a backlog, then the caller's SIGTERM --------------------------------------------------

Outcome backlogBandSource(Bus& bus) {
  constexpr int kSteps = 300;
  constexpr int kHumans = 64;
  auto acks = std::make_shared<int>(0);
  bus.runtime().subscribe<step_ack_t>(channels::kStepAck,
                                      [acks](const step_ack_t& m, std::int64_t) {
                                        if (m.participant == "band_source") ++*acks;
                                      });
  bus.publish(channels::kGoals, corridorGoals(kEpoch_us, kHumans));
  bus.spin(100);
  bus.setRate(8e6);
  for (int k = 0; k < kSteps; ++k)
    bus.publish(channels::kAgentStates, corridorStates(kEpoch_us + k * kPeriod_us, k, kHumans, k));
  bus.spin(200);
  const Watched* w = bus.find("band_source");
  if (!w || !alive(w->pid)) return {false, "band_source died under the backlog"};
  return {true, fmt("%d lockstep steps of %d humans queued, %d planned before the stop", kSteps,
                    kHumans, *acks)};
}

Outcome backlogSituationAssessor(Bus& bus) {
  constexpr int kSteps = 100;
  constexpr int kHumans = 16;
  constexpr int kPoses = 250;
  auto acks = std::make_shared<int>(0);
  bus.runtime().subscribe<step_ack_t>(channels::kStepAck,
                                      [acks](const step_ack_t& m, std::int64_t) {
                                        if (m.participant == "situation_assessor") ++*acks;
                                      });
  bus.publish(channels::kReferencePaths, referencePaths(kEpoch_us, -1, 1, kHumans, 2));
  bus.spin(100);
  bus.setRate(20e6);
  for (int k = 0; k < kSteps; ++k)
    bus.publish(channels::kBands, corridorBands(kEpoch_us + k * kPeriod_us, k, kHumans, kPoses));
  bus.spin(200);
  const Watched* w = bus.find("situation_assessor");
  if (!w || !alive(w->pid)) return {false, "situation_assessor died under the backlog"};
  return {true, fmt("%d lockstep bands of %d humans x %d poses queued, %d assessed "
                    "before the stop",
                    kSteps, kHumans, kPoses, *acks)};
}

// ---- 4. per-id floods -------------------------------------------------------------------------

std::string receivedDeltas(Bus& bus, const std::vector<Before>& bs) {
  std::string out;
  for (const auto& b : bs) {
    const auto a = after(bus, b);
    if (!out.empty()) out += ", ";
    out += b.w ? b.w->name : "?";
    out += a ? fmt(" received +%lld", static_cast<long long>(a->received - b.status.received))
             : std::string(" no status");
  }
  return out;
}

Outcome referencePathIdFlood(Bus& bus) {
  constexpr int kMessages = 3000;
  constexpr int kIdsPerMessage = 64;
  const std::vector<Before> bs = {before(bus, "path_assessor"), before(bus, "situation_assessor")};
  // ~2.6 kB each: at this rate the assessors keep up (a backlog in LCM's queue is no per-id state).
  bus.setRate(4e6);
  for (int i = 0; i < kMessages; ++i)
    bus.publish(
        channels::kReferencePaths,
        referencePaths(kEpoch_us + i * 10'000, -1, 1 + kIdsPerMessage * i, kIdsPerMessage, 2));
  return {true, fmt("%d reference paths of %d new ids each (%d ids): ", kMessages, kIdsPerMessage,
                    kMessages * kIdsPerMessage) +
                    receivedDeltas(bus, bs)};
}

Outcome situationIdFlood(Bus& bus) {
  constexpr int kMessages = 5000;
  const std::string reason = "hostile " + std::string(60'000, 'r');
  const std::vector<Before> bs = {before(bus, "dialogue_manager")};
  bus.setRate(60e6);
  for (int i = 0; i < kMessages; ++i)
    bus.publish(channels::kSituation, situation(kEpoch_us + i * 10'000, -1, 1000 + i, 9.0, reason));
  return {true, fmt("%d situations of new humans with 60 kB reasons (%.0f MB): ", kMessages,
                    static_cast<double>(bus.publishedBytes()) / 1e6) +
                    receivedDeltas(bus, bs)};
}

// ---- 5. far-future lockstep steps ---------------------------------------------------------------

Outcome futureStepFlood(Bus& bus) {
  constexpr int kMessages = 20'000;
  const std::vector<Before> bs = {before(bus, "path_assessor"), before(bus, "situation_assessor")};
  std::vector<double> cpu0;
  cpu0.reserve(bs.size());
  for (const auto& b : bs) cpu0.push_back(b.w ? cpuSeconds(b.w->pid).value_or(0.0) : 0.0);
  bus.setRate(4e6);
  for (int i = 0; i < kMessages; ++i)
    bus.publish(channels::kReferencePaths,
                referencePaths(kEpoch_us + i * kPeriod_us, 1'000'000 + 7LL * i, 1, 1, 2));
  Outcome out{true, fmt("%d reference paths of distinct far-future steps:", kMessages)};
  for (std::size_t k = 0; k < bs.size(); ++k) {
    const Before& b = bs[k];
    if (!b.w) continue;
    // The status after the flood comes once the daemon has read it (10 s: a loaded machine).
    const auto a = after(bus, b, 10.0);
    const double cpu_s = cpuSeconds(b.w->pid).value_or(0.0) - cpu0[k];
    if (!a) {
      out.ok = false;
      out.answer += " " + b.w->name + " sent no status within 10 s;";
      continue;
    }
    // Which steps the gate keeps (at most limits.max_pending_steps ahead, the oldest of a peer
    // never heard from giving way) is not visible from here: node_runtime_limits_test and
    // fuzz_lcm_sequence count them. Here: the daemon stays responsive, its CPU and RSS bounded.
    out.answer += fmt(" %s received +%lld rejected +%lld, cpu %.2f s (cap %.0f s);",
                      b.w->name.c_str(), static_cast<long long>(a->received - b.status.received),
                      static_cast<long long>(a->rejected - b.status.rejected), cpu_s,
                      kFutureStepFloodCpuCap_s);
    if (cpu_s > kFutureStepFloodCpuCap_s) {
      out.ok = false;
      out.answer += " (CPU over the cap)";
    }
  }
  return out;
}

// ---- 6. distance requests: a reserved reply channel, a flood of fresh ones ----------------------

Outcome distReplyStatusChannel(Bus& bus) {
  struct State {
    int forged{0};  ///< messages on COOPNAV_STATUS that are no status
    bool answered{false};
  };
  auto st = std::make_shared<State>();
  // Raw: a reply on COOPNAV_STATUS decodes as no daemon_status_t (another fingerprint).
  lcm::Subscription* raw = bus.runtime().lcm().subscribeFunction(
      channels::kStatus,
      +[](const lcm::ReceiveBuffer* rbuf, const std::string&, State* s) {
        daemon_status_t m;
        try {
          decodeOrReject(rbuf->data, rbuf->data_size, m);
        } catch (const RejectedMessage&) {
          ++s->forged;
        }
      },
      st.get());
  const std::string good = std::string(channels::kDistanceReplyPrefix) + "HOSTILE";
  bus.runtime().subscribe<distance_reply_t>(good, [st](const distance_reply_t& m, std::int64_t) {
    if (m.request_id == 2) st->answered = true;
  });
  const Before b = before(bus, "obstacle_distance_server");
  bus.publish(channels::kDistanceRequest, distanceRequest(1, channels::kStatus));
  bus.spin(300);
  bus.publish(channels::kDistanceRequest, distanceRequest(2, good));
  bus.spinUntil([&] { return st->answered; }, 3.0);
  bus.spin(300);
  const auto a = after(bus, b);
  const double rejected = a ? static_cast<double>(a->rejected - b.status.rejected) : -1.0;
  // The raw subscription's context is this probe's state: it ends with the probe.
  const int forged = st->forged;
  bus.runtime().lcm().unsubscribe(raw);
  if (forged > 0) return {false, fmt("%d replies published on COOPNAV_STATUS", forged)};
  if (rejected < 1) return {false, "request naming COOPNAV_STATUS not counted as rejected"};
  if (!st->answered) return {false, "no reply to the good request after it"};
  return {true, fmt("request naming COOPNAV_STATUS rejected (+%.0f), no reply on it; the next "
                    "request answered",
                    rejected)};
}

Outcome distReplyChannelFlood(Bus& bus) {
  constexpr int kRequests = 100'000;
  const std::vector<Before> bs = {before(bus, "obstacle_distance_server")};
  bus.setRate(3e6);
  for (int i = 0; i < kRequests; ++i)
    bus.publish(channels::kDistanceRequest,
                distanceRequest(i, std::string(channels::kDistanceReplyPrefix) + "HOSTILE_" +
                                       std::to_string(i)));
  return {true,
          fmt("%d requests, each with a new reply channel: ", kRequests) + receivedDeltas(bus, bs)};
}

// ---- 8. robot-action reasons that would forge or flood band_source's log ------------------------

/// A reason that, logged as it is, starts a line of its own that looks like a critical one,
/// and clears the terminal of whoever tails the log.
const char* kForgedReason =
    "hostile\n[0000-00-00 00:00:00.000] [coopnav:1] [critical] FORGED: band_source stopped"
    "\x1b[2J\x1b[31m\r";

Outcome actionReasonForgery(Bus& bus) {
  auto cmds = std::make_shared<int>(0);
  bus.runtime().subscribe<velocity_command_t>(
      channels::kRobotCmd, [cmds](const velocity_command_t&, std::int64_t) { ++*cmds; });
  bus.publish(channels::kGoals, corridorGoals(kEpoch_us, 1));
  bus.spin(100);
  bus.publish(channels::kRobotAction,
              robotAction(kEpoch_us, robot_action_t::ACTION_DOCK, 4242, kForgedReason));
  for (int i = 0; i < 5; ++i) {
    bus.spin(100);
    bus.publish(channels::kAgentStates, corridorStates(kEpoch_us + i * kPeriod_us, -1, 1, i));
  }
  bus.spinUntil([&] { return *cmds > 0; }, 5.0);
  return {*cmds > 0, fmt("DOCK with a newline, a forged line and ANSI escapes in its reason; "
                         "%d commands after it",
                         *cmds)};
}

Outcome actionReasonFlood(Bus& bus) {
  constexpr int kActions = 3000;
  const std::string reason = "hostile flood " + std::string(60'000, 'f');
  const std::vector<Before> bs = {before(bus, "band_source")};
  bus.setRate(60e6);
  for (int i = 0; i < kActions; ++i)
    bus.publish(channels::kRobotAction,
                robotAction(kEpoch_us + i * kPeriod_us, robot_action_t::ACTION_RESUME, 1, reason));
  return {true, fmt("%d robot actions with 60 kB reasons: ", kActions) + receivedDeltas(bus, bs)};
}

// ---- 10. restart journal over its cap ---------------------------------------------------------

Outcome journalFlood(Bus& bus) {
  constexpr int kMessages = 50;  // 64 paths x 60 points: ~62 kB each, ~3 MiB in all
  const Before b = before(bus, "path_assessor");
  bus.setRate(20e6);
  for (int i = 0; i < kMessages; ++i)
    bus.publish(channels::kReferencePaths,
                referencePaths(kEpoch_us + i * kPeriod_us, -1, 1, 64, 60));
  const auto a = after(bus, b);
  const std::string sent = fmt("%.1f MiB of journaled reference paths",
                               static_cast<double>(bus.publishedBytes()) / kMiB);
  if (!a) return {false, sent + "; no status after them"};
  if (a->state != daemon_status_t::STATE_DEGRADED || a->detail.find("journal") == std::string::npos)
    return {false, sent + "; status " + stateName(a->state) + " \"" + shortText(a->detail) +
                       "\", not DEGRADED naming the journal"};
  return {true, sent + "; DEGRADED: " + shortText(a->detail)};
}

// ---- 10. a flood at the fastest rate one peer publishes ---------------------------------------

double g_flood_s = 2.0;

/// Publishes `make(i)` on `channel` as fast as this process can for g_flood_s (RSS polled every
/// 20 ms by the bus), lets the daemon settle, then sends 5 normal messages 50 ms apart and checks
/// that the daemon handled them (its `received` grows by them): it still answers normal traffic.
template <class Make>
Outcome flood(Bus& bus, const std::string& daemon, const char* channel, Make make) {
  const Before b = before(bus, daemon);
  const auto t0 = Clock::now();
  auto next_poll = t0;
  std::int64_t sent = 0;
  std::int64_t bytes = 0;
  while (msSince(t0) < g_flood_s * 1000.0) {
    const auto msg = make(sent, false);
    bus.runtime().publish(channel, msg);
    bytes += msg.getEncodedSize();
    ++sent;
    if (Clock::now() >= next_poll) {
      bus.spin(0);  // polls the daemon's memory, handles its status
      next_poll = Clock::now() + std::chrono::milliseconds(20);
    }
  }
  const double rate = static_cast<double>(sent) / std::max(1e-3, msSince(t0) / 1000.0);
  bus.spin(1000);
  const Watched* w = bus.find(daemon);
  if (!w || !alive(w->pid)) return {false, daemon + " died under the flood"};
  const auto mid = after(bus, b);
  const std::string counts = mid ? fmt("received +%lld dropped +%lld",
                                       static_cast<long long>(mid->received - b.status.received),
                                       static_cast<long long>(mid->dropped - b.status.dropped))
                                 : std::string("no status");
  const std::string sent_text =
      fmt("%lld messages (%.1f MB) in %.1f s, %.0f/s: ", static_cast<long long>(sent),
          static_cast<double>(bytes) / 1e6, g_flood_s, rate) +
      counts;
  if (!mid) return {false, sent_text};
  const Before b2 = before(bus, daemon);
  for (int i = 0; i < 5; ++i) {
    bus.runtime().publish(channel, make(sent + i, true));
    bus.spin(50);
  }
  const auto a = after(bus, b2);
  const long long normal = a ? static_cast<long long>(a->received - b2.status.received) : -1;
  if (normal < 5)
    return {false, sent_text + fmt("; then %lld of 5 normal messages handled", normal)};
  return {true, sent_text + "; then the 5 normal messages handled"};
}

Outcome floodAgentStates(Bus& bus, const std::string& daemon) {
  return flood(bus, daemon, channels::kAgentStates, [](std::int64_t i, bool) {
    return corridorStates(kEpoch_us + i * 1000, -1, 1, static_cast<int>(i % 1000));
  });
}
Outcome floodPathAssessor(Bus& bus) { return floodAgentStates(bus, "path_assessor"); }
Outcome floodBandSource(Bus& bus) { return floodAgentStates(bus, "band_source"); }
Outcome floodSituationAssessor(Bus& bus) {
  // Bands of 16 humans x 250 poses (~0.5 MB each), as the backlog probe.
  return flood(bus, "situation_assessor", channels::kBands, [](std::int64_t i, bool) {
    return corridorBands(kEpoch_us + i * 1000, -1, 16, 250);
  });
}
Outcome floodDialogueManager(Bus& bus) {
  return flood(bus, "dialogue_manager", channels::kSituation, [](std::int64_t i, bool) {
    return situation(kEpoch_us + i * 1000, -1, 1, 3.0, "flood");
  });
}
Outcome floodDistanceServer(Bus& bus) {
  return flood(bus, "obstacle_distance_server", channels::kDistanceRequest,
               [](std::int64_t i, bool) {
                 return distanceRequest(i, std::string(channels::kDistanceReplyPrefix) + "FLOOD");
               });
}

const std::vector<Probe> kProbes = {
    {"bands_time_span",
     {"situation_assessor"},
     "bands: robot and human band of 2 poses 10^7 s apart",
     "a BAD_BANDS situation within 3 s (capped time grid), RSS small",
     true,
     bandsTimeSpan},
    {"agent_states_int64_max",
     {"band_source"},
     "agent states at INT64_MAX, then 20 at 10 Hz",
     "velocity commands go on (jump rejected or resynced after 3)",
     true,
     agentStatesInt64Max},
    {"reference_paths_int64_max",
     {"path_assessor"},
     "a reference path at INT64_MAX - 1, then agent states and paths at 10 Hz",
     "path assessments go on",
     true,
     referencePathsInt64Max},
    {"situation_int64_max",
     {"dialogue_manager"},
     "a situation at INT64_MAX - 1, then situations and agent states at 10 Hz",
     "round 1 still speaks on the normal situations",
     true,
     situationInt64Max},
    {"backlog_band_source",
     {"band_source"},
     "300 lockstep steps of 64 humans at once",
     "alive; SIGTERM while the backlog drains: exit 0 within 1 s (caller)",
     false,
     backlogBandSource},
    {"backlog_situation_assessor",
     {"situation_assessor"},
     "100 lockstep bands of 16 humans x 250 poses at once (no distance server)",
     "alive; SIGTERM while the backlog drains: exit 0 within 1 s (caller)",
     false,
     backlogSituationAssessor},
    {"reference_path_id_flood",
     {"path_assessor", "situation_assessor"},
     "3000 reference paths of 64 new ids each",
     "per-id state capped (limits.max_ids): RSS bounded",
     true,
     referencePathIdFlood},
    {"situation_id_flood",
     {"dialogue_manager"},
     "5000 situations of new humans, 60 kB reasons",
     "per-id state and text capped: RSS bounded",
     true,
     situationIdFlood},
    {"future_step_flood",
     {"path_assessor", "situation_assessor"},
     "20000 reference paths of distinct far-future lockstep steps",
     "rejected beyond limits.max_pending_steps; CPU and RSS bounded",
     true,
     futureStepFlood},
    {"dist_reply_status_channel",
     {"obstacle_distance_server"},
     "a distance request whose reply channel is COOPNAV_STATUS",
     "rejected, no reply on COOPNAV_STATUS; the next request answered",
     true,
     distReplyStatusChannel},
    {"dist_reply_channel_flood",
     {"obstacle_distance_server"},
     "100000 distance requests, each with a new COOPNAV_DIST_REP_ channel",
     "answered; RSS bounded (LCM keeps ~100 B per channel name)",
     true,
     distReplyChannelFlood},
    {"action_reason_forgery",
     {"band_source"},
     "robot action whose reason holds a newline, a forged log line and ANSI escapes",
     "no forged line in the log: control characters as \\xNN (caller reads the log)",
     true,
     actionReasonForgery},
    {"action_reason_flood",
     {"band_source"},
     "3000 robot actions with 60 kB reasons",
     "log lines cut to limits.max_text_bytes, rate-limited, \"suppressed N lines\" (caller)",
     true,
     actionReasonFlood},
    {"flood_path_assessor",
     {"path_assessor"},
     "small agent states as fast as one peer publishes, for --flood-s",
     "RSS under the cap, the drops counted, 5 normal messages handled after",
     true,
     floodPathAssessor},
    {"flood_band_source",
     {"band_source"},
     "small agent states as fast as one peer publishes, for --flood-s",
     "RSS under the cap, the drops counted, 5 normal messages handled after",
     true,
     floodBandSource},
    {"flood_situation_assessor",
     {"situation_assessor"},
     "bands of 16 humans x 250 poses as fast as one peer publishes, for --flood-s",
     "RSS under the cap, the drops counted, 5 normal messages handled after",
     true,
     floodSituationAssessor},
    {"flood_dialogue_manager",
     {"dialogue_manager"},
     "situations as fast as one peer publishes, for --flood-s",
     "RSS under the cap, the drops counted, 5 normal messages handled after",
     true,
     floodDialogueManager},
    {"flood_obstacle_distance_server",
     {"obstacle_distance_server"},
     "distance requests as fast as one peer publishes, for --flood-s",
     "RSS under the cap, the drops counted, 5 normal messages handled after",
     true,
     floodDistanceServer},
    {"journal_flood",
     {"path_assessor"},
     "~3 MiB of journaled input to a daemon with --state-dir, limits.journal_max_mib=1",
     "journal stops at its cap (caller), status DEGRADED naming the journal",
     true,
     journalFlood},
};

}  // namespace

const std::vector<Probe>& probes() { return kProbes; }
void setFloodSeconds(double s) { g_flood_s = s; }

const Probe* findProbe(const std::string& name) {
  for (const auto& p : kProbes)
    if (name == p.name) return &p;
  return nullptr;
}

}  // namespace coopnav::hostile
