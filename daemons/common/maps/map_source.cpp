#include "maps/map_source.hpp"

#include "runtime/daemon_main.hpp"

namespace coopnav {

void MapSource::resolvePaths(const std::string& base_dir) {
  map_file = resolvePath(base_dir, map_file);
}

LoadedField loadDistanceField(const MapSource& source, bool build_tree) {
  LoadedField out;
  try {
    MapLoadOptions opts;
    opts.bt_z_min_m = source.bt_z_min_m;
    opts.bt_z_max_m = source.bt_z_max_m;
    opts.max_cells = source.max_map_cells;
    opts.build_tree = build_tree;
    out.map = loadMap(source.map_file, opts);
  } catch (const MapLoadError& e) {
    throw StartupError(e.what());
  }
  out.field = std::make_shared<GridDistanceField>(
      std::move(out.map.grid),
      source.unknown_is_obstacle ? UnknownPolicy::kObstacle : UnknownPolicy::kFree);
  return out;
}

}  // namespace coopnav
