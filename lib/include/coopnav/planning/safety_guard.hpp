#pragma once
/// @file The last safety layer under the planner (beyond the paper): whatever the mode,
/// the velocity sent never closes the surface gap to a human below a minimum clearance, and a
/// human closing on a robot at rest makes it move away when it has room. With nobody near it
/// returns the planner's command unchanged, bit for bit. Pure logic; states come in as values.

#include <cstdint>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/planning/room.hpp"

namespace coopnav {

struct GuardOptions {
  /// The command may not bring the robot's body nearer a human's than this, where standing still
  /// would not [m].
  double min_clearance_m{0.2};
  /// Humans at constant velocity and the robot under the command, predicted this long [s] ...
  double horizon_s{1.0};
  /// ... every this [s].
  double sample_dt_s{0.1};
  /// A closing human predicted to come nearer than this gap within the horizon (under the
  /// command) makes the robot move away [m].
  double evade_gap_m{0.05};
  /// Evading keeps the robot's body this far from walls (or no nearer than it already is) [m].
  double evade_wall_margin_m{0.05};
};

/// Values mirror coopnav_velocity_command_t.GUARD_*.
enum class GuardAction : std::int8_t { kNone = 0, kSlowed = 1, kStopped = 2, kEvading = 3 };
const char* toString(GuardAction a);

struct GuardHuman {
  Eigen::Vector2d position{0.0, 0.0};
  Eigen::Vector2d velocity{0.0, 0.0};  ///< world frame [m/s]
  double radius_m{0.3};
};

struct GuardInput {
  Pose2 robot;
  double robot_radius_m{0.34};
  Velocity2 command_body;  ///< the planner's command (robot body frame)
  std::vector<GuardHuman> humans;
  /// Obstacles of the moment (laser returns, people's legs among them), world frame [m]: the
  /// command may not bring the robot's body nearer one than min_clearance_m either, where
  /// standing still would not (they stand still: they never make the robot evade), and an
  /// evasion keeps its wall margin from them as from the map. Empty: as without a scan.
  std::vector<Eigen::Vector2d> obstacle_points;
  RobotLimits limits;
};

struct GuardOutput {
  Velocity2 command_body;  ///< what to send
  GuardAction action{GuardAction::kNone};
  double scale{1.0};  ///< kSlowed / kStopped: the factor applied to the planner's command
};

/// The guarded command. Scaling: the largest factor in [0, 1] of the command under which, at
/// every sample of the horizon and for every human whose gap is then below min_clearance_m, the
/// gap is no smaller than with the robot at rest and the robot has not moved towards the human:
/// the robot's own motion never brings it, or keeps it, below the clearance.
/// Evading: when a closing human is predicted within evade_gap_m under the (guarded) command
/// (at rest, stopped, or the planner's own avoidance that is too slow), the direction among a fan
/// around "away from the human" (holonomic) or along the heading, forwards or backwards
/// (differential drive), that keeps the largest predicted gap, larger than the command's, has
/// free room and is allowed by the scaling's rule (it never moves towards a human within the
/// clearance), at the fastest speed the limits allow; none such: the command stays.
GuardOutput guardCommand(const DistanceMap& map, const GuardInput& in, const GuardOptions& o);

}  // namespace coopnav
