#pragma once
/// @file The one interface every consumer of obstacle distances uses (band planner, world sim,
/// situation assessor via the server). Implementations: the grid distance field (EDT) and
/// analytic maps in tests.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace coopnav {

/// Outcome of one distance query; mirrors coopnav_distance_result_t.STATUS_*.
enum class DistanceStatus : std::int8_t {
  kOk = 0,
  kOutsideMap = 1,    ///< query point outside the map's extent
  kUnknownSpace = 2,  ///< query point in unknown space
  kInObstacle = 3,    ///< query point inside an occupied cell (distance 0)
  kNotFound = 4,      ///< no obstacle within range (RAY: free up to the range)
  kInvalidQuery = 5,  ///< non-finite point, zero normal/direction, non-positive range
};

const char* toString(DistanceStatus s);

struct DistanceResult {
  DistanceStatus status{DistanceStatus::kInvalidQuery};
  /// [m] from the query point to the nearest obstacle surface; RAY: free length along the ray.
  /// Meaningful for kOk and kInObstacle (0); for SIDE kNotFound = max range; for RAY kNotFound =
  /// free length travelled: the max range, or less when the ray leaves the map first.
  double distance_m{0.0};
  /// World-frame point on the obstacle found (RAY: hit point). Meaningful for kOk.
  Eigen::Vector2d obstacle{0.0, 0.0};
};

/// A static 2-D map of obstacles answering the three query kinds of the distance server.
/// All points and vectors are in the world frame, metres. Implementations are immutable after
/// construction, so const calls are safe from several threads.
class DistanceMap {
 public:
  virtual ~DistanceMap() = default;

  /// Axis-aligned extent of the map in the world frame.
  virtual Eigen::AlignedBox2d bounds() const = 0;
  /// Grid resolution (the accuracy of every answer) [m]; 0 for analytic maps.
  virtual double resolution_m() const = 0;

  /// NEAREST: nearest obstacle to p.
  virtual DistanceResult nearest(const Eigen::Vector2d& p) const = 0;
  /// SIDE: nearest obstacle o in the half-plane {o : (o - q).n >= 0} (n need not be unit),
  /// searched up to max_range_m from q. The paper's "closest obstacle away from the robot/human".
  virtual DistanceResult nearestInHalfPlane(const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                            double max_range_m) const = 0;
  /// RAY: free distance from p along dir (need not be unit) up to max_range_m.
  virtual DistanceResult ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                             double max_range_m) const = 0;
};

}  // namespace coopnav
