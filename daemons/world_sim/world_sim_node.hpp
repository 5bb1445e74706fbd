#pragma once
/// @file World simulator daemon: runs a scenario (docs/scenario-format.md) of a robot driven by
/// its velocity commands and simulated humans driven by their behaviours (lib/sim), and publishes
/// the agent states stamped with simulated time. Lockstep (docs/lockstep.md): a step advances only
/// when every participant of the scenario has acknowledged the previous one, so a run repeats to
/// the last byte. Real time: paced by the monotonic clock times a speed factor, nobody waited for.

#include <chrono>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "config/band_config_yaml.hpp"
#include "config/config.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/sim/heard_words.hpp"
#include "coopnav/sim/simulation.hpp"
#include "coopnav/sim/tracker.hpp"
#include "coopnav/sim/world_run.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/limits.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_gate.hpp"
#include "runtime/step_outputs.hpp"
#include "scenario.hpp"
#include "sensing.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

/// The scenario's `tracker` section, key by key overridden from the config: -1 (the default)
/// keeps the scenario's value (lib/include/coopnav/sim/tracker.hpp, docs/scenario-format.md).
struct TrackerOverrides {
  double position_sigma_m{-1.0};
  int velocity_window_steps{-1};
  double miss_probability{-1.0};
  double drop_after_s{-1.0};
  int id_switches{-1};
  double id_switch_window_s{-1.0};
  double range_m{-1.0};

  template <class V>
  void visit(V& v) {
    key(v, "position_sigma_m", position_sigma_m, 0.0, 2.0);
    key(v, "velocity_window_steps", velocity_window_steps, 1.0, 100.0);
    key(v, "miss_probability", miss_probability, 0.0, 0.99);
    key(v, "drop_after_s", drop_after_s, 0.0, 3600.0);
    key(v, "id_switches", id_switches, 0.0, 1000.0);
    key(v, "id_switch_window_s", id_switch_window_s, 0.0, 86400.0);
    key(v, "range_m", range_m, 0.0, 1e6);
  }
  /// The scenario's parameters with every key given here (not -1) replaced.
  sim::TrackerParams apply(sim::TrackerParams p) const;

 private:
  template <class V, class T>
  static void key(V& v, const char* name, T& field, double min, double max) {
    v(name, field, Range{-1.0, max});
    const auto x = static_cast<double>(field);
    if (x != -1.0 && x < min) {
      std::ostringstream s;
      s << "= " << x << " must be -1 (the scenario's value) or in [" << min << ", " << max << "]";
      v.require(false, name, s.str());
    }
  }
};

struct WorldSimConfig {
  /// Scenario file (docs/scenario-format.md). Relative to this config file's folder (to the
  /// working directory when there is no config file).
  std::string scenario{""};
  /// scenario: the scenario's lockstep.enabled decides; lockstep / real_time override it.
  std::string mode{"scenario"};
  /// Real-time mode: simulated seconds per wall second; 0 keeps the scenario's
  /// rates.real_time_factor.
  double real_time_factor{0.0};
  /// After the final SIM_STATUS, exit 0 (a script runs one scenario per process); false keeps the
  /// daemon alive, idle, until SIGTERM.
  bool exit_at_end{true};
  /// Lockstep: wall seconds to wait for every participant's first status message before the run
  /// fails with STATE_PARTICIPANT_TIMEOUT (daemons start in any order; a few seconds suffice).
  double wait_ready_timeout_s{30.0};
  /// Lockstep: wall seconds without every ack of the current step after which the step's
  /// messages are published again, identical (a datagram was lost, or a participant restarted);
  /// repeats go on until the scenario's lockstep.step_timeout_s ends the run. Liveness only: a
  /// repeat never changes what is simulated. 0 = never.
  double retransmit_period_s{0.25};
  /// The dual-band planner of planner-backed (facilitating) humans, who plan with the robot as
  /// their anticipated other (defaults: lib/include/coopnav/band/band_config.hpp).
  BandPlannerConfigYaml human_planner;

  /// What a people tracker would publish of the humans: overrides of the scenario's `tracker`
  /// section, key by key (-1 = the scenario's value), e.g. --set tracker.position_sigma_m=0.05.
  TrackerOverrides tracker;
  /// scenario: the scenario's publish_human_goals decides; true / false override it (false:
  /// COOPNAV_GOALS carries only the robot's goal).
  std::string publish_human_goals{"scenario"};
  /// scenario: the scenario's laser section decides (a scan on COOPNAV_SCAN each step when
  /// enabled); off: no scan whatever the scenario says (the planner and guard then see the map
  /// and the people only).
  std::string laser{"scenario"};
  /// Empty: none. Else a file this run writes what became of every cue whose words ended, one
  /// JSON object a line (docs/scenario-format.md "Cue outcomes"): what a population tabulates of
  /// what the simulated humans heard. Relative to the working directory; created empty at start.
  std::string cue_outcomes_file{""};
  /// scenario: the scenario's avoidance_timing decides; trigger / realistic override it (e.g.
  /// --set avoidance_timing=realistic for a whole population).
  std::string avoidance_timing{"scenario"};
  /// The onset distribution of realistic timing (defaults and their source:
  /// lib/include/coopnav/sim/behaviour.hpp, RealisticOnsetParams).
  sim::RealisticOnsetParams realistic_onset;

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("scenario", scenario);
    v("mode", mode, OneOf{{"scenario", "lockstep", "real_time"}});
    v("real_time_factor", real_time_factor, Range{0.0, 1000.0});
    v("exit_at_end", exit_at_end);
    v("wait_ready_timeout_s", wait_ready_timeout_s, Range{0.01, 3600.0});
    v("retransmit_period_s", retransmit_period_s, Range{0.0, 3600.0});
    v("human_planner", human_planner);
    v("tracker", tracker);
    v("publish_human_goals", publish_human_goals, OneOf{{"scenario", "true", "false"}});
    v("laser", laser, OneOf{{"scenario", "off"}});
    v("cue_outcomes_file", cue_outcomes_file);
    v("avoidance_timing", avoidance_timing, OneOf{{"scenario", "trigger", "realistic"}});
    world_sim::SimParamsYaml<sim::RealisticOnsetParams> onset_yaml{&realistic_onset};
    v("realistic_onset", onset_yaml);
    v.require(!scenario.empty(), "scenario", "must name a scenario file");
    v("limits", limits);
  }
  void resolvePaths(const std::string& base_dir);
};

class WorldSimNode {
 public:
  using Config = WorldSimConfig;
  /// Loads and checks the scenario and its map; throws StartupError naming the file, the key and
  /// the value at fault.
  WorldSimNode(const Config& config, Runtime& runtime);

  bool lockstep() const { return lockstep_; }
  /// The tracker model in force (the scenario's, with the config's overrides).
  const sim::Tracker& tracker() const { return *tracker_; }
  bool publishHumanGoals() const { return publish_human_goals_; }
  bool ended() const { return run_.ended(); }
  const world_sim::Scenario& scenario() const { return scenario_; }

 private:
  /// One line per cue whose words ended: heard?, complies?, when it acts; and its record in
  /// cue_outcomes_file.
  void logCue(const sim::CueOutcome& o);
  void onStatus(const daemon_status_t& msg);
  void onCommand(const velocity_command_t& msg);
  void onUtterance(const utterance_t& msg);
  void onBands(const bands_t& msg);
  /// An input the step gate counts (StepGate::accept); stored directly when free-running.
  template <class Store>
  void accept(const char* participant, const char* channel, std::int64_t step,
              const std::string& key, Store&& store);
  /// A said utterance becomes a cue the addressed human hears when its words end (what it does
  /// then is its behaviour's: lib/sim, ResponsiveParams).
  void hear(const utterance_t& msg);
  void storeBands(const bands_t& msg);

  void checkReady();
  void start();
  /// Lockstep: the acks of step_ are in (or `degraded`: someone stayed silent).
  void onStepAcknowledged(bool degraded, const std::string& missing);
  void submitCurrentStep();
  void tickFast();
  void tickRealTime();
  /// Applies the inputs of step_ and integrates to step_ + 1, publishes it; false once ended.
  bool advance();
  void applyInputs();
  void publishStep();
  void publishSimStatus(std::int8_t state, const std::string& detail);
  /// Lockstep: publishes the current step again when its acks are overdue.
  void retransmitIfOverdue();
  /// Before step 0: goals and a "here" ack, so the daemons know the world before it starts.
  void announce();
  void finish(std::int8_t state, const std::string& detail);
  /// The end-of-run sentence (sim::endDetail) with what the node knows: the last command's mode
  /// and words said.
  std::string endDetail(const sim::StepResult& r) const;

  Config config_;
  Runtime& runtime_;
  world_sim::Scenario scenario_;
  std::shared_ptr<GridDistanceField> field_;
  std::unique_ptr<sim::Simulation> sim_;
  /// Between the true humans and COOPNAV_AGENT_STATES / COOPNAV_GOALS; physics uses the truth.
  std::unique_ptr<sim::Tracker> tracker_;
  /// Unmapped obstacles' clearance and the robot's laser (scenario `unmapped_obstacles`, `laser`).
  std::unique_ptr<world_sim::WorldSensing> sensing_;
  bool publish_human_goals_{true};
  bool lockstep_{true};
  double real_time_factor_{1.0};
  double step_period_s_{0.1};
  std::unique_ptr<StepGate> gate_;
  StepOutputs outputs_;
  std::chrono::steady_clock::time_point step_published_at_;
  std::int64_t retransmits_{0};
  std::int64_t band_step_{-1};  ///< step of the latest bands applied or pending

  /// Waiting for the participants, running, ended; the lockstep end (lib/sim world_run.hpp).
  sim::WorldRun run_;
  std::chrono::steady_clock::time_point phase_since_;
  std::int64_t step_{0};  ///< index of the agent states last published
  std::vector<AgentState> agents_;

  std::optional<VelocityCommand> command_;
  Velocity2 last_command_{0.0, 0.0, 0.0};  ///< body frame, applied over the current step
  std::int64_t stale_commands_{0};
  sim::HeardWords heard_;  ///< words said, until the step that applies them
  std::optional<BandsSnapshot> band_;
  std::optional<std::int8_t> last_mode_;  ///< of the latest robot command (standstill detail)
  std::string last_said_;                 ///< latest utterance, "text" to human N (same)
  bool behind_logged_{false};
  std::ofstream cue_outcomes_;  ///< config_.cue_outcomes_file, open when given
};

}  // namespace coopnav
