#pragma once
/// @file World simulator daemon: runs a scenario (docs/scenario-format.md) of a robot driven by
/// its velocity commands and simulated humans driven by their behaviours (lib/sim), and publishes
/// the agent states stamped with simulated time. Lockstep (docs/lockstep.md): a step advances only
/// when every participant of the scenario has acknowledged the previous one, so a run repeats to
/// the last byte. Real time: paced by the monotonic clock times a speed factor, nobody waited for.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/band_config_yaml.hpp"
#include "config/config.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/sim/simulation.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/limits.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_gate.hpp"
#include "runtime/step_outputs.hpp"
#include "scenario.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

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
    v.require(!scenario.empty(), "scenario", "must name a scenario file");
    v("limits", limits);
  }
  void resolvePaths(const std::string& base_dir);
};

/// The first robot-human contact in words, e.g. "human 1 walked into the robot at rest at t
/// 23.40 s" or "the robot drove into human 2 at 0.32 m/s at t 12.30 s".
std::string contactDetail(const sim::RobotHumanContact& contact, double fault_speed_m_s);

class WorldSimNode {
 public:
  using Config = WorldSimConfig;
  /// Loads and checks the scenario and its map; throws StartupError naming the file, the key and
  /// the value at fault.
  WorldSimNode(const Config& config, Runtime& runtime);

  bool lockstep() const { return lockstep_; }
  bool ended() const { return phase_ == Phase::kEnded; }
  const world_sim::Scenario& scenario() const { return scenario_; }

 private:
  enum class Phase { kWaitingReady, kRunning, kEnded };
  /// Lockstep: how the simulation ended, kept while the acks of its last step are awaited.
  struct Ending {
    std::int8_t state;
    std::string detail;
  };
  struct PendingCue {
    sim::Cue cue;
    std::int64_t step{-1};
  };

  void onStatus(const daemon_status_t& msg);
  void onCommand(const velocity_command_t& msg);
  void onUtterance(const utterance_t& msg);
  void onBands(const bands_t& msg);
  /// An input the step gate counts (StepGate::accept); stored directly when free-running.
  template <class Store>
  void accept(const char* participant, const char* channel, std::int64_t step,
              const std::string& key, Store&& store);
  /// A simulated human hears an utterance (only a request to move changes it).
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
  std::string endDetail(const sim::StepResult& r) const;

  Config config_;
  Runtime& runtime_;
  world_sim::Scenario scenario_;
  std::shared_ptr<GridDistanceField> field_;
  std::unique_ptr<sim::Simulation> sim_;
  bool lockstep_{true};
  double real_time_factor_{1.0};
  double step_period_s_{0.1};
  std::unique_ptr<StepGate> gate_;
  StepOutputs outputs_;
  std::chrono::steady_clock::time_point step_published_at_;
  std::int64_t retransmits_{0};
  std::int64_t band_step_{-1};  ///< step of the latest bands applied or pending

  Phase phase_{Phase::kWaitingReady};
  std::set<std::string> ready_;
  std::chrono::steady_clock::time_point phase_since_;
  std::int64_t step_{0};  ///< index of the agent states last published
  std::optional<Ending> ending_;
  std::vector<AgentState> agents_;

  std::optional<VelocityCommand> command_;
  Velocity2 last_command_{0.0, 0.0, 0.0};  ///< body frame, applied over the current step
  std::int64_t stale_commands_{0};
  std::vector<PendingCue> cues_;
  std::optional<BandsSnapshot> band_;
  std::optional<std::int8_t> last_mode_;  ///< of the latest robot command (standstill detail)
  std::string last_said_;                 ///< latest utterance, "text" to human N (same)
  bool behind_logged_{false};
};

}  // namespace coopnav
