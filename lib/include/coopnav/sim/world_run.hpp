#pragma once
/// @file The world simulator's run, from waiting for its participants to its end, and the
/// sentence that says how it ended: pure (no LCM, no clock, no I/O). world_sim's node decodes,
/// calls this and publishes (daemons/world_sim); the simulation itself is sim::Simulation.

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coopnav/sim/simulation.hpp"

namespace coopnav::sim {

/// How a run ended (world_sim's sim_status_t.STATE_*, without the wire).
enum class RunEnd : std::uint8_t {
  kGoalsReached,
  kCollision,
  kTimeLimit,
  kStandstill,
  kParticipantTimeout,  ///< a participant never sent a status, or left a step unacknowledged
  kError,               ///< the run cannot go on (e.g. the robot's kinematics differ)
};

/// The run end of a simulation status that is not kRunning.
RunEnd runEndOf(SimStatus status);

/// What the end-of-run sentence says besides the simulation's own summary.
struct EndContext {
  double time_limit_s{0.0};           ///< the scenario's
  double standstill_distance_m{0.0};  ///< the scenario's standstill rule
  double standstill_time_s{0.0};
  double contact_fault_speed_m_s{0.0};  ///< SimSettings: the robot is at fault above it
  /// The robot's last command mode in words ("navigating", "at its goal"); none: never commanded.
  std::optional<std::string> robot_mode;
  bool robot_mode_at_goal{false};  ///< that mode is the command's "goal reached"
  std::string last_said;           ///< "\"words\" to human N" of the last words heard; "": none
};

/// The first robot-human contact in words, e.g. "human 1 walked into the robot at rest at t
/// 23.40 s" or "the robot drove into human 2 at 0.32 m/s at t 12.30 s".
std::string contactDetail(const RobotHumanContact& contact, double fault_speed_m_s);

/// The sentence of a run's end (its SIM status detail) for the step the simulation ended on;
/// "" while `r.status` is kRunning.
std::string endDetail(const StepResult& r, const SimSummary& sum, const EndContext& ctx);

/// The run's phases: waiting for every lockstep participant's first status, running, ended. In
/// lockstep the step on which the simulation ended is answered like every other one before the
/// run ends (the participants' outputs of it, e.g. the path assessor's last CM, are part of the
/// run; a lost datagram of it would otherwise make a lossy run end one step short of the clean
/// one); a participant silent on a step ends the run, named.
class WorldRun {
 public:
  enum class Phase : std::uint8_t { kWaitingReady, kRunning, kEnded };
  struct Finish {
    RunEnd end{RunEnd::kError};
    std::string detail;
    /// The step that ended the run was not acknowledged in time by someone (named in detail).
    bool last_step_unacknowledged{false};
  };

  /// participants: the scenario's lockstep participants (none when free-running); step_timeout_s:
  /// the scenario's, for the sentences.
  WorldRun(std::vector<std::string> participants, double step_timeout_s);

  Phase phase() const { return phase_; }
  bool ended() const { return phase_ == Phase::kEnded; }

  /// A daemon's status was heard while waiting: true when its name is new (then the node checks
  /// whether every participant is ready).
  bool heard(const std::string& name);
  /// The participants not heard yet, ", "-separated in scenario order; "" when all are ready.
  std::string missing() const;
  /// Waiting for more than wait_ready_timeout_s: how the run ends.
  Finish neverReady(double wait_ready_timeout_s) const;

  void start() { phase_ = Phase::kRunning; }
  /// The simulation ended. `hold`: lockstep with acks, the run ends once the acks of this step
  /// are in (stepAcknowledged); else it ends now (the returned finish).
  std::optional<Finish> simulationEnded(RunEnd end, std::string detail, bool hold);
  /// The simulation has ended and the run waits for the acks of its last step.
  bool ending() const { return ending_.has_value(); }
  /// The acks of `step` are in, or (degraded) someone stayed silent: `missing` names them. The
  /// finish when the run ends now; none: go on with the next step.
  std::optional<Finish> stepAcknowledged(std::int64_t step, bool degraded,
                                         const std::string& missing);
  /// The run ended (phase kEnded); anything after it is ignored by the node.
  void finish() { phase_ = Phase::kEnded; }

 private:
  std::vector<std::string> participants_;
  double step_timeout_s_;
  std::set<std::string> ready_;
  Phase phase_{Phase::kWaitingReady};
  std::optional<Finish> ending_;
};

}  // namespace coopnav::sim
