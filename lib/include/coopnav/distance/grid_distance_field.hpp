#pragma once
/// @file Exact 2-D Euclidean distance field on an occupancy grid, answering NEAREST, SIDE and RAY.
///
/// Distance convention (every query, and the brute-force tests, use exactly this):
///  - Obstacles are cells: kOccupied, plus kUnknown under UnknownPolicy::kObstacle.
///  - NEAREST and SIDE snap the query point p to the centre c of its cell. With o the centre of the
///    chosen obstacle cell, distance_m = |o - c| - res/2: the centre-to-centre distance minus half
///    a cell (res/2 for a 4-neighbour, where it is c's distance to the shared face). It is exact on
///    the grid and removes the +res/2 bias of centre-to-centre EDTs. `obstacle` is the point on
///    segment c -> o at res/2 from o (in the closed square of the obstacle cell, on its face for a
///    4-neighbour), so |obstacle - c| == distance_m.
///  - RAY is not snapped: it walks the cells crossed by p + t*dir (Amanatides & Woo 1987) and
///    reports the t [m] where the ray enters the first obstacle cell's square.
///  - Cells outside the grid are never obstacles.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/distance/occupancy_grid.hpp"

namespace coopnav {

/// How unknown cells take part in distances. A query point in an unknown cell always gets
/// kUnknownSpace, whatever the policy.
enum class UnknownPolicy : std::uint8_t {
  kObstacle = 0,  ///< unknown cells are obstacles (safe default; open.pgm's pillar is unknown)
  kFree = 1,      ///< unknown cells are ignored
};

/// Immutable distance field over an OccupancyGrid2. Build: Felzenszwalb & Huttenlocher, "Distance
/// Transforms of Sampled Functions", Theory of Computing 8 (2012), doi:10.4086/toc.2012.v008a019,
/// extended to carry the nearest obstacle cell; 9 B/cell. SIDE: branch-and-bound over a k-d tree
/// of boundary obstacle cells. RAY: Amanatides & Woo, "A Fast Voxel Traversal Algorithm for Ray
/// Tracing", Eurographics 1987. All queries are const and thread-safe.
class GridDistanceField final : public DistanceMap {
 public:
  /// Builds the field (O(cells)). An empty grid gives a field where every point is kOutsideMap.
  explicit GridDistanceField(OccupancyGrid2 grid, UnknownPolicy unknown = UnknownPolicy::kObstacle);

  Eigen::AlignedBox2d bounds() const override;
  double resolution_m() const override { return grid_.resolution_m(); }

  /// NEAREST (see file comment for the convention). kNotFound when the map has no obstacle.
  DistanceResult nearest(const Eigen::Vector2d& p) const override;
  /// SIDE: nearest obstacle cell with centre o such that (o - q).n/|n| >= -sideTolerance_m(),
  /// with distance_m <= max_range_m (kNotFound otherwise; distance_m then = max_range_m).
  /// Distance measured from the centre of q's cell as for NEAREST, so SIDE == NEAREST whenever the
  /// nearest obstacle lies in the half-plane. The tolerance admits every cell whose square touches
  /// the half-plane, which keeps the answer from jumping when the side test flickers.
  DistanceResult nearestInHalfPlane(const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                    double max_range_m) const override;
  /// RAY: free length along dir from p. kOk with the entry point into the first obstacle cell;
  /// kNotFound when the ray reaches max_range_m or leaves the grid first (distance_m = the length
  /// travelled, min(max range, distance to the grid edge)).
  DistanceResult ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                     double max_range_m) const override;

  const OccupancyGrid2& grid() const { return grid_; }
  UnknownPolicy unknownPolicy() const { return unknown_; }
  /// Side-test tolerance res/sqrt(2) [m]: half a cell diagonal.
  double sideTolerance_m() const { return grid_.resolution_m() * M_SQRT1_2; }
  /// True when cell (i, j) is inside the grid and an obstacle under the unknown policy.
  bool isObstacle(int i, int j) const;
  /// Squared centre-to-centre distance [cells^2] from cell (i, j) to its nearest obstacle cell;
  /// -1 when the map has no obstacle. Precondition: grid().contains(i, j).
  std::int64_t squaredCellDistance(int i, int j) const { return sq_dist_[grid_.linearIndex(i, j)]; }
  /// Nearest obstacle cell of (i, j) (one of them on ties); (-1, -1) when none.
  CellIndex nearestObstacleCell(int i, int j) const;
  /// Number of boundary obstacle cells (with a non-obstacle 4-neighbour) indexed for SIDE.
  std::size_t boundaryCellCount() const { return boundary_.size(); }
  /// The metric distance [m] of a squared cell distance under the convention above.
  double cellDistanceToMetres(std::int64_t sq_cells) const {
    return std::sqrt(static_cast<double>(sq_cells)) * grid_.resolution_m() -
           0.5 * grid_.resolution_m();
  }

 private:
  struct KdNode {
    std::int32_t begin, end;                  // range in boundary_
    std::int32_t left, right;                 // children, -1 for a leaf
    std::int32_t min_i, min_j, max_i, max_j;  // bounding box of the cells, inclusive
  };

  void computeEdt();
  void buildBoundaryTree();
  std::int32_t buildKd(std::int32_t begin, std::int32_t end, int depth);
  /// The whole answer for a query point that is not in free space (not finite, outside the map,
  /// unknown, or in an obstacle, which is then its own nearest obstacle); otherwise nullopt, and
  /// the point's cell in *cell.
  std::optional<DistanceResult> answerUnlessFree(const Eigen::Vector2d& p, CellIndex* cell) const;
  DistanceResult resultFor(const CellIndex& c, const CellIndex& o, std::int64_t sq_cells) const;

  OccupancyGrid2 grid_;
  UnknownPolicy unknown_;
  std::vector<std::uint8_t> obstacle_;  // 1 = obstacle under the unknown policy
  std::vector<std::int32_t> sq_dist_;   // [cells^2], -1 = no obstacle anywhere
  std::vector<std::int32_t> nearest_;   // linear index of the nearest obstacle cell, -1 = none
  std::vector<CellIndex> boundary_;     // boundary obstacle cells, in k-d tree order
  std::vector<KdNode> kd_;
};

}  // namespace coopnav
