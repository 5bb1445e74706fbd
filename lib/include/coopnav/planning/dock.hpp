#pragma once
/// @file Docking (paper §II-D, design-readings "Decision pipeline"): when the human cannot make
/// room, the robot moves to the nearest wall on the side away from the human, waits until the
/// human has passed, then resumes to its goal. Pure logic; time comes from the inputs.

#include <cstdint>
#include <optional>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav {

struct DockOptions {
  double robot_radius_m{0.34};
  double margin_m{0.1};        ///< clearance beyond the radius kept from the wall
  double search_range_m{5.0};  ///< how far sideways a wall is looked for
  double max_ahead_m{1.5};     ///< candidates from this far behind … ahead of the robot
  double step_m{0.25};         ///< spacing of candidates along the heading
};

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

/// Planner-level modes of the robot (navigate → docking → holding → resuming → navigate …).
enum class RobotMode : std::int8_t {
  kNavigate = 0,
  kDocking = 1,
  kHolding = 2,
  kResuming = 3,
  kGoalReached = 4,
};

const char* toString(RobotMode m);

struct ModeMachineOptions {
  double dock_reached_tolerance_m{0.15};
  double goal_tolerance_m{0.2};
  double human_passed_margin_m{0.3};  ///< robot this far behind the human along its heading
  double human_far_m{5.0};            ///< or the human this far away and going away:
  double human_receding_m{0.5};       ///< farther than at the dock request by this much
  double hold_timeout_s{30.0};        ///< CoHAN's backoff timeout
  DockOptions dock{};
};

/// Inputs of one update: time and states from messages, plus the dialogue's requests.
struct ModeInput {
  double stamp_s{0.0};
  Pose2 robot;
  Pose2 goal;
  bool has_human{false};
  Pose2 human;  ///< position + heading (heading of motion if walking)
  bool dock_requested{false};
  bool resume_requested{false};
};

struct ModeOutput {
  RobotMode mode{RobotMode::kNavigate};
  Pose2 active_goal;       ///< where the planner should go now (dock pose or the goal)
  bool hold_still{false};  ///< command zero velocity (holding)
  bool changed{false};     ///< mode changed in this update
  std::optional<DockStatus> dock_failure;  ///< a requested dock that could not be found
};

class DockModeMachine {
 public:
  explicit DockModeMachine(ModeMachineOptions options = {}) : opt_(options) {}
  ModeOutput update(const DistanceMap& map, const ModeInput& in);
  RobotMode mode() const { return mode_; }

  /// True once the robot is behind the human along the human's heading (by the margin).
  static bool humanHasPassed(const Pose2& robot, const Pose2& human, double margin_m);

 private:
  ModeMachineOptions opt_;
  RobotMode mode_{RobotMode::kNavigate};
  Pose2 dock_;
  double hold_since_s_{0.0};
  double dock_start_dist_m_{0.0};  ///< robot–human distance when the dock was asked for
};

}  // namespace coopnav
