#pragma once
/// @file Dialogue manager: the decision pipeline of paper §II-D run per human (lib/dialogue's
/// HumanDecision), fed by the situation and path assessors, emitting utterances, robot actions
/// and path-assessor controls. In lockstep it acts on step k once situation_assessor and
/// path_assessor have acknowledged k (docs/lockstep.md row 4), then acknowledges k; free-running
/// (step -1) it acts on each situation with the latest path assessment of that human.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/dialogue/crowd.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/dialogue/speech_timing.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "runtime/id_recency.hpp"
#include "runtime/limits.hpp"
#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_node.hpp"
#include "speech_output.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"
#include "wire/dialogue.hpp"

namespace coopnav {

/// English templates; the defaults are lib/dialogue's TextTemplates.
struct TemplatesConfig : dialogue::TextTemplates {
  template <class V>
  void visit(V& v) {
    v("inform_direction", inform_direction);
    v("ask_to_move", ask_to_move);
    v("inform_dock_if_needed", inform_dock_if_needed);
    v("repeat_direction", repeat_direction);
    v("ask_to_move_more", ask_to_move_more);
    v("inform_docking", inform_docking);
    v("inform_precautionary_docking", inform_precautionary_docking);
    v("inform_wider_place", inform_wider_place);
    v("inform_retreat", inform_retreat);
    v("inform_stopping", inform_stopping);
    v("thank", thank);
    v("inform_going_first", inform_going_first);
    v("inform_resuming", inform_resuming);
    v("inform_docking_short", inform_docking_short);
    v("inform_precautionary_docking_short", inform_precautionary_docking_short);
    v("inform_wider_place_short", inform_wider_place_short);
    v("inform_retreat_short", inform_retreat_short);
    v("inform_stopping_short", inform_stopping_short);
    v("left_word", left_word);
    v("right_word", right_word);
    for (const auto* t :
         {&inform_direction, &ask_to_move, &inform_dock_if_needed, &repeat_direction,
          &ask_to_move_more, &inform_docking, &inform_precautionary_docking, &inform_wider_place,
          &inform_retreat, &inform_stopping, &thank, &inform_going_first, &inform_resuming})
      v.require(!t->empty(), "templates", "no template may be empty");
    v.require(!left_word.empty() && !right_word.empty(), "left_word",
              "left_word and right_word must not be empty");
  }
};

/// Groups and addresses when several people are in the scene (lib/dialogue/crowd.hpp).
struct CrowdConfigYaml : dialogue::CrowdConfig {
  template <class V>
  void visit(V& v) {
    v("group_distance_m", group_distance_m, Range{0.0, 10.0});
    v("group_velocity_diff_m_s", group_velocity_diff_m_s, Range{0.0, 5.0});
    v("ahead_half_angle_rad", ahead_half_angle_rad, Range{0.0, 1.5});
  }
};

/// Stand-offs resolved (lib/dialogue/stand_off.hpp); the defaults are lib/dialogue's.
struct StandOffConfigYaml : dialogue::StandOffConfig {
  bool resolve{dialogue::DecisionConfig{}.resolve_stand_offs};
  template <class V>
  void visit(V& v) {
    v("resolve", resolve);
    v("robot_still_m_s", robot_still_m_s, Range{0.0, 1.0});
    v("human_still_m_s", human_still_m_s, Range{0.0, 2.0});
    v("near_gap_m", near_gap_m, Range{0.0, 20.0});
    v("t_cross_progress_s", t_cross_progress_s, Range{0.0, 60.0});
    v("mutual_wait_s", mutual_wait_s, Range{0.1, 600.0});
    v("dock_progress_m", dock_progress_m, Range{0.0, 20.0});
    v("dock_wait_s", dock_wait_s, Range{0.1, 3600.0});
  }
};

struct DialogueManagerConfig {
  double round1_t_cross_s{dialogue::DecisionConfig{}.round1_t_cross_s};
  double round2_t_cross_s{dialogue::DecisionConfig{}.round2_t_cross_s};
  double round2_response_s{dialogue::DecisionConfig{}.round2_response_s};
  double round2_latest_t_cross_s{dialogue::DecisionConfig{}.round2_latest_t_cross_s};
  bool precautionary_dock{dialogue::DecisionConfig{}.precautionary_dock};
  double crossing_range_m{dialogue::DecisionConfig{}.crossing_range_m};
  /// The judgement of cooperation round 2 and the stand-offs act on (dialogue::
  /// CooperationJudgement): "cm" (the paper's IsContributing) or "forecast" (p_contributing >=
  /// forecast_threshold).
  std::string judgement{dialogue::toString(dialogue::DecisionConfig{}.judgement)};
  double forecast_threshold{dialogue::DecisionConfig{}.forecast_threshold};
  CrowdConfigYaml crowd;
  StandOffConfigYaml stand_off;
  double crossed_hysteresis_m{0.2};
  double human_gone_s{2.0};
  /// [s] A path assessment older than this (message time, against the situation decided on) is
  /// not acted on: CM and IsContributing are unknown (round 2 then takes its precautionary
  /// dock, or stays silent). The path assessor publishes every planning cycle (10 Hz); a
  /// lockstep run never sees an older one (each step waits for it), a free-running one does
  /// when the path assessor or its host is gone.
  double path_max_age_s{0.5};
  int gate_timeout_ms{2000};
  bool gate_wait_for_unseen{true};
  /// The path assessment profile acted on (path_assessment_t.profile; config/path_assessor.yaml
  /// is `paper`, config/path_assessor_calibrated.yaml `calibrated`): assessments of another
  /// profile are rejected, so a path assessor started with the wrong file is noticed.
  std::string assessment_profile{"paper"};
  /// Decide and act as usual, say nothing: every utterance is published with DELIVERY_MUTED (the
  /// log keeps what would have been said) and none is spoken or heard. The twin of a speaking
  /// run, to measure what the words change (docs/population.md "Speaking and muted").
  bool muted{false};
  TemplatesConfig templates;
  SpeechConfig speech;

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("round1_t_cross_s", round1_t_cross_s, Range{0.5, 60.0});
    v("round2_t_cross_s", round2_t_cross_s, Range{0.0, 60.0});
    v("round2_response_s", round2_response_s, Range{0.0, 30.0});
    v("round2_latest_t_cross_s", round2_latest_t_cross_s, Range{0.0, 60.0});
    v("precautionary_dock", precautionary_dock);
    v("crossing_range_m", crossing_range_m, Range{0.5, 50.0});
    v("judgement", judgement, OneOf{{"cm", "forecast"}});
    v("forecast_threshold", forecast_threshold, Range{0.0, 1.0});
    v("crowd", crowd);
    v("stand_off", stand_off);
    v("crossed_hysteresis_m", crossed_hysteresis_m, Range{0.0, 5.0});
    v("human_gone_s", human_gone_s, Range{0.1, 600.0});
    v("path_max_age_s", path_max_age_s, Range{0.05, 600.0});
    v("gate_timeout_ms", gate_timeout_ms, Range{10.0, 600000.0});
    v("gate_wait_for_unseen", gate_wait_for_unseen);
    v("assessment_profile", assessment_profile, OneOf{{"paper", "calibrated", "custom"}});
    v("muted", muted);
    v("templates", templates);
    v("speech", speech);
    v.require(round2_t_cross_s < round1_t_cross_s, "round2_t_cross_s",
              "must be less than round1_t_cross_s (round 2 comes after round 1)");
    v.require(round2_latest_t_cross_s <= round2_t_cross_s, "round2_latest_t_cross_s",
              "must not exceed round2_t_cross_s (it bounds how long round 2 waits)");
    v("limits", limits);
  }
  dialogue::DecisionConfig decisionConfig() const;
  /// speech.wav_dir and a speech.program with a '/' are relative to the config file's folder.
  void resolvePaths(const std::string& base_dir);
};

class DialogueManagerNode {
 public:
  using Config = DialogueManagerConfig;
  static constexpr const char* kSituationAssessor = "situation_assessor";
  static constexpr const char* kPathAssessor = "path_assessor";

  DialogueManagerNode(const Config& config, Runtime& runtime);

  /// For tests: the decision of human `id`, or nullptr before its first situation.
  const dialogue::HumanDecision* decision(std::int32_t id) const;
  std::size_t pendingSteps() const { return steps_->pending(); }
  const SpeechOutput& speech() const { return speech_; }
  /// How long saying `text` takes [s]: measured with the speech program at start when speech is
  /// on, else estimated (dialogue::estimateSpeechDuration).
  double speechDuration(const std::string& text) const;
  /// For tests: ids with per-id state (a decision, a crossed tracker or a path assessment).
  std::size_t idsKept() const { return heard_.size(); }
  /// For tests: decisions kept (one per human).
  std::size_t humansKept() const { return humans_.size(); }
  /// For tests: the longest text from a message kept (a situation's reason) [bytes].
  std::size_t longestKeptTextBytes() const;

 private:
  /// A path assessment and its message time: one older than path_max_age_s is not acted on.
  struct StampedPath {
    dialogue::PathSnapshot snapshot;
    std::int64_t utime{0};
  };
  /// Everything received for one step, applied in one go when the gate lets the step run.
  struct SituationIn {
    DialogueStamp stamp;
    dialogue::SituationSnapshot snapshot;
  };
  struct StepInputs {
    std::optional<AgentStatesSnapshot> agents;
    std::map<std::int32_t, StampedPath> paths;
    std::map<std::int32_t, SituationIn> situations;
    std::int64_t utime{0};  ///< the step's input time (first message of it, or the clock's)
    bool has_utime{false};
  };
  struct Human {
    explicit Human(const dialogue::DecisionConfig& c) : decision(c) {}
    dialogue::HumanDecision decision;
    dialogue::SituationSnapshot last_situation;
    std::optional<double> heard_by_s;          ///< [s] when the words said to it so far have ended
    std::int64_t stale_path_logged_utime{-1};  ///< the stale assessment last warned about
  };
  struct Tracked {
    dialogue::CrossedTracker crossed;
    std::int64_t last_seen_utime{0};         ///< set when the human is first seen
    Eigen::Vector2d position_m{0.0, 0.0};    ///< [m] as last seen (track continuity)
    Eigen::Vector2d velocity_m_s{0.0, 0.0};  ///< [m/s] as last seen
    double radius_m{0.3};                    ///< [m] as last seen
  };
  /// A new id where a human with an interaction (open or ended) was lost and heading: the
  /// tracker switched ids (lib/geometry/track_continuity.hpp); the interaction goes on under the
  /// new id.
  void continueSwitchedIds(const AgentStatesSnapshot& agents);
  /// Files a converted input into its step's bucket (may throw RejectedMessage: over a cap).
  using Store = std::function<void(StepInputs&)>;
  struct SpeechItem {
    std::string text;
    std::string wav_stem;
  };

  /// Measures every template text with the speech program (start-up, speech on).
  void measureTemplates();
  void onSituation(const situation_t& msg);
  void onPathAssessment(const path_assessment_t& msg);
  void onAgentStates(const agent_states_t& msg);
  void onStepAck(const step_ack_t& ack);

  /// Files an input of `step` under its bucket: `convert` converts (and may throw
  /// RejectedMessage) and returns the Store that files it; an input stamped too far from the
  /// clock is rejected. The step's work is submitted once, after the first input is filed, also
  /// when it was rejected, so that the step is acknowledged whatever happens. Throws
  /// RejectedMessage for a step that goes backwards.
  /// `publisher`/`channel`/`key` identify the message for the step gate's counts: a repeat of
  /// one already filed is not filed again (a repeat of the world's agent states re-sends our
  /// answers of the latest steps instead).
  template <class Convert>
  void fileInput(std::int64_t step, std::int64_t utime, const char* publisher, const char* channel,
                 const std::string& key, Convert convert);
  /// Schedules the work of `step`, whose inputs are being filed in inputs_[step].
  void schedule(std::int64_t step);
  /// Offers a message's utime to the clock: true when the message may be used; false when it is
  /// stamped too far from the clock (the caller rejects it). A resync re-bases the per-id times.
  bool clockAccepts(std::int64_t utime);
  /// `utime` if the clock has none or it is within limits.max_time_jump_s of it, else the clock's
  /// time (an ack stamped far off never stamps a step).
  std::int64_t nearClock(std::int64_t utime) const;
  /// The clock's time; `fallback` before any input was accepted.
  std::int64_t clockNow(std::int64_t fallback) const { return clock_.now().value_or(fallback); }
  std::size_t maxIds() const { return static_cast<std::size_t>(runtime_.limits().max_ids); }
  std::size_t maxTextBytes() const { return runtime_.limits().maxTextBytes(); }
  void runStep(StepNode::Step& run);
  void process(StepNode::Step& run, StepInputs& in);
  /// What one human's decision produced at this step, emitted once every human has decided (the
  /// crowd logic judges their utterances together).
  struct Decided {
    DialogueStamp stamp;
    dialogue::DecisionOutput out;
    std::optional<double> t_cross_s;
  };
  Decided decide(const StepNode::Step& run, std::int32_t id, const DialogueStamp& stamp,
                 const dialogue::SituationSnapshot& situation);
  /// Emits the step's decisions, their utterances addressed, told once per group and never
  /// contradicting each other (lib/dialogue/crowd.hpp).
  void emitDecided(StepNode::Step& run, std::vector<Decided>& decided);
  /// Ends the interaction of every human absent from the agent states for human_gone_s.
  void endAbsent(StepNode::Step& run, const AgentStatesSnapshot& agents);
  /// Forgets ids not heard of for limits.forget_after_s (message time) and the least recently
  /// heard of beyond limits.max_ids; a human whose interaction is still open has it ended first
  /// (recorder stopped, a dock resumed). One log line per batch.
  void forgetStale(StepNode::Step& run);
  void forget(std::int32_t id);
  /// `quiet`: no log line per round (an interaction ended by forgetting it: one line per batch).
  /// `coordinated`: per utterance of `out`, what the crowd logic made of it (nullptr: said as
  /// decided, to nobody else).
  void emit(StepNode::Step& run, const DialogueStamp& stamp, const dialogue::DecisionOutput& out,
            std::optional<double> t_cross_s, bool quiet = false,
            const std::vector<const dialogue::CoordinatedUtterance*>* coordinated = nullptr);

  Config config_;
  dialogue::DecisionConfig decision_config_;
  Runtime& runtime_;
  std::int64_t last_done_step_{-1};  ///< latest lockstep step acted on
  /// Joined a run after its step 0 without a journal (a restart that lost its state): the humans
  /// already there may have heard rounds this process does not know of, so it decides nothing
  /// for them (no repeated round, no dock on a guess) and says so.
  bool joined_late_{false};
  bool first_step_seen_{false};
  std::set<std::int32_t> history_unknown_;
  SpeechOutput speech_;
  /// Measured durations of every template text (both sides), when speech is on.
  std::map<std::string, double> measured_s_;
  /// The robot's one voice: when each utterance starts, and whether it is said at all.
  dialogue::SpeechTimeline voice_;
  std::map<std::int64_t, StepInputs> inputs_;  ///< per step: its inputs until it runs
  std::int64_t newest_step_{-1};
  std::map<std::int32_t, Human> humans_;
  std::map<std::int32_t, Tracked> tracked_;
  std::map<std::int32_t, StampedPath> latest_path_;
  dialogue::CrowdConversation crowd_;
  Pose2 robot_pose_;             ///< as last seen in the agent states (where "on my left" is)
  double robot_speed_m_s_{0.0};  ///< [m/s] as last seen (the stand-off watch)
  double robot_radius_m_{0.0};   ///< [m] as last seen
  bool robot_known_{false};      ///< agent states were seen
  /// The time of every input, guarded: a message stamped far from it is rejected, so one
  /// situation stamped INT64_MAX cannot pin the times below (docs/bad-inputs.md "Caps").
  MessageClock clock_;
  /// The assessors' acked steps: one far off the others is refused (onStepAck).
  JumpGuard ack_steps_;
  /// Every id with per-id state (humans_, tracked_, latest_path_, history_unknown_), by when it
  /// was last heard of on any input: the order in which ids are forgotten.
  IdRecency heard_;
  /// Ids seen in the agent states whose absence was not yet handled, by when last seen.
  IdRecency present_;
  /// Humans whose decision began while they were absent from the agent states: their absence is
  /// judged at the next agent states (they are not in present_).
  std::set<std::int32_t> judge_absence_;
  std::optional<std::int64_t> latest_agents_utime_;
  std::vector<SpeechItem> speech_pending_;
  bool degraded_{false};
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
