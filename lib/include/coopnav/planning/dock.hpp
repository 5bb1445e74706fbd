#pragma once
/// @file Docking (paper §II-D, design-readings "Decision pipeline"): when the human cannot make
/// room, the robot moves to the nearest wall on the side away from the human, waits until the
/// human has passed, then resumes to its goal. Pure logic; time comes from the inputs.

#include <cstdint>
#include <functional>
#include <optional>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/planning/room.hpp"

namespace coopnav {

enum class DockStatus : std::int8_t {
  kOk = 0,
  kInvalidInput = 1,
  kNoWall = 2,       ///< no wall within range on the side away from the human
  kUnreachable = 3,  ///< every candidate is blocked or too narrow
};

struct DockResult {
  DockStatus status{DockStatus::kInvalidInput};
  Pose2 pose;                   ///< dock pose (heading = the robot's heading, parallel to the wall)
  Side side{Side::kUndefined};  ///< side of the robot (looking along its heading) it docks to
  double wall_distance_m{0.0};  ///< from the dock pose's centre to the wall
};

/// Dock pose on the side of the robot away from the human (as the robot looks along its
/// heading; a human dead ahead gives the robot's right, keep-right).
/// Candidates along the robot heading; each is placed radius + margin from the wall found by a
/// sideways ray, must have that clearance (DistanceMap::nearest) and a straight, clear approach
/// from the robot. The nearest valid candidate wins.
DockResult findDockPose(const DistanceMap& map, const Pose2& robot, const Pose2& human,
                        const DockOptions& options = {});

/// The unit normal, across `axis`, towards the side of the robot away from the human (dead
/// ahead: the right of `axis`, keep-right).
Eigen::Vector2d sideAwayFrom(const Eigen::Vector2d& axis, const Eigen::Vector2d& robot,
                             const Eigen::Vector2d& human);

/// findDockPose's search with its frame given: candidates from `robot` along `axis` (unit),
/// each pushed along `towards_wall` (unit, across the axis) to `radius_m` + margin from the wall.
/// Of the candidates `accept` takes (all, when empty) the cheapest wins: the shortest move, a
/// move along the axis counting 1.5x (it shortens the gap to the human).
DockResult findDockPoseAlong(const DistanceMap& map, const Pose2& robot,
                             const Eigen::Vector2d& axis, const Eigen::Vector2d& towards_wall,
                             double radius_m, const DockOptions& options,
                             const std::function<bool(const Eigen::Vector2d&)>& accept = {});

/// Planner-level modes of the robot (navigate → docking → holding → resuming → navigate …;
/// docking / holding → retreating → holding / docking / resuming).
enum class RobotMode : std::int8_t {
  kNavigate = 0,
  kDocking = 1,
  kHolding = 2,
  kResuming = 3,
  kGoalReached = 4,
  kRetreating = 5,  ///< backing away the way it came while the human keeps closing
};

const char* toString(RobotMode m);

struct ModeMachineOptions {
  /// The dock pose is reached within this [m]: the robot drives there itself (driveTowards), so
  /// it can be tighter than the planner's goal tolerance.
  double dock_reached_tolerance_m{0.05};
  /// Holding at the dock pose, the robot keeps itself on it to within this [m] (settleOn).
  double dock_settle_tolerance_m{0.01};
  double goal_tolerance_m{0.2};
  double human_passed_margin_m{0.3};  ///< robot this far behind the human along its heading
  double human_far_m{5.0};            ///< or the human this far away and going away:
  double human_receding_m{0.5};       ///< farther than at the dock request by this much
  double hold_timeout_s{30.0};        ///< CoHAN's backoff timeout
  DockOptions dock{};
  RoomOptions room{};
};

/// Inputs of one update: time and states from messages, plus the dialogue's requests.
struct ModeInput {
  double stamp_s{0.0};
  Pose2 robot;
  double robot_radius_m{0.34};
  Pose2 goal;
  bool has_human{false};
  Pose2 human;                               ///< position + heading (heading of motion if walking)
  Eigen::Vector2d human_velocity{0.0, 0.0};  ///< world frame [m/s]
  double human_radius_m{0.3};
  const Path2* trail{nullptr};  ///< the robot's recent positions, oldest first (Trail)
  RobotLimits limits;
  bool dock_requested{false};
  bool resume_requested{false};
};

struct ModeOutput {
  RobotMode mode{RobotMode::kNavigate};
  Pose2 active_goal;       ///< where the planner should go now (dock pose or the goal)
  bool hold_still{false};  ///< command zero velocity (holding) ...
  /// ... but for keeping on the dock pose (active_goal) when it holds at one (settleOn).
  bool settle{false};
  bool changed{false};                     ///< mode changed in this update
  std::optional<DockStatus> dock_failure;  ///< a requested dock that could not be found
  /// Docking: the route the robot drives itself (waypoints to the dock pose; the planner's band
  /// keeps its clearance from walls and would stop short of a flush dock).
  Path2 route;
  /// Retreating: the direction to back away in (world, unit).
  std::optional<Eigen::Vector2d> retreat_direction;
  /// The room decision taken at this update's dock request or escalation (kUnknown otherwise).
  RoomMove room{RoomMove::kUnknown};
};

class DockModeMachine {
 public:
  explicit DockModeMachine(ModeMachineOptions options = {}) : opt_(options) {}
  ModeOutput update(const DistanceMap& map, const ModeInput& in);
  RobotMode mode() const { return mode_; }
  const ModeMachineOptions& options() const { return opt_; }

  /// True once the robot is behind the human along the human's heading (by the margin).
  static bool humanHasPassed(const Pose2& robot, const Pose2& human, double margin_m);

 private:
  /// Holding where the robot stands (not at a dock pose).
  void holdHere(const ModeInput& in);
  /// Starts the move of a room decision; false when it is no move (kUnknown).
  bool start(const RoomDecision& d, const ModeInput& in, ModeOutput& out);

  ModeMachineOptions opt_;
  RobotMode mode_{RobotMode::kNavigate};
  Pose2 dock_;
  Path2 route_;
  RoomMove dock_move_{RoomMove::kUnknown};  ///< what the dock being driven to is
  bool on_dock_{false};  ///< holding at the dock pose it drove to (not where it stopped)
  double hold_since_s_{0.0};
  double dock_start_dist_m_{0.0};  ///< robot–human distance when the dock was asked for
  /// From the human to the robot when the dock was asked for (unit): the human has passed once
  /// the robot is behind them along it.
  Eigen::Vector2d dock_axis_{1.0, 0.0};
};

/// Encounter of the mode input's robot and human.
Encounter encounterOf(const ModeInput& in);

}  // namespace coopnav
