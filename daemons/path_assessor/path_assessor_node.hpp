#pragma once
/// @file Human path assessor (paper §II-C): one PathRecorder per human, fed every agent-states
/// message; publishes CA, CM and IsContributing per human per agent-states message, then
/// acknowledges the step. Recording is started, stopped and reset by the dialogue manager's
/// control messages; in lockstep the work of step k waits for the dialogue manager's ack of
/// step k-1, so the controls it issued at k-1 are applied first (docs/lockstep.md).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/assessment/path_assessment.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_node.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

struct PathAssessorNodeConfig {
  /// The lib recorder's own settings, read in place: its initialisers are the only defaults.
  assessment::PathAssessorConfig recorder;
  /// [ms] how long step k waits for the dialogue manager's ack of k-1 before running degraded.
  int gate_timeout_ms{2000};

  template <class V>
  void visit(V& v) {
    v("sample_period_s", recorder.sample_period_s, Range{1e-3, 10.0});
    v("gamma", recorder.gamma, Range{1e-6, 1.0});
    v("tau_m", recorder.tau_m, Range{-10.0, 10.0});
    v("side_deadband_m", recorder.side_deadband_m, Range{0.0, 5.0});
    v("history_s", recorder.history_s, Range{0.0, 60.0});
    v("gate_timeout_ms", gate_timeout_ms, Range{1, 600000});
  }

  const assessment::PathAssessorConfig& recorderConfig() const { return recorder; }
};

class PathAssessorNode {
 public:
  using Config = PathAssessorNodeConfig;
  PathAssessorNode(const Config& config, Runtime& runtime);

  /// The recorder of a human, nullptr if that human was never seen (tests, diagnostics).
  const assessment::PathRecorder* recorder(std::int32_t human_id) const;

 private:
  struct Human {
    assessment::PathRecorder recorder;
    /// Reference paths by the step they were published at (-1 free-running); a START of step j
    /// uses the latest one published at or before j, whatever arrived since.
    std::map<std::int64_t, Path2> references;
    bool seen_in_states{false};
  };

  void onAgentStates(const agent_states_t& msg);
  void onReferencePaths(const reference_paths_t& msg);
  void onControl(const path_assessor_control_t& msg);
  /// Applies one recorder control; throws RejectedMessage / DroppedMessage as a handler does.
  void applyControl(const RecorderControl& c);
  /// Lockstep: the controls of steps before `step`, in arrival order (each logged on failure).
  void applyControlsBefore(std::int64_t step);
  void assess(const AgentStatesSnapshot& states, StepNode::Step& step);
  Human& human(std::int32_t id);
  /// [s] message time on the node's time base (utime of the first message seen), so the
  /// recorder's grid arithmetic works on small numbers whatever the clock's epoch.
  double seconds(std::int64_t utime);

  Config config_;
  Runtime& runtime_;
  std::vector<RecorderControl> controls_;  ///< lockstep controls not yet applied
  std::map<std::int32_t, Human> humans_;
  std::optional<std::int64_t> base_utime_;
  std::map<std::int32_t, std::int64_t> last_seen_utime_;  ///< per human: forget those gone
  StepNode steps_;  ///< last: steps still held when the node goes away are not acknowledged
};

}  // namespace coopnav
