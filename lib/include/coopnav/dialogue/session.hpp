#pragma once
/// @file The dialogue with everyone in the scene, one step at a time: the multi-person logic the
/// dialogue manager runs. One record per person (its decision of paper §II-D, where it was last
/// seen, its latest path assessment, when it heard the robot's words), kept in one map and in
/// two orders (last heard of, last present). Per step: the agents' positions (crossed
/// detection, presence, a tracker id switch continued), the path assessments, one decision per
/// person in id order, their words coordinated as a crowd (crowd.hpp) and planned on the robot's
/// one voice (speech_timing.hpp), then the interactions of people absent for human_gone_s ended
/// and ids long gone forgotten. Pure: time comes in as message utimes [us]; what comes out is
/// the messages to publish, in order, the notes to log and the sentences to speak.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "coopnav/dialogue/crowd.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/dialogue/overtake_words.hpp"
#include "coopnav/dialogue/speech_timing.hpp"
#include "coopnav/geometry/id_recency.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav::dialogue {

struct SessionConfig {
  DecisionConfig decision;
  CrowdConfig crowd;
  /// A person ahead walking the robot's way: followed in silence, passed with words.
  OvertakeWordsConfig overtake;
  double crossed_hysteresis_m{0.2};    ///< [m] CrossedTracker's hysteresis
  double crossed_max_distance_m{5.0};  ///< [m] updateCrossed: a crossing is seen this near
  /// [s] A person absent from the agent states this long has left: its interaction ends (and a
  /// new id where it was heading no longer continues it).
  double human_gone_s{2.0};
  /// [s] A path assessment older than this (message time, against the situation decided on) is
  /// not acted on: CM and IsContributing are unknown (round 2 then takes its precautionary
  /// dock, or stays silent). The path assessor publishes every planning cycle (10 Hz); a
  /// lockstep run never sees an older one (each step waits for it), a free-running one does
  /// when the path assessor or its host is gone.
  double path_max_age_s{0.5};
  /// Decide and act as usual, say nothing: every utterance is planned kMuted.
  bool muted{false};
  /// Words announcing a change of what the robot does (it makes room, or goes first) cut the
  /// words being said when they would otherwise be too late (SpeechTimeline::planFirstFitting).
  bool interrupt_for_change{true};
  /// [words/min] a sentence not measured (setMeasuredDurations) is estimated at this rate (the
  /// daemon's speech.rate_wpm).
  double speech_rate_wpm{175.0};
};

/// What identifies an output: the time and step decided at, and whom it is about.
struct Stamp {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int32_t human_id{0};
};

/// The robot and the humans at one instant (the world's agent states).
struct SceneSnapshot {
  std::int64_t utime{0};  ///< [us]
  AgentState robot;
  std::vector<AgentState> humans;
};

/// A path assessment and its message time: one older than path_max_age_s is not acted on.
struct StampedPath {
  PathSnapshot snapshot;
  std::int64_t utime{0};
};

struct StampedSituation {
  Stamp stamp;
  SituationSnapshot snapshot;
};

/// Everything one step brings.
struct SessionInput {
  std::int64_t step{-1};
  std::int64_t utime{0};  ///< [us] the step's time (its first input's, or the clock's)
  /// [us] the daemon's message clock; nullopt before any input was accepted.
  std::optional<std::int64_t> clock_utime;
  std::optional<SceneSnapshot> agents;
  std::map<std::int32_t, StampedPath> paths;
  std::map<std::int32_t, StampedSituation> situations;
};

/// An utterance as published: its delivery (said, muted, too late, told to the group,
/// contradicting) and the other members of the person's group.
struct UtteranceOut {
  Stamp stamp;
  Utterance utterance;
  std::optional<double> t_cross_s;  ///< nullopt: round 3 (no crossing ahead)
  SpeechSlot slot;
  std::vector<std::int32_t> group;
};
struct RobotActionOut {
  Stamp stamp;
  RobotAction action{RobotAction::kDock};
  std::string why;  ///< the round and branch that decided it (full length: the caller caps it)
};
struct RecorderOut {
  Stamp stamp;
  RecorderCommand command{RecorderCommand::kStart};
  std::string why;
  std::optional<double> d_oh_m;  ///< [m] with a kStart: the situation's d_OH
  std::optional<double> d_h_m;   ///< [m] with a kStart: the situation's d_h
};
using SessionMessage = std::variant<UtteranceOut, RobotActionOut, RecorderOut>;

struct SessionNote {
  enum class Level : std::int8_t { kDebug, kInfo, kWarn };
  Level level{Level::kInfo};
  std::string text;
};

struct SpeechRequest {
  std::string text;
  std::string wav_stem;  ///< u<utime>_h<id>_r<round>_<act>
};

struct SessionOutput {
  /// In publication order (docs/lockstep.md row 4: per decision its utterances, robot actions,
  /// recorder controls; the decisions in id order, then absences ended, then ids forgotten).
  std::vector<SessionMessage> messages;
  std::vector<SessionNote> notes;
  std::vector<SpeechRequest> speak;  ///< sentences planned kSaid, in order
};

class Session {
 public:
  /// `forget_after_s`, `max_ids`: the daemon's caps (docs/bad-inputs.md "Caps"): an id not heard
  /// of for max(forget_after_s, human_gone_s) is forgotten, and so are the least recently heard
  /// of beyond max_ids.
  Session(const SessionConfig& config, double forget_after_s, std::size_t max_ids);

  /// One step: crossed detection and presence from the agents, the path assessments, the
  /// decisions of the situations (and round 3 of those who crossed on this step's agents), the
  /// absent ended, the stale forgotten.
  SessionOutput step(const SessionInput& in);

  /// The first step is joined late (a restart that lost its state): the people of `in` may have
  /// heard rounds this Session holds no record of, so nothing is decided for them; the returned
  /// note names them.
  SessionNote joinLate(const SessionInput& in);

  /// The message clock was resynchronised at `utime`: the times kept per person belong to the old
  /// time base, so their ages restart from it.
  void restamp(std::int64_t utime);

  /// Measured durations of sentences [s] (the speech program's); others are estimated.
  void setMeasuredDurations(std::map<std::string, double> measured_s) {
    measured_s_ = std::move(measured_s);
  }
  /// How long saying `text` takes [s]: measured, else estimateSpeechDuration.
  double speechDuration(const std::string& text) const;

  /// The decision of person `id`, or nullptr before its first situation.
  const HumanDecision* decision(std::int32_t id) const;
  /// Ids kept (a decision, a position, a path assessment), as counted against max_ids.
  std::size_t idsKept() const { return heard_.size(); }
  /// Decisions kept (one per person spoken with).
  std::size_t humansKept() const;
  /// The longest situation reason kept [bytes].
  std::size_t longestKeptTextBytes() const;

 private:
  /// Everything kept about one person.
  struct Person {
    /// From its first situation (none for an id only seen, or only assessed).
    std::optional<HumanDecision> decision;
    SituationSnapshot last_situation;
    std::optional<double> heard_by_s;          ///< [s] when the words said to it so far ended
    std::int64_t stale_path_logged_utime{-1};  ///< the stale assessment last noted
    bool seen{false};                          ///< in the agent states at least once
    CrossedTracker crossed;
    std::int64_t last_seen_utime{0};         ///< [us] set when first seen
    Eigen::Vector2d position_m{0.0, 0.0};    ///< [m] as last seen (track continuity)
    Eigen::Vector2d velocity_m_s{0.0, 0.0};  ///< [m/s] as last seen
    double heading_rad{0.0};                 ///< [rad] as last seen (a person standing faces it)
    double radius_m{0.3};                    ///< [m] as last seen
    std::optional<StampedPath> path;         ///< the latest path assessment
    /// Joined late (joinLate): its rounds so far are unknown, nothing is decided for it.
    bool history_unknown{false};
    /// Its decision began while it was absent from the agent states: its absence is judged at
    /// the next agent states (it is not in present_).
    bool judge_absence{false};
    /// Ahead walking the robot's way: the words and the pass (overtake_words.hpp).
    OvertakeWords overtake;
  };
  /// What one person's decision produced at this step, emitted once everyone has decided.
  struct Decided {
    Stamp stamp;
    DecisionOutput out;
    std::optional<double> t_cross_s;
  };

  void see(const SceneSnapshot& agents, std::int64_t now, std::set<std::int32_t>& crossed_now,
           SessionOutput& out);
  /// A new id where a person with an interaction (open or ended) was lost and heading: the
  /// tracker switched ids (lib/geometry/track_continuity.hpp); the record goes on under it.
  void continueSwitchedIds(const SceneSnapshot& agents, SessionOutput& out);
  Decided decide(std::int64_t step, std::int32_t id, const Stamp& stamp,
                 const SituationSnapshot& situation, std::optional<std::int64_t> clock_utime,
                 SessionOutput& out);
  /// The step's decisions, their utterances addressed, told once per group and never
  /// contradicting each other (crowd.hpp).
  void emitDecided(std::vector<Decided>& decided, SessionOutput& out);
  void endAbsent(std::int64_t step, const SceneSnapshot& agents, SessionOutput& out);
  /// Forgets ids not heard of for max(forget_after_s, human_gone_s) and the least recently heard
  /// of beyond max_ids; an interaction still open is ended first. One note per batch.
  void forgetStale(const SessionInput& in, SessionOutput& out);
  void forget(std::int32_t id);
  /// `quiet`: no note per round. `coordinated`: per utterance of `decision`, what the crowd
  /// logic made of it (nullptr: said as decided, to nobody else).
  void emit(const Stamp& stamp, const DecisionOutput& decision, std::optional<double> t_cross_s,
            SessionOutput& out, bool quiet = false,
            const std::vector<const CoordinatedUtterance*>* coordinated = nullptr);

  SessionConfig config_;
  double forget_after_s_;
  std::size_t max_ids_;
  std::map<std::int32_t, Person> people_;
  /// Every id of people_, by when it was last heard of on any input: the order of forgetting.
  IdRecency heard_;
  /// Ids seen in the agent states whose absence was not yet handled, by when last seen.
  IdRecency present_;
  CrowdConversation crowd_;
  /// The robot's one voice: when each utterance starts, and whether it is said at all.
  SpeechTimeline voice_;
  std::map<std::string, double> measured_s_;
  Pose2 robot_pose_;                              ///< as last seen (where "on my left" is)
  double robot_speed_m_s_{0.0};                   ///< [m/s] as last seen (the stand-off watch)
  Eigen::Vector2d robot_velocity_m_s_{0.0, 0.0};  ///< [m/s] world frame, as last seen
  double robot_radius_m_{0.0};                    ///< [m] as last seen
  bool robot_known_{false};                       ///< agent states were seen
  std::optional<std::int64_t> latest_agents_utime_;
};

}  // namespace coopnav::dialogue
