#pragma once
/// @file Obstacle distance server: loads the known map into an OctoMap (the map of record), builds
/// the exact 2-D distance field, and answers batched NEAREST / SIDE / RAY queries by request/reply.

#include <memory>
#include <string>

#include "config/config.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance_request_t.hpp"
#include "maps/map_source.hpp"
#include "runtime/limits.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

struct ObstacleDistanceServerConfig {
  /// The known map: the same file as the other map-loading daemons of a run.
  MapSource map;
  /// If set, the map of record is written there as .bt at start (for octovis).
  std::string write_bt_path{""};
  /// Queries asking for more range than this are clamped to it [m].
  double max_range_cap_m{50.0};

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    map.visit(v);  // its keys at the top level of this YAML
    v("write_bt_path", write_bt_path);
    v("max_range_cap_m", max_range_cap_m, Range{0.1, 1000.0});
    v("limits", limits);
  }
  void resolvePaths(const std::string& base_dir);
};

class ObstacleDistanceServerNode {
 public:
  using Config = ObstacleDistanceServerConfig;
  /// Loads the map; throws StartupError naming the file and the problem.
  ObstacleDistanceServerNode(const Config& config, Runtime& runtime);

  const GridDistanceField& field() const { return *field_; }

 private:
  void onRequest(const distance_request_t& msg);

  Config config_;
  Runtime& runtime_;
  std::shared_ptr<GridDistanceField> field_;
};

}  // namespace coopnav
