#pragma once
/// @file A person ahead of the robot walking its way, or standing in it (issue 44: a slower
/// walker, a person who pauses): the robot follows them at a comfortable distance and passes
/// when the corridor leaves room beside them. The classification both the band source (how to
/// move) and the dialogue manager (what to say) make of the same agent states, so that what is
/// said and what is done are read from one geometry. Pure: no map (the room beside the person is
/// the band source's, planning/overtake.hpp).

#include <cstdint>
#include <optional>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// Who counts as a person ahead going the robot's way. Defaults in this one place.
struct SameWayOptions {
  /// [m] Surface gap along the robot's way beyond which nobody is followed yet.
  double ahead_range_m{6.0};
  /// [m/s] A person walking (at standing_speed_m_s or faster) goes the robot's way when their
  /// velocity along the robot's way is at least this ...
  double min_speed_along_m_s{-0.1};
  /// [m/s] ... slower, they stand, and go the robot's way when they face it (heading within 90°
  /// of it): someone who stopped on the way, not one who stopped facing the robot to let it by.
  /// Under a walk (>= 0.5 m/s), above a tracked person's velocity noise.
  double standing_speed_m_s{0.2};
  /// [m] ... and is in the robot's way when the lateral distance between centres is below the
  /// two radii plus this: a person the robot already clears by it is not followed.
  double lane_margin_m{0.6};
};

/// A person ahead walking the robot's way, in the robot's frame (its heading).
struct SameWayPerson {
  std::int32_t id{0};
  double along_m{0.0};    ///< [m] centre ahead of the robot's centre along its heading (> 0)
  double lateral_m{0.0};  ///< [m] centre left (> 0) of the robot's line
  double gap_m{0.0};      ///< [m] surface to surface
  double speed_along_m_s{0.0};
  double radius_m{0.3};
  /// The side the robot is on as that person sees it (they face the robot's way): kLeft when
  /// the robot is to their left. kUndefined when the robot is straight behind them (within
  /// 1 cm).
  Side robot_side{Side::kUndefined};
};

/// The nearest person (surface gap) ahead of the robot, in its way and walking its way (or
/// standing), within ahead_range_m. Humans' velocities are world-frame.
std::optional<SameWayPerson> sameWayAhead(const Pose2& robot, double robot_radius_m,
                                          const std::vector<AgentState>& humans,
                                          const SameWayOptions& options);

/// The same person, by id, if they are still ahead of the robot and walking its way (the lane
/// test left out: a robot in the lane beside them is still behind them until it has passed).
std::optional<SameWayPerson> sameWayPerson(const Pose2& robot, double robot_radius_m,
                                           const AgentState& human, const SameWayOptions& options);

/// [m] The surface gap between the robot's body and the person's, across the robot's way: what
/// the robot clears them by if it drives straight on.
double lateralClearance(const SameWayPerson& p, double robot_radius_m);

}  // namespace coopnav
