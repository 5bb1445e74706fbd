#pragma once
/// @file The world simulator's physics: a robot disc driven by body-frame velocity commands and
/// human discs driven by their behaviours, integrated at a fixed physics step with acceleration
/// limits; collisions (disc-disc, disc-wall), goals, time limit. Pure and deterministic: the same
/// WorldSpec and command sequence give bit-identical states.

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/sim/behaviour.hpp"
#include "coopnav/sim/random.hpp"

namespace coopnav::sim {

enum class Kinematics : std::uint8_t { kDifferential = 0, kHolonomic = 1 };

/// Body-frame velocity and acceleration limits of the robot. Commands are clamped to them.
struct RobotLimits {
  double max_forward_m_s{0.8};
  double max_backward_m_s{0.2};
  double max_lateral_m_s{0.5};  ///< holonomic only; a differential drive has none
  double max_omega_rad_s{1.2};
  double max_acc_forward_m_s2{0.8};
  double max_acc_lateral_m_s2{0.8};
  double max_acc_omega_rad_s2{2.0};
  template <class V>
  void visit(V& v) {
    v.number("max_forward_m_s", max_forward_m_s, 0.0, 5.0);
    v.number("max_backward_m_s", max_backward_m_s, 0.0, 5.0);
    v.number("max_lateral_m_s", max_lateral_m_s, 0.0, 5.0);
    v.number("max_omega_rad_s", max_omega_rad_s, 0.0, 10.0);
    v.number("max_acc_forward_m_s2", max_acc_forward_m_s2, 0.01, 20.0);
    v.number("max_acc_lateral_m_s2", max_acc_lateral_m_s2, 0.01, 20.0);
    v.number("max_acc_omega_rad_s2", max_acc_omega_rad_s2, 0.01, 50.0);
  }
};

struct RobotSpec {
  Pose2 start;
  Pose2 goal;
  double radius_m{0.47};  ///< CoHAN's PR2 footprint radius (cohan2_params_pr2.yaml)
  Kinematics kinematics{Kinematics::kDifferential};
  RobotLimits limits;
  double goal_tolerance_m{0.3};
};

struct HumanSpec {
  std::int32_t id{1};  ///< >= 1 (0 is the robot)
  Pose2 start;
  Pose2 goal;
  Path2 via;                       ///< optional waypoints between start and goal
  double speed_m_s{1.0};           ///< preferred speed (mean when speed_stddev_m_s > 0)
  double speed_stddev_m_s{0.0};    ///< preferred speed drawn once from N(speed, stddev)
  double velocity_noise_m_s{0.0};  ///< per-step N(0, sigma) added to the desired velocity
  double radius_m{0.3};
  double max_acc_m_s2{1.5};  ///< walking acceleration limit
  double goal_tolerance_m{0.2};
  BehaviourConfig behaviour;
};

struct SimSettings {
  double physics_dt_s{0.05};  ///< fixed physics step (>= 20 Hz)
  int substeps_per_step{2};   ///< physics steps per step() call (publish period)
  double time_limit_s{60.0};
  bool end_on_goals{true};            ///< end when the robot and every human reached its goal
  bool end_on_robot_collision{true};  ///< end when the robot touches a human or a wall
  /// [m/s] At the first robot-human contact the robot is at fault when its velocity towards the
  /// human exceeds this; at or below it the human walked into a robot at rest or moving away.
  /// Above odometry noise, below any deliberate motion of a planner.
  double contact_fault_speed_m_s{0.05};
  /// [s] The run ends in kStandstill once no agent has moved more than standstill_distance_m for
  /// this long and not every goal is reached (an encounter neither side resolves); 0 = never.
  double standstill_time_s{15.0};
  double standstill_distance_m{0.1};  ///< [m] moving less than this is standing still
};

/// [s] One onset of avoidance: median · exp(log_sd · z), z ~ N(0, 1), cut at max_s.
double drawOnset(const RealisticOnsetParams& p, Rng& rng);

struct WorldSpec {
  std::uint64_t seed{0};
  SimSettings settings;
  /// kRealistic: each facilitating, late_facilitating and responsive human gets an onset drawn
  /// from `onset` (BehaviourConfig::onset_s), from a stream of its own (seed, id), so its other
  /// draws are the same as under kTrigger.
  AvoidanceTiming avoidance_timing{AvoidanceTiming::kTrigger};
  RealisticOnsetParams onset;
  RobotSpec robot;
  std::vector<HumanSpec> humans;
};

enum class SimStatus : std::uint8_t {
  kRunning = 0,
  kGoalsReached = 1,
  kCollision = 2,
  kTimeLimit = 3,
  kStandstill = 4  ///< nobody moved for standstill_time_s and not every goal is reached
};
const char* toString(SimStatus s);

/// Agent id used for walls in collision events.
constexpr std::int32_t kWallId = -1;
/// Agent id of the robot.
constexpr std::int32_t kRobotId = 0;

struct SimEvent {
  enum class Kind : std::uint8_t { kCollision = 0, kGoalReached = 1, kEnded = 2 };
  Kind kind{Kind::kEnded};
  double t_s{0.0};
  std::int32_t agent_id{kRobotId};
  std::int32_t other_id{kWallId};         ///< collision partner (kWallId for a wall)
  double clearance_m{0.0};                ///< surface gap at the event (< 0: overlap)
  SimStatus status{SimStatus::kRunning};  ///< kEnded: the final status
};

/// The result of one step(): states at the new time and what happened during it.
struct StepResult {
  double t_s{0.0};
  std::vector<AgentState> agents;  ///< robot first (id 0, world-frame velocity), then humans
  std::vector<SimEvent> events;
  std::vector<CueOutcome> cues;  ///< cues whose words ended during the step, in time order
  SimStatus status{SimStatus::kRunning};
};

/// The first robot-human contact of a run and who is at fault.
struct RobotHumanContact {
  std::int32_t human_id{0};
  double t_s{0.0};  ///< sim time of the physics step in which it began
  /// Robot's world velocity towards the human (along the unit vector from the robot's centre to
  /// the human's) in that step [m/s]: > 0 closing.
  double robot_speed_towards_m_s{0.0};
  bool robot_at_fault{false};  ///< robot_speed_towards_m_s > SimSettings::contact_fault_speed_m_s
};

/// The robot's velocity towards a human: the component of its world velocity along the unit
/// vector from its centre to the human's (> 0 closing); 0 for coincident centres.
double robotSpeedTowards(const AgentState& robot, const AgentState& human);

/// Totals of a run so far.
struct SimSummary {
  SimStatus status{SimStatus::kRunning};
  double t_s{0.0};
  double min_robot_human_clearance_m{std::numeric_limits<double>::infinity()};  ///< surface gap
  /// Sim time at which min_robot_human_clearance_m was first reached; NaN while no human.
  double min_robot_human_clearance_t_s{std::numeric_limits<double>::quiet_NaN()};
  std::optional<RobotHumanContact> first_contact;  ///< none while the robot touched nobody
  double robot_goal_time_s{-1.0};                  ///< -1 while not reached
  std::vector<double> human_goal_time_s;  ///< per human, in spec order; -1 while not reached
  int collisions{0};
};

class Simulation {
 public:
  /// `map` may be nullptr (no walls); it must outlive the simulation. Throws
  /// std::invalid_argument for an inconsistent spec (non-positive step, duplicate ids, ...).
  Simulation(const WorldSpec& spec, const DistanceMap* map,
             const PlannerAdapterFactory& planner_factory = {});

  /// Advances one publish period (settings.substeps_per_step physics steps) with the robot's
  /// body-frame command (vx forward, vy left, omega ccw; clamped to the limits and reached under
  /// the acceleration limits). After the run has ended, returns the final state unchanged.
  StepResult step(const Velocity2& robot_cmd_body);

  /// Delivers an utterance to a human: its words end at cue.t_s (a past time counts as the next
  /// physics step). A responsive human then draws whether it heard (hearing_range_m) and complies,
  /// and its reaction time (ResponsiveParams), from a stream of its own, so that what it hears
  /// does not change the other draws of the run (a muted twin run walks the same). An unknown
  /// human id is ignored.
  void addCue(const Cue& cue);
  /// Cues of human `human_id` whose words have not ended yet (0 for an unknown id).
  std::size_t pendingCues(std::int32_t human_id) const;
  /// The robot's latest band, its t_s = 0 at stamp_s (sim time). Behaviours may read it.
  void setRobotBand(const Band& band, double stamp_s);

  double time_s() const { return t_s_; }
  SimStatus status() const { return status_; }
  const SimSummary& summary() const { return summary_; }
  /// Current states: robot first, then humans in spec order.
  std::vector<AgentState> agents() const;
  /// Current status of each human's behaviour, in spec order.
  std::vector<BehaviourStatus> behaviourStatus() const;
  /// Reference path of each human (start -> via -> goal), in spec order.
  const Path2& referencePath(std::size_t human_index) const { return humans_[human_index].path; }
  /// Robot velocity in its body frame.
  const Velocity2& robotBodyVelocity() const { return robot_body_vel_; }
  const WorldSpec& spec() const { return spec_; }
  /// Per human, in spec order: its avoidance onset (WorldSpec::avoidance_timing kRealistic), or
  /// nullopt (the behaviour's own trigger).
  std::vector<std::optional<double>> onsets() const;

 private:
  struct Human {
    HumanSpec spec;
    AgentState state;
    Path2 path;
    double preferred_speed_m_s{1.0};
    std::unique_ptr<HumanBehaviour> behaviour;
    std::vector<Cue> pending;  ///< words not yet ended, by t_s
    std::vector<Cue> acting;   ///< complied with, t_s = when it starts acting, by t_s
    Rng rng;
    Rng cue_rng;  ///< the hearing, compliance and reaction draws only
    bool at_goal{false};
  };

  void physicsStep(const Velocity2& cmd_body, StepResult& out);
  /// The cues of `h` whose words have ended by now: heard?, complies?, when it acts.
  void hearCues(Human& h, std::vector<CueOutcome>& out);
  void integrateRobot(const Velocity2& cmd_body, double dt_s);
  void checkCollisions(std::vector<SimEvent>& events);
  /// True once nobody has moved more than standstill_distance_m for standstill_time_s.
  bool standingStill();
  void end(SimStatus s, std::vector<SimEvent>& events);

  WorldSpec spec_;
  const DistanceMap* map_;
  double t_s_{0.0};
  std::int64_t physics_steps_{0};
  SimStatus status_{SimStatus::kRunning};
  AgentState robot_;
  Velocity2 robot_body_vel_;
  bool robot_at_goal_{false};
  std::vector<Human> humans_;
  Band robot_band_;
  double robot_band_stamp_s_{0.0};
  bool has_band_{false};
  std::vector<std::vector<bool>> in_contact_;  ///< [agent][agent or wall]: edge-triggered events
  SimSummary summary_;
  std::vector<Eigen::Vector2d> still_at_;  ///< robot, humans: where each was when all last moved
  double still_since_s_{0.0};
};

}  // namespace coopnav::sim
