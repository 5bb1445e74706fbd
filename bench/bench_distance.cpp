// bench_distance: build time and query cost of the grid distance field on open.pgm, beside
// DynamicEDTOctomap (Lau, Sprunk & Burgard 2013) on the same map. Prints figures, then
// "RESULT <key> <value>" lines. Timing: median of repeated runs (the machine is shared and noisy).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/map_loader.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance/octree_conversion.hpp"

#ifdef COOPNAV_HAVE_DYNAMICEDT3D
#include <dynamicEDT3D/dynamicEDTOctomap.h>
#endif

namespace {

using Clock = std::chrono::steady_clock;

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Median over runs of the wall time [s] of one call of f.
double medianSeconds(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return medianOf(t);
}

struct Query {
  Eigen::Vector2d p, v;  // point (free cell) and unit normal / direction
};

volatile double g_sink = 0.0;  // keeps the query loops from being optimised away

}  // namespace

int main() {
  using namespace coopnav;
  const std::string map_path = std::string(COOPNAV_SOURCE_DIR) + "/test/data/maps/open.yaml";
  const LoadedMap map = loadMap(map_path);
  const OccupancyGrid2& grid = map.grid;
  std::printf("map %s: %d x %d cells @ %.3f m, %zu occupied, %zu unknown\n", map_path.c_str(),
              grid.width(), grid.height(), grid.resolution_m(), grid.count(CellState::kOccupied),
              grid.count(CellState::kUnknown));

  constexpr int kBuildRuns = 15;
  std::unique_ptr<GridDistanceField> field;
  const double ours_s = medianSeconds(kBuildRuns, [&] {
    field = std::make_unique<GridDistanceField>(grid, UnknownPolicy::kObstacle);
  });
  std::printf(
      "GridDistanceField build (FH EDT + boundary k-d tree): %.2f ms (median of %d), "
      "%zu boundary cells\n",
      1e3 * ours_s, kBuildRuns, field->boundaryCellCount());

  // Queries from free cells, fixed seed.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> ux(grid.origin_m().x(), grid.max_m().x());
  std::uniform_real_distribution<double> uy(grid.origin_m().y(), grid.max_m().y());
  std::uniform_real_distribution<double> ua(-M_PI, M_PI);
  std::vector<Query> queries;
  constexpr std::size_t kQueries = 100000;
  while (queries.size() < kQueries) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const auto c = grid.cellOf(p);
    if (!c || grid.at(c->x(), c->y()) != CellState::kFree) continue;
    const double a = ua(rng);
    queries.push_back({p, Eigen::Vector2d(std::cos(a), std::sin(a))});
  }
  constexpr int kQueryRuns = 7;
  constexpr double kRange_m = 10.0;
  const auto per_query_ns = [&](const std::function<double(const Query&)>& q) {
    return 1e9 / kQueries * medianSeconds(kQueryRuns, [&] {
             double sum = 0.0;
             for (const Query& x : queries) sum += q(x);
             g_sink = sum;
           });
  };
  const double nearest_ns =
      per_query_ns([&](const Query& x) { return field->nearest(x.p).distance_m; });
  const double side_ns = per_query_ns(
      [&](const Query& x) { return field->nearestInHalfPlane(x.p, x.v, kRange_m).distance_m; });
  const double ray_ns =
      per_query_ns([&](const Query& x) { return field->ray(x.p, x.v, kRange_m).distance_m; });
  std::printf(
      "queries (%zu from free cells, range %.0f m, median of %d): NEAREST %.1f ns, "
      "SIDE %.1f ns, RAY %.1f ns\n",
      kQueries, kRange_m, kQueryRuns, nearest_ns, side_ns, ray_ns);

  double speedup = std::nan("");
#ifdef COOPNAV_HAVE_DYNAMICEDT3D
  {
    // Same obstacles as ours: unknown cells are marked as walls in the source tree (not
    // treatUnknownAsOccupied, which would make every unknown voxel of the bbox an obstacle), in
    // the grid frame, one voxel layer of bbox, maxdist 5 m.
    OccupancyGrid2 walls = grid;
    for (int j = 0; j < walls.height(); ++j) {
      for (int i = 0; i < walls.width(); ++i) {
        if (walls.at(i, j) == CellState::kUnknown) walls.set(i, j, CellState::kOccupied);
      }
    }
    const auto tree = gridToOctree(walls, 2);
    const double res = grid.resolution_m();
    const octomap::point3d bbx_min(0.0f, 0.0f, static_cast<float>(0.5 * res));
    const octomap::point3d bbx_max(static_cast<float>((grid.width() - 0.5) * res),
                                   static_cast<float>((grid.height() - 0.5) * res),
                                   static_cast<float>(0.5 * res));
    constexpr float kMaxDist_m = 5.0f;
    constexpr int kDynRuns = 7;
    std::unique_ptr<DynamicEDTOctomap> dyn;
    const double dyn_s = medianSeconds(kDynRuns, [&] {
      dyn.reset();
      dyn = std::make_unique<DynamicEDTOctomap>(kMaxDist_m, tree.get(), bbx_min, bbx_max, false);
      dyn->update(true);
    });
    speedup = dyn_s / ours_s;
    std::printf(
        "DynamicEDTOctomap ctor + update (maxdist %.0f m, 1 layer): %.2f ms (median of "
        "%d)\n",
        kMaxDist_m, 1e3 * dyn_s, kDynRuns);
    std::printf("build speed-up ours vs DynamicEDTOctomap: %.1fx\n", speedup);

    const auto to_tree = [&](const Eigen::Vector2d& p) {
      return octomap::point3d(static_cast<float>(p.x() - grid.origin_m().x()),
                              static_cast<float>(p.y() - grid.origin_m().y()),
                              static_cast<float>(0.5 * res));
    };
    const double dyn_ns = per_query_ns([&](const Query& x) {
      float d = 0.0f;
      octomap::point3d o(0.0f, 0.0f, 0.0f);
      dyn->getDistanceAndClosestObstacle(to_tree(x.p), d, o);
      return static_cast<double>(d);
    });
    // Agreement on centre-to-centre distances where DynamicEDT is not saturated, queried at the
    // cell centre (float coordinates could round a point near a cell edge into the neighbour).
    double max_diff_m = 0.0;
    std::size_t compared = 0;
    for (const Query& x : queries) {
      const auto c = grid.cellOf(x.p);
      const float d = dyn->getDistance(to_tree(grid.cellCenter_m(c->x(), c->y())));
      if (d < 0.0f || d >= dyn->getMaxDist()) continue;
      const double ours_c2c_m = field->nearest(x.p).distance_m + 0.5 * res;
      max_diff_m = std::max(max_diff_m, std::abs(ours_c2c_m - d));
      ++compared;
    }
    std::printf(
        "DynamicEDTOctomap NEAREST with obstacle: %.1f ns; max |ours - DynEDT| "
        "(centre-to-centre) over %zu queries: %.4f m\n",
        dyn_ns, compared, max_diff_m);
  }
#else
  std::printf("DynamicEDT3D not found: no comparison\n");
#endif

  // ---- LCM round trip (to be added: RTT of a 100-point request vs a bare LCM echo) ----
  // Print its figures here and its "RESULT distance_rtt_ratio_vs_echo <x>" line below.

  std::printf("RESULT distance_build_speedup_vs_dynamicedt %.2f\n", speedup);
  std::printf("RESULT distance_query_ns %.1f\n", nearest_ns);
  return 0;
}
