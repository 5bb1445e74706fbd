#pragma once
/// @file The last check every simulated human but an oblivious one makes on its desired velocity:
/// a robot that is not coming at it is a body in its way, as a wall is. Where the robot's disc
/// leaves room between it and the wall for the human's body (with squeeze_margin_m to each), the
/// human steers round it and squeezes past, as people do in a tight spot; where it does not, the
/// human stops wait_gap_m short of it and waits, and goes on once the robot has made room. Without
/// it every model but the social force one walks straight into a robot at rest on its path (they
/// only avoid a robot coming towards them), and the social force one too in a 1.8 m corridor.
/// Pure and deterministic.

#include <cstdint>

#include "coopnav/geometry/types.hpp"
#include "coopnav/sim/behaviour.hpp"

namespace coopnav::sim {

/// What the body check is doing this step.
enum class BodyCheckMode : std::uint8_t {
  kOff = 0,      ///< no robot near, or a robot coming at the human: the model's own velocity
  kClear = 1,    ///< the model's velocity is only kept out of the robot's disc
  kSqueeze = 2,  ///< steering round the robot to pass it on side() (the model's plan falls short)
  kWait = 3,     ///< no room to pass: stopping short of the robot, waiting
};
const char* toString(BodyCheckMode m);

/// Free room beside a robot, across the human's path direction: what the wall leaves on each side
/// of the robot's body, from rays of the distance map through the robot's centre.
struct RoomBesideRobot {
  double left_m;   ///< between the robot's body and the wall to the path's left (inf = no wall)
  double right_m;  ///< the same to the right
};
/// `n_left`: unit normal to the left of the human's path direction. A nullptr map: no walls.
RoomBesideRobot roomBesideRobot(const DistanceMap* map, const AgentState& robot,
                                const Eigen::Vector2d& n_left);

class BodyCheck {
 public:
  explicit BodyCheck(const BodyCheckParams& p) : p_(p) {}

  /// `want` (the model's desired world velocity) kept out of the robot's body as described in the
  /// file comment. `planned_offset_m`: the model's own commanded lateral offset from its reference
  /// path (left > 0): where it means to be when it reaches the robot.
  Velocity2 apply(const BehaviourContext& ctx, const Velocity2& want, double planned_offset_m);

  BodyCheckMode mode() const { return mode_; }
  /// Side of the robot it passes on while squeezing: +1 left, -1 right of its path direction.
  double side() const { return side_; }
  /// Squeezing: the lateral offset from the reference path it steers to (left > 0).
  double targetOffset() const { return target_offset_m_; }

 private:
  BodyCheckParams p_;
  BodyCheckMode mode_{BodyCheckMode::kOff};
  bool latched_{false};  ///< a squeeze past the robot is under way (kept until it is behind)
  double side_{-1.0};
  double target_offset_m_{0.0};
};

}  // namespace coopnav::sim
