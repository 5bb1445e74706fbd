#pragma once
/// @file Global shortest-path planner on a DistanceMap: A* (Hart, Nilsson & Raphael 1968) on an
/// 8-connected grid at `resolution_m`, cells blocked where the clearance is below the agent's
/// radius, step cost raised near obstacles (clearance cost), then line-of-sight shortcutting
/// (the Theta* idea as post-processing) and resampling. Used for the robot's path and the
/// human's reference (shortest) path to its known goal (paper §II-A).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav {

enum class PathStatus : std::int8_t {
  kOk = 0,
  kInvalidInput = 1,  ///< non-finite point or non-positive radius
  kStartOutsideMap = 2,
  kGoalOutsideMap = 3,
  kStartInObstacle = 4,  ///< start inside an obstacle (or with less than half the radius free)
  kGoalInObstacle = 5,
  kNoPath = 6,
};

const char* toString(PathStatus s);

struct PathResult {
  PathStatus status{PathStatus::kNoPath};
  Path2 path;  ///< start … goal, points every sample_spacing_m; empty unless kOk
  double length_m{0.0};
};

class GridPathPlanner {
 public:
  struct Options {
    double resolution_m{0.1};      ///< grid cell size (>= the map's resolution)
    double clearance_pref_m{0.5};  ///< clearance beyond the radius below which steps cost more
    double clearance_weight{2.0};  ///< step cost × (1 + w · shortfall / pref); 0: pure shortest
    bool shortcut{true};           ///< line-of-sight shortcutting
    double sample_spacing_m{0.1};  ///< spacing of the returned points
  };

  /// Samples the map's clearance once on the grid (the map is immutable).
  GridPathPlanner(std::shared_ptr<const DistanceMap> map, Options options);

  /// Shortest path for a disc of radius inflation_radius_m. A start or goal with less than the
  /// full radius (but at least half) free is accepted: agents stand close to walls.
  /// `points`: obstacles of the moment (laser returns the static map does not hold, issue 45),
  /// each a point without extent: the cells near them get the nearer of the map's clearance and
  /// theirs for this query only, so the path goes round them with the radius and the clearance
  /// preference it keeps from walls. The start and goal are judged on the static map alone: an
  /// agent standing near a return must still be able to plan away from it.
  PathResult plan(const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                  double inflation_radius_m, const std::vector<Eigen::Vector2d>& points = {}) const;

  const Options& options() const { return options_; }

 private:
  struct Cell {
    int ix;
    int iy;
  };
  bool toCell(const Eigen::Vector2d& p, Cell* c) const;
  Eigen::Vector2d center(int ix, int iy) const;
  float clearanceAt(const std::vector<float>& grid, const Eigen::Vector2d& p) const;
  bool segmentClear(const std::vector<float>& grid, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b, double min_clear) const;
  /// The clearance grid lowered near `points` within reach_m (a copy; the grid is shared).
  std::vector<float> withPoints(const std::vector<Eigen::Vector2d>& points, double reach_m) const;

  std::shared_ptr<const DistanceMap> map_;
  Options options_;
  Eigen::Vector2d origin_{0.0, 0.0};
  int nx_{0};
  int ny_{0};
  std::vector<float> clearance_m_;  ///< per cell; < 0 outside/unknown
};

/// Total length of a polyline [m].
double pathLength(const Path2& path);

/// Points every spacing_m along the polyline (first and last kept).
Path2 resamplePath(const Path2& path, double spacing_m);

/// The part of `path` from arc length from_m over length_m (clamped to the path).
Path2 subPath(const Path2& path, double from_m, double length_m);

}  // namespace coopnav
