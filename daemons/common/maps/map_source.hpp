#pragma once
/// @file The map settings shared by every daemon that loads the known map (distance server,
/// band source), and the one place that turns them into a distance field. Their keys sit at the
/// top level of the daemon's YAML: the parent's visit() calls MapSource::visit with its visitor.

#include <cstdint>
#include <memory>
#include <string>

#include "config/config.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "maps/map_loader.hpp"

namespace coopnav {

struct MapSource {
  /// Map: ROS map_server YAML (+PGM), OctoMap .bt, a walls YAML or a scenario file (its map:).
  /// Relative to the config file.
  std::string map_file{"maps/open.yaml"};
  /// Unknown cells count as obstacles (open.pgm's pillar interior is unknown).
  bool unknown_is_obstacle{true};
  /// Height band [m] of a .bt map projected to 2-D.
  double bt_z_min_m{0.05};
  double bt_z_max_m{2.0};
  /// Most cells the map may have: a bigger one stops the daemon at start (exit 3) before it is
  /// allocated. 2^22 (102 m square at 5 cm) loads in a few seconds and ~0.5 GB.
  std::int64_t max_map_cells{kMaxMapCells};

  template <class V>
  void visit(V& v) {
    v("map_file", map_file);
    v("unknown_is_obstacle", unknown_is_obstacle);
    v("bt_z_min_m", bt_z_min_m, Range{-100.0, 100.0});
    v("bt_z_max_m", bt_z_max_m, Range{-100.0, 100.0});
    v("max_map_cells", max_map_cells, Range{1.0, static_cast<double>(kMaxMapCellsCeiling)});
    v.require(bt_z_max_m > bt_z_min_m, "bt_z_max_m", "must be greater than bt_z_min_m");
    v.require(!map_file.empty(), "map_file", "must name a map file");
  }
  void resolvePaths(const std::string& base_dir);
};

struct LoadedField {
  LoadedMap map;  ///< the map of record (its grid is moved into the field)
  std::shared_ptr<GridDistanceField> field;
};

/// Loads the map and builds its distance field; throws StartupError naming the file and the
/// problem (a daemon stops at start with exit 3). build_tree: MapLoadOptions::build_tree.
LoadedField loadDistanceField(const MapSource& source, bool build_tree = true);

}  // namespace coopnav
