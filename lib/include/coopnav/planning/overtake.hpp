#pragma once
/// @file Behind a person ahead walking the robot's way (geometry/same_way.hpp): the robot follows
/// them at the person's pace, a comfortable gap behind, in the lane beside them where the
/// corridor leaves room for its body and a clearance; once told it may pass (the dialogue
/// manager has said so: robot action GO_FIRST for that person), it drives past in that lane at
/// its own speed. Where no lane fits, it follows to its goal: that is progress, not a stalemate.
/// The planner's band alone does neither: its relative-velocity and safety terms hold it a step
/// behind and beside the person at their pace, never passing (issue 44). Pure: no clock.

#include <optional>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/same_way.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/planning/room.hpp"

namespace coopnav {

/// Following and passing (config/band_source.yaml `overtake`). Defaults in this one place.
struct OvertakeOptions {
  SameWayOptions same_way;
  /// [m] Surface gap kept behind the person while following: the outer edge of Hall's personal
  /// distance (Hall 1966: 0.45–1.2 m), where walkers following one another in a corridor keep
  /// about a stride and a half.
  double follow_gap_m{1.2};
  /// [s] A gap off follow_gap_m is closed in about this long: the speed is the person's plus
  /// (gap − follow_gap_m) / this, within the robot's limits.
  double follow_time_s{2.0};
  /// [m] Body to body beside the person while passing: above the guard's min_clearance_m (0.2),
  /// so that the guard does not stop the pass.
  double pass_clearance_m{0.25};
  /// [m] Body to wall in the lane beside the person.
  double wall_clearance_m{0.05};
  /// [m] The point the robot heads for is this far ahead of it.
  double lookahead_m{1.5};
  /// [m] Passed once the person's body is this far behind the robot's along the way (then the
  /// planner drives again, and may come back in front of them).
  double passed_margin_m{0.5};
  /// [s] A pass ends after this long even if the person is not passed yet (they sped up).
  double max_pass_s{40.0};
};

/// The lane beside the person the robot would pass in.
struct PassLane {
  bool fits{false};
  /// The robot's side as the person sees it (they face the robot's way); kUndefined when no
  /// lane fits.
  Side side{Side::kUndefined};
  /// [m] Lateral offset of the lane's centre line from the robot's line (> 0 left), in the
  /// robot's frame as SameWayPerson::lateral_m.
  double lateral_m{0.0};
  double room_left_m{0.0};   ///< [m] from the person's centre to the obstacle on the robot's left
  double room_right_m{0.0};  ///< ... on its right
};

/// The lane beside `p`, seen in `frame` (the robot's position, its heading the way it goes: its
/// path's direction, not a holonomic robot's body heading): on a side where the room from the
/// person's centre to the wall holds the person's radius, pass_clearance_m, the robot's body and
/// wall_clearance_m. Both fit: the side the robot is already on, else the roomier one.
PassLane passLane(const DistanceMap& map, const Pose2& frame, double robot_radius_m,
                  const SameWayPerson& p, const OvertakeOptions& o);

/// The lane on `side` while passing: as passLane's, but kept on that side, its offset from the
/// person cut where the wall comes nearer than the robot's body and wall_clearance_m.
PassLane laneOnSide(const DistanceMap& map, const Pose2& frame, double robot_radius_m,
                    const SameWayPerson& p, Side side, const OvertakeOptions& o);

/// [m/s] The following speed: the person's pace (never backwards), plus the gap error over
/// follow_time_s, at most max_m_s.
double followSpeed(const SameWayPerson& p, const OvertakeOptions& o, double max_m_s);

/// Body-frame command while following: along the way (`frame`'s heading) at followSpeed,
/// towards the lane when one fits (else on its own line).
Velocity2 followCommand(const Pose2& robot, const Pose2& frame, const SameWayPerson& p,
                        const PassLane& lane, const OvertakeOptions& o, const RobotLimits& limits);

/// Body-frame command while passing: along the lane at the robot's full speed.
Velocity2 passCommand(const Pose2& robot, const Pose2& frame, const PassLane& lane,
                      const OvertakeOptions& o, const RobotLimits& limits);

}  // namespace coopnav
