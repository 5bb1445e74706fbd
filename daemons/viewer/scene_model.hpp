#pragma once
/// @file The viewer's scene: what the page draws, as plain state built from the coopnav messages
/// (agents, bands, reference paths, situations, path assessments, utterances, actions, the
/// robot's mode, every daemon's status and the simulator's), and its JSON. No bus, no clock, no
/// thread: the node feeds it messages (live or from a log) and hands its JSON to the HTTP side.
///
/// Every message is converted through daemons/common/wire; one that does not convert (NaN, an
/// unknown enum, a count over its bound) throws RejectedMessage and changes nothing. Time is the
/// messages' utime only: the scene's time is the newest data utime heard (agent states, guarded
/// against jumps as in the daemons); daemon statuses carry wall-clock stamps and are aged against
/// the newest status stamp heard, never against a clock, each stamp first checked against the
/// time the viewer received it (the caller's receive clock: LCM's recv_utime live, the logger's
/// timestamp in replay), so a forged stamp cannot age the real daemons.
///
/// Everything held is bounded whatever the bus sends: text is valid UTF-8 (invalid bytes become
/// U+FFFD where they enter) and cut to limits.max_text_bytes, so a frame always serialises;
/// polylines (reference paths, bands, CA windows) are decimated to max_polyline_points when
/// they enter; per-human entries (traces, situations, reference paths) age out on the message
/// clock (limits.forget_after_s) and are capped at limits.max_ids, the least recently heard
/// going first; the daemon table is capped at limits.max_ids, the stalest going first.

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/limits.hpp"
#include "runtime/message_clock.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"
#include "wire/dialogue.hpp"

namespace coopnav::viewer {

/// What the scene keeps beyond the latest message of each kind.
struct SceneOptions {
  /// Utterances and robot actions kept (newest), for the bubbles and the plots' round markers.
  int max_utterances{64};
  /// CM points kept per human for its plot (newest).
  int cm_history_points{600};
  /// [s] spacing of the CA samples a path assessment carries (path_assessor sample_period_s): the
  /// plot's time axis for them (the message carries the samples, not their period).
  double ca_sample_period_s{0.1};
  /// [s] a speech bubble stays this long after the robot finished saying it.
  double bubble_hold_s{3.0};
  /// [s] a daemon whose latest status is this much older than the newest status heard is shown
  /// silent (statuses are stamped with the wall clock of their sender).
  double status_stale_s{3.0};
  /// Most points kept of one polyline (a reference path, a band, a CA window): longer ones are
  /// decimated evenly, first and last points kept. Bounds the scene, its JSON and a replay
  /// checkpoint whatever the message sizes.
  int max_polyline_points{256};
  /// Caps shared with the daemons (ids kept, ageing, time jumps, text).
  InputLimits limits;
};

/// Why a message was not taken into the scene, per channel (the JSON's "viewer.skipped").
struct SkipCounts {
  std::map<std::string, std::int64_t> rejected;  ///< did not convert (NaN, enum, bound, jump)
  std::int64_t total() const;
};

class SceneModel {
 public:
  explicit SceneModel(SceneOptions options = {});

  /// The map for the d_OH / d_OR segments (nearest obstacle in the assessor's half-plane);
  /// without one they are drawn along the half-plane's normal, the value's length.
  void setDistanceMap(std::shared_ptr<const DistanceMap> map) { map_ = std::move(map); }

  // Each apply() converts through wire and throws RejectedMessage (nothing changed) when the
  // message does not convert. Returns nothing: the scene is the state.
  void apply(const agent_states_t& msg);
  void apply(const bands_t& msg);
  void apply(const reference_paths_t& msg);
  void apply(const situation_t& msg);
  void apply(const path_assessment_t& msg);
  void apply(const path_assessor_control_t& msg);
  void apply(const utterance_t& msg);
  void apply(const robot_action_t& msg);
  void apply(const velocity_command_t& msg);
  void apply(const goals_t& msg);
  /// `received_utime`: when the viewer received it (wall clock, µs; LCM's recv_utime, or the
  /// logger's timestamp in replay). A stamp more than limits.max_time_jump_s before it is
  /// rejected; one after it counts as received then (a status cannot be newer than its arrival).
  void apply(const daemon_status_t& msg, std::int64_t received_utime);
  void apply(const sim_status_t& msg);

  /// Decodes `data` as the type of `channel` (the coopnav channel table) and applies it; a
  /// channel the viewer does not draw is ignored (false). Throws RejectedMessage as apply().
  /// `received_utime` as for a daemon status.
  bool applyRaw(const std::string& channel, const void* data, std::size_t size,
                std::int64_t received_utime);

  /// Counts a message not taken (the node and the replay call it on RejectedMessage).
  void countRejected(const std::string& channel) { ++skipped_.rejected[channel]; }
  const SkipCounts& skipped() const { return skipped_; }

  /// The scene's time: the newest agent-states utime accepted; nullopt before any.
  std::optional<std::int64_t> utime() const { return clock_.now(); }
  bool hasAgents() const { return states_.has_value(); }
  std::size_t humansDrawn() const { return states_ ? states_->humans.size() : 0; }

  /// The whole scene as JSON (the page's one input; docs in daemons/viewer/README.md).
  nlohmann::json toJson() const;

 private:
  struct HumanTrace {
    std::optional<PathAssessmentRecord> assessment;  ///< window_ca_m moved to `ca`
    std::vector<std::pair<double, double>> ca;       ///< (t [s], CA [m]) of the latest, decimated
    std::deque<std::pair<double, double>> cm;        ///< (t [s], CM [m]) newest last
    /// (t [s], p_contributing) newest last; only known values (the wire checked them in [0, 1])
    std::deque<std::pair<double, double>> p_contributing;
    std::vector<std::pair<double, std::string>> controls;  ///< (t [s], START / STOP / RESET)
    std::int64_t last_utime{0};
  };
  struct StatusEntry {
    daemon_status_t msg;
    std::int64_t stamp{0};  ///< msg.utime, or its receive time when the stamp is after that
  };
  struct ReferenceEntry {
    std::int64_t utime{0};
    ReferencePaths::Entry entry;
  };
  /// Rejects a data message stamped more than limits.max_time_jump_s off the scene's time.
  void checkTime(std::int64_t utime, const char* what) const;
  HumanTrace& trace(std::int32_t id, std::int64_t utime);
  void forgetOld();
  /// Forgets the scene's data (not the statuses nor the counts): a new run began.
  void newTimeLine();
  nlohmann::json situationJson(const SituationRecord& s) const;
  std::string keep(const std::string& text) const;

  SceneOptions options_;
  std::shared_ptr<const DistanceMap> map_;
  MessageClock clock_;
  std::optional<AgentStatesSnapshot> states_;
  std::optional<BandsSnapshot> bands_;
  std::map<std::int32_t, ReferenceEntry> references_;
  std::map<std::int32_t, SituationRecord> situations_;
  std::map<std::int32_t, HumanTrace> traces_;
  std::deque<UtteranceMsg> utterances_;
  std::deque<RobotActionMsg> actions_;
  std::optional<VelocityCommand> command_;
  std::optional<GoalsSnapshot> goals_;
  std::map<std::string, StatusEntry> statuses_;
  std::int64_t newest_status_utime_{0};
  std::optional<sim_status_t> sim_;
  SkipCounts skipped_;
};

/// `text` with every byte that is not part of a well-formed UTF-8 character (RFC 3629: no
/// overlong forms, no surrogates, nothing above U+10FFFF) replaced by U+FFFD: JSON cannot carry
/// anything else, and one bad byte would make every frame fail to serialise.
std::string validUtf8(const std::string& text);

/// At most `max_points` of `points`, evenly spaced by index, the first and the last kept.
template <class T>
std::vector<T> decimated(std::vector<T> points, int max_points) {
  const std::size_t n = static_cast<std::size_t>(std::max(max_points, 2));
  if (points.size() <= n) return points;
  std::vector<T> out;
  out.reserve(n);
  const std::size_t last = points.size() - 1;
  for (std::size_t i = 0; i < n; ++i) out.push_back(std::move(points[i * last / (n - 1)]));
  return out;
}

/// Names of the wire enums as the page shows them.
const char* robotModeName(std::int8_t mode);

}  // namespace coopnav::viewer
