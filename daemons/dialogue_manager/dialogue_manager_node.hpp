#pragma once
/// @file Dialogue manager: the decision pipeline of paper §II-D run per human (lib/dialogue's
/// HumanDecision), fed by the situation and path assessors, emitting utterances, robot actions
/// and path-assessor controls. In lockstep it acts on step k once situation_assessor and
/// path_assessor have acknowledged k (docs/lockstep.md row 4), then acknowledges k; free-running
/// (step -1) it acts on each situation with the latest path assessment of that human.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/dialogue/decision.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
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
    v("thank", thank);
    v("left_word", left_word);
    v("right_word", right_word);
    for (const auto* t :
         {&inform_direction, &ask_to_move, &inform_dock_if_needed, &repeat_direction,
          &ask_to_move_more, &inform_docking, &inform_precautionary_docking, &thank})
      v.require(!t->empty(), "templates", "no template may be empty");
    v.require(!left_word.empty() && !right_word.empty(), "left_word",
              "left_word and right_word must not be empty");
  }
};

struct DialogueManagerConfig {
  double round1_t_cross_s{dialogue::DecisionConfig{}.round1_t_cross_s};
  double round2_t_cross_s{dialogue::DecisionConfig{}.round2_t_cross_s};
  bool precautionary_dock{dialogue::DecisionConfig{}.precautionary_dock};
  double crossed_hysteresis_m{0.2};
  double human_gone_s{2.0};
  int gate_timeout_ms{2000};
  bool gate_wait_for_unseen{true};
  TemplatesConfig templates;
  SpeechConfig speech;

  template <class V>
  void visit(V& v) {
    v("round1_t_cross_s", round1_t_cross_s, Range{0.5, 60.0});
    v("round2_t_cross_s", round2_t_cross_s, Range{0.0, 60.0});
    v("precautionary_dock", precautionary_dock);
    v("crossed_hysteresis_m", crossed_hysteresis_m, Range{0.0, 5.0});
    v("human_gone_s", human_gone_s, Range{0.1, 600.0});
    v("gate_timeout_ms", gate_timeout_ms, Range{10.0, 600000.0});
    v("gate_wait_for_unseen", gate_wait_for_unseen);
    v("templates", templates);
    v("speech", speech);
    v.require(round2_t_cross_s < round1_t_cross_s, "round2_t_cross_s",
              "must be less than round1_t_cross_s (round 2 comes after round 1)");
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

 private:
  /// Everything received for one step, applied in one go when the gate lets the step run.
  struct SituationIn {
    DialogueStamp stamp;
    dialogue::SituationSnapshot snapshot;
  };
  struct StepInputs {
    std::optional<AgentStatesSnapshot> agents;
    std::map<std::int32_t, dialogue::PathSnapshot> paths;
    std::map<std::int32_t, SituationIn> situations;
    std::int64_t utime{-1};  ///< the step's input time (first message of it)
  };
  struct Human {
    explicit Human(const dialogue::DecisionConfig& c) : decision(c) {}
    dialogue::HumanDecision decision;
    dialogue::SituationSnapshot last_situation;
  };
  struct Tracked {
    dialogue::CrossedTracker crossed;
    std::int64_t last_seen_utime{-1};
  };
  struct SpeechItem {
    std::string text;
    std::string wav_stem;
  };

  void onSituation(const situation_t& msg);
  void onPathAssessment(const path_assessment_t& msg);
  void onAgentStates(const agent_states_t& msg);
  void onStepAck(const step_ack_t& ack);

  /// Files an input of `step` under its bucket: `fill` converts (and may throw RejectedMessage);
  /// the step's work is submitted once, after the first input is filed, also when it was
  /// rejected, so that the step is acknowledged whatever happens. Throws RejectedMessage for a
  /// step that goes backwards.
  /// `publisher`/`channel`/`key` identify the message for the step gate's counts: a repeat of
  /// one already filed is not filed again (a repeat of the world's agent states re-sends our
  /// answers of the latest steps instead).
  template <class Fill>
  void fileInput(std::int64_t step, std::int64_t utime, const char* publisher, const char* channel,
                 const std::string& key, Fill fill);
  /// Schedules the work of `step`, whose inputs are being filed in inputs_[step].
  void schedule(std::int64_t step);
  void runStep(StepNode::Step& run);
  void process(StepNode::Step& run, StepInputs& in);
  void decide(StepNode::Step& run, std::int32_t id, const DialogueStamp& stamp,
              const dialogue::SituationSnapshot& situation);
  void emit(StepNode::Step& run, const DialogueStamp& stamp, const dialogue::DecisionOutput& out,
            std::optional<double> t_cross_s);

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
  std::map<std::int64_t, StepInputs> inputs_;  ///< per step: its inputs until it runs
  std::int64_t newest_step_{-1};
  std::map<std::int32_t, Human> humans_;
  std::map<std::int32_t, Tracked> tracked_;
  std::map<std::int32_t, dialogue::PathSnapshot> latest_path_;
  std::int64_t latest_agents_utime_{-1};
  std::vector<SpeechItem> speech_pending_;
  bool degraded_{false};
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
