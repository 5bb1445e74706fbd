#include "coopnav/distance/occupancy_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav {

const char* toString(DistanceStatus s) {
  switch (s) {
    case DistanceStatus::kOk:
      return "OK";
    case DistanceStatus::kOutsideMap:
      return "OUTSIDE_MAP";
    case DistanceStatus::kUnknownSpace:
      return "UNKNOWN_SPACE";
    case DistanceStatus::kInObstacle:
      return "IN_OBSTACLE";
    case DistanceStatus::kNotFound:
      return "NOT_FOUND";
    case DistanceStatus::kInvalidQuery:
      return "INVALID_QUERY";
  }
  return "INVALID_STATUS";
}

OccupancyGrid2::OccupancyGrid2(int width, int height, double resolution_m,
                               const Eigen::Vector2d& origin_m, CellState fill)
    : width_(width), height_(height), resolution_m_(resolution_m), origin_m_(origin_m) {
  // Cell indices are stored as int32 by the distance field, hence the product bound.
  if (width < 0 || height < 0 || static_cast<long long>(width) * height > (1LL << 30)) {
    throw std::invalid_argument("OccupancyGrid2: bad size");
  }
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m) || !origin_m.allFinite()) {
    throw std::invalid_argument("OccupancyGrid2: resolution must be > 0 and origin finite");
  }
  cells_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
}

std::optional<CellIndex> OccupancyGrid2::cellOf(const Eigen::Vector2d& p_m) const {
  if (!p_m.allFinite() || cells_.empty()) return std::nullopt;
  const double gx = std::floor((p_m.x() - origin_m_.x()) / resolution_m_);
  const double gy = std::floor((p_m.y() - origin_m_.y()) / resolution_m_);
  if (!(gx >= 0.0 && gy >= 0.0 && gx < width_ && gy < height_)) return std::nullopt;
  return CellIndex(static_cast<int>(gx), static_cast<int>(gy));
}

std::size_t OccupancyGrid2::count(CellState s) const {
  return static_cast<std::size_t>(std::count(cells_.begin(), cells_.end(), s));
}

}  // namespace coopnav
