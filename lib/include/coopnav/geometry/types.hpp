#pragma once
/// @file Domain types shared by every lib/ area. World frame: x, y in metres, theta in radians
/// counter-clockwise from +x (see ../../../../README.md, "Frames").

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace coopnav {

/// Planar pose in the world frame.
struct Pose2 {
  double x_m{0.0};
  double y_m{0.0};
  double theta_rad{0.0};

  Eigen::Vector2d position() const { return {x_m, y_m}; }
  bool operator==(const Pose2& o) const {
    return x_m == o.x_m && y_m == o.y_m && theta_rad == o.theta_rad;
  }
};

/// Planar velocity in the world frame (not the body frame).
struct Velocity2 {
  double vx_m_s{0.0};
  double vy_m_s{0.0};
  double omega_rad_s{0.0};
  bool operator==(const Velocity2& o) const {
    return vx_m_s == o.vx_m_s && vy_m_s == o.vy_m_s && omega_rad_s == o.omega_rad_s;
  }
};

/// One pose of a timed band: t_s is the time from the band's start stamp.
struct TimedPose {
  double t_s{0.0};
  Pose2 pose;
  bool operator==(const TimedPose& o) const { return t_s == o.t_s && pose == o.pose; }
};

/// A timed elastic band as published: poses with non-decreasing time from start.
struct Band {
  std::vector<TimedPose> poses;
  bool operator==(const Band& o) const { return poses == o.poses; }
};

/// A geometric path (no timing), e.g. a shortest reference path.
using Path2 = std::vector<Eigen::Vector2d>;

enum class AgentKind : std::uint8_t { kRobot = 0, kHuman = 1 };

/// Observed state of one agent at a time stamp (from localisation, tracker or simulator).
struct AgentState {
  std::int32_t id{0};  ///< robot: 0 by convention; humans: tracker ids >= 1
  AgentKind kind{AgentKind::kHuman};
  Pose2 pose;
  Velocity2 velocity;
  double radius_m{0.3};
};

/// Lateral side as seen by an agent looking along its heading.
enum class Side : std::int8_t { kUndefined = 0, kLeft = 1, kRight = -1 };

inline Side opposite(Side s) {
  return s == Side::kLeft ? Side::kRight : (s == Side::kRight ? Side::kLeft : Side::kUndefined);
}

/// Three-valued predicate: the paper's predicates plus "unknown" when an input is missing.
enum class Tristate : std::int8_t { kUnknown = -1, kFalse = 0, kTrue = 1 };

inline Tristate toTristate(bool b) { return b ? Tristate::kTrue : Tristate::kFalse; }

}  // namespace coopnav
