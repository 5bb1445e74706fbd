#include "coopnav/planning/goal_inference.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace coopnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();
/// A ridge cell's nearest obstacle point and its neighbour's lie at least this many times its
/// clearance apart: feet >= 60° apart as seen from the cell (a bump on a wall gives less).
constexpr double kRidgeSeparationPerClearance = 1.0;
/// ... and at least this many cells apart (two feet on one wall face differ by up to ~1 cell).
constexpr double kRidgeMinSeparationCells = 2.0;
/// A skeleton branch into a convex corner of free space (a room corner) or to a bump on a wall
/// runs until the free space's edge: its tip has at most the agent's radius plus about one cell
/// of clearance. A corridor's or a room's end keeps half its width. Tips with less clearance
/// than radius + this many cells are pruned.
constexpr double kTipMarginCells = 2.5;
/// A corner branch runs along the corner's bisector, losing clearance at 1/√2 per metre: its
/// length minus √2 × its drop in clearance is ~0, where a corridor's is its length.
constexpr double kCornerBranchSlope = M_SQRT2;
/// A goal in a passable cell seeds the passable cells within this many cells (the 2 x 2 block a
/// lookup at the goal interpolates, whatever the goal's place in its cell).
constexpr double kSeedCells = 1.5;
/// Pruning passes over the skeleton (each removes at least one branch or stops).
constexpr int kMaxPruningPasses = 256;
/// A corridor end's axis is taken over at least this many skeleton cells (a cell-to-cell step
/// alone gives only the 8 directions of the grid).
constexpr double kMinAxisCells = 10.0;
/// Path-length evidence within this many grid cells (a diagonal step: the grid's own error) is
/// a tie between goals.
constexpr double kTieCells = M_SQRT2;
/// A corridor end's region reaches at most this many times its clearance to either side.
constexpr double kCrossSectionPerClearance = 1.5;

/// 8-neighbourhood in the circular order of Zhang & Suen (P2..P9: N, NE, E, SE, S, SW, W, NW),
/// with j growing upwards (N = +j).
constexpr std::array<std::array<int, 2>, 8> kRing{
    {{0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}}};

/// The grid the candidates and distance fields live on: cells of res over the map's bounds.
struct SampleGrid {
  Eigen::Vector2d origin{0.0, 0.0};
  double res{0.1};
  int nx{0};
  int ny{0};

  bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < nx && j < ny; }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
  }
  std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  Eigen::Vector2d center(int i, int j) const {
    return origin + res * Eigen::Vector2d(i + 0.5, j + 0.5);
  }
};

/// The grid over map's bounds at max(resolution_m, the map's); false when it is degenerate or
/// larger than kMaxGoalGridCells.
bool makeGrid(const DistanceMap& map, double resolution_m, SampleGrid* g) {
  g->res = std::max(resolution_m, map.resolution_m());
  if (!(g->res > 0.0) || !std::isfinite(g->res)) g->res = 0.1;
  const Eigen::AlignedBox2d b = map.bounds();
  if (b.isEmpty() || !b.min().allFinite() || !b.max().allFinite()) return false;
  const Eigen::Vector2d cells = b.sizes() / g->res;
  if (!(cells.x() * cells.y() <= static_cast<double>(kMaxGoalGridCells))) return false;
  g->origin = b.min();
  g->nx = std::max(1, static_cast<int>(std::ceil(cells.x())));
  g->ny = std::max(1, static_cast<int>(std::ceil(cells.y())));
  return g->size() <= kMaxGoalGridCells;
}

/// Clearance of a NEAREST answer [m]: +inf with no obstacle anywhere, 0 in an obstacle, -1 where
/// nothing is known (outside the map, unknown space, invalid).
double clearanceOf(const DistanceResult& r) {
  switch (r.status) {
    case DistanceStatus::kOk:
      return r.distance_m;
    case DistanceStatus::kNotFound:
      return kInf;
    case DistanceStatus::kInObstacle:
      return 0.0;
    default:
      return -1.0;
  }
}

// ---- Candidates --------------------------------------------------------------------------------

/// Opening candidates: runs of free cells along each side of the grid (bottom, right, top, left),
/// each run from its first to its last cell centre, moved inset_m inwards from the border.
void appendOpenings(const SampleGrid& g, const std::vector<std::uint8_t>& free, double inset_m,
                    std::vector<GoalRegion>* out) {
  const Eigen::Vector2d lo = g.origin;
  const Eigen::Vector2d hi = g.origin + g.res * Eigen::Vector2d(g.nx, g.ny);
  struct Side {
    int i0, j0, di, dj, n;  // first cell, step, cell count
  };
  const std::array<Side, 4> sides{{{0, 0, 1, 0, g.nx},
                                   {g.nx - 1, 0, 0, 1, g.ny},
                                   {g.nx - 1, g.ny - 1, -1, 0, g.nx},
                                   {0, g.ny - 1, 0, -1, g.ny}}};
  for (std::size_t s = 0; s < sides.size(); ++s) {
    const Side& side = sides[s];
    auto inset = [&](Eigen::Vector2d p) {
      if (s == 0) p.y() = lo.y() + inset_m;
      if (s == 1) p.x() = hi.x() - inset_m;
      if (s == 2) p.y() = hi.y() - inset_m;
      if (s == 3) p.x() = lo.x() + inset_m;
      return p;
    };
    int run_start = -1;
    for (int k = 0; k <= side.n; ++k) {
      const bool f = k < side.n && free[g.index(side.i0 + k * side.di, side.j0 + k * side.dj)] != 0;
      if (f && run_start < 0) run_start = k;
      if (f || run_start < 0) continue;
      const Eigen::Vector2d first =
          g.center(side.i0 + run_start * side.di, side.j0 + run_start * side.dj);
      const Eigen::Vector2d last =
          g.center(side.i0 + (k - 1) * side.di, side.j0 + (k - 1) * side.dj);
      out->push_back({inset(first), inset(last)});
      run_start = -1;
    }
  }
}

/// Zhang & Suen (1984) thinning of mask (1 = set) in place: two sub-iterations until stable.
void thin(const SampleGrid& g, std::vector<std::uint8_t>* mask) {
  auto at = [&](int i, int j) { return g.contains(i, j) && (*mask)[g.index(i, j)] != 0; };
  std::vector<std::size_t> remove;
  bool changed = true;
  while (changed) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      remove.clear();
      for (int j = 0; j < g.ny; ++j) {
        for (int i = 0; i < g.nx; ++i) {
          if (!at(i, j)) continue;
          std::array<bool, 8> p{};
          int count = 0;
          for (std::size_t k = 0; k < 8; ++k) {
            p[k] = at(i + kRing[k][0], j + kRing[k][1]);
            count += p[k] ? 1 : 0;
          }
          if (count < 2 || count > 6) continue;
          int transitions = 0;
          for (std::size_t k = 0; k < 8; ++k) transitions += (!p[k] && p[(k + 1) % 8]) ? 1 : 0;
          if (transitions != 1) continue;
          // p[0] N, p[2] E, p[4] S, p[6] W.
          if (pass == 0 && ((p[0] && p[2] && p[4]) || (p[2] && p[4] && p[6]))) continue;
          if (pass == 1 && ((p[0] && p[2] && p[6]) || (p[0] && p[4] && p[6]))) continue;
          remove.push_back(g.index(i, j));
        }
      }
      for (const std::size_t k : remove) (*mask)[k] = 0;
      changed = changed || !remove.empty();
    }
  }
}

/// Skeleton topology of one cell: number of set 8-neighbours and 0→1 transitions around it.
struct Neighbourhood {
  int count{0};
  int transitions{0};
};

Neighbourhood neighbourhood(const SampleGrid& g, const std::vector<std::uint8_t>& mask, int i,
                            int j) {
  Neighbourhood n;
  std::array<bool, 8> p{};
  for (std::size_t k = 0; k < 8; ++k) {
    const int a = i + kRing[k][0];
    const int b = j + kRing[k][1];
    p[k] = g.contains(a, b) && mask[g.index(a, b)] != 0;
    n.count += p[k] ? 1 : 0;
  }
  for (std::size_t k = 0; k < 8; ++k) n.transitions += (!p[k] && p[(k + 1) % 8]) ? 1 : 0;
  return n;
}

bool isEnd(const Neighbourhood& n) { return n.count == 1 || (n.count == 2 && n.transitions == 1); }
bool isJunction(const Neighbourhood& n) { return n.transitions >= 3; }

/// Removes skeleton leaf branches ending at the free space's edge (kTipMarginCells) or whose
/// chord (tip to junction) minus √2 × their drop in clearance (kCornerBranchSlope) is below
/// min_length_m, pass after pass, until none is removed. A pass judges every leaf branch of the
/// same skeleton and then removes the failing ones together, so that both corner branches at a
/// corridor's end go and the corridor's centre line ends there (removing one first would extend the
/// other).
void pruneBranches(const SampleGrid& g, const std::vector<double>& clearance, double radius_m,
                   double min_length_m, std::vector<std::uint8_t>* skel) {
  std::vector<std::size_t> walk;
  std::vector<std::size_t> doomed;
  for (int pass = 0; pass < kMaxPruningPasses; ++pass) {
    doomed.clear();
    for (int j = 0; j < g.ny; ++j) {
      for (int i = 0; i < g.nx; ++i) {
        if ((*skel)[g.index(i, j)] == 0) continue;
        const Neighbourhood n0 = neighbourhood(g, *skel, i, j);
        if (n0.count == 0) {  // an isolated cell
          doomed.push_back(g.index(i, j));
          continue;
        }
        if (!isEnd(n0)) continue;
        // Walk from the end to the first junction (excluded) or the other end (included).
        walk.clear();
        walk.push_back(g.index(i, j));
        int ci = i, cj = j;
        bool junction = false;
        std::size_t last = walk.front();
        while (true) {
          int next_i = -1, next_j = -1;
          // 4-neighbours first (even ring slots), then diagonals: a staircase is walked along.
          for (int parity = 0; parity < 2 && next_i < 0; ++parity) {
            for (std::size_t k = static_cast<std::size_t>(parity); k < 8; k += 2) {
              const int a = ci + kRing[k][0];
              const int b = cj + kRing[k][1];
              if (!g.contains(a, b) || (*skel)[g.index(a, b)] == 0) continue;
              if (std::find(walk.begin(), walk.end(), g.index(a, b)) != walk.end()) continue;
              next_i = a;
              next_j = b;
              break;
            }
          }
          if (next_i < 0) break;  // the other end of a simple path
          ci = next_i;
          cj = next_j;
          last = g.index(ci, cj);
          if (isJunction(neighbourhood(g, *skel, ci, cj))) {
            junction = true;
            break;
          }
          walk.push_back(last);
        }
        const double tip_m = clearance[walk.front()];
        const bool at_edge = tip_m < radius_m + kTipMarginCells * g.res;
        // The chord, not the walked length: a thinned diagonal is walked as a staircase, whose
        // length overstates a corner branch's by up to √2.
        const double chord_m = (g.center(i, j) - g.center(ci, cj)).norm();
        const double unexplained_m =
            chord_m - kCornerBranchSlope * std::max(0.0, clearance[last] - tip_m);
        if (!at_edge && unexplained_m >= min_length_m) continue;
        doomed.insert(doomed.end(), walk.begin(), walk.end());
        if (!junction) doomed.push_back(last);
      }
    }
    if (doomed.empty()) break;
    for (const std::size_t k : doomed) (*skel)[k] = 0;
  }
}

/// The cross-section of free space through p along direction n (unit): as far as free cells
/// reach on either side, at most max_m, sampled at half a cell.
GoalRegion crossSection(const SampleGrid& g, const std::vector<std::uint8_t>& free,
                        const Eigen::Vector2d& p, const Eigen::Vector2d& n, double max_m) {
  auto isFree = [&](const Eigen::Vector2d& q) {
    const Eigen::Vector2d c = (q - g.origin) / g.res;
    const int i = static_cast<int>(std::floor(c.x()));
    const int j = static_cast<int>(std::floor(c.y()));
    return g.contains(i, j) && free[g.index(i, j)] != 0;
  };
  const double step_m = 0.5 * g.res;
  const int max_steps = static_cast<int>(std::min<double>(2 * (g.nx + g.ny), max_m / step_m));
  std::array<Eigen::Vector2d, 2> ends{p, p};
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector2d dir = side == 0 ? n : Eigen::Vector2d(-n);
    for (int k = 1; k <= max_steps; ++k) {
      const Eigen::Vector2d q = p + (k * step_m) * dir;
      if (!isFree(q)) break;
      ends[static_cast<std::size_t>(side)] = q;
    }
  }
  return {ends[0], ends[1]};
}

/// The direction a skeleton branch points to at its end cell (i, j): the chord from the cell
/// walk_m back along it (or its junction) to the cell skip_m back from the end, so that the kink a
/// thinned end keeps does not tilt it.
Eigen::Vector2d branchDirection(const SampleGrid& g, const std::vector<std::uint8_t>& skel, int i,
                                int j, double skip_m, double walk_m) {
  std::vector<std::size_t> seen{g.index(i, j)};
  int ci = i, cj = j;
  Eigen::Vector2d near = g.center(i, j);
  double length_m = 0.0;
  while (length_m < walk_m) {
    int next_i = -1, next_j = -1;
    for (std::size_t k = 0; k < 8 && next_i < 0; ++k) {
      const int a = ci + kRing[k][0];
      const int b = cj + kRing[k][1];
      if (!g.contains(a, b) || skel[g.index(a, b)] == 0) continue;
      if (std::find(seen.begin(), seen.end(), g.index(a, b)) != seen.end()) continue;
      next_i = a;
      next_j = b;
    }
    if (next_i < 0) break;
    length_m += g.res * ((next_i != ci && next_j != cj) ? M_SQRT2 : 1.0);
    ci = next_i;
    cj = next_j;
    seen.push_back(g.index(ci, cj));
    if (length_m <= skip_m) near = g.center(ci, cj);
    if (isJunction(neighbourhood(g, skel, ci, cj))) break;
  }
  Eigen::Vector2d d = near - g.center(ci, cj);
  if (!(d.norm() > g.res)) d = g.center(i, j) - g.center(ci, cj);  // a short branch: all of it
  return d.norm() > 0.0 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(1.0, 0.0);
}

void appendDeadEnds(const SampleGrid& g, const std::vector<double>& clearance,
                    const std::vector<Eigen::Vector2d>& foot, const std::vector<std::uint8_t>& free,
                    double radius_m, double min_length_m, std::vector<GoalRegion>* out) {
  std::vector<std::uint8_t> skel(g.size(), 0);
  const double min_sep_m = kRidgeMinSeparationCells * g.res;
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = g.index(i, j);
      if (free[k] == 0 || !std::isfinite(clearance[k])) continue;
      const double need_m = std::max(min_sep_m, kRidgeSeparationPerClearance * clearance[k]);
      for (std::size_t r = 0; r < 8; r += 2) {
        const int a = i + kRing[r][0];
        const int b = j + kRing[r][1];
        if (!g.contains(a, b)) continue;
        const std::size_t kn = g.index(a, b);
        if (!(clearance[kn] > 0.0) || !std::isfinite(clearance[kn])) continue;
        if ((foot[k] - foot[kn]).norm() >= need_m) {
          skel[k] = 1;
          break;
        }
      }
    }
  }
  thin(g, &skel);
  pruneBranches(g, clearance, radius_m, min_length_m, &skel);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = g.index(i, j);
      if (skel[k] == 0 || !isEnd(neighbourhood(g, skel, i, j))) continue;
      // The corridor's axis near its end: the branch over about two corridor widths.
      const Eigen::Vector2d u = branchDirection(
          g, skel, i, j, clearance[k], std::max(4.0 * clearance[k], kMinAxisCells * g.res));
      // A corridor's side walls are its end's clearance away; farther free space is a hall the
      // branch ends in, not the corridor.
      out->push_back(crossSection(g, free, g.center(i, j), Eigen::Vector2d(-u.y(), u.x()),
                                  kCrossSectionPerClearance * clearance[k]));
    }
  }
}

// ---- Distance fields ---------------------------------------------------------------------------

using QueueItem = std::pair<double, std::uint32_t>;
using MinQueue = std::priority_queue<QueueItem, std::vector<QueueItem>, std::greater<>>;

/// Calls step(kn, length_m) for each 8-neighbour kn of cell k whose class is `to`, a diagonal
/// only when neither cell it cuts past is blocked (class 0): one expansion for both phases of the
/// distance fields.
template <class Step>
void forEachStep(const SampleGrid& g, const std::vector<std::uint8_t>& cls, std::size_t k,
                 std::uint8_t to, Step&& step) {
  const int i = static_cast<int>(k % static_cast<std::size_t>(g.nx));
  const int j = static_cast<int>(k / static_cast<std::size_t>(g.nx));
  for (const auto& r : kRing) {
    const int a = i + r[0];
    const int b = j + r[1];
    if (!g.contains(a, b)) continue;
    const std::size_t kn = g.index(a, b);
    if (cls[kn] != to) continue;
    const bool diagonal = r[0] != 0 && r[1] != 0;
    if (diagonal && (cls[g.index(a, j)] == 0 || cls[g.index(i, b)] == 0)) continue;
    step(kn, g.res * (diagonal ? M_SQRT2 : 1.0));
  }
}

}  // namespace

Eigen::Vector2d GoalRegion::target(const Eigen::Vector2d& p, double inset_m) const {
  const Eigen::Vector2d ab = b - a;
  const double len_m = ab.norm();
  if (!(len_m > 2.0 * inset_m) || !p.allFinite()) return centre();
  const double s_m = std::clamp((p - a).dot(ab) / len_m, inset_m, len_m - inset_m);
  return a + (s_m / len_m) * ab;
}

std::vector<GoalRegion> mapGoalCandidates(const DistanceMap& map,
                                          const GoalCandidateOptions& options) {
  SampleGrid g;
  if (!makeGrid(map, options.resolution_m, &g)) return {};
  std::vector<double> clearance(g.size(), -1.0);
  std::vector<Eigen::Vector2d> foot(g.size(), Eigen::Vector2d::Zero());
  std::vector<std::uint8_t> free(g.size(), 0);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = g.index(i, j);
      const DistanceResult r = map.nearest(g.center(i, j));
      clearance[k] = clearanceOf(r);
      if (r.status == DistanceStatus::kOk) foot[k] = r.obstacle;
      free[k] = clearance[k] >= options.agent_radius_m ? 1 : 0;
    }
  }
  std::vector<GoalRegion> raw;
  appendOpenings(g, free, options.opening_inset_m, &raw);
  appendDeadEnds(g, clearance, foot, free, options.agent_radius_m, options.min_dead_end_length_m,
                 &raw);
  std::vector<GoalRegion> out;
  for (const GoalRegion& p : raw) {
    const bool near = std::any_of(out.begin(), out.end(), [&](const GoalRegion& q) {
      return (p.centre() - q.centre()).norm() < options.min_separation_m;
    });
    if (!near) out.push_back(p);
  }
  return out;
}

namespace {

std::vector<GoalRegion> pointRegions(const std::vector<Eigen::Vector2d>& points) {
  std::vector<GoalRegion> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(GoalRegion::point(p));
  return out;
}

}  // namespace

GoalDistances::GoalDistances(std::shared_ptr<const DistanceMap> map,
                             const std::vector<Eigen::Vector2d>& goals,
                             const GoalInferenceOptions& options)
    : GoalDistances(std::move(map), pointRegions(goals), options) {}

GoalDistances::GoalDistances(std::shared_ptr<const DistanceMap> map, std::vector<GoalRegion> goals,
                             const GoalInferenceOptions& options)
    : map_(std::move(map)), goals_(std::move(goals)), options_(options) {
  if (!map_) return;
  SampleGrid g;
  if (!makeGrid(*map_, options_.resolution_m, &g)) {
    field_m_.assign(goals_.size(), {});  // every lookup +inf
    return;
  }
  options_.resolution_m = g.res;
  origin_ = g.origin;
  nx_ = g.nx;
  ny_ = g.ny;
  const double r_m = options_.agent_radius_m;
  // Cell classes: 2 passable (clearance >= r), 1 fringe (0 < clearance < r), 0 blocked.
  std::vector<std::uint8_t> cls(g.size(), 0);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double c = clearanceOf(map_->nearest(g.center(i, j)));
      cls[g.index(i, j)] = c >= r_m ? 2 : (c > 0.0 ? 1 : 0);
    }
  }
  const double reach_m = r_m + g.res;  // how far a fringe cell / off-grid goal looks for passable
  const int reach_cells = static_cast<int>(std::ceil(reach_m / g.res));
  field_m_.assign(goals_.size(), {});
  std::vector<float> depth_m(g.size(), kInfF);
  for (std::size_t gi = 0; gi < goals_.size(); ++gi) {
    std::vector<float>& f = field_m_[gi];
    f.assign(g.size(), kInfF);
    const GoalRegion& region = goals_[gi];
    if (!region.a.allFinite() || !region.b.allFinite()) continue;
    std::vector<std::size_t> seeded;
    // Seeds of one point of the region: the passable cells around it (the four a lookup there
    // interpolates), or, when its cell is not passable, those within reach_m.
    auto seedAround = [&](const Eigen::Vector2d& goal) {
      const Eigen::Vector2d cell = (goal - g.origin) / g.res;
      if (!(cell.x() > -reach_cells && cell.y() > -reach_cells && cell.x() < g.nx + reach_cells &&
            cell.y() < g.ny + reach_cells))
        return;
      const int ci = static_cast<int>(std::floor(cell.x()));
      const int cj = static_cast<int>(std::floor(cell.y()));
      const bool own = g.contains(ci, cj) && cls[g.index(ci, cj)] == 2;
      const double seed_m = own ? kSeedCells * g.res : reach_m;
      for (int j = cj - reach_cells; j <= cj + reach_cells; ++j) {
        for (int i = ci - reach_cells; i <= ci + reach_cells; ++i) {
          if (!g.contains(i, j) || cls[g.index(i, j)] != 2) continue;
          const double d = (g.center(i, j) - goal).norm();
          if (d > seed_m) continue;
          const std::size_t k = g.index(i, j);
          if (!std::isfinite(f[k])) seeded.push_back(k);
          f[k] = std::min(f[k], static_cast<float>(d));
        }
      }
    };
    // A segment seeds every half cell along it.
    const int samples = 1 + static_cast<int>(std::ceil(region.length_m() / (0.5 * g.res)));
    if (samples > 2 * (g.nx + g.ny) + 2) continue;  // longer than the map: not a place
    for (int s = 0; s < samples; ++s) {
      const double t = samples == 1 ? 0.0 : static_cast<double>(s) / (samples - 1);
      seedAround(region.a + t * (region.b - region.a));
    }
    MinQueue q;
    for (const std::size_t k : seeded) q.emplace(f[k], static_cast<std::uint32_t>(k));
    // Phase 1: Dijkstra over passable cells, 8-connected; a diagonal step needs both cells it
    // cuts past unblocked.
    while (!q.empty()) {
      const auto [d_top, k] = q.top();
      const auto d = d_top;  // a lambda cannot capture a structured binding (C++17)
      q.pop();
      if (d > f[k]) continue;
      forEachStep(g, cls, k, 2, [&](std::size_t kn, double step_m) {
        // Compared as stored (float): a double below its own rounded float would be pushed
        // again and again.
        const auto nd = static_cast<float>(d + step_m);
        if (nd < f[kn]) {
          f[kn] = nd;
          q.emplace(f[kn], static_cast<std::uint32_t>(kn));
        }
      });
    }
    // Phase 2: fringe cells, from passable cells, at most reach_m into the fringe; never back.
    std::fill(depth_m.begin(), depth_m.end(), kInfF);
    for (std::size_t k = 0; k < g.size(); ++k) {
      if (cls[k] == 2 && std::isfinite(f[k])) q.emplace(f[k], static_cast<std::uint32_t>(k));
    }
    while (!q.empty()) {
      const auto [d_top, k] = q.top();
      const auto d = d_top;  // a lambda cannot capture a structured binding (C++17)
      q.pop();
      if (d > f[k]) continue;
      const double base_depth = cls[k] == 2 ? 0.0 : depth_m[k];
      forEachStep(g, cls, k, 1, [&](std::size_t kn, double step_m) {
        if (base_depth + step_m > reach_m) return;
        const auto nd = static_cast<float>(d + step_m);
        if (nd < f[kn]) {
          f[kn] = nd;
          depth_m[kn] = static_cast<float>(base_depth + step_m);
          q.emplace(f[kn], static_cast<std::uint32_t>(kn));
        }
      });
    }
  }
}

double GoalDistances::distance(std::size_t goal, const Eigen::Vector2d& p) const {
  if (goal >= goals_.size() || !p.allFinite()) return kInf;
  if (!map_) return (p - goals_[goal].closest(p)).norm();
  const std::vector<float>& f = field_m_[goal];
  if (f.empty()) return kInf;
  const double res = options_.resolution_m;
  const Eigen::Vector2d rel = (p - origin_) / res;
  // Outside the grid (compared as doubles: a far point must not reach the int cast).
  if (!(rel.x() >= 0.0 && rel.y() >= 0.0 && rel.x() <= nx_ && rel.y() <= ny_)) return kInf;
  // Bilinear between the four cell centres around p, over the finite ones.
  const double u = rel.x() - 0.5;
  const double v = rel.y() - 0.5;
  const int i0 = static_cast<int>(std::floor(u));
  const int j0 = static_cast<int>(std::floor(v));
  const double fu = u - i0;
  const double fv = v - j0;
  double sum = 0.0, weight = 0.0, nearest = kInf, nearest_d2 = kInf;
  for (int dj = 0; dj < 2; ++dj) {
    for (int di = 0; di < 2; ++di) {
      const int i = i0 + di;
      const int j = j0 + dj;
      if (i < 0 || j < 0 || i >= nx_ || j >= ny_) continue;
      const float value = f[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) +
                            static_cast<std::size_t>(i)];
      if (!std::isfinite(value)) continue;
      const double w = (di != 0 ? fu : 1.0 - fu) * (dj != 0 ? fv : 1.0 - fv);
      sum += w * value;
      weight += w;
      const double d2 = (di - fu) * (di - fu) + (dj - fv) * (dj - fv);
      if (d2 < nearest_d2) {
        nearest_d2 = d2;
        nearest = value + std::sqrt(d2) * res;
      }
    }
  }
  if (weight > 1e-9) return sum / weight;
  return nearest;  // p on a cell centre whose own value is +inf: the nearest finite one
}

GoalBelief::GoalBelief(std::shared_ptr<const GoalDistances> distances, std::vector<double> prior)
    : distances_(std::move(distances)) {
  const std::size_t n = distances_ ? distances_->goals().size() : 0;
  bool valid = prior.size() == n && n > 0;
  double total = 0.0;
  for (const double w : prior) {
    valid = valid && std::isfinite(w) && w >= 0.0;
    total += w;
  }
  valid = valid && total > 0.0 && std::isfinite(total);
  prior_.assign(n, n > 0 ? 1.0 / static_cast<double>(n) : 0.0);
  if (valid) {
    for (std::size_t i = 0; i < n; ++i) prior_[i] = prior[i] / total;
  }
  probability_ = prior_;
  start_distance_m_.assign(n, kInf);
  distance_m_.assign(n, kInf);
}

bool GoalBelief::observe(double t_s, const Eigen::Vector2d& position) {
  if (!std::isfinite(t_s) || !position.allFinite()) return false;
  if (observations_ > 0 && !(t_s > last_t_s_)) return false;
  ++observations_;
  last_t_s_ = t_s;
  const std::size_t n = prior_.size();
  if (n == 0) return true;
  const GoalInferenceOptions& o = distances_->options();
  if (anchored_) {
    const double step_m = (position - last_).norm();
    if (step_m < o.min_step_m) return true;  // jitter: the position used stays
    walked_m_ += step_m;
  }
  bool any_finite = false;
  for (std::size_t i = 0; i < n; ++i) {
    distance_m_[i] = distances_->distance(i, position);
    any_finite = any_finite || std::isfinite(distance_m_[i]);
  }
  if (!any_finite) return true;  // outside the map / cut off: nothing learnt, belief kept
  last_ = position;
  if (!anchored_) {
    anchored_ = true;
    start_ = position;
    start_distance_m_ = distance_m_;
  }
  recompute();
  return true;
}

int GoalBelief::mostLikely() const {
  int best = -1;
  for (std::size_t i = 0; i < probability_.size(); ++i) {
    if (best < 0 || probability_[i] > probability_[static_cast<std::size_t>(best)])
      best = static_cast<int>(i);
  }
  if (best < 0 || !anchored_ || !distances_->geodesic()) return best;
  // Goals whose path-length evidence differs by less than the grid resolves are tied: a walk
  // down a corridor fits every place beyond its end or its next junction alike. People keep
  // going straight unless they turn, so the tie goes to the goal whose shortest path from here
  // is the straightest (the least longer than the straight line to the region: detours within
  // a grid step are alike), then the nearest.
  const GoalInferenceOptions& o = distances_->options();
  const double floor = probability_[static_cast<std::size_t>(best)] *
                       std::exp(-o.beta_per_m * kTieCells * o.resolution_m);
  const double same_m = kTieCells * o.resolution_m;
  const auto detour_m = [&](std::size_t i) {
    return distance_m_[i] - (distances_->goals()[i].closest(last_) - last_).norm();
  };
  auto pick = static_cast<std::size_t>(best);
  double pick_detour_m = detour_m(pick);
  for (std::size_t i = 0; i < probability_.size(); ++i) {
    if (i == pick || !(probability_[i] > 0.0) || probability_[i] < floor) continue;
    const double d_m = detour_m(i);
    const bool straighter = d_m < pick_detour_m - same_m;
    const bool as_straight_and_nearer =
        std::abs(d_m - pick_detour_m) <= same_m && distance_m_[i] < distance_m_[pick];
    if (straighter || as_straight_and_nearer) {
      pick = i;
      pick_detour_m = d_m;
    }
  }
  return static_cast<int>(pick);
}

int GoalBelief::plannedGoal(int current, double switch_margin_m) const {
  const int best = mostLikely();
  if (best < 0 || current < 0 || current == best ||
      static_cast<std::size_t>(current) >= probability_.size())
    return best;
  const double p_current = probability_[static_cast<std::size_t>(current)];
  const double p_best = probability_[static_cast<std::size_t>(best)];
  if (!(p_current > 0.0)) return best;
  const double beta = distances_->options().beta_per_m;
  return std::log(p_best) - std::log(p_current) > beta * std::max(0.0, switch_margin_m) ? best
                                                                                        : current;
}

// Dragan & Srinivasa, "Legibility and Predictability of Robot Motion", HRI 2013,
// doi:10.1109/HRI.2013.6483603, eq. (4) with C = path length (paper §II-A gives the goals; this is
// what stands in for them): P(g | ξ_{s→q}) ∝ P(g) exp(−β(|ξ| + L(q, g))) / exp(−β L(s, g)).
// |ξ| is common to all goals and cancels in the normalisation.
void GoalBelief::recompute() {
  const std::size_t n = prior_.size();
  const GoalInferenceOptions& o = distances_->options();
  std::vector<double>& log_w = probability_;  // computed in place, then normalised
  bool any = false;
  bool any_ahead = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double lq = distance_m_[i];
    const double ls = start_distance_m_[i];
    log_w[i] = -kInf;
    if (!std::isfinite(lq) || !std::isfinite(ls) || !(prior_[i] > 0.0)) continue;
    log_w[i] = std::log(prior_[i]) - o.beta_per_m * (lq - ls);
    any = true;
    any_ahead = any_ahead || lq >= o.reached_radius_m;
  }
  if (!any) {  // every goal unreachable: nothing to prefer
    probability_ = prior_;
    return;
  }
  if (any_ahead) {
    for (std::size_t i = 0; i < n; ++i) {
      if (distance_m_[i] < o.reached_radius_m) log_w[i] = -kInf;
    }
  }
  // log-sum-exp normalisation.
  double max_lw = -kInf;
  for (const double lw : log_w) max_lw = std::max(max_lw, lw);
  double total = 0.0;
  for (double& lw : log_w) {
    lw = std::isfinite(lw) ? std::exp(lw - max_lw) : 0.0;
    total += lw;
  }
  for (double& p : probability_) p /= total;
}

}  // namespace coopnav
