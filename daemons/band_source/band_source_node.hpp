#pragma once
/// @file Band source: the CoHAN-style dual-band planner (lib/band) behind LCM. From the agent
/// states, the goals and the dialogue's robot actions it plans, each control cycle, the robot's
/// band and one anticipated band per human, the humans' reference paths and the robot's velocity
/// command; a DOCK action sends the robot to a wall-side pose until the human has passed.
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
#include "coopnav/agent_states_t.hpp"
#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "coopnav/planning/dock.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "coopnav/planning/room.hpp"
#include "coopnav/planning/safety_guard.hpp"
#include "coopnav/robot_action_t.hpp"
#include "maps/map_source.hpp"
#include "runtime/id_recency.hpp"
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

/// Going first (robot_action_t.ACTION_GO_FIRST, README "Going first").
struct GoFirstYaml {
  /// [m/s] The robot drives past the person at this speed while the planner's command is slower.
  double speed_m_s{0.3};
  /// [m] Along its global path, the point it heads for is this far ahead.
  double lookahead_m{1.5};
  /// [m] Body to body, the lateral gap to the person it keeps where the walls allow.
  double clearance_m{0.2};
  /// [s] Going first ends after this long even if the person is not passed yet.
  double max_s{20.0};

  template <class V>
  void visit(V& v) {
    v("speed_m_s", speed_m_s, Range{0.05, 2.0});
    v("lookahead_m", lookahead_m, Range{0.3, 10.0});
    v("clearance_m", clearance_m, Range{0.0, 2.0});
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
  std::int64_t cycles() const { return cycles_; }
  /// For tests: lockstep steps whose time is kept until they are planned.
  std::size_t stepsKept() const { return step_utime_.size(); }
  /// For tests: agent ids the planner may hold memory for (bands, paths).
  std::size_t plannerIdsKept() const { return planner_ids_.size(); }
  /// For tests: the reason of the robot action waiting for the next cycle ("" if none).
  const std::string& pendingActionReason() const;

 private:
  struct RefPath {
    Path2 path;
    std::int32_t revision{0};
  };

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
  void plan(const AgentStatesSnapshot& states, StepNode::Step& step);
  /// bands_t.ROOM_* for each planned human: how the robot would make room for it if asked now
  /// (only for humans ahead and closing; ROOM_UNKNOWN for the others).
  std::vector<std::int8_t> roomPlans(const AgentStatesSnapshot& states, const PlanResult& result);
  /// The command of a mode the robot drives itself (docking, retreating), else the planner's.
  Velocity2 modeCommand(const AgentStatesSnapshot& states, const ModeOutput& mode,
                        const PlanResult& result, bool hold, bool idle) const;
  /// While going first (GO_FIRST): the command past the person when the planner's is slower,
  /// else `planned`; ends going first once the person is passed, gone or the time is up.
  Velocity2 goFirstCommand(const AgentStatesSnapshot& states, const PlanResult& result,
                           const Velocity2& planned);
  /// The safety guard applied to `command`, logged when its action changes.
  GuardOutput guard(const AgentStatesSnapshot& states, const Velocity2& command);
  void publishReferencePaths(const AgentStatesSnapshot& states, const PlanResult& result,
                             const std::set<std::int32_t>& with_goal, StepNode::Step& step);
  void notePlanTime(double ms);
  /// Updates the goal belief of every human `given` has no goal for and returns the goals to plan
  /// with (the most likely, once min_walked_m is walked); publishes the beliefs.
  std::map<std::int32_t, Pose2> inferGoals(const AgentStatesSnapshot& s,
                                           const std::map<std::int32_t, Pose2>& given,
                                           StepNode::Step& step);
  /// Bounds the planner's per-agent memory (limits.max_ids, limits.forget_after_s).
  void boundPlannerMemory(const AgentStatesSnapshot& states, const PlanResult& result);

  Config config_;
  Runtime& runtime_;
  std::shared_ptr<const GridDistanceField> map_;
  std::unique_ptr<DualBandPlanner> planner_;
  DockModeMachine modes_;
  RobotLimits limits_;  ///< the planner's robot limits, for the commands it does not plan
  /// The robot's recent positions while it navigates: the way back for a wider place or a retreat.
  Trail trail_;
  GuardAction last_guard_{GuardAction::kNone};
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
  std::optional<std::int32_t> dock_human_id_;  ///< the human a dock is for, while docking / holding
  /// Going first (GO_FIRST) past this human since this time [s of message time].
  struct GoingFirst {
    std::int32_t human_id{0};
    double since_s{0.0};
  };
  std::optional<GoingFirst> go_first_;
  std::optional<std::int64_t> last_cycle_utime_;          ///< free-running throttle
  std::optional<AgentStatesSnapshot> free_running_next_;  ///< newest not yet planned
  std::map<std::int32_t, RefPath> refs_;                  ///< published reference path per human id
  std::optional<std::int64_t> last_refs_utime_;
  std::set<std::int32_t> humans_without_goal_;
  /// Goal inference (nullptr when disabled or without candidates): the candidates' distance
  /// fields, one belief per human whose goal is inferred, forgotten like the planner's ids.
  std::shared_ptr<const GoalDistances> goal_distances_;
  std::map<std::int32_t, GoalBelief> goal_beliefs_;
  IdRecency goal_belief_recency_;
  /// The goal a human is planned with: the region's index and where on it the human was
  /// heading when it was chosen.
  struct InferredGoal {
    int index{-1};
    Eigen::Vector2d target{0.0, 0.0};
  };
  std::map<std::int32_t, InferredGoal> inferred_goal_;
  std::set<std::int32_t> humans_unplanned_;  ///< beyond planner.max_planned_others
  /// Agent ids planned since the planner's memory was last cleared (it keeps a band and a path
  /// per id it ever planned), and the time of that clearing or of the last check for ids gone.
  std::set<std::int32_t> planner_ids_;
  std::optional<std::int64_t> planner_memory_check_utime_;
  std::string detail_;

  std::int64_t cycles_{0};
  std::vector<double> plan_ms_;  ///< wall time per planning call since the last summary
  std::vector<double> all_plan_ms_;
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
