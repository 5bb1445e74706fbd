#pragma once
/// @file A plain 2-D occupancy grid: the common currency between the map loaders (daemons/common),
/// the OctoMap map of record and the distance field.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace coopnav {

/// State of one grid cell, as read from a map (ROS map_server trinary semantics).
enum class CellState : std::int8_t { kFree = 0, kOccupied = 1, kUnknown = -1 };

/// Integer cell index: i along world x (column), j along world y (row, j = 0 at the bottom).
using CellIndex = Eigen::Vector2i;

/// Row-major 2-D occupancy grid, axis-aligned with the world frame (no yaw).
/// Cell (i, j) covers x in [origin.x + i*res, origin.x + (i+1)*res) and the same in y, so row
/// j = 0 is the bottom (smallest y), unlike image rows.
class OccupancyGrid2 {
 public:
  /// An empty 0x0 grid.
  OccupancyGrid2() = default;
  /// width x height cells of resolution_m [m] (> 0), all set to fill; origin_m is the world
  /// position [m] of the lower-left corner of cell (0, 0).
  OccupancyGrid2(int width, int height, double resolution_m, const Eigen::Vector2d& origin_m,
                 CellState fill = CellState::kUnknown);

  int width() const { return width_; }
  int height() const { return height_; }
  /// Edge length of a cell [m].
  double resolution_m() const { return resolution_m_; }
  /// World position [m] of the lower-left corner of cell (0, 0).
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  bool empty() const { return cells_.empty(); }
  std::size_t size() const { return cells_.size(); }

  bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < width_ && j < height_; }
  std::size_t linearIndex(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(i);
  }
  /// Precondition: contains(i, j).
  CellState at(int i, int j) const { return cells_[linearIndex(i, j)]; }
  /// Precondition: contains(i, j).
  void set(int i, int j, CellState s) { cells_[linearIndex(i, j)] = s; }
  const std::vector<CellState>& cells() const { return cells_; }

  /// Cell holding world point p_m [m]; nullopt when p_m is non-finite or outside the grid.
  std::optional<CellIndex> cellOf(const Eigen::Vector2d& p_m) const;
  /// World position [m] of the centre of cell (i, j) (any i, j, also outside the grid).
  Eigen::Vector2d cellCenter_m(int i, int j) const {
    return origin_m_ + resolution_m_ * Eigen::Vector2d(i + 0.5, j + 0.5);
  }
  /// World-frame extent [m]: lower-left corner of cell (0,0) to upper-right of the last cell.
  Eigen::Vector2d max_m() const {
    return origin_m_ + resolution_m_ * Eigen::Vector2d(width_, height_);
  }

  /// Number of cells in state s.
  std::size_t count(CellState s) const;

  bool operator==(const OccupancyGrid2& o) const {
    return width_ == o.width_ && height_ == o.height_ && resolution_m_ == o.resolution_m_ &&
           origin_m_ == o.origin_m_ && cells_ == o.cells_;
  }
  bool operator!=(const OccupancyGrid2& o) const { return !(*this == o); }

 private:
  int width_{0};
  int height_{0};
  double resolution_m_{0.0};
  Eigen::Vector2d origin_m_{0.0, 0.0};
  std::vector<CellState> cells_;
};

}  // namespace coopnav
