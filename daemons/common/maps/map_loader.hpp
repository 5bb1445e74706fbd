#pragma once
/// @file Map loading for the distance server and the simulator: the I/O side of lib/distance.
///
/// Sources, dispatched by loadMap():
///  - ROS map_server YAML (`image:` key) + PGM (P2 or P5), trinary mode; see loadRosMap().
///  - OctoMap binary `.bt`: the leaves in a height band projected to a 2-D grid.
///  - A walls map (`walls:` / `boxes:` keys), rasterised 4-connected; see rasteriseWallsMap().
///  - A scenario file (`map:` key): its map, whichever of the above it is.
/// Every failure throws MapLoadError naming the file and the key / line / value at fault. Every
/// file is read once through readFileCapped (config/file_read.hpp): a regular file under its cap;
/// a key given twice in a mapping the loader reads, or a resolution outside
/// [kMinMapResolution_m, kMaxMapResolution_m], is a bad map.

#include <octomap/OcTree.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstddef>
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

/// Bounds of a map's resolution [m per cell], whatever its source (ROS map, walls map, .bt).
/// Below 1 mm a cell is finer than any range sensor resolves, and max_map_cells (2^22) covers
/// 2 m square; above 10 m one cell is wider than any corridor the robot meets a person in. Out
/// of them a map is a slip of units, not a map: a ROS map at 1e-9 m loaded, and every query fell
/// outside it.
inline constexpr double kMinMapResolution_m = 1e-3;
inline constexpr double kMaxMapResolution_m = 10.0;

/// Size caps of the map files read whole at start (config/file_read.hpp; a map YAML is capped at
/// kMaxYamlFileBytes). They follow the cell limit, so that no map max_map_cells allows is refused
/// for its bytes and no file much larger than such a map is read: a file over its cap (or
/// /dev/zero, which read whole took 17-20 s and ~2 GB before std::bad_alloc) is a bad map.
/// Room for a file's header and comments beyond its cells.
inline constexpr std::size_t kMapFileHeaderBytes = std::size_t{1} << 20;
/// PGM: the widest pixel is a P2 "65535\r\n", 7 bytes (P5 takes 1 or 2); 8 at the default
/// max_map_cells: a 33 MiB image.
inline constexpr std::size_t kMaxPgmBytesPerCell = 8;
/// OctoMap .bt: 2 bytes per inner node, ~0.3 bytes per voxel of a tree that cannot be pruned
/// (measured: 1024 x 1024 x 4 random voxels, 1.2 MiB). Our own 2-D trees (2 layers) take under
/// 1 byte per cell; 16 leave room for a 3-D map's height layers (walls ~40 voxels tall at 5 cm,
/// free space pruned): 65 MiB at the default max_map_cells. OctoMap's reader builds the whole tree
/// before the height band and the cell limit apply, ~170 MB and ~1 s per MiB of unprunable
/// voxels: the cap bounds that too, and a file at it that is all unprunable voxels still takes
/// minutes and GBs (the loader does not count the nodes before OctoMap reads them).
inline constexpr std::size_t kMaxBtBytesPerCell = 16;

/// The cap of a PGM image / a .bt file for a map of at most max_cells cells.
std::size_t maxPgmBytes(std::int64_t max_cells);
std::size_t maxBtBytes(std::int64_t max_cells);

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

/// A place people walk to, annotated on a map by `goal_regions: [{x0_m, y0_m, x1_m, y1_m}]`
/// [m, world frame]: a segment across a corridor's end or along a door, a point when its ends
/// are equal. The band source's goal inference takes them as candidate goals, for maps whose
/// shape does not show where people go (a hall whose corridors open into it has no dead end).
struct MapGoalRegion {
  Eigen::Vector2d a{0.0, 0.0};
  Eigen::Vector2d b{0.0, 0.0};
};

/// Most goal regions a map may annotate.
inline constexpr std::size_t kMaxMapGoalRegions = 256;

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
  /// The map file's `goal_regions`, then those of the scenario section naming it.
  std::vector<MapGoalRegion> goal_regions;
};

/// A PGM image, row 0 at the top.
struct PgmImage {
  int width{0};
  int height{0};
  int maxval{0};
  std::vector<std::uint16_t> pixels;  ///< row-major, width * height values in [0, maxval]
};

/// Loads a map file: `.bt`, or a YAML file holding either a ROS map (`image:`) or a walls map
/// (`walls:` and/or `boxes:`), each YAML one with optional `goal_regions` (MapGoalRegion).
LoadedMap loadMap(const std::string& path, const MapLoadOptions& options = {});

/// Loads a scenario's `map:` section: `file: <path>` (relative to base_dir unless absolute), or
/// the keys of a ROS map or a walls map inline. where names the section in messages.
LoadedMap loadMapFromNode(const YAML::Node& map_node, const std::string& base_dir,
                          const MapLoadOptions& options = {},
                          const std::string& where = "map section");

/// Reads a binary (P5, 8 or 16 bit) or ASCII (P2) PGM, with comments: a regular file of at most
/// maxPgmBytes(max_cells) bytes.
PgmImage readPgm(const std::string& path, std::int64_t max_cells = kMaxMapCells);

/// Reads a ROS map_server YAML node: image, resolution, origin [x, y, yaw = 0], negate,
/// occupied_thresh, free_thresh, optional mode (only `trinary`). An image path is taken relative
/// to base_dir unless absolute. where names the YAML file in messages.
OccupancyGrid2 loadRosMap(const YAML::Node& node, const std::string& base_dir,
                          const std::string& where, std::int64_t max_cells = kMaxMapCells);

/// [m] Thickness of a synthetic wall that does not give one (docs/scenario-format.md): the same
/// for world_sim and for a daemon that loads the scenario file as its map.
inline constexpr double kDefaultWallThickness_m = 0.2;

/// [m] Grid resolution of a synthetic map that does not give `resolution_m`: as for the wall
/// thickness, one default for world_sim and for a daemon loading the scenario file as its map.
inline constexpr double kDefaultWallsMapResolution_m = 0.05;

/// Rasterises optional `resolution_m` (kDefaultWallsMapResolution_m), `walls: [{x0_m, y0_m,
/// x1_m, y1_m, thickness_m}]` (thickness optional, kDefaultWallThickness_m),
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
