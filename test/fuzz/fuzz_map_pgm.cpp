// readPgm on its own: P2 (ASCII) and P5 (8 / 16 bit binary) images with comments, as a ROS map
// YAML's `image:` names them. Expected refusal: MapLoadError. An accepted image must hold
// width * height values within maxval.
#include "fuzz_util.hpp"
#include "maps/map_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  const std::string path = fuzz::scratch().write("image.pgm", data, size);
  try {
    const PgmImage img = readPgm(path);
    if (img.width <= 0 || img.height <= 0 || img.maxval <= 0 ||
        img.pixels.size() !=
            static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height))
      fuzz::fail("pgm: accepted image has an inconsistent size");
    for (const auto v : img.pixels)
      if (v > img.maxval) fuzz::fail("pgm: accepted pixel above maxval");
  } catch (const MapLoadError&) {
  }
  return 0;
}
