#pragma once
/// @file Reading a recorded run (an lcm-logger file): the one log reader of every tool (the
/// viewer's replay, coopnav_ctl), raw events or the decoded coopnav messages the log tools need.
/// A log is untrusted input: events on foreign channels, payloads that do not decode
/// as their channel's type, garbage between events and a cut-off last event are counted and
/// skipped, never fatal.
///
/// The event framing (LCM log-file format: 28-byte big-endian header, channel, payload) is parsed
/// here rather than by lcm::LogFile because Debian's LCM 1.3.1 reader asserts on a channel length
/// >= 1000 (abort) and allocates any data length a corrupt header claims; this reader checks both
/// against the file before trusting them, and resynchronises on the next sync word. Only a
/// regular file is read (a device or FIFO is refused at open), and never past its size at open.

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/goal_estimates_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"

namespace coopnav::logfile {

/// What reading a log met, for the user (stderr) and the summary.
struct LogReadCounts {
  std::int64_t events{0};   ///< well-framed events read
  std::int64_t decoded{0};  ///< decoded as their channel's type and kept
  /// Coopnav channels the tools do not use (bands, acks, ...), and robot commands of an older
  /// shape than this build's (logs recorded before the guard field).
  std::int64_t not_needed{0};
  std::int64_t unknown_channel{0};  ///< channels that are not coopnav's (LCM_SELF_TEST, ...)
  std::int64_t undecodable{0};      ///< payload does not decode as its channel's type
  std::int64_t bad_headers{0};      ///< headers with impossible lengths (skipped, resynchronised)
  std::int64_t skipped_bytes{0};    ///< bytes passed over to find the next sync word
  /// Events identical (channel and payload) to an earlier one: a step published again after a
  /// loss or a restart (docs/lockstep.md); read once.
  std::int64_t repeats{0};
  bool truncated{false};  ///< the file ends inside an event
  std::map<std::string, std::int64_t> undecodable_by_channel;

  /// True when anything was skipped for being broken (not for being foreign or unused).
  bool anyCorruption() const {
    return undecodable > 0 || bad_headers > 0 || skipped_bytes > 0 || truncated;
  }
  /// One line: "events 812, decoded 640, not needed 150, unknown channel 2, undecodable 1 ...".
  std::string describe() const;
};

/// One framed event of a log file.
struct RawEvent {
  std::int64_t event_number{0};
  std::int64_t timestamp_us{0};  ///< logger receive time (wall clock): never used for logic
  std::string channel;
  std::vector<std::uint8_t> data;
};

/// Streams the events of one log file. Throws std::runtime_error when the file cannot be opened
/// or is not a regular file.
class LogEventReader {
 public:
  explicit LogEventReader(const std::string& path);
  ~LogEventReader();
  LogEventReader(const LogEventReader&) = delete;
  LogEventReader& operator=(const LogEventReader&) = delete;

  /// Next well-framed event; false at the end of the file.
  bool next(RawEvent& out);
  LogReadCounts& counts() { return counts_; }

 private:
  bool findSync();
  std::FILE* file_{nullptr};
  std::int64_t file_size_{0};
  LogReadCounts counts_;
};

/// The coopnav messages of one run, each kind in log order, and the log order across kinds.
struct RunLog {
  enum class Kind : std::uint8_t {
    kAgentStates,
    kSituation,
    kPathAssessment,
    kUtterance,
    kRobotAction,
    kRecorderControl,
    kSimStatus,
    kReferencePaths,
    kDaemonStatus,
    kRestart,  ///< a step ack of a daemon that restarted mid-run (first one per restart)
    kVelocityCommand,
    kGoalEstimates,
  };
  struct Ref {
    Kind kind;
    std::size_t index;  ///< into the vector of that kind
  };

  std::vector<agent_states_t> agent_states;
  std::vector<situation_t> situations;
  std::vector<path_assessment_t> assessments;
  std::vector<utterance_t> utterances;
  std::vector<robot_action_t> actions;
  std::vector<path_assessor_control_t> controls;
  std::vector<sim_status_t> sim_status;
  std::vector<reference_paths_t> reference_paths;
  std::vector<daemon_status_t> daemon_status;    ///< wall-clock reports: never in default outputs
  std::vector<step_ack_t> restarts;              ///< first ack of each daemon's restart
  std::vector<velocity_command_t> commands;      ///< the robot's (modes and guard: summary counts)
  std::vector<goal_estimates_t> goal_estimates;  ///< inferred goals (summary: at round 1)
  /// Per lockstep participant (step acks): the highest step it acknowledged. A participant that
  /// stopped answering (killed, cut off) shows as one behind the others; at most
  /// kMaxAckParticipants names (more than any coopnav run has: the rest are not kept).
  std::map<std::string, std::int64_t> last_acked_step;
  static constexpr std::size_t kMaxAckParticipants = 64;
  std::vector<Ref> order;
  LogReadCounts counts;
};

/// Reads and decodes a whole log. Throws std::runtime_error when the file cannot be opened.
RunLog readRunLog(const std::string& path);

/// Decodes one event into `run` (or counts why not). Exposed for tests.
void addEvent(const RawEvent& event, RunLog& run);

}  // namespace coopnav::logfile

namespace coopnav::ctl {
// The log tools (tools/ctl) name the reader as their own.
using namespace coopnav::logfile;  // NOLINT(google-build-using-namespace)
}  // namespace coopnav::ctl
