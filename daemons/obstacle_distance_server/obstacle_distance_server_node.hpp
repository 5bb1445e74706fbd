#pragma once
/// @file Obstacle distance server: loads the known map into an OctoMap (the map of record), builds
/// the exact 2-D distance field, and answers batched NEAREST / SIDE / RAY queries by request/reply.

#include <memory>
#include <string>

#include "common/config.hpp"
#include "common/runtime.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance_request_t.hpp"

namespace coopnav {

struct ObstacleDistanceServerConfig {
  /// Map: ROS map_server YAML (+PGM), OctoMap .bt, or a walls YAML. Relative to the config file.
  std::string map_file{"maps/open.yaml"};
  /// Unknown cells count as obstacles for distances (open.pgm's pillar interior is unknown).
  bool unknown_is_obstacle{true};
  /// Height band [m] of a .bt map projected to 2-D.
  double bt_z_min_m{0.05};
  double bt_z_max_m{2.0};
  /// If set, the map of record is written there as .bt at start (for octovis).
  std::string write_bt_path{""};
  /// Queries asking for more range than this are clamped to it [m].
  double max_range_cap_m{50.0};

  template <class V>
  void visit(V& v) {
    v("map_file", map_file);
    v("unknown_is_obstacle", unknown_is_obstacle);
    v("bt_z_min_m", bt_z_min_m, Range{-100.0, 100.0});
    v("bt_z_max_m", bt_z_max_m, Range{-100.0, 100.0});
    v("write_bt_path", write_bt_path);
    v("max_range_cap_m", max_range_cap_m, Range{0.1, 1000.0});
    v.require(bt_z_max_m > bt_z_min_m, "bt_z_max_m", "must be greater than bt_z_min_m");
    v.require(!map_file.empty(), "map_file", "must name a map file");
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
  std::unique_ptr<GridDistanceField> field_;
};

}  // namespace coopnav
