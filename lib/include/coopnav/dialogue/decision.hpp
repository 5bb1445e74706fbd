#pragma once
/// @file Decision logic of paper §II-D for one human: three rounds (t_CROSS ≈ 7 s, ≈ 4 s, after
/// crossing), each firing once per interaction, read exactly as in docs/design-readings.md
/// "Decision pipeline". Pure: no clock (time is an input), no I/O; the daemon turns the output into
/// utterance, robot-action and path-assessor-control messages.
///
/// Unknown handling: a branch that needs an UNKNOWN predicate (or an undefined Dir where a side
/// must be spoken) stays silent and records why in RoundOutcome::reason, with one exception, the
/// precautionary dock of round 2 (DecisionConfig::precautionary_dock): when the crossing is near
/// and what is unknown leaves open that the robot is constrained by a human who is not making
/// room, the robot docks and the round says it is degraded. Never a dock from the flowchart on an
/// unknown; a precautionary dock is always marked (RoundOutcome::degraded, "degraded:" in its
/// branch).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/dialogue/stand_off.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav::dialogue {

/// Speech acts; values mirror coopnav_utterance_t.ACT_*.
enum class SpeechAct : std::int8_t {
  kInformDirection = 1,     ///< round 1: "I will pass on your {dir}." (dir = Dir)
  kAskToMove = 2,           ///< round 1: describe the situation, ask to move (dir = opposite(Dir))
  kInformDockIfNeeded = 3,  ///< round 1: both constrained
  kRepeatDirection = 4,     ///< round 2: Dir again (dir = Dir)
  kAskToMoveMore = 5,       ///< round 2: contributing, ask a bit more (dir = opposite(Dir))
  kInformDocking = 6,       ///< round 2: docking, "I will wait here for you to pass."
  kThank = 7,               ///< round 3: the human facilitated
  // Round 2's dock said as what the robot will really do (RoomPlan), not only "wait here":
  kInformWiderPlace = 8,  ///< it goes back to a wider place on its own path
  kInformRetreat = 9,     ///< it backs away the way it came (also: a dock escalated to a retreat)
  kInformStopping = 10,   ///< no move leaves room: it stops where it is
  // A stand-off resolved (stand_off.hpp; not in the paper): the robot goes on.
  kInformGoingFirst = 11,  ///< the person made room: "Thank you, I will go first."
  kInformResuming = 12,    ///< the person did not come to pass the dock: "I will go now."
};
const char* toString(SpeechAct a);

/// Path assessor commands; values mirror coopnav_path_assessor_control_t.COMMAND_*.
enum class RecorderCommand : std::int8_t { kStart = 1, kStop = 2, kReset = 3 };
const char* toString(RecorderCommand c);

/// How the robot would make room for this human if asked now (the band source's check of the
/// passage its dock would leave); values mirror coopnav_bands_t.ROOM_*.
enum class RoomPlan : std::int8_t {
  kUnknown = 0,     ///< not assessed: the dock is said as before ("I will wait here ...")
  kDockHere = 1,    ///< a dock nearby leaves the human a wide enough passage
  kWiderPlace = 2,  ///< only a wider place back along the robot's path does
  kRetreat = 3,     ///< the robot backs away while the human closes
  kNone = 4,        ///< no move leaves room
};
const char* toString(RoomPlan p);

/// Robot actions; values mirror coopnav_robot_action_t.ACTION_*.
/// kGoFirst: not docked, the person made room: the robot passes them now (a stand-off's end).
/// kSlow: the robot drives on at the band source's slow speed while round 2 waits for evidence
/// (MakeTimeConfig); any later action ends it (kResume: on at full speed).
enum class RobotAction : std::int8_t { kDock = 1, kResume = 2, kGoFirst = 3, kSlow = 4 };
const char* toString(RobotAction a);

/// English text templates; "{dir}" is replaced by left_word / right_word.
struct TextTemplates {
  std::string inform_direction{"I will pass on your {dir}."};
  std::string ask_to_move{"It is narrow here. Could you move to your {dir}, please?"};
  std::string inform_dock_if_needed{"It is narrow here. I will wait at the side if needed."};
  std::string repeat_direction{"I am passing on your {dir}."};
  std::string ask_to_move_more{"Could you move a little more to your {dir}, please?"};
  std::string inform_docking{"I will wait here for you to pass."};
  /// The precautionary dock's sentence (DecisionConfig::precautionary_dock), same act. Without
  /// the distance server the dialogue manager cannot know that a wall is near: in an open
  /// corridor the band source finds no dock pose and the robot keeps its band, which gives way
  /// without stopping, so "I will wait here" would be untrue. This promise holds either way.
  std::string inform_precautionary_docking{"I will make room for you to pass."};
  std::string inform_wider_place{"I will go back to a wider place to let you pass."};
  std::string inform_retreat{"I will back up to let you pass."};
  std::string inform_stopping{"I will stop here. Please pass carefully."};
  std::string thank{"Thank you."};
  std::string inform_going_first{"Thank you, I will go first."};
  std::string inform_resuming{"I will go now."};
  /// Shorter wordings of the making-room sentences, said when the full one would end after the
  /// crossing (SpeechTimeline::planFirstFitting): a person about to meet a robot that stops or
  /// backs away is better told in two words than not at all. Each keeps the promise of its long
  /// form; an empty one means there is no shorter wording.
  std::string inform_docking_short{"I will wait."};
  std::string inform_precautionary_docking_short{"I will make room."};
  std::string inform_wider_place_short{"I will go back."};
  std::string inform_retreat_short{"I will back up."};
  std::string inform_stopping_short{"I will stop."};
  std::string left_word{"left"};
  std::string right_word{"right"};
};

/// Renders the template of act with {dir} replaced (every occurrence). dir kUndefined -> "".
std::string renderText(const TextTemplates& templates, SpeechAct act, Side dir);

/// Which judgement of the person's cooperation the decisions before the crossing act on (round
/// 2's IsContributing and the stand-off resolution's "made room"). Round 1 reads none (the
/// flowchart decides it on the situation alone, and the path assessor's window and forecast
/// start with its recorder START); round 3, after the crossing, always reads the paper's
/// IsContributing, the measure of what was done.
enum class CooperationJudgement : std::int8_t {
  /// Paper §II-C: IsContributing = CM > τ over the window since the last reset (the path
  /// assessor's is_contributing). It measures a side step once made: real walkers start theirs
  /// 0.8–2.4 s before the closest approach, after round 2.
  kCm = 0,
  /// The path assessor's forecast p_contributing (assessment/forecast.hpp: the probability that
  /// the person will have stepped >= 0.3 m aside by the crossing) against
  /// DecisionConfig::forecast_threshold; unknown while p_contributing is (NaN on the wire).
  kForecast = 1,
};
const char* toString(CooperationJudgement j);
/// "cm" or "forecast"; false when neither.
bool parseCooperationJudgement(const std::string& s, CooperationJudgement& out);

/// Making time for round 2 (not in the paper). Real walkers start to step aside
/// 0.8–2.4 s before the closest approach, so at round 2 (t_CROSS ≈ 4 s) no judgement of the
/// person knows more than chance. When round 2 is due on the branch that reads the judgement
/// (StillNeedsToContribute and RobotIsConstrained both true) and the forecast is not decisive
/// (p_contributing unknown, or neither it nor 1 - p_contributing reaches `confidence`), the robot
/// slows (RobotAction::kSlow, the band source's slow speed) and round 2 waits: it is decided at
/// the first step where the forecast is decisive, or where a round-2 input that does not read
/// the person changes the branch, or at t_CROSS <= latest_t_cross_s, whatever the forecast then
/// says (the judgement of DecisionConfig::judgement, as without making time). Slower, the robot
/// reaches a given t_CROSS later in the person's approach, and the less far it has to brake
/// and turn, the later a dock stays possible. Only with CooperationJudgement::kForecast (CM
/// has no degree of confidence to wait on).
struct MakeTimeConfig {
  /// false: round 2 as without it (the paper's profile).
  bool enabled{false};
  /// The forecast is decisive when p_contributing >= this or <= 1 - this (0.5..1). 0.85: round 2
  /// then acts on a probability of being right of at least 0.85, the agreement asked of round-2
  /// decisions, as the forecast (calibrated on the real pairs) states it. Not fitted to a run.
  double confidence{0.85};
  /// [s] Round 2 waits at most until t_CROSS <= this (0..round2_latest_t_cross_s). 2.0:
  /// round2_latest_t_cross_s (3 s) is set for a robot at full speed (0.7 m/s), which needs 2.3 s
  /// to stop at its 0.3 m/s^2; at the band source's slow speed (0.3 m/s) it needs 1 s, so the
  /// same margin holds down to 3 - 1.3 ≈ 1.7 s; 2.0 keeps 0.3 s more.
  double latest_t_cross_s{2.0};
};

/// Decision tuning. Defaults in this one place.
struct DecisionConfig {
  double round1_t_cross_s{7.0};  ///< [s] round 1 when t_CROSS first falls to <= this (§II-D)
  double round2_t_cross_s{4.0};  ///< [s] round 2 when t_CROSS first falls to <= this (§II-D)
  /// [s] Round 2 judges how the human responded to round 1's words, so it waits until they have
  /// been heard (DecisionInput::heard_by_s) and this long more: a reaction (≈ 1 s, notes
  /// §7) and a second of moving, for CM to show it. Not in the paper, whose rounds are times to
  /// crossing only: a 3 s sentence said at t_CROSS 7 s ends at 4 s, and judging the human then
  /// judges someone who has not yet heard it. 0 = the paper's reading: no wait at all.
  double round2_response_s{2.0};
  /// [s] ... but round 2 never waits beyond t_CROSS <= this, so that a dock is still possible.
  double round2_latest_t_cross_s{3.0};
  /// Round 2 with an input unknown (RobotIsConstrained, CM, d_h or IsContributing; e.g. the
  /// distance server is down) while nothing known rules a dock out (the robot is not known to be
  /// free, the human not known to have moved enough nor to be moving aside): dock as a precaution
  /// and mark the round degraded. Not in the paper, whose flowchart stays silent on an unknown
  /// (design-readings "unknown never leads to a dock"): silent, a robot with its assessment
  /// half blind drives on towards a person who does not yield, and waiting at the wall for a
  /// few seconds is the safe side of that choice. false: the paper's silent reading.
  bool precautionary_dock{true};
  /// [m] An interaction (round 1, and so every round) begins only with a human the robot is
  /// crossing: the closest approach is still ahead (t_CROSS > 0; at 0 the two are moving apart or
  /// alongside) and the planned centre distance there, d_HR, is at most this. Not in the paper,
  /// whose one human always crosses; in a crowd, the people walking away, and those the robot
  /// passes beyond social distance, are not spoken to. 3.6 m: the outer edge of Hall's social
  /// zone (Hall 1966: social distance 1.2–3.6 m), taken between centres, so bodies are nearer than
  /// that.
  double crossing_range_m{3.6};
  /// The judgement of cooperation round 2 and the stand-off resolution act on (see
  /// CooperationJudgement). kCm: the paper's.
  CooperationJudgement judgement{CooperationJudgement::kCm};
  /// With kForecast: contributing when p_contributing >= this. 0.5: the forecast is a logistic
  /// model fitted by maximum likelihood on the 172 real head-on pairs (config/
  /// path_assessor_forecast.yaml), so its probabilities are calibrated on them, and 0.5 is where
  /// making room and not are equally likely there (the Bayes decision for equal costs; its
  /// held-out accuracy at 2 s before the crossing is 0.677, tools/ctl/README.md "Judgement in
  /// time"). Fixed from that data, not from any scenario.
  double forecast_threshold{0.5};
  TextTemplates templates;
  /// Resolve a stand-off (StandOffWatch) once round 1 has fired and until the crossing: a
  /// mutual wait or a dock the person does not come to pass ends, within a bounded time, in a
  /// decision that is said and done (HumanDecision::resolveStandOff). Not in the paper, whose
  /// robot waits for as long as the person does (issue 44: a silent standstill is a failure).
  /// false: the paper's reading, a dock ends only when the person has passed or left.
  bool resolve_stand_offs{true};
  /// A mutual wait with a person who made room, the robot not docked: the robot goes first
  /// (RobotAction::kGoFirst, said). false: nothing is done then (the round's reason says why).
  bool go_first_when_not_docked{true};
  StandOffConfig stand_off;
  /// Slow down and decide round 2 later when the forecast cannot yet tell (MakeTimeConfig).
  MakeTimeConfig make_time;
};

/// Situation assessor output for this human at one time (coopnav_situation_t).
struct SituationSnapshot {
  std::optional<double> t_cross_s;  ///< [s] from now to closest approach; nullopt = unknown
  Tristate human_needs_to_contribute{Tristate::kUnknown};
  Tristate human_is_constrained{Tristate::kUnknown};
  Tristate robot_is_constrained{Tristate::kUnknown};
  Side dir{Side::kUndefined};    ///< side the robot passes on, as the human sees it
  std::optional<double> d_h_m;   ///< [m] nullopt = unknown
  std::optional<double> d_oh_m;  ///< [m] body clearance away from the robot; nullopt = unknown
  std::optional<double>
      d_hr_m;          ///< [m] |CP_h - CP_r|, the planned passing distance; nullopt = unknown
  std::string reason;  ///< the assessor's why for anything unknown ("" = all known)
  RoomPlan room_plan{RoomPlan::kUnknown};  ///< what a dock for this human would do now
  bool robot_retreating{false};            ///< the band source is backing away (any human)
};

/// Path assessor output for this human (coopnav_path_assessment_t), window since the last reset.
struct PathSnapshot {
  std::optional<double> cm_window_m;             ///< [m] nullopt = no samples
  Tristate is_contributing{Tristate::kUnknown};  ///< CM > τ over the same window
  /// The forecast that the human will have made room by the crossing, in [0, 1]; nullopt =
  /// unknown (no forecast profile, or too little track since the recorder START).
  std::optional<double> p_contributing;
};

/// IsContributing as the decisions before the crossing judge it under `config.judgement`: the
/// path's is_contributing (kCm), or p_contributing >= forecast_threshold (kForecast; unknown
/// while p_contributing is unknown or NaN).
Tristate judgeContributing(const DecisionConfig& config, const PathSnapshot& path);
/// What that judgement read, for a round's branch: "contributing" / "!contributing" /
/// "contributing unknown", with the forecast's probability and threshold under kForecast (e.g.
/// "forecast contributing (p 0.71 >= 0.50)").
std::string describeContributing(const DecisionConfig& config, const PathSnapshot& path);

struct DecisionInput {
  double t_s{0.0};  ///< [s] decision time (the situation's time), any monotonic time base
  SituationSnapshot situation;
  PathSnapshot path;
  bool crossed{false};  ///< the agents have crossed (see CrossedTracker)
  /// [s] when the robot's words said to this human so far have ended (same time base as t_s);
  /// nullopt when nothing was said to it (or the robot is muted).
  std::optional<double> heard_by_s;
  /// The robot and this human now (speeds, distance), for the stand-off watch; nullopt when the
  /// agent states do not hold them (the watch then learns nothing this step).
  std::optional<StandOffInput> motion;
};

struct Utterance {
  SpeechAct act{SpeechAct::kInformDirection};
  /// INFORM/REPEAT: side the robot passes on; ASK_*: side the human is asked to move to;
  /// kUndefined for the others.
  Side direction{Side::kUndefined};
  int round{0};
  std::string text;
  /// Said to resolve a stand-off (HumanDecision::resolveStandOff): nobody is going, so the
  /// words have no crossing to be late for, and the action they announce waits for nothing.
  bool resolves_stand_off{false};
};

/// The wordings of utterance `u`, longest first: its own text, then the shorter wording of the
/// same promise when it is a making-room sentence with one (TextTemplates::*_short) that differs.
std::vector<std::string> wordings(const TextTemplates& templates, const Utterance& u);

/// Record of one fired round: which flowchart branch was taken and why (also when silent).
struct RoundOutcome {
  int round{0};
  double t_s{0.0};
  std::optional<double> t_cross_s;
  std::string branch;  ///< e.g. "needs & !robot_constrained -> inform Dir"
  std::string reason;  ///< why it stayed silent or is degraded, "" when it followed the flowchart
  /// Acted on a fallback, not on the flowchart (the precautionary dock): branch says "degraded:",
  /// reason says what was unknown.
  bool degraded{false};
  /// Round 2 was due and waits for evidence (MakeTimeConfig): no flowchart branch was taken; the
  /// round fires later (its own outcome then).
  bool deferred{false};
};

struct DecisionOutput {
  std::vector<Utterance> utterances;
  std::vector<RecorderCommand> recorder_commands;  ///< in order of issue
  /// With a kStart: the situation it was decided on, whose d_OH and d_h the path assessor judges
  /// the room by (its tau_mode); nullopt when unknown.
  std::optional<double> start_d_oh_m;
  std::optional<double> start_d_h_m;
  std::vector<RobotAction> robot_actions;
  std::vector<RoundOutcome> rounds;  ///< rounds fired at this step (0, 1 or 2 entries)
  bool empty() const {
    return utterances.empty() && recorder_commands.empty() && robot_actions.empty() &&
           rounds.empty();
  }
};

/// Per-human decision state machine of paper §II-D.
/// Round 1 fires at the first step with known t_CROSS <= round1_t_cross_s; round 2 at the first
/// LATER step with t_CROSS <= round2_t_cross_s (never in the same step as round 1, so that its CM
/// has samples since the recorder start); round 3 at the first step with crossed == true. Each
/// fires at most once per interaction, whatever t_CROSS does afterwards. Rounds 1 and 2 are
/// skipped once crossed.
class HumanDecision {
 public:
  explicit HumanDecision(const DecisionConfig& config = {});

  /// Advances the state machine with the latest snapshots; returns what to do now.
  DecisionOutput step(const DecisionInput& input);
  /// The human left the scene: ends the interaction (stops the recorder if it was started, resumes
  /// a docked robot). No further rounds fire.
  DecisionOutput endInteraction(double t_s, const std::string& reason);

  bool roundFired(int round) const;
  bool docked() const { return docked_; }
  /// The robot was slowed for this human (RobotAction::kSlow) and no later action ended it.
  bool slowed() const { return slowed_; }
  const StandOffWatch& standOffWatch() const { return watch_; }
  bool ended() const { return ended_; }

 private:
  void round1(const DecisionInput& in, DecisionOutput& out);
  void round2(const DecisionInput& in, DecisionOutput& out);
  void round3(const DecisionInput& in, DecisionOutput& out);
  /// Round 2 is due: true when it waits for evidence (MakeTimeConfig), the robot slowed (once).
  bool deferRound2(const DecisionInput& in, DecisionOutput& out);
  /// Round 2's fallback when an input is unknown; true when it docked (r filled in).
  bool precautionaryDock(const DecisionInput& in, Tristate still, RoundOutcome& r,
                         DecisionOutput& out);
  /// precautionary: the sentence is TextTemplates::inform_precautionary_docking.
  /// room: the band source's plan for this human; the sentence says that move.
  void dock(DecisionOutput& out, bool precautionary, RoomPlan room);
  void say(SpeechAct act, Side dir, int round, DecisionOutput& out) const;
  /// While docked for this human: a dock that escalated to a retreat is said once.
  void announceRetreat(const DecisionInput& in, DecisionOutput& out);
  /// A stand-off reached (StandOffWatch): decided on the cooperation assessment. Docked: resume,
  /// saying "Thank you, I will go first." when the person made room and the passage fits, else
  /// "I will go now.". Not docked, in a mutual wait: the person made room, the robot goes first
  /// (once per interaction) and says so; the person did not, or going first did not end the
  /// wait, the robot makes room (dock, wider place, retreat: the band source's room plan) and
  /// says so, again at every later stand-off. Never silent (issue 44).
  void resolveStandOff(const DecisionInput& in, StandOff what, DecisionOutput& out);

  DecisionConfig config_;
  bool fired_[3]{false, false, false};
  bool recorder_started_{false};
  bool docked_{false};
  bool retreat_said_{false};
  bool ended_{false};
  bool docked_ever_{false};              ///< a dock was requested in this interaction
  bool went_first_{false};               ///< a stand-off ended in GO_FIRST in this interaction
  bool dock_resolves_stand_off_{false};  ///< the current dock was requested by resolveStandOff
  bool round2_deferred_{false};          ///< round 2 waits for evidence (MakeTimeConfig)
  bool slowed_{false};                   ///< kSlow requested, no later action yet
  StandOffWatch watch_;
};

/// Crossed detection state for one human (design-readings: the robot is behind the human along
/// the human's heading, having been ahead).
struct CrossedTracker {
  bool seen_ahead{false};
  bool crossed{false};  ///< latched once true
  /// The human's heading when the robot was first seen ahead (unit, world): "behind" is judged
  /// along it from then on, so that a heading that flips later (a tracker's heading from the
  /// noisy velocity of a person standing and waiting) does not put the robot behind them.
  Eigen::Vector2d axis{0.0, 0.0};
};

/// [m] Robot position along the human's heading, relative to the human (> 0 = ahead).
double robotAlongHumanHeading_m(const Pose2& human, const Eigen::Vector2d& robot_m);

/// Pure update of the crossed detection with hysteresis: "ahead" once the robot is more than
/// hysteresis_m ahead along the human's heading, "crossed" once, having been ahead, it is more
/// than hysteresis_m behind along the heading it was first seen ahead on (CrossedTracker::axis),
/// while within max_distance_m of the human. The robot gets behind a person by passing them,
/// near; far off, "behind" is a person who turned back: no crossing.
/// Non-finite input leaves the state unchanged.
CrossedTracker updateCrossed(CrossedTracker previous, const Pose2& human,
                             const Eigen::Vector2d& robot_m, double hysteresis_m = 0.2,
                             double max_distance_m = 5.0);

}  // namespace coopnav::dialogue
