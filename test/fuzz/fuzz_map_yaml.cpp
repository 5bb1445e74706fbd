// The map loaders a daemon runs at start on its map_file (MapSource -> loadDistanceField, as the
// distance server and the band source do): a ROS map_server YAML with its PGM image, a walls /
// boxes YAML, or a scenario file whose `map:` section is a file or walls. The input is the YAML,
// optionally followed by "\n--8<--\n" and the bytes of map.pgm (the image the YAML may name); both
// are written to a scratch folder. Expected refusal: StartupError (exit 3), nothing else.
#include "fuzz_util.hpp"
#include "maps/map_source.hpp"
#include "runtime/daemon_main.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  const std::vector<std::string> parts = fuzz::splitParts(data, size, 2);
  const auto& dir = fuzz::scratch();
  MapSource source;
  source.max_map_cells = fuzz::kMaxMapCells;
  source.map_file = dir.write("map.yaml", reinterpret_cast<const std::uint8_t*>(parts[0].data()),
                              parts[0].size());
  dir.write("map.pgm", reinterpret_cast<const std::uint8_t*>(parts[1].data()), parts[1].size());
  try {
    const LoadedField loaded = loadDistanceField(source);
    if (!loaded.field || !loaded.map.tree) fuzz::fail("map: loaded without a field or a tree");
    (void)loaded.field->nearest(loaded.field->bounds().center());
  } catch (const StartupError&) {
  }
  return 0;
}
