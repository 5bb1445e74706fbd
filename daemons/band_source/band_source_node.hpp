#pragma once
/// @file Band source: the CoHAN-style dual-band planner (lib/band) behind LCM. From the agent
/// states, the goals and the dialogue's robot actions it plans, each control cycle, the robot's
/// band and one anticipated band per human, the humans' reference paths and the robot's velocity
/// command; a DOCK action sends the robot to a wall-side pose until the human has passed. The
/// cycle itself (goal choice, modes, dock tracking, command) is lib/band's BandCycle: the node
/// decodes, files by step, calls it and publishes what it returns.
/// Lockstep: one agent-states step = one control cycle, acknowledged after its outputs.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/band_config_yaml.hpp"
#include "config/config.hpp"
#include "config/same_way_yaml.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/band/band_cycle.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "coopnav/robot_action_t.hpp"
#include "maps/map_source.hpp"
#include "runtime/limits.hpp"
#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_node.hpp"
#include "scan_obstacles.hpp"
#include "wire/conversions.hpp"
#include "wire/dialogue.hpp"

namespace coopnav {

/// A configured candidate goal [m, world frame].
struct GoalPointYaml {
  double x_m{0.0};
  double y_m{0.0};
  template <class V>
  void visit(V& v) {
    v("x_m", x_m, Range{-1e6, 1e6});
    v("y_m", y_m, Range{-1e6, 1e6});
  }
};

/// Goal inference for humans with no goal in COOPNAV_GOALS (lib/planning/goal_inference.hpp).
struct GoalInferenceYaml {
  /// false: such a human gets a constant-velocity band and no reference path (CoHAN's const_vel).
  bool enabled{true};
  /// Candidates from the map (openings, corridor ends) besides `candidates`.
  bool map_candidates{true};
  std::vector<GoalPointYaml> candidates;
  GoalCandidateOptions candidate_options{};
  GoalInferenceOptions options{};
  /// [m] track walked before its most likely goal is planned with: a shorter track says too
  /// little, and a goal flipping would flip the reference path (constant velocity until then).
  double min_walked_m{1.0};
  /// [m] a planned goal gives way to another only when the other's path-length evidence is better
  /// by this much (GoalBelief::plannedGoal): real pedestrians avoid by ~0.4 m and up to ~1 m
  /// (test/data/pedestrians), and such a step must not re-plan the reference path.
  double switch_margin_m{1.0};

  template <class V>
  void visit(V& v) {
    v("enabled", enabled);
    v("map_candidates", map_candidates);
    v("candidates", candidates);
    v("beta_per_m", options.beta_per_m, Range{1e-3, 100.0});
    v("resolution_m", options.resolution_m, Range{0.02, 1.0});
    v("agent_radius_m", options.agent_radius_m, Range{0.0, 2.0});
    v("min_step_m", options.min_step_m, Range{0.0, 1.0});
    v("reached_radius_m", options.reached_radius_m, Range{0.0, 10.0});
    v("min_separation_m", candidate_options.min_separation_m, Range{0.1, 100.0});
    v("opening_inset_m", candidate_options.opening_inset_m, Range{0.0, 5.0});
    v("min_dead_end_length_m", candidate_options.min_dead_end_length_m, Range{0.0, 100.0});
    v("min_walked_m", min_walked_m, Range{0.0, 100.0});
    v("switch_margin_m", switch_margin_m, Range{0.0, 100.0});
  }
};

/// Going first (robot_action_t.ACTION_GO_FIRST, README "Going first"); defaults: lib's.
struct GoFirstYaml : GoFirstOptions {
  template <class V>
  void visit(V& v) {
    v("speed_m_s", speed_m_s, Range{0.05, 2.0});
    v("lookahead_m", lookahead_m, Range{0.3, 10.0});
    v("clearance_m", clearance_m, Range{0.0, 2.0});
    v("max_s", max_s, Range{1.0, 600.0});
  }
};

/// Following a person ahead walking the robot's way and passing them (lib planning/overtake.hpp,
/// README "Behind a slower person"); defaults: lib's.
struct OvertakeYaml : OvertakeOptions {
  template <class V>
  void visit(V& v) {
    visitSameWayKeys(v, same_way);
    v("follow_gap_m", follow_gap_m, Range{0.3, 10.0});
    v("follow_time_s", follow_time_s, Range{0.2, 30.0});
    v("pass_clearance_m", pass_clearance_m, Range{0.0, 2.0});
    v("wall_clearance_m", wall_clearance_m, Range{0.0, 1.0});
    v("lookahead_m", lookahead_m, Range{0.3, 10.0});
    v("passed_margin_m", passed_margin_m, Range{0.0, 10.0});
    v("max_pass_s", max_pass_s, Range{1.0, 600.0});
  }
};

/// Slowing while round 2 waits for evidence (robot_action_t.ACTION_SLOW, README "Slowing");
/// defaults: lib's.
struct SlowYaml : SlowOptions {
  template <class V>
  void visit(V& v) {
    v("speed_m_s", speed_m_s, Range{0.05, 2.0});
    v("max_s", max_s, Range{1.0, 600.0});
  }
};

struct BandSourceConfig {
  /// The known map: the same file as the other map-loading daemons of a run.
  MapSource map;
  /// Free-running only: at most this many cycles per second of message time (CoHAN: 10 Hz). In
  /// lockstep every step is a cycle; the simulator's publish_hz sets the rate.
  double control_hz{10.0};
  /// Total LM iterations per cycle; 0 = planner.no_inner_iterations x no_outer_iterations.
  /// The only solver budget in lockstep, so a run repeats to the last digit.
  int max_iterations{0};
  /// Free-running only: solver time budget per cycle [s], 0 = none (iterations only).
  double free_running_time_budget_s{0.0};
  /// Lockstep: how long a step waits for dialogue_manager's ack of the previous step before it is
  /// planned without it [s] (liveness only).
  double step_gate_timeout_s{2.0};
  /// Reference paths are republished unchanged this often [s of message time] for late joiners;
  /// 0 = only when a path changes.
  double reference_paths_republish_s{1.0};
  /// Dock / hold / retreat / resume, and the room decision (lib/planning/room.hpp).
  ModeMachineOptionsYaml dock;
  /// The last safety layer under the planner (lib/planning/safety_guard.hpp).
  GuardOptionsYaml guard;
  /// Going first past a person who made room (robot action GO_FIRST).
  GoFirstYaml go_first;
  /// Behind a slower person walking the robot's way: follow, and pass when told (GO_FIRST).
  OvertakeYaml overtake;
  /// Slowing while the dialogue waits for evidence (robot action SLOW).
  SlowYaml slow;
  /// The dual-band planner (defaults: lib/include/coopnav/band/band_config.hpp, CoHAN 2.0 sim).
  BandPlannerConfigYaml planner;
  /// Goals of humans the goals message does not give.
  GoalInferenceYaml goal_inference;
  /// Laser scans (COOPNAV_SCAN) as obstacles of the moment for the guard and the planner.
  ScanObstaclesConfig scan;

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    map.visit(v);  // its keys at the top level of this YAML
    v("control_hz", control_hz, Range{0.1, 1000.0});
    v("max_iterations", max_iterations, Range{0, 10000});
    v("free_running_time_budget_s", free_running_time_budget_s, Range{0.0, 10.0});
    v("step_gate_timeout_s", step_gate_timeout_s, Range{0.01, 600.0});
    v("reference_paths_republish_s", reference_paths_republish_s, Range{0.0, 3600.0});
    v("dock", dock);
    v("guard", guard);
    v("go_first", go_first);
    v("overtake", overtake);
    v("slow", slow);
    v("planner", planner);
    v("goal_inference", goal_inference);
    v("scan", scan);
    v("limits", limits);
  }
  void resolvePaths(const std::string& base_dir);
};

class BandSourceNode {
 public:
  using Config = BandSourceConfig;
  /// The StepGate participant whose ack of step k-1 step k waits for (its robot actions).
  static constexpr const char* kDialogueParticipant = "dialogue_manager";

  /// Loads the map; throws StartupError naming the file and the problem.
  BandSourceNode(const Config& config, Runtime& runtime);
  /// Logs the planning-time summary.
  ~BandSourceNode();
  BandSourceNode(const BandSourceNode&) = delete;
  BandSourceNode& operator=(const BandSourceNode&) = delete;

  /// Planning cycles run so far (for tests).
  std::int64_t cycles() const { return cycle_->cycles(); }
  /// For tests: lockstep steps whose time is kept until they are planned.
  std::size_t stepsKept() const { return step_utime_.size(); }
  /// For tests: agent ids the planner may hold memory for (bands, paths).
  std::size_t plannerIdsKept() const { return cycle_->plannerIdsKept(); }
  /// For tests: the reason of the robot action waiting for the next cycle ("" if none).
  const std::string& pendingActionReason() const;

 private:
  void onAgentStates(const agent_states_t& msg);
  /// The agent states' clock was resynchronised at `utime`: the times kept from the old time
  /// base restart from it.
  void onResync(std::int64_t utime);
  /// Free-running: plans the newest agent states received since the last cycle, if any.
  void planLatestFreeRunning();
  void onGoals(const goals_t& msg);
  void onRobotAction(const robot_action_t& msg);
  /// A laser scan: an input of its step (lockstep) or the newest one (free-running).
  void onScan(const laser_scan_t& msg);
  /// Leaves humans far off the map out of planning (a tracker glitch), with a log line.
  void leaveOutFarHumans(AgentStatesSnapshot& states) const;
  /// One control cycle; never throws (it may run from the gate's timer).
  void cycle(const AgentStatesSnapshot& states, StepNode::Step& step);
  /// The cycle's inputs -> BandCycle -> the step's outputs.
  void plan(const AgentStatesSnapshot& states, StepNode::Step& step);
  void notePlanTime(double ms);
  Config config_;
  Runtime& runtime_;
  std::shared_ptr<const GridDistanceField> map_;
  /// The control cycle: planner, mode machine, goal beliefs, reference paths.
  std::unique_ptr<BandCycle> cycle_;
  ScanObstacles scans_;
  /// The scan points of the cycle being planned (ScanObstacles::take at its start).
  ScanObstacles::Points scan_points_;
  /// The agent states' time: a message stamped far from it is rejected and does not move it, so
  /// one stamped INT64_MAX cannot make every later one "backwards" (docs/bad-inputs.md "Caps").
  MessageClock clock_;
  MessageClock goals_clock_;                         ///< the same for the goals
  std::map<std::int64_t, std::int64_t> step_utime_;  ///< utime of each step queued in the gate
  std::set<std::int64_t> goal_utimes_;               ///< utimes of the latest goals received

  std::optional<GoalsSnapshot> goals_;
  /// The robot action to apply at the next cycle: of those received since the last one, the
  /// latest wins.
  std::optional<RobotActionMsg> action_;
  std::optional<std::int64_t> last_cycle_utime_;          ///< free-running throttle
  std::optional<AgentStatesSnapshot> free_running_next_;  ///< newest not yet planned
  std::string detail_;

  std::vector<double> plan_ms_;  ///< wall time per planning call since the last summary
  std::vector<double> all_plan_ms_;
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
