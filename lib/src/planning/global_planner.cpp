#include "coopnav/planning/global_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace coopnav {

const char* toString(PathStatus s) {
  switch (s) {
    case PathStatus::kOk:
      return "ok";
    case PathStatus::kInvalidInput:
      return "invalid_input";
    case PathStatus::kStartOutsideMap:
      return "start_outside_map";
    case PathStatus::kGoalOutsideMap:
      return "goal_outside_map";
    case PathStatus::kStartInObstacle:
      return "start_in_obstacle";
    case PathStatus::kGoalInObstacle:
      return "goal_in_obstacle";
    case PathStatus::kNoPath:
      return "no_path";
  }
  return "unknown";
}

double pathLength(const Path2& path) {
  double l = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) l += (path[i + 1] - path[i]).norm();
  return l;
}

Path2 resamplePath(const Path2& path, double spacing_m) {
  if (path.size() < 2 || !(spacing_m > 0.0)) return path;
  Path2 out{path.front()};
  double carry = 0.0;  // distance since the last emitted point
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector2d& a = path[i];
    const Eigen::Vector2d d = path[i + 1] - a;
    const double len = d.norm();
    double s = spacing_m - carry;
    while (s < len) {
      out.push_back(a + d * (s / len));
      s += spacing_m;
    }
    carry = len - (s - spacing_m);
  }
  if ((out.back() - path.back()).norm() < 0.3 * spacing_m && out.size() > 1) out.pop_back();
  out.push_back(path.back());
  return out;
}

Path2 subPath(const Path2& path, double from_m, double length_m) {
  if (path.size() < 2) return path;
  const double to_m = from_m + length_m;
  Path2 out;
  double arc = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector2d& a = path[i];
    const Eigen::Vector2d d = path[i + 1] - a;
    const double len = d.norm();
    const double a0 = arc, a1 = arc + len;
    if (a1 >= from_m && a0 <= to_m && len > 0.0) {
      const double s0 = std::clamp((from_m - a0) / len, 0.0, 1.0);
      const double s1 = std::clamp((to_m - a0) / len, 0.0, 1.0);
      if (out.empty()) out.push_back(a + s0 * d);
      out.push_back(a + s1 * d);
    }
    arc = a1;
    if (arc > to_m) break;
  }
  if (out.empty()) out.push_back(path.back());
  return out;
}

GridPathPlanner::GridPathPlanner(std::shared_ptr<const DistanceMap> map, Options options)
    : map_(std::move(map)), options_(options) {
  options_.resolution_m = std::max(options_.resolution_m, map_->resolution_m());
  if (!(options_.resolution_m > 0.0)) options_.resolution_m = 0.1;
  const Eigen::AlignedBox2d b = map_->bounds();
  origin_ = b.min();
  nx_ = std::max(1, static_cast<int>(std::ceil(b.sizes().x() / options_.resolution_m)));
  ny_ = std::max(1, static_cast<int>(std::ceil(b.sizes().y() / options_.resolution_m)));
  clearance_m_.assign(static_cast<std::size_t>(nx_) * ny_, -1.0f);
  for (int iy = 0; iy < ny_; ++iy) {
    for (int ix = 0; ix < nx_; ++ix) {
      const DistanceResult r = map_->nearest(center(ix, iy));
      float c = -1.0f;
      if (r.status == DistanceStatus::kOk) c = static_cast<float>(r.distance_m);
      if (r.status == DistanceStatus::kNotFound) c = std::numeric_limits<float>::max();
      if (r.status == DistanceStatus::kInObstacle) c = 0.0f;
      clearance_m_[static_cast<std::size_t>(iy) * nx_ + ix] = c;
    }
  }
}

Eigen::Vector2d GridPathPlanner::center(int ix, int iy) const {
  return origin_ +
         Eigen::Vector2d((ix + 0.5) * options_.resolution_m, (iy + 0.5) * options_.resolution_m);
}

bool GridPathPlanner::toCell(const Eigen::Vector2d& p, Cell* c) const {
  const Eigen::Vector2d q = (p - origin_) / options_.resolution_m;
  // Compared as doubles first: a point 1e200 m away (or NaN) must not reach the int cast.
  if (!(q.x() >= 0.0 && q.y() >= 0.0 && q.x() < nx_ && q.y() < ny_)) return false;
  const int ix = static_cast<int>(std::floor(q.x()));
  const int iy = static_cast<int>(std::floor(q.y()));
  if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) return false;
  *c = {ix, iy};
  return true;
}

float GridPathPlanner::clearanceAt(const std::vector<float>& grid, const Eigen::Vector2d& p) const {
  Cell c{};
  if (!toCell(p, &c)) return -1.0f;
  return grid[static_cast<std::size_t>(c.iy) * nx_ + c.ix];
}

std::vector<float> GridPathPlanner::withPoints(const std::vector<Eigen::Vector2d>& points,
                                               double reach_m) const {
  std::vector<float> grid = clearance_m_;
  const double res_m = options_.resolution_m;
  const int span = static_cast<int>(std::ceil(reach_m / res_m)) + 1;
  for (const Eigen::Vector2d& p : points) {
    Cell c{};
    if (!p.allFinite() || !toCell(p, &c)) continue;
    for (int iy = std::max(0, c.iy - span); iy <= std::min(ny_ - 1, c.iy + span); ++iy) {
      for (int ix = std::max(0, c.ix - span); ix <= std::min(nx_ - 1, c.ix + span); ++ix) {
        const double d = (center(ix, iy) - p).norm();
        if (d > reach_m) continue;
        float& g = grid[static_cast<std::size_t>(iy) * nx_ + ix];
        // Unknown or outside (< 0) stays so: a return cannot make a cell acceptable.
        if (g >= 0.0f) g = std::min(g, static_cast<float>(d));
      }
    }
  }
  return grid;
}

bool GridPathPlanner::segmentClear(const std::vector<float>& grid, const Eigen::Vector2d& a,
                                   const Eigen::Vector2d& b, double min_clear) const {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * options_.resolution_m))));
  for (int k = 0; k <= n; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / n);
    if ((p - a).norm() < options_.resolution_m) continue;
    if (clearanceAt(grid, p) < min_clear) return false;
  }
  return true;
}

PathResult GridPathPlanner::plan(const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                                 double radius_m,
                                 const std::vector<Eigen::Vector2d>& points) const {
  PathResult res;
  if (!start.allFinite() || !goal.allFinite() || !(radius_m >= 0.0)) {
    res.status = PathStatus::kInvalidInput;
    return res;
  }
  Cell cs{}, cg{};
  if (!toCell(start, &cs)) {
    res.status = PathStatus::kStartOutsideMap;
    return res;
  }
  if (!toCell(goal, &cg)) {
    res.status = PathStatus::kGoalOutsideMap;
    return res;
  }
  // The point itself decides, not the cell centre: a wall can be 0.05 m from a cell centre.
  auto pointClear = [&](const Eigen::Vector2d& p) {
    const DistanceResult r = map_->nearest(p);
    if (r.status == DistanceStatus::kNotFound) return std::numeric_limits<double>::max();
    if (r.status == DistanceStatus::kOk) return r.distance_m;
    if (r.status == DistanceStatus::kInObstacle) return 0.0;
    return -1.0;
  };
  const double start_clear = pointClear(start);
  const double goal_clear = pointClear(goal);
  if (start_clear < 0.0) {
    res.status = PathStatus::kStartOutsideMap;
    return res;
  }
  if (goal_clear < 0.0) {
    res.status = PathStatus::kGoalOutsideMap;
    return res;
  }
  if (start_clear <= 0.5 * radius_m) {
    res.status = PathStatus::kStartInObstacle;
    return res;
  }
  if (goal_clear <= 0.5 * radius_m) {
    res.status = PathStatus::kGoalInObstacle;
    return res;
  }

  const double res_m = options_.resolution_m;
  // Beyond radius + clearance preference a point changes neither passability nor step cost.
  std::vector<float> with_points;
  if (!points.empty())
    with_points = withPoints(points, radius_m + std::max(0.0, options_.clearance_pref_m) + res_m);
  const std::vector<float>& grid = points.empty() ? clearance_m_ : with_points;
  // Cells near start/goal may be passed with half the radius: the agent already stands there.
  const double escape_m = radius_m + 1.5 * res_m;
  auto idx = [&](int ix, int iy) { return static_cast<std::size_t>(iy) * nx_ + ix; };
  auto passable = [&](int ix, int iy) {
    const float c = grid[idx(ix, iy)];
    if (c >= radius_m) return true;
    if (c <= 0.5 * radius_m) return false;
    const Eigen::Vector2d p = center(ix, iy);
    return (p - start).norm() < escape_m || (p - goal).norm() < escape_m;
  };
  auto stepFactor = [&](int ix, int iy) {
    if (options_.clearance_weight <= 0.0 || options_.clearance_pref_m <= 0.0) return 1.0;
    const double short_m =
        std::max(0.0, options_.clearance_pref_m - (grid[idx(ix, iy)] - radius_m));
    return 1.0 + options_.clearance_weight * std::min(short_m, options_.clearance_pref_m) /
                     options_.clearance_pref_m;
  };

  const std::size_t n = grid.size();
  std::vector<double> g(n, std::numeric_limits<double>::infinity());
  std::vector<std::int32_t> parent(n, -1);
  std::vector<char> closed(n, 0);
  using Item = std::pair<double, std::int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const Eigen::Vector2d goal_c = center(cg.ix, cg.iy);
  auto h = [&](int ix, int iy) { return (center(ix, iy) - goal_c).norm(); };
  g[idx(cs.ix, cs.iy)] = 0.0;
  open.push({h(cs.ix, cs.iy), static_cast<std::int32_t>(idx(cs.ix, cs.iy))});
  const std::size_t goal_i = idx(cg.ix, cg.iy);
  bool found = false;
  constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [f, ci] = open.top();
    open.pop();
    const std::size_t cu = static_cast<std::size_t>(ci);
    if (closed[cu]) continue;
    closed[cu] = 1;
    if (cu == goal_i) {
      found = true;
      break;
    }
    const int ix = static_cast<int>(cu % nx_), iy = static_cast<int>(cu / nx_);
    for (int k = 0; k < 8; ++k) {
      const int jx = ix + kDx[k], jy = iy + kDy[k];
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      const std::size_t j = idx(jx, jy);
      if (closed[j] || !passable(jx, jy)) continue;
      // No corner cutting between two blocked cells.
      if (k >= 4 && (!passable(ix + kDx[k], iy) || !passable(ix, iy + kDy[k]))) continue;
      const double step = (k >= 4 ? M_SQRT2 : 1.0) * res_m * stepFactor(jx, jy);
      const double ng = g[cu] + step;
      if (ng < g[j]) {
        g[j] = ng;
        parent[j] = ci;
        open.push({ng + h(jx, jy), static_cast<std::int32_t>(j)});
      }
    }
  }
  if (!found) {
    res.status = PathStatus::kNoPath;
    return res;
  }
  Path2 cells;
  for (std::int32_t c = static_cast<std::int32_t>(goal_i); c >= 0; c = parent[c]) {
    cells.push_back(center(c % nx_, c / nx_));
  }
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  cells.back() = goal;
  if (cells.size() == 1) cells.push_back(goal);

  Path2 path;
  if (options_.shortcut && cells.size() > 2) {
    // Greedy line-of-sight shortcutting, never to a clearance lower than the A* path had there
    // (capped at radius + pref, so the clearance cost is not undone).
    std::vector<float> clear(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) clear[i] = clearanceAt(grid, cells[i]);
    path.push_back(cells[0]);
    std::size_t i = 0;
    while (i + 1 < cells.size()) {
      std::size_t best = i + 1;
      // The sight line's own start may sit closer to a wall (the agent's start): only the
      // cells it reaches set the bar, and segmentClear skips the first cell.
      double min_c = std::numeric_limits<double>::max();
      int misses = 0;  // bounded search: a long run of blocked sights ends it
      constexpr int kMaxMisses = 40;
      for (std::size_t j = i + 1; j < cells.size() && misses < kMaxMisses; ++j) {
        min_c = std::min<double>(min_c, clear[j]);
        const double need = std::min(min_c, radius_m + options_.clearance_pref_m) - 1e-3;
        if (segmentClear(grid, cells[i], cells[j], need)) {
          best = j;
          misses = 0;
        } else {
          ++misses;
        }
      }
      path.push_back(cells[best]);
      i = best;
    }
  } else {
    path = cells;
  }
  res.path = resamplePath(path, options_.sample_spacing_m);
  res.length_m = pathLength(res.path);
  res.status = PathStatus::kOk;
  return res;
}

}  // namespace coopnav
