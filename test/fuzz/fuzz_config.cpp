// Every daemon's config loading as runDaemon does it (daemon_main.hpp): loadConfig<Config> on the
// file (YAML parse, keys, types, ranges, cross-field checks, unknown keys), resolvePaths, and the
// --print-config output, which must load again to the same printout. The first input byte picks
// the daemon, the rest is the YAML file. Expected refusal: ConfigError (exit 2), nothing else.
#include <string>

#include "band_source_node.hpp"
#include "config/config.hpp"
#include "dialogue_manager_node.hpp"
#include "fuzz_util.hpp"
#include "obstacle_distance_server_node.hpp"
#include "path_assessor_node.hpp"
#include "runtime/daemon_main.hpp"
#include "situation_assessor_node.hpp"
#include "world_sim_node.hpp"

namespace {

using namespace coopnav;

template <class Config>
void loadLikeDaemon(const std::uint8_t* data, std::size_t size) {
  const auto& dir = fuzz::scratch();
  const std::string path = dir.write("config.yaml", data, size);
  Config config;
  try {
    config = loadConfig<Config>(path);
  } catch (const ConfigError&) {
    return;
  }
  const std::string printed = configToYaml(config);
  const std::string reprinted_path = dir.write(
      "printed.yaml", reinterpret_cast<const std::uint8_t*>(printed.data()), printed.size());
  try {
    if (configToYaml(loadConfig<Config>(reprinted_path)) != printed)
      fuzz::fail("config: --print-config output loads to a different config");
  } catch (const ConfigError&) {
    fuzz::fail("config: --print-config output of an accepted config is refused");
  }
  if constexpr (detail::HasResolvePaths<Config>::value) config.resolvePaths(dir.path());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t* yaml = data + 1;
  const std::size_t yaml_size = size - 1;
  // The configs in config/system.yaml's start order, the world last (scripts/fuzz.sh --seed).
  switch (data[0] % 6) {
    case 0:
      loadLikeDaemon<ObstacleDistanceServerConfig>(yaml, yaml_size);
      break;
    case 1:
      loadLikeDaemon<BandSourceConfig>(yaml, yaml_size);
      break;
    case 2:
      loadLikeDaemon<SituationAssessorConfig>(yaml, yaml_size);
      break;
    case 3:
      loadLikeDaemon<PathAssessorNodeConfig>(yaml, yaml_size);
      break;
    case 4:
      loadLikeDaemon<DialogueManagerConfig>(yaml, yaml_size);
      break;
    default:
      loadLikeDaemon<WorldSimConfig>(yaml, yaml_size);
      break;
  }
  return 0;
}
