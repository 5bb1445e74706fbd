#pragma once
/// @file Human path assessor (paper §II-C): one PathRecorder per human, fed every agent-states
/// message; publishes CA, CM and IsContributing per human per agent-states message, then
/// acknowledges the step. Recording is started, stopped and reset by the dialogue manager's
/// control messages; in lockstep the work of step k waits for the dialogue manager's ack of
/// step k-1, so the controls it issued at k-1 are applied first (docs/lockstep.md). Beside CM, a
/// forecast of cooperation per human (assessment::CooperationForecaster, forecast_profile) over the
/// same interaction: started at START, fed the same observations, stopped at STOP.

#include <cstdint>
#include <list>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/assessment/forecast.hpp"
#include "coopnav/assessment/path_assessment.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "runtime/id_recency.hpp"
#include "runtime/limits.hpp"
#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_node.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

struct PathAssessorNodeConfig {
  /// The lib recorder's own settings, read in place: its initialisers are the only defaults.
  assessment::PathAssessorConfig recorder;
  /// recorder.tau_mode by name ("fixed" | "room"); its default is the lib's.
  std::string tau_mode{assessment::toString(assessment::PathAssessorConfig{}.tau_mode)};
  /// recorder.side_rule by name ("path_side" | "human_side"); its default is the lib's.
  std::string side_rule{assessment::toString(assessment::PathAssessorConfig{}.side_rule)};
  /// Name of the assessment profile these settings are (published in every path_assessment_t;
  /// the dialogue manager acts only on the profile it is configured for): `paper` (the paper's
  /// γ, τ and rules, config/path_assessor.yaml), `calibrated` (fitted on real walkers,
  /// config/path_assessor_calibrated.yaml) or `custom`.
  std::string profile{"paper"};
  /// The forecast profile (coopnav_ctl forecast --write-profile;
  /// config/path_assessor_forecast.yaml), relative to the config file's folder. "" = no forecast:
  /// p_contributing is published NaN.
  std::string forecast_profile;
  /// [ms] how long step k waits for the dialogue manager's ack of k-1 before running degraded.
  int gate_timeout_ms{2000};

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("profile", profile, OneOf{{"paper", "calibrated", "custom"}});
    v("sample_period_s", recorder.sample_period_s, Range{1e-3, 10.0});
    v("gamma", recorder.gamma, Range{1e-6, 1.0});
    v("tau_m", recorder.tau_m, Range{-10.0, 10.0});
    v("tau_mode", tau_mode,
      OneOf{{assessment::toString(assessment::TauMode::kFixed),
             assessment::toString(assessment::TauMode::kRoom)}});
    v("room_fraction", recorder.room_fraction, Range{1e-3, 1.0});
    v("room_tau_floor_m", recorder.room_tau_floor_m, Range{0.0, 10.0});
    v("side_deadband_m", recorder.side_deadband_m, Range{0.0, 5.0});
    v("side_rule", side_rule,
      OneOf{{assessment::toString(assessment::SideRule::kPathSide),
             assessment::toString(assessment::SideRule::kHumanSide)}});
    v("history_s", recorder.history_s, Range{0.0, 60.0});
    v("forecast_profile", forecast_profile);
    v("gate_timeout_ms", gate_timeout_ms, Range{1, 600000});
    v("limits", limits);
  }

  /// forecast_profile is relative to the config file's folder.
  void resolvePaths(const std::string& base_dir);

  /// The recorder's settings with tau_mode and side_rule applied (both validated by OneOf).
  assessment::PathAssessorConfig recorderConfig() const {
    assessment::PathAssessorConfig c = recorder;
    c.tau_mode = assessment::tauModeFromString(tau_mode).value_or(c.tau_mode);
    c.side_rule = assessment::sideRuleFromString(side_rule).value_or(c.side_rule);
    return c;
  }
};

class PathAssessorNode {
 public:
  using Config = PathAssessorNodeConfig;
  PathAssessorNode(const Config& config, Runtime& runtime);

  /// The recorder of a human, nullptr if that human was never seen (tests, diagnostics).
  const assessment::PathRecorder* recorder(std::int32_t human_id) const;
  /// Its forecaster, nullptr likewise or when no forecast_profile is configured.
  const assessment::CooperationForecaster* forecaster(std::int32_t human_id) const;
  /// Humans with state kept (seen in agent states or named by a reference path; at most
  /// limits.max_ids between messages), and their reference paths in all (tests, diagnostics).
  std::size_t humansKept() const { return humans_.size(); }
  std::size_t referencePathsKept() const;
  /// Lockstep recorder controls waiting for their step (at most limits.max_ids).
  std::size_t controlsWaiting() const { return controls_.size(); }

 private:
  struct Human {
    assessment::PathRecorder recorder;
    /// Set when a forecast profile is configured.
    std::optional<assessment::CooperationForecaster> forecaster;
    /// Reference paths by the step they were published at (-1 free-running); a START of step j
    /// uses the latest one published at or before j, whatever arrived since.
    std::map<std::int64_t, Path2> references;
    bool seen_in_states{false};
    double last_seen_s{0.0};                 ///< [s] message time, as last seen (continuity)
    Eigen::Vector2d position_m{0.0, 0.0};    ///< [m] as last seen
    Eigen::Vector2d velocity_m_s{0.0, 0.0};  ///< [m/s] as last seen
  };
  /// A new id where a human with a recording (running or stopped) was lost and heading: the
  /// tracker switched ids (lib/geometry/track_continuity.hpp); the recording goes on under the
  /// new id.
  void continueSwitchedIds(const AgentStatesSnapshot& states, double t_s);
  /// Reference paths kept per human, by step: the START of a step still waiting needs at most
  /// the paths of a few steps back (the gate holds a step for one step of the dialogue manager).
  static constexpr std::size_t kReferencesPerHuman = 16;

  void onAgentStates(const agent_states_t& msg);
  void onReferencePaths(const reference_paths_t& msg);
  void onControl(const path_assessor_control_t& msg);
  /// Applies one recorder control; throws RejectedMessage / DroppedMessage as a handler does.
  void applyControl(const RecorderControl& c);
  /// Lockstep: the controls of steps before `step`, in arrival order (each logged on failure).
  void applyControlsBefore(std::int64_t step);
  void assess(const AgentStatesSnapshot& states, StepNode::Step& step);
  /// The state of human `id`, created (and heard now) if new.
  Human& human(std::int32_t id);
  /// Human `id` heard of now: in agent states, or (never seen there yet) in a reference path.
  /// Ages it out from then (limits.forget_after_s).
  void hear(std::int32_t id);
  /// Offers a message's utime to the clock: throws RejectedMessage on a jump, starts a new time
  /// line on a resync (forgetting every human: their recorders' times are on the old one).
  void offerTime(std::int64_t utime, const char* what);
  /// Forgets humans not heard of for limits.forget_after_s of message time, then the least
  /// recently heard beyond limits.max_ids; one log line for the lot. Only the forgotten are
  /// visited, so a message costs O(its humans + forgotten).
  void forgetHumans();
  /// [s] message time on the node's time base (the clock's first or resynced utime), so the
  /// recorder's grid arithmetic works on small numbers whatever the clock's epoch.
  double seconds(std::int64_t utime);

  Config config_;
  Runtime& runtime_;
  std::optional<assessment::ForecastModel> forecast_;  ///< forecast_profile, loaded at start
  std::vector<RecorderControl> controls_;              ///< lockstep controls not yet applied
  /// The time of agent states and reference paths (one time line: the band source stamps its
  /// paths with the agent states' utime); messages stamped far off it are rejected.
  MessageClock clock_;
  std::map<std::int32_t, Human> humans_;
  IdRecency recency_;  ///< ids of humans_ by when last heard of
  std::optional<std::int64_t> base_utime_;
  /// Time lines started (resyncs): work prepared on an earlier one is not run on this one.
  std::uint64_t time_line_{0};
  StepNode steps_;  ///< last: steps still held when the node goes away are not acknowledged
};

}  // namespace coopnav
