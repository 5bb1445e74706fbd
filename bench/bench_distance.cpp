// bench_distance: build time and query cost of the grid distance field on open.pgm, beside
// DynamicEDTOctomap (Lau, Sprunk & Burgard 2013) on the same map. Prints figures, then
// "RESULT <key> <value>" lines. Timing: median of repeated runs (the machine is shared and noisy).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance/octree_conversion.hpp"
#include "maps/map_loader.hpp"
#include "wire/conversions.hpp"

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

// An isolated port so the bench never meets a running system.
const char* kBenchUrl = "udpm://239.255.76.67:7961?ttl=0&recv_buf_size=4194304";

struct RawHandler {
  bool got{false};
  void onMessage(const lcm::ReceiveBuffer*, const std::string&) { got = true; }
};

// Round-trip times [us] of `payload` published on `out` until anything arrives on `in`.
std::vector<double> roundTrips(lcm::LCM& lcm, const std::string& out, const std::string& in,
                               const std::vector<std::uint8_t>& payload, int n) {
  RawHandler h;
  lcm::Subscription* sub = lcm.subscribe(in, &RawHandler::onMessage, &h);
  std::vector<double> us;
  for (int i = 0; i < n; ++i) {
    h.got = false;
    const auto t0 = Clock::now();
    lcm.publish(out, payload.data(), static_cast<unsigned>(payload.size()));
    while (!h.got) {
      if (lcm.handleTimeout(1000) <= 0) break;
    }
    if (h.got) us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  lcm.unsubscribe(sub);
  return us;
}

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

  // ---- LCM round trip: a 100-query request to the real server process vs a bare echo ----
  // Both go through the same host network stack with the same request bytes, so the ratio is
  // the server's decode + answer + encode cost over the transport's own.
  double rtt_ratio = std::nan("");
  {
    std::vector<DistanceQuery> qs;
    std::mt19937 rng2(7);
    std::uniform_real_distribution<double> qx(6.0, 30.0), qy(4.0, 9.0), qa(-M_PI, M_PI);
    for (int i = 0; i < 100; ++i) {
      DistanceQuery q;
      q.kind = static_cast<DistanceQueryKind>(i % 3);
      q.point = {qx(rng2), qy(rng2)};
      const double a = qa(rng2);
      q.vector = {std::cos(a), std::sin(a)};
      q.max_range_m = 5.0;
      qs.push_back(q);
    }
    const auto req = toLcm(0, 1, "COOPNAV_DIST_REP_BENCH", qs);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(req.getEncodedSize()));
    req.encode(bytes.data(), 0, static_cast<int>(bytes.size()));

    const pid_t echo = coopnav::bench::startEcho(kBenchUrl, "BENCH_ECHO_REQ", "BENCH_ECHO_REP");
    const std::string server_exe =
        std::string(COOPNAV_BINARY_DIR) +
        "/daemons/obstacle_distance_server/coopnav_obstacle_distance_server";
    const pid_t server = ::fork();
    if (server == 0) {
      ::execl(server_exe.c_str(), server_exe.c_str(), "--lcm-url", kBenchUrl, "--set",
              ("map_file=" + map_path).c_str(), "--log-level", "warn", (char*)nullptr);
      ::_exit(127);
    }
    lcm::LCM lcm(kBenchUrl);
    // Warm up until both answer (the server loads its map first).
    for (int i = 0; i < 200; ++i) {
      if (!roundTrips(lcm, channels::kDistanceRequest, "COOPNAV_DIST_REP_BENCH", bytes, 1)
               .empty() &&
          !roundTrips(lcm, "BENCH_ECHO_REQ", "BENCH_ECHO_REP", bytes, 1).empty())
        break;
    }
    // Interleaved rounds so load changes on this shared machine hit both alike.
    std::vector<double> server_us, echo_us;
    for (int round = 0; round < 20; ++round) {
      auto s1 = roundTrips(lcm, channels::kDistanceRequest, "COOPNAV_DIST_REP_BENCH", bytes, 50);
      auto e1 = roundTrips(lcm, "BENCH_ECHO_REQ", "BENCH_ECHO_REP", bytes, 50);
      server_us.insert(server_us.end(), s1.begin(), s1.end());
      echo_us.insert(echo_us.end(), e1.begin(), e1.end());
    }
    ::kill(server, SIGTERM);
    ::kill(echo, SIGKILL);
    int st = 0;
    ::waitpid(server, &st, 0);
    ::waitpid(echo, &st, 0);
    const double s50 = coopnav::bench::percentile(server_us, 0.5),
                 s99 = coopnav::bench::percentile(server_us, 0.99);
    const double e50 = coopnav::bench::percentile(echo_us, 0.5),
                 e99 = coopnav::bench::percentile(echo_us, 0.99);
    std::printf(
        "LCM round trip, 100-query request (%zu bytes), %zu/%zu samples: server p50 %.1f us "
        "p99 %.1f us; bare echo p50 %.1f us p99 %.1f us\n",
        bytes.size(), server_us.size(), echo_us.size(), s50, s99, e50, e99);
    rtt_ratio = s50 / e50;
    std::printf("server/echo p50 ratio %.2f, p99 ratio %.2f\n", rtt_ratio, s99 / e99);
  }

  std::printf("RESULT distance_build_speedup_vs_dynamicedt %.2f\n", speedup);
  std::printf("RESULT distance_query_ns %.1f\n", nearest_ns);
  std::printf("RESULT distance_rtt_ratio_vs_echo %.2f\n", rtt_ratio);
  return 0;
}
