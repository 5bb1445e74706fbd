#pragma once
/// @file Map loading for the distance server and the simulator: the I/O side of lib/distance.
///
/// Sources, dispatched by loadMap():
///  - ROS map_server YAML (`image:` key) + PGM (P2 or P5), trinary mode; see loadRosMap().
///  - OctoMap binary `.bt`: the leaves in a height band projected to a 2-D grid.
///  - A walls map (`walls:` / `boxes:` keys), rasterised 4-connected; see rasteriseWallsMap().
///  - A scenario file (`map:` key): its map, whichever of the above it is.
/// Every failure throws MapLoadError naming the file and the key / line / value at fault.

#include <octomap/OcTree.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "coopnav/distance/occupancy_grid.hpp"

namespace coopnav {

/// A map that cannot be loaded; what() names the file and the key, line or value at fault.
class MapLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Most cells a loaded map may have by default (2048 x 2048: 102 m square at 5 cm). Loading one
/// that large (grid, OctoMap of record, distance field) takes a few seconds and ~0.5 GB; a walls
/// YAML of a few lines or a .bt of a few coarse leaves could otherwise ask for up to 2^30 cells,
/// minutes and GBs at start (found by the fuzzers). A daemon raises it with `max_map_cells`.
inline constexpr std::int64_t kMaxMapCells = std::int64_t{1} << 22;
/// Ceiling of `max_map_cells`: 2^26 cells (410 m square at 5 cm) take ~8 GB to load.
inline constexpr std::int64_t kMaxMapCellsCeiling = std::int64_t{1} << 26;

struct MapLoadOptions {
  /// Voxel layers of the OcTree built from a 2-D source (even numbers let the tree prune).
  int slab_layers{2};
  /// Height band [m] (tree frame) of a .bt projected to the grid; a voxel counts if its z extent
  /// overlaps [bt_z_min_m, bt_z_max_m]. The default covers the slab our own 2-D trees hold.
  double bt_z_min_m{0.0};
  double bt_z_max_m{0.1};
  /// World position [m] of a .bt's frame origin (trees we write are in the grid frame, so this is
  /// the origin of the grid they came from).
  Eigen::Vector2d bt_origin_m{0.0, 0.0};
  /// A map of more cells than this is a MapLoadError, raised before the grid is allocated.
  std::int64_t max_cells{kMaxMapCells};
  /// Build the OcTree of record from a 2-D source. Only the distance server keeps it (written with
  /// write_bt_path); the band source and world_sim use the grid alone, and building the tree was
  /// a third of world_sim's map loading. Either way a grid the tree could not hold is refused, so
  /// every daemon accepts the same maps. (A .bt is read into its tree in any case.)
  bool build_tree{true};
};

/// A loaded map: the OcTree of record and the grid the distance field is built from.
struct LoadedMap {
  /// Map of record, in the tree frame: world = tree + tree_origin_m (x, y; z unchanged). Null for
  /// a 2-D source loaded with build_tree false.
  std::unique_ptr<octomap::OcTree> tree;
  /// World position [m] of the tree frame's origin.
  Eigen::Vector2d tree_origin_m{0.0, 0.0};
  /// The 2-D grid, world frame.
  OccupancyGrid2 grid;
  /// Where it came from (a file path, or "<scenario>: map" for inline walls), for messages.
  std::string source;
};

/// A PGM image, row 0 at the top.
struct PgmImage {
  int width{0};
  int height{0};
  int maxval{0};
  std::vector<std::uint16_t> pixels;  ///< row-major, width * height values in [0, maxval]
};

/// Loads a map file: `.bt`, or a YAML file holding either a ROS map (`image:`) or a walls map
/// (`walls:` and/or `boxes:`).
LoadedMap loadMap(const std::string& path, const MapLoadOptions& options = {});

/// Loads a scenario's `map:` section: `file: <path>` (relative to base_dir unless absolute), or
/// the keys of a ROS map or a walls map inline. where names the section in messages.
LoadedMap loadMapFromNode(const YAML::Node& map_node, const std::string& base_dir,
                          const MapLoadOptions& options = {},
                          const std::string& where = "map section");

/// Reads a binary (P5, 8 or 16 bit) or ASCII (P2) PGM, with comments.
PgmImage readPgm(const std::string& path);

/// Reads a ROS map_server YAML node: image, resolution, origin [x, y, yaw = 0], negate,
/// occupied_thresh, free_thresh, optional mode (only `trinary`). An image path is taken relative
/// to base_dir unless absolute. where names the YAML file in messages.
OccupancyGrid2 loadRosMap(const YAML::Node& node, const std::string& base_dir,
                          const std::string& where, std::int64_t max_cells = kMaxMapCells);

/// Rasterises `resolution_m`, `walls: [{x0_m, y0_m, x1_m, y1_m, thickness_m}]`,
/// `boxes: [{min_x_m, min_y_m, max_x_m, max_y_m}]`, optional `margin_m` (>= 0, default 0) into a
/// grid covering their bounding box plus the margin; every cell not a wall or box is free. A wall
/// occupies the cells whose centre is within thickness/2 of its segment plus the 4-connected
/// cells its centre line crosses, so no distance wave leaks through a thin diagonal wall. A box
/// occupies every cell its rectangle overlaps.
OccupancyGrid2 rasteriseWallsMap(const YAML::Node& node, const std::string& where,
                                 std::int64_t max_cells = kMaxMapCells);

/// Writes tree as an OctoMap binary file (octovis) without modifying it.
void writeBt(const octomap::OcTree& tree, const std::string& path);

}  // namespace coopnav
