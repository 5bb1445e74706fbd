// An OctoMap binary tree (.bt) as a daemon's map_file: OctoMap's reader, the projection of the
// height band to the 2-D grid and the distance field (MapSource -> loadDistanceField). Expected
// refusal: StartupError (exit 3), nothing else.
#include "fuzz_util.hpp"
#include "maps/map_source.hpp"
#include "runtime/daemon_main.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  MapSource source;
  source.max_map_cells = fuzz::kMaxMapCells;
  source.map_file = fuzz::scratch().write("map.bt", data, size);
  // The band our own 2-D trees hold (map_loader.hpp: MapLoadOptions), so seeds written by writeBt
  // load and the fuzzer starts from real trees.
  source.bt_z_min_m = 0.0;
  source.bt_z_max_m = 0.1;
  try {
    const LoadedField loaded = loadDistanceField(source);
    if (!loaded.field || !loaded.map.tree) fuzz::fail("bt: loaded without a field or a tree");
    (void)loaded.field->nearest(loaded.field->bounds().center());
  } catch (const StartupError&) {
  }
  return 0;
}
