#pragma once
/// @file Top-level CoHAN-style dual-band planner (Singamaneni et al., "Human-aware navigation
/// planner for diverse human-robot interaction contexts", IROS 2021; Khambhaita & Alami 2020):
/// one call plans the planning agent's band jointly with one anticipated band per other agent
/// and returns the bands, the reference paths and the velocity command.
///
/// The planning agent is any agent: band_source passes the robot (kind kRobot) and the tracked
/// humans as `others`; world_sim's "facilitating" human passes the simulated human as `agent`
/// and the robot (kind kRobot) as an `other`, which is then anticipated with the "minimal
/// contribution" weights, so the simulated human yields early. Limits follow each agent's
/// kind (config.robot / config.human); weights follow the role (planning_weights for `agent`,
/// other_weights for `others`). Time comes only from request.stamp_s.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "coopnav/band/band_config.hpp"
#include "coopnav/band/band_optimizer.hpp"
#include "coopnav/band/timed_elastic_band.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/planning/global_planner.hpp"

namespace coopnav {

/// One anticipated agent.
struct OtherAgentInput {
  AgentState state;  ///< id, kind (kRobot makes it "the robot" in the coupling terms), pose…
  /// Known goal (paper §II-A). Non-finite x/y: unknown → constant-velocity prediction.
  Pose2 goal;
  /// Reference (shortest) path; empty: planned here with A* to `goal` and cached per id.
  Path2 reference_path;
};

struct PlanRequest {
  double stamp_s{0.0};  ///< time of the states (from the agent-state messages)
  AgentState agent;     ///< the planning agent (normally the robot)
  Pose2 goal;           ///< the planning agent's goal (theta used unless free_goal_heading)
  std::vector<OtherAgentInput> others;
  /// Obstacles of the moment (laser returns the static map may not hold), world frame [m]: the
  /// bands' obstacle term sees the nearer of the map and these (PointObstacleMap), and the
  /// planning agent's global path goes round them: a cached path that passes nearer than its
  /// radius (less one grid cell) to one is planned again with them. Empty: the static map alone,
  /// as without a scan. The others' reference paths stay on the static map (the d_h reference
  /// of the paper is the shortest path the person would take without the robot).
  std::vector<Eigen::Vector2d> obstacle_points;
  int max_iterations{0};      ///< total LM iterations; <= 0: config inner × outer
  double time_budget_s{0.0};  ///< solver time budget; <= 0: unlimited
  /// Monotonic clock [s] for the time budget and PlanResult::solver_time_s (lib/ reads no
  /// clock); empty: no budget, solver_time_s 0.
  std::function<double()> clock_s;
};

enum class PlanStatus : std::int8_t {
  kOk = 0,
  kGoalReached = 1,    ///< within xy_goal_tolerance: zero command, band = current pose
  kInvalidInput = 2,   ///< non-finite agent pose or goal position
  kInvalidConfig = 3,  ///< config.validate() failed (see DualBandPlanner::configErrors())
  kOutsideMap = 4,     ///< agent or goal outside the map
  kStartInObstacle = 5,
  kGoalInObstacle = 6,
  kNoPath = 7,
};

const char* toString(PlanStatus s);

struct OtherAgentResult {
  std::int32_t id{0};
  Band band;             ///< anticipated band, time from request.stamp_s
  Path2 reference_path;  ///< the path the band was held to (the d_h reference)
  /// How the reference was obtained: kOk (given or A*), otherwise the A* failure, in which
  /// case a straight line / constant-velocity path was used.
  PathStatus reference_status{PathStatus::kOk};
  bool reference_changed{false};  ///< differs from the previous call's (publish on change)
  /// Beyond the nearest max_planned_others: the band is predicted (laid along its reference at
  /// its speed, a straight line to its goal when no path is known), not optimised jointly.
  bool predicted{false};
};

struct PlanResult {
  PlanStatus status{PlanStatus::kInvalidInput};
  Band agent_band;   ///< time from request.stamp_s
  Path2 agent_path;  ///< the global path the band follows
  /// The planned ones in the order of the valid request.others, then the predicted ones (in
  /// request order).
  std::vector<OtherAgentResult> others;
  std::vector<std::int32_t> skipped_ids;  ///< others with non-finite state, ignored
  /// Valid others beyond config max_planned_others (the farthest), in request order: their band
  /// in `others` is predicted, not planned (OtherAgentResult::predicted).
  std::vector<std::int32_t> unplanned_ids;
  Velocity2 command_body;  ///< BODY frame: vx forward, vy left, ω; zero unless kOk
  int iterations{0};
  int accepted_steps{0};  ///< of the iterations, LM steps taken (the rest rejected)
  double final_cost{0.0};
  double solver_time_s{0.0};
  bool budget_exhausted{false};
  bool warm_started{false};  ///< the bands kept are the warm candidate's
  /// A warm candidate (last cycle's bands) was optimised beside the fresh one this cycle.
  bool warm_candidate{false};
  std::vector<TermCost> term_costs;  ///< per cost term after the last iteration
  /// The obstacles of the moment block every path to the goal: the band follows the static
  /// map's path as far as they let it (the guard holds the robot short of them).
  bool path_blocked{false};
};

class DualBandPlanner {
 public:
  /// map must not be null. An invalid config is kept and reported by every plan() call.
  DualBandPlanner(BandPlannerConfig config, std::shared_ptr<const DistanceMap> map);

  /// One planning cycle. Never throws on bad input; see PlanStatus.
  PlanResult plan(const PlanRequest& request);

  /// Forgets warm-start bands and cached paths (e.g. after a new goal or a teleport).
  void reset();

  const BandPlannerConfig& config() const { return config_; }
  const std::vector<BandPlannerConfig::Error>& configErrors() const { return config_errors_; }

 private:
  /// One candidate: bands laid on the paths, or (allow_warm) last cycle's where still usable;
  /// *used_warm set when any band was warm. Stores its bands as the warm-start memory.
  PlanResult planOnce(const PlanRequest& request, bool allow_warm, bool* used_warm);

  struct Memory {
    TimedElasticBand band;
    double stamp_s{0.0};
  };
  struct CachedPath {
    Eigen::Vector2d goal{0.0, 0.0};
    Path2 path;
    PathStatus status{PathStatus::kOk};
    /// The static map's path, taken because the obstacles of the moment blocked every other.
    bool blocked{false};
  };

  BandPlannerConfig config_;
  std::vector<BandPlannerConfig::Error> config_errors_;
  std::shared_ptr<const DistanceMap> map_;
  std::unique_ptr<GridPathPlanner> global_;
  std::map<std::int32_t, Memory> bands_;      ///< warm start per agent id
  std::map<std::int32_t, CachedPath> paths_;  ///< global / reference path per agent id
};

}  // namespace coopnav
