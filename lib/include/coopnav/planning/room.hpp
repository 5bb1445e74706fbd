#pragma once
/// @file Making room for a human who cannot pass (beyond the paper: §II-D only says "dock"; the
/// reading is in docs/design-readings.md "Decision pipeline"). A dock is offered only when it
/// really leaves the human a passage for its body; otherwise the robot goes back along its own
/// path to a wider place it reaches before the human does; otherwise it backs away the way it
/// came while the human keeps closing (CoHAN's backoff recovery). Pure logic on a DistanceMap;
/// time and states come in as values.

#include <cstdint>
#include <optional>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// The robot's body-frame velocity limits (the planner's robot kinematics).
struct RobotLimits {
  bool holonomic{true};          ///< false: differential drive (no lateral velocity)
  double max_forward_m_s{0.7};   ///< [m/s]
  double max_backward_m_s{0.4};  ///< [m/s], a magnitude
  double max_lateral_m_s{0.7};   ///< [m/s], holonomic only
  double max_omega_rad_s{1.2};   ///< [rad/s]
};

/// `body` scaled down by one factor (its direction kept) until every component is within the
/// limits; a differential drive's lateral component is dropped first.
Velocity2 clampToLimits(const Velocity2& body, const RobotLimits& limits);

/// Fastest time [s] for the robot at heading `theta_rad` to cover `distance_m` along the world
/// direction `dir`. Holonomic: it just moves there, keeping its heading. Differential drive: it
/// turns to face the way forwards or backwards and drives, whichever is sooner.
double travelTime(double distance_m, const Eigen::Vector2d& dir, double theta_rad,
                  const RobotLimits& limits);

/// Body-frame command that moves the robot straight towards `target` (world), at most at
/// `speed_m_s` and slowing down within `slow_radius_m` of it. Holonomic: slides there keeping its
/// heading; differential drive: turns towards it and drives forwards, or backwards when that
/// covers `distance_m` (at least the distance to the target) sooner, as travelTime.
Velocity2 driveTowards(const Pose2& robot, const Eigen::Vector2d& target, double speed_m_s,
                       double slow_radius_m, const RobotLimits& limits, double distance_m = 0.0);

/// Body-frame command that keeps the robot on `target` (world) once it is there: a slow
/// proportional approach (the route follower's gain) while it is more than `tolerance_m` off,
/// zero within it. Holding a dock pose: docking ends within its reached tolerance, and what the
/// robot stands off the pose, away from the wall, is taken from the passage the dock leaves.
Velocity2 settleOn(const Pose2& robot, const Eigen::Vector2d& target, double tolerance_m,
                   const RobotLimits& limits);

/// Length of `route` left from its point nearest `p` (plus the distance to it) [m].
double lengthLeft(const Path2& route, const Eigen::Vector2d& p);

/// Body-frame command that moves the robot along the world direction `dir` (unit) at the
/// fastest speed its limits allow: holonomic, straight there; differential drive, backing when
/// that covers `distance_m` sooner than turning round and driving forward, else turning.
Velocity2 driveAlong(const Pose2& robot, const Eigen::Vector2d& dir, double distance_m,
                     const RobotLimits& limits);

/// Body-frame command that follows `route` (waypoints, the first near the robot) to its last
/// point, at most `speed_m_s`, slowing down in proportion to the distance left so that it stops
/// on the last point.
Velocity2 followRoute(const Pose2& robot, const Path2& route, double speed_m_s,
                      const RobotLimits& limits);

/// Values mirror coopnav_bands_t.ROOM_*.
enum class RoomMove : std::int8_t {
  kUnknown = 0,     ///< not assessed, or nothing to make room in (no wall within range)
  kDockHere = 1,    ///< a dock pose nearby leaves the human a wide enough passage
  kWiderPlace = 2,  ///< a wider place back along the robot's path, reached before the human
  kRetreat = 3,     ///< back away the way it came while the human closes
  kNone = 4,        ///< no move leaves room: stop where it is
};
const char* toString(RoomMove m);

/// Options of the room decision beyond the dock pose's (DockOptions).
struct RoomOptions {
  /// Free width needed beside the robot = the human's diameter + this [m].
  double passage_margin_m{0.1};
  /// A wider place is looked for this far back along the robot's path [m], every step [m].
  double wider_search_m{15.0};
  double wider_step_m{0.25};
  /// The robot must be in the wider place this long before the human gets there [s].
  double reach_margin_s{1.0};
  /// A human keeps closing while the gap shrinks faster than this [m/s].
  double closing_speed_m_s{0.1};
  /// The retreat heads for the point this far back along the path [m].
  double retreat_lookahead_m{1.0};
  /// Free space needed behind the robot to retreat at all (beyond its radius) [m].
  double retreat_min_room_m{0.3};
};

/// Free width left to a human beside a robot standing at `robot_position`.
struct PassageCheck {
  bool ok{false};
  double free_width_m{0.0};  ///< narrowest free width on the human's side of the robot's body
  double needed_m{0.0};      ///< the human's diameter + passage_margin_m
};

/// The passage beside a robot of `robot_radius_m` at `robot_position`: from the robot's far side
/// (the side opposite `towards_wall`, unit) a ray across the corridor, sampled along `axis` (unit,
/// the line the human walks) over the stretch where the two bodies are side by side (± the sum
/// of the radii). The narrowest free width must hold the human's body plus the margin.
PassageCheck checkPassage(const DistanceMap& map, const Eigen::Vector2d& robot_position,
                          double robot_radius_m, const Eigen::Vector2d& axis,
                          const Eigen::Vector2d& towards_wall, double human_radius_m,
                          double passage_margin_m);

/// One robot and one human, as the room decision sees them.
struct Encounter {
  Pose2 robot;
  double robot_radius_m{0.34};
  Eigen::Vector2d human_position{0.0, 0.0};
  Eigen::Vector2d human_velocity{0.0, 0.0};  ///< world frame [m/s]
  double human_radius_m{0.3};
  /// The robot's recent positions, oldest first (the way it came); may be empty.
  const Path2* trail{nullptr};
  RobotLimits limits;
};

/// Unit vector from the robot towards where the human comes from: against the human's motion
/// when it walks, else towards the human, else the robot's heading; replaced by the direction
/// of the robot's trail near it (signed the same way) when that lies within 45 degrees of it, so
/// that a human stepping aside askew does not tilt the passage measured across the corridor.
Eigen::Vector2d encounterAxis(const Encounter& e);

/// Rate at which the gap between the robot (at rest) and the human shrinks [m/s]; > 0 closing.
double closingSpeed(const Encounter& e);

/// Free width on the side of the robot away from the wall it stands by: the passage at the robot's
/// current position (the side is the one away from the human, as for a dock).
PassageCheck passageHere(const DistanceMap& map, const Encounter& e, double passage_margin_m);

/// Where a dock pose may be.
struct DockOptions {
  double robot_radius_m{0.34};  ///< used when the encounter gives none (findDockPose)
  /// Gap kept between the robot's body and the wall it docks at [m]: flush, within a margin
  /// for the grid's and the controller's error.
  double margin_m{0.05};
  double search_range_m{5.0};  ///< how far sideways a wall is looked for [m]
  double max_ahead_m{1.5};     ///< candidates from this far behind … ahead of the robot [m]
  double step_m{0.25};         ///< spacing of candidates along the encounter axis [m]
};

/// What the robot would do now to make room for the human.
struct RoomDecision {
  RoomMove move{RoomMove::kUnknown};
  Pose2 target;              ///< kDockHere / kWiderPlace: where it goes (heading: the robot's)
  Path2 route;               ///< kDockHere / kWiderPlace: waypoints from the robot to target
  PassageCheck passage;      ///< at target (kDockHere / kWiderPlace), else here
  double robot_time_s{0.0};  ///< kWiderPlace: the robot's travel time to target
  double human_time_s{0.0};  ///< kWiderPlace: the human's time to reach it
};

/// The room decision, in order: a dock pose nearby (flush to the wall within the dock's margin)
/// whose passage holds; else the nearest place back along the trail where such a pose exists
/// and that the robot reaches reach_margin_s before the human (the robot at its top speed, the
/// human at its current one); else a retreat when there is room behind; else kNone. kUnknown
/// when there is no wall within range on either side and the passage here holds (nothing to
/// make room in: the band planner avoids).
RoomDecision decideRoom(const DistanceMap& map, const Encounter& e, const DockOptions& dock,
                        const RoomOptions& room);

/// Direction (world, unit) in which to retreat: back along the trail from the robot's foot on
/// it, else straight away from the human; nullopt when there is less than retreat_min_room_m
/// free behind.
std::optional<Eigen::Vector2d> retreatDirection(const DistanceMap& map, const Encounter& e,
                                                const RoomOptions& room);

/// The robot's recent positions, oldest first, at most `max_length_m` of path, points at least
/// `spacing_m` apart. Coming back near an earlier point cuts the loop after it, so that the trail
/// stays the way the robot came.
class Trail {
 public:
  explicit Trail(double max_length_m = 20.0, double spacing_m = 0.1)
      : max_length_m_(max_length_m), spacing_m_(spacing_m) {}
  void add(const Eigen::Vector2d& p);
  void clear() { points_.clear(); }
  const Path2& points() const { return points_; }

 private:
  double max_length_m_;
  double spacing_m_;
  Path2 points_;
};

}  // namespace coopnav
