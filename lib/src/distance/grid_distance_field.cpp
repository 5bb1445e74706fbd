#include "coopnav/distance/grid_distance_field.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

namespace coopnav {
namespace {

constexpr std::int32_t kLeafSize = 8;
// A k-d box is pruned from SIDE only when clearly outside the half-plane: the box corners and the
// cells inside it are evaluated with different roundings.
constexpr double kSidePruneSlack_m = 1e-9;

bool rangeValid(double max_range_m) { return max_range_m > 0.0; }  // false for NaN too

DistanceResult statusOnly(DistanceStatus s) {
  DistanceResult r;
  r.status = s;
  return r;
}

}  // namespace

GridDistanceField::GridDistanceField(OccupancyGrid2 grid, UnknownPolicy unknown)
    : grid_(std::move(grid)), unknown_(unknown) {
  computeEdt();
  buildBoundaryTree();
}

Eigen::AlignedBox2d GridDistanceField::bounds() const {
  return Eigen::AlignedBox2d(grid_.origin_m(), grid_.max_m());
}

bool GridDistanceField::isObstacle(int i, int j) const {
  return grid_.contains(i, j) && obstacle_[grid_.linearIndex(i, j)] != 0;
}

CellIndex GridDistanceField::nearestObstacleCell(int i, int j) const {
  const std::int32_t k = nearest_[grid_.linearIndex(i, j)];
  if (k < 0) return CellIndex(-1, -1);
  return CellIndex(k % grid_.width(), k / grid_.width());
}

// Separable exact EDT (Felzenszwalb & Huttenlocher 2012): a 1-D pass per column gives the nearest
// obstacle row, then the lower envelope of parabolas per row picks the best column. Keeping the
// argmin column (and its row from pass 1) yields the nearest obstacle cell for free.
void GridDistanceField::computeEdt() {
  const int w = grid_.width();
  const int h = grid_.height();
  sq_dist_.assign(grid_.size(), -1);
  nearest_.assign(grid_.size(), -1);
  if (grid_.empty()) return;

  obstacle_.resize(grid_.size());
  const bool unknown_is_obstacle = unknown_ == UnknownPolicy::kObstacle;
  for (std::size_t k = 0; k < grid_.size(); ++k) {
    const CellState s = grid_.cells()[k];
    obstacle_[k] = s == CellState::kOccupied || (s == CellState::kUnknown && unknown_is_obstacle);
  }

  // Pass 1, row by row (cache-friendly): nearest obstacle row in the same column, from below
  // then from above.
  const std::size_t stride = static_cast<std::size_t>(w);
  std::vector<std::int32_t> col_row(grid_.size(), -1);
  for (int j = 0; j < h; ++j) {
    const std::size_t row = static_cast<std::size_t>(j) * stride;
    for (int i = 0; i < w; ++i) {
      if (obstacle_[row + i]) {
        col_row[row + i] = j;
      } else if (j > 0) {
        col_row[row + i] = col_row[row - stride + i];
      }
    }
  }
  for (int j = h - 2; j >= 0; --j) {
    const std::size_t row = static_cast<std::size_t>(j) * stride;
    for (int i = 0; i < w; ++i) {
      const std::int32_t above = col_row[row + stride + i];
      std::int32_t& r = col_row[row + i];
      if (above > j && (r < 0 || above - j < j - r)) r = above;
    }
  }

  std::vector<std::int64_t> f(static_cast<std::size_t>(w));
  std::vector<int> v(static_cast<std::size_t>(w));
  std::vector<double> z(static_cast<std::size_t>(w) + 1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int j = 0; j < h; ++j) {
    int k = -1;
    for (int q = 0; q < w; ++q) {
      const std::int32_t r = col_row[grid_.linearIndex(q, j)];
      if (r < 0) continue;  // no obstacle in this column: an infinite parabola never wins
      f[q] = static_cast<std::int64_t>(r - j) * (r - j);
      if (k < 0) {
        k = 0;
        v[0] = q;
        z[0] = -kInf;
        z[1] = kInf;
        continue;
      }
      double s = 0.0;
      while (true) {
        const int p = v[k];
        s = (static_cast<double>(f[q] + static_cast<std::int64_t>(q) * q) -
             static_cast<double>(f[p] + static_cast<std::int64_t>(p) * p)) /
            (2.0 * (q - p));
        if (s <= z[k]) {
          --k;  // z[0] = -inf guarantees k stays >= 0
        } else {
          break;
        }
      }
      ++k;
      v[k] = q;
      z[k] = s;
      z[k + 1] = kInf;
    }
    if (k < 0) continue;
    int e = 0;
    for (int q = 0; q < w; ++q) {
      while (z[e + 1] < q) ++e;
      const int p = v[e];
      const int row = col_row[grid_.linearIndex(p, j)];
      const std::size_t idx = grid_.linearIndex(q, j);
      const std::int64_t di = q - p;
      const std::int64_t dj = row - j;
      sq_dist_[idx] = static_cast<std::int32_t>(di * di + dj * dj);
      nearest_[idx] = static_cast<std::int32_t>(grid_.linearIndex(p, row));
    }
  }
}

// Only boundary obstacle cells (with a non-obstacle 4-neighbour) can be the answer to SIDE: the
// centre c of the query cell lies in the tolerant half-plane H (|c - q| projects to at most
// res/sqrt(2) on n), so for an interior candidate o in H one of its 4-neighbours towards c is in
// H too (H is convex and holds o, c and one of the two other corners of their bounding box) and
// strictly nearer c. Hence o is not nearest.
void GridDistanceField::buildBoundaryTree() {
  boundary_.clear();
  kd_.clear();
  for (int j = 0; j < grid_.height(); ++j) {
    for (int i = 0; i < grid_.width(); ++i) {
      if (!isObstacle(i, j)) continue;
      const bool boundary = (grid_.contains(i - 1, j) && !isObstacle(i - 1, j)) ||
                            (grid_.contains(i + 1, j) && !isObstacle(i + 1, j)) ||
                            (grid_.contains(i, j - 1) && !isObstacle(i, j - 1)) ||
                            (grid_.contains(i, j + 1) && !isObstacle(i, j + 1));
      if (boundary) boundary_.emplace_back(i, j);
    }
  }
  if (!boundary_.empty()) {
    kd_.reserve(2 * boundary_.size() / kLeafSize + 2);
    buildKd(0, static_cast<std::int32_t>(boundary_.size()), 0);
  }
}

std::int32_t GridDistanceField::buildKd(std::int32_t begin, std::int32_t end, int depth) {
  KdNode node{begin,
              end,
              -1,
              -1,
              std::numeric_limits<std::int32_t>::max(),
              std::numeric_limits<std::int32_t>::max(),
              std::numeric_limits<std::int32_t>::min(),
              std::numeric_limits<std::int32_t>::min()};
  for (std::int32_t k = begin; k < end; ++k) {
    node.min_i = std::min(node.min_i, boundary_[k].x());
    node.min_j = std::min(node.min_j, boundary_[k].y());
    node.max_i = std::max(node.max_i, boundary_[k].x());
    node.max_j = std::max(node.max_j, boundary_[k].y());
  }
  const std::int32_t id = static_cast<std::int32_t>(kd_.size());
  kd_.push_back(node);
  if (end - begin <= kLeafSize) return id;
  const int axis = (node.max_i - node.min_i >= node.max_j - node.min_j) ? 0 : 1;
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(boundary_.begin() + begin, boundary_.begin() + mid, boundary_.begin() + end,
                   [axis](const CellIndex& a, const CellIndex& b) { return a[axis] < b[axis]; });
  const std::int32_t left = buildKd(begin, mid, depth + 1);
  const std::int32_t right = buildKd(mid, end, depth + 1);
  kd_[id].left = left;
  kd_[id].right = right;
  return id;
}

std::optional<DistanceResult> GridDistanceField::answerUnlessFree(const Eigen::Vector2d& p,
                                                                  CellIndex* cell) const {
  if (!p.allFinite()) return statusOnly(DistanceStatus::kInvalidQuery);
  const auto c = grid_.cellOf(p);
  if (!c) return statusOnly(DistanceStatus::kOutsideMap);
  *cell = *c;
  const CellState s = grid_.at(c->x(), c->y());
  if (s == CellState::kOccupied) {
    DistanceResult r = statusOnly(DistanceStatus::kInObstacle);
    r.obstacle = p;
    return r;
  }
  if (s == CellState::kUnknown) return statusOnly(DistanceStatus::kUnknownSpace);
  return std::nullopt;
}

DistanceResult GridDistanceField::resultFor(const CellIndex& c, const CellIndex& o,
                                            std::int64_t sq_cells) const {
  DistanceResult r;
  r.status = DistanceStatus::kOk;
  r.distance_m = cellDistanceToMetres(sq_cells);
  const Eigen::Vector2d p_c = grid_.cellCenter_m(c.x(), c.y());
  const Eigen::Vector2d p_o = grid_.cellCenter_m(o.x(), o.y());
  // sq_cells >= 1: the query cell is never an obstacle here.
  r.obstacle = p_o + (p_c - p_o) * (0.5 / std::sqrt(static_cast<double>(sq_cells)));
  return r;
}

DistanceResult GridDistanceField::nearest(const Eigen::Vector2d& p) const {
  CellIndex c;
  if (auto answer = answerUnlessFree(p, &c)) return *answer;
  const std::int64_t sq = squaredCellDistance(c.x(), c.y());
  if (sq < 0) return statusOnly(DistanceStatus::kNotFound);
  return resultFor(c, nearestObstacleCell(c.x(), c.y()), sq);
}

DistanceResult GridDistanceField::nearestInHalfPlane(const Eigen::Vector2d& q,
                                                     const Eigen::Vector2d& n,
                                                     double max_range_m) const {
  if (!q.allFinite() || !n.allFinite() || !rangeValid(max_range_m)) {
    return statusOnly(DistanceStatus::kInvalidQuery);
  }
  const double n_norm = n.norm();
  if (!(n_norm > 0.0) || !std::isfinite(n_norm)) return statusOnly(DistanceStatus::kInvalidQuery);
  CellIndex c;
  if (auto answer = answerUnlessFree(q, &c)) return *answer;

  DistanceResult not_found = statusOnly(DistanceStatus::kNotFound);
  not_found.distance_m = max_range_m;
  const std::int64_t sq_nearest = squaredCellDistance(c.x(), c.y());
  if (sq_nearest < 0 || cellDistanceToMetres(sq_nearest) > max_range_m) return not_found;

  const Eigen::Vector2d n_unit = n / n_norm;
  const double tol_m = sideTolerance_m();
  const double res = grid_.resolution_m();
  // (o - q).n in metres for cell centre o, computed the same way for candidates and corners.
  const Eigen::Vector2d base_m = grid_.origin_m() + Eigen::Vector2d(0.5 * res, 0.5 * res) - q;
  const auto side_m = [&](std::int32_t i, std::int32_t j) {
    return (base_m + res * Eigen::Vector2d(i, j)).dot(n_unit);
  };

  const CellIndex o_nearest = nearestObstacleCell(c.x(), c.y());
  if (side_m(o_nearest.x(), o_nearest.y()) >= -tol_m) return resultFor(c, o_nearest, sq_nearest);

  // Largest squared cell distance within range, by the same formula as the answer.
  const double cells_in_range = max_range_m / res + 0.5;
  const std::int64_t sq_grid_max = static_cast<std::int64_t>(grid_.width()) * grid_.width() +
                                   static_cast<std::int64_t>(grid_.height()) * grid_.height();
  std::int64_t sq_max = sq_grid_max;
  if (cells_in_range * cells_in_range < static_cast<double>(sq_grid_max)) {
    sq_max = static_cast<std::int64_t>(std::floor(cells_in_range * cells_in_range));
    while (sq_max > 0 && cellDistanceToMetres(sq_max) > max_range_m) --sq_max;
    while (cellDistanceToMetres(sq_max + 1) <= max_range_m) ++sq_max;
  }

  std::int64_t best_sq = sq_max + 1;
  CellIndex best(-1, -1);
  std::array<std::int32_t, 64> stack{};
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const KdNode& node = kd_[stack[--top]];
    const std::int64_t dx = std::max({0, node.min_i - c.x(), c.x() - node.max_i});
    const std::int64_t dy = std::max({0, node.min_j - c.y(), c.y() - node.max_j});
    if (dx * dx + dy * dy >= best_sq) continue;
    const double corner_max =
        std::max({side_m(node.min_i, node.min_j), side_m(node.min_i, node.max_j),
                  side_m(node.max_i, node.min_j), side_m(node.max_i, node.max_j)});
    if (corner_max < -tol_m - kSidePruneSlack_m) continue;
    if (node.left < 0) {
      for (std::int32_t k = node.begin; k < node.end; ++k) {
        const CellIndex& o = boundary_[k];
        const std::int64_t di = o.x() - c.x();
        const std::int64_t dj = o.y() - c.y();
        const std::int64_t sq = di * di + dj * dj;
        if (sq < best_sq && side_m(o.x(), o.y()) >= -tol_m) {
          best_sq = sq;
          best = o;
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last) so best_sq shrinks early.
    const KdNode& l = kd_[node.left];
    const KdNode& r = kd_[node.right];
    const auto box_sq = [&c](const KdNode& b) {
      const std::int64_t bx = std::max({0, b.min_i - c.x(), c.x() - b.max_i});
      const std::int64_t by = std::max({0, b.min_j - c.y(), c.y() - b.max_j});
      return bx * bx + by * by;
    };
    if (box_sq(l) <= box_sq(r)) {
      stack[top++] = node.right;
      stack[top++] = node.left;
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  if (best.x() < 0) return not_found;
  return resultFor(c, best, best_sq);
}

DistanceResult GridDistanceField::ray(const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                                      double max_range_m) const {
  if (!p.allFinite() || !dir.allFinite() || !rangeValid(max_range_m)) {
    return statusOnly(DistanceStatus::kInvalidQuery);
  }
  const double dir_norm = dir.norm();
  if (!(dir_norm > 0.0) || !std::isfinite(dir_norm)) {
    return statusOnly(DistanceStatus::kInvalidQuery);
  }
  CellIndex c;
  if (auto answer = answerUnlessFree(p, &c)) return *answer;

  // Amanatides & Woo (1987) in cell units; the next boundary crossing is recomputed from the
  // start each step rather than accumulated, so long rays do not drift.
  const double res = grid_.resolution_m();
  const Eigen::Vector2d d = dir / dir_norm;
  const Eigen::Vector2d g = (p - grid_.origin_m()) / res;
  const double t_max_cells = max_range_m / res;
  const int step_i = d.x() > 0.0 ? 1 : (d.x() < 0.0 ? -1 : 0);
  const int step_j = d.y() > 0.0 ? 1 : (d.y() < 0.0 ? -1 : 0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int i = c.x();
  int j = c.y();
  const double inv_dx = 1.0 / d.x();  // inf when d.x() == 0, unused then
  const double inv_dy = 1.0 / d.y();
  const auto crossing = [](int cell, int step, double g0, double inv_d0) {
    if (step == 0) return kInf;
    return (static_cast<double>(step > 0 ? cell + 1 : cell) - g0) * inv_d0;
  };
  double tx = crossing(i, step_i, g.x(), inv_dx);
  double ty = crossing(j, step_j, g.y(), inv_dy);
  while (true) {
    double t = 0.0;
    if (tx < ty) {
      t = tx;
      i += step_i;
      tx = crossing(i, step_i, g.x(), inv_dx);
    } else {
      t = ty;
      j += step_j;
      ty = crossing(j, step_j, g.y(), inv_dy);
    }
    if (t > t_max_cells) {
      DistanceResult r = statusOnly(DistanceStatus::kNotFound);
      r.distance_m = max_range_m;
      return r;
    }
    if (!grid_.contains(i, j)) {
      DistanceResult r = statusOnly(DistanceStatus::kNotFound);
      r.distance_m = t * res;
      return r;
    }
    if (isObstacle(i, j)) {
      DistanceResult r;
      r.status = DistanceStatus::kOk;
      r.distance_m = t * res;
      r.obstacle = p + d * r.distance_m;
      return r;
    }
  }
}

}  // namespace coopnav
