#pragma once
/// @file One control cycle of the band source: the logic the robot runs, behind the daemon's
/// decoding and publishing. From the agent states, the goals and the dialogue's latest robot
/// action: the goal choice (the robot's; the humans' given or inferred, goal_inference.hpp), the
/// mode machine (navigate / dock / hold / retreat / resume, dock.hpp) and the human a dock is for,
/// the dual-band plan (dual_band_planner.hpp), the room each human would be given (room.hpp), the
/// command of the mode under the safety guard (safety_guard.hpp), the reference paths and their
/// revisions, and the bounds on the planner's per-agent memory. Pure: time comes in as message
/// utimes [us]; a monotonic clock (for the free-running time budget and the reported planning
/// time only) is the caller's; what comes out is the values to publish and the notes to log.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/id_recency.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/planning/dock.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "coopnav/planning/overtake.hpp"
#include "coopnav/planning/room.hpp"
#include "coopnav/planning/safety_guard.hpp"

namespace coopnav {

/// Going first past a person who made room (robot action GO_FIRST; the band source's README
/// "Going first").
struct GoFirstOptions {
  /// [m/s] The robot drives past the person at this speed while the planner's command is slower.
  double speed_m_s{0.3};
  /// [m] Along its global path, the point it heads for is this far ahead.
  double lookahead_m{1.5};
  /// [m] Body to body, the lateral gap to the person it keeps where the walls allow.
  double clearance_m{0.2};
  /// [s] Going first ends after this long even if the person is not passed yet.
  double max_s{20.0};
};

/// Slowing while the dialogue waits for evidence (robot action SLOW, the dialogue manager's
/// make_time; the band source's README "Slowing").
struct SlowOptions {
  /// [m/s] Cap on the command's speed while slowed: under half the robot's walk, so that a dock
  /// or a stop decided late is still done before the person arrives.
  double speed_m_s{0.3};
  /// [s] Slowing ends after this long even without a newer action.
  double max_s{10.0};
};

/// The band source's tuning, as its YAML gives it (config/band_source.yaml); the daemon fills
/// every field.
struct BandCycleConfig {
  BandPlannerConfig planner;
  /// Dock / hold / retreat / resume; goal tolerance and robot radius are the planner's.
  ModeMachineOptions modes;
  GuardOptions guard;
  GoFirstOptions go_first;
  /// Following a person ahead who walks the robot's way, and passing them (overtake.hpp).
  OvertakeOptions overtake;
  SlowOptions slow;
  int max_iterations{0};                    ///< total LM iterations per cycle (0: the planner's)
  double free_running_time_budget_s{0.0};   ///< [s] per free-running cycle, 0 = none
  double reference_paths_republish_s{0.0};  ///< [s] of message time; 0 = only on a change
  double goal_min_walked_m{0.0};            ///< goal_inference.min_walked_m
  double goal_switch_margin_m{0.0};         ///< goal_inference.switch_margin_m
  double goal_agent_radius_m{0.0};          ///< goal_inference.agent_radius_m
  double forget_after_s{0.0};               ///< [s] limits.forget_after_s
  std::size_t max_ids{0};                   ///< limits.max_ids
};

/// A goal of the goals message.
struct AgentGoal {
  std::int32_t agent_id{0};
  AgentKind kind{AgentKind::kHuman};
  Pose2 pose;  ///< theta NaN = any heading
};

/// The dialogue's latest robot action since the last cycle.
struct CycleAction {
  bool dock{false};  ///< DOCK (else RESUME, or GO_FIRST when go_first)
  std::int32_t human_id{0};
  bool go_first{false};  ///< GO_FIRST: drive on past this person (goFirstCommand)
  bool slow{false};      ///< SLOW: drive on at most at slow.speed_m_s (slowCommand)
};

struct BandCycleInput {
  std::int64_t utime{0};  ///< [us] the agent states'
  std::int64_t step{-1};  ///< lockstep step, -1 free-running
  AgentState robot;
  std::vector<AgentState> humans;
  std::optional<std::vector<AgentGoal>> goals;  ///< nullopt: no goals message yet
  std::optional<CycleAction> action;
  std::vector<Eigen::Vector2d> planner_points;  ///< obstacles of the moment (scan) for the planner
  std::vector<Eigen::Vector2d> guard_points;    ///< ... and for the guard
};

struct BandCycleNote {
  enum class Level : std::int8_t { kDebug, kInfo, kWarn };
  Level level{Level::kInfo};
  std::string text;
};

/// The goal beliefs of the humans whose goal is inferred (goal_estimates_t).
struct CycleGoalEstimates {
  struct Human {
    std::int32_t agent_id{0};
    int most_likely{-1};
    double walked_m{0.0};
    std::int32_t observations{0};
    std::vector<double> probability;
  };
  std::vector<Eigen::Vector2d> goals;
  std::vector<Human> humans;
};

struct CycleReferencePath {
  std::int32_t agent_id{0};
  std::int32_t revision{0};
  Path2 path;
};

struct BandCycleOutput {
  /// In the lockstep order: goal estimates, reference paths, bands, command.
  std::optional<CycleGoalEstimates> goal_estimates;
  std::optional<std::vector<CycleReferencePath>> reference_paths;  ///< on a change or when due
  PlanResult plan;
  std::vector<RoomMove> room_plans;  ///< per plan.others: how the robot would make room
  /// The command's mode: idle (no goal), stopped (no usable plan and no driven mode), else mode.
  bool idle{false};
  bool stopped{false};
  RobotMode mode{RobotMode::kNavigate};
  Velocity2 command_body;  ///< under the guard
  GuardAction guard{GuardAction::kNone};
  double plan_ms{0.0};  ///< [ms] the planner's call, on the caller's clock (0 without one)
  std::vector<BandCycleNote> notes;
};

class BandCycle {
 public:
  /// `goals`: the candidate goals' distance fields for goal inference (nullptr: none, humans
  /// without a given goal get constant-velocity bands). `clock_s`: the caller's monotonic clock
  /// (the free-running time budget and plan_ms; empty: neither).
  BandCycle(const BandCycleConfig& config, std::shared_ptr<const DistanceMap> map,
            std::shared_ptr<const GoalDistances> goals, std::function<double()> clock_s);

  /// Range errors of the planner's configuration (empty when valid).
  const std::vector<BandPlannerConfig::Error>& configErrors() const {
    return planner_->configErrors();
  }

  BandCycleOutput step(const BandCycleInput& s);

  /// The agent states' clock was resynchronised at `utime`: the times kept from the old time
  /// base restart from it, goal beliefs restart.
  void restamp(std::int64_t utime);

  std::int64_t cycles() const { return cycles_; }
  /// Agent ids the planner may hold memory for (bands, paths).
  std::size_t plannerIdsKept() const { return planner_ids_.size(); }

 private:
  struct RefPath {
    Path2 path;
    std::int32_t revision{0};
  };
  /// The goal a human is planned with: the region's index and where on it the human was
  /// heading when it was chosen.
  struct InferredGoal {
    int index{-1};
    Eigen::Vector2d target{0.0, 0.0};
  };

  /// ROOM plan for each planned human (only for humans ahead and closing; kUnknown else).
  /// `obstacles`: the map with the cycle's obstacles of the moment.
  std::vector<RoomMove> roomPlans(const BandCycleInput& s, const PlanResult& result,
                                  const DistanceMap& obstacles) const;
  /// The command of a mode the robot drives itself (docking, retreating), else the planner's.
  Velocity2 modeCommand(const BandCycleInput& s, const ModeOutput& mode, const PlanResult& result,
                        bool hold, bool idle) const;
  /// While going first (GO_FIRST): the command past the person when the planner's is slower,
  /// else `planned`; ends going first once the person is passed, gone or the time is up.
  Velocity2 goFirstCommand(const BandCycleInput& s, const PlanResult& result,
                           const Velocity2& planned, BandCycleOutput& out);
  /// Behind a person ahead walking the robot's way (overtake.hpp): GO_FIRST for them passes
  /// them in the lane beside them; else the robot follows them (its pace capped to theirs, in
  /// that lane where one fits). `planned` when there is nobody to follow.
  /// `goal`: the robot's; a person beyond it is not in its way. `result`: the plan (its global
  /// path gives the robot's way).
  Velocity2 overtakeCommand(const BandCycleInput& s, const Pose2& goal, const PlanResult& result,
                            const Velocity2& planned, BandCycleOutput& out);
  /// While slowed (SLOW): `command` with its speed capped at slow.speed_m_s; ends slowing once
  /// the person is passed, gone or the time is up.
  Velocity2 slowCommand(const BandCycleInput& s, const Velocity2& command, BandCycleOutput& out);
  /// The safety guard applied to `command`, noted when its action changes.
  GuardOutput guard(const BandCycleInput& s, const Velocity2& command, BandCycleOutput& out);
  void referencePaths(const BandCycleInput& s, const PlanResult& result,
                      const std::set<std::int32_t>& with_goal, BandCycleOutput& out);
  /// Updates the goal belief of every human `given` has no goal for and returns the goals to plan
  /// with (the most likely, once min_walked_m is walked); the beliefs go into out.
  std::map<std::int32_t, Pose2> inferGoals(const BandCycleInput& s,
                                           const std::map<std::int32_t, Pose2>& given,
                                           BandCycleOutput& result);
  /// Bounds the planner's per-agent memory (max_ids, forget_after_s).
  void boundPlannerMemory(const BandCycleInput& s, const PlanResult& result, BandCycleOutput& out);

  BandCycleConfig config_;
  std::shared_ptr<const DistanceMap> map_;
  std::function<double()> clock_s_;
  std::unique_ptr<DualBandPlanner> planner_;
  DockModeMachine modes_;
  RobotLimits limits_;  ///< the planner's robot limits, for the commands it does not plan
  /// The robot's recent positions while it navigates: the way back for a wider place or a retreat.
  Trail trail_;
  GuardAction last_guard_{GuardAction::kNone};
  std::optional<std::int32_t> dock_human_id_;  ///< the human a dock is for, while docking / holding
  /// Going first (GO_FIRST) past this human since this time [s of message time].
  struct GoingFirst {
    std::int32_t human_id{0};
    double since_s{0.0};
  };
  std::optional<GoingFirst> go_first_;
  /// Passing a person ahead walking the robot's way (GO_FIRST for them): who, since when, and
  /// the robot's side as they see it.
  struct Passing {
    std::int32_t human_id{0};
    double since_s{0.0};
    Side side{Side::kUndefined};
  };
  std::optional<Passing> passing_;
  std::optional<std::int32_t> following_id_;  ///< the person followed (noted when it changes)
  std::optional<GoingFirst> slow_;            ///< slowed (SLOW) for this human since this time
  std::map<std::int32_t, RefPath> refs_;      ///< published reference path per human id
  std::optional<std::int64_t> last_refs_utime_;
  std::set<std::int32_t> humans_without_goal_;
  /// Goal inference (nullptr when disabled or without candidates): one belief per human whose
  /// goal is inferred, forgotten like the planner's ids.
  std::shared_ptr<const GoalDistances> goal_distances_;
  std::map<std::int32_t, GoalBelief> goal_beliefs_;
  IdRecency goal_belief_recency_;
  std::map<std::int32_t, InferredGoal> inferred_goal_;
  std::set<std::int32_t> humans_unplanned_;  ///< beyond planner.max_planned_others
  /// Agent ids planned since the planner's memory was last cleared (it keeps a band and a path
  /// per id it ever planned), and the time of that clearing or of the last check for ids gone.
  std::set<std::int32_t> planner_ids_;
  std::optional<std::int64_t> planner_memory_check_utime_;
  std::int64_t cycles_{0};
};

}  // namespace coopnav
