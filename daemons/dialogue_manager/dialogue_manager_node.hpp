#pragma once
/// @file Dialogue manager: the decision pipeline of paper §II-D run per human, fed by the
/// situation and path assessors, emitting utterances, robot actions and path-assessor controls.
/// The node decodes and files each input under its step, hands the step to lib/dialogue's
/// Session (the multi-person logic: one record per person) and publishes what it returns. In
/// lockstep it acts on step k once situation_assessor and path_assessor have acknowledged k
/// (docs/lockstep.md row 4), then acknowledges k; free-running (step -1) it acts on each
/// situation with the latest path assessment of that human.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config/same_way_yaml.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/dialogue/crowd.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/dialogue/session.hpp"
#include "coopnav/dialogue/speech_timing.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
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
  bool go_first{dialogue::DecisionConfig{}.go_first_when_not_docked};
  template <class V>
  void visit(V& v) {
    v("resolve", resolve);
    v("go_first", go_first);
    v("robot_still_m_s", robot_still_m_s, Range{0.0, 1.0});
    v("robot_dither_m_s", robot_dither_m_s, Range{0.0, 2.0});
    v("human_still_m_s", human_still_m_s, Range{0.0, 2.0});
    v("near_gap_m", near_gap_m, Range{0.0, 20.0});
    v("t_cross_progress_s", t_cross_progress_s, Range{0.0, 60.0});
    v("mutual_wait_s", mutual_wait_s, Range{0.1, 600.0});
    v("dock_progress_m", dock_progress_m, Range{0.0, 20.0});
    v("dock_wait_s", dock_wait_s, Range{0.1, 3600.0});
    v("backing_off_s", backing_off_s, Range{0.1, 600.0});
  }
};

/// Behind a person ahead walking the robot's way (lib/dialogue/overtake_words.hpp); the defaults
/// are lib/dialogue's.
struct OvertakeWordsYaml : dialogue::OvertakeWordsConfig {
  template <class V>
  void visit(V& v) {
    v("enabled", enabled);
    visitSameWayKeys(v, same_way);
    v("pass_clearance_m", pass_clearance_m, Range{0.0, 2.0});
    v("announce_gap_m", announce_gap_m, Range{0.0, 50.0});
    v("retry_s", retry_s, Range{0.0, 600.0});
    v("text", text);
  }
};

/// Slow down and decide round 2 later while the forecast cannot tell (lib/dialogue/decision.hpp
/// MakeTimeConfig; README "Making time"); defaults: lib's.
struct MakeTimeYaml : dialogue::MakeTimeConfig {
  template <class V>
  void visit(V& v) {
    v("enabled", enabled);
    v("confidence", confidence, Range{0.5, 1.0});
    v("latest_t_cross_s", latest_t_cross_s, Range{0.0, 60.0});
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
  OvertakeWordsYaml overtake;
  MakeTimeYaml make_time;
  double crossed_hysteresis_m{dialogue::SessionConfig{}.crossed_hysteresis_m};
  double crossed_max_distance_m{dialogue::SessionConfig{}.crossed_max_distance_m};
  double human_gone_s{dialogue::SessionConfig{}.human_gone_s};
  /// [s] A path assessment older than this is not acted on (dialogue::SessionConfig).
  double path_max_age_s{dialogue::SessionConfig{}.path_max_age_s};
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
  /// Words announcing a change of what the robot does (it makes room, or goes first) cut the
  /// words being said when they would otherwise be too late (SpeechTimeline::planFirstFitting).
  bool interrupt_for_change{true};
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
    v("overtake", overtake);
    v("make_time", make_time);
    v("crossed_hysteresis_m", crossed_hysteresis_m, Range{0.0, 5.0});
    v("crossed_max_distance_m", crossed_max_distance_m, Range{0.1, 100.0});
    v("human_gone_s", human_gone_s, Range{0.1, 600.0});
    v("path_max_age_s", path_max_age_s, Range{0.05, 600.0});
    v("gate_timeout_ms", gate_timeout_ms, Range{10.0, 600000.0});
    v("gate_wait_for_unseen", gate_wait_for_unseen);
    v("assessment_profile", assessment_profile, OneOf{{"paper", "calibrated", "custom"}});
    v("muted", muted);
    v("interrupt_for_change", interrupt_for_change);
    v("templates", templates);
    v("speech", speech);
    v.require(round2_t_cross_s < round1_t_cross_s, "round2_t_cross_s",
              "must be less than round1_t_cross_s (round 2 comes after round 1)");
    v.require(round2_latest_t_cross_s <= round2_t_cross_s, "round2_latest_t_cross_s",
              "must not exceed round2_t_cross_s (it bounds how long round 2 waits)");
    v.require(make_time.latest_t_cross_s <= round2_latest_t_cross_s, "make_time.latest_t_cross_s",
              "must not exceed round2_latest_t_cross_s (making time only waits longer)");
    v.require(!make_time.enabled || judgement == "forecast", "make_time.enabled",
              "needs judgement: forecast (it waits for the forecast to be decisive)");
    v("limits", limits);
  }
  dialogue::DecisionConfig decisionConfig() const;
  dialogue::SessionConfig sessionConfig() const;
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
  const dialogue::HumanDecision* decision(std::int32_t id) const { return session_.decision(id); }
  std::size_t pendingSteps() const { return steps_->pending(); }
  const SpeechOutput& speech() const { return speech_; }
  /// How long saying `text` takes [s]: measured with the speech program at start when speech is
  /// on, else estimated (dialogue::estimateSpeechDuration).
  double speechDuration(const std::string& text) const { return session_.speechDuration(text); }
  /// For tests: ids with per-id state (a decision, a position or a path assessment).
  std::size_t idsKept() const { return session_.idsKept(); }
  /// For tests: decisions kept (one per human).
  std::size_t humansKept() const { return session_.humansKept(); }
  /// For tests: the longest text from a message kept (a situation's reason) [bytes].
  std::size_t longestKeptTextBytes() const;

 private:
  /// Everything received for one step, handed to the session in one go when the gate lets the
  /// step run.
  struct StepInputs {
    dialogue::SessionInput in;
    bool has_utime{false};  ///< in.utime is set (first message of the step, or the clock's)
  };
  /// Files a converted input into its step's bucket (may throw RejectedMessage: over a cap).
  using Store = std::function<void(StepInputs&)>;

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
  /// The message clock resynchronised at `utime`: the per-id times are re-based on it.
  void onResync(std::int64_t utime);
  /// `utime` if the clock has none or it is within limits.max_time_jump_s of it, else the clock's
  /// time (an ack stamped far off never stamps a step).
  std::int64_t nearClock(std::int64_t utime) const;
  std::size_t maxIds() const { return static_cast<std::size_t>(runtime_.limits().max_ids); }
  std::size_t maxTextBytes() const { return runtime_.limits().maxTextBytes(); }
  void runStep(StepNode::Step& run);
  /// Publishes what the session decided, in its order, and logs its notes.
  void publish(StepNode::Step& run, const dialogue::SessionOutput& out);

  Config config_;
  Runtime& runtime_;
  std::int64_t last_done_step_{-1};  ///< latest lockstep step acted on
  /// A first live step after 0 without a journal is a restart that lost its state: the session
  /// is told (Session::joinLate) and decides nothing for the humans already there.
  bool first_step_seen_{false};
  SpeechOutput speech_;
  std::map<std::int64_t, StepInputs> inputs_;  ///< per step: its inputs until it runs
  std::int64_t newest_step_{-1};
  /// Everyone in the scene, one record per person: the logic of a step.
  dialogue::Session session_;
  /// The time of every input, guarded: a message stamped far from it is rejected, so one
  /// situation stamped INT64_MAX cannot pin the times below (docs/bad-inputs.md "Caps").
  MessageClock clock_;
  /// The assessors' acked steps: one far off the others is refused (onStepAck).
  JumpGuard ack_steps_;
  std::vector<dialogue::SpeechRequest> speech_pending_;
  bool degraded_{false};
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
