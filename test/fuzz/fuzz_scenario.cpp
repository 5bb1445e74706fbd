// world_sim's scenario loading as WorldSimNode's constructor runs it: parseScenario (YAML, keys,
// ranges, agents, behaviours), the scenario's map (inline walls / boxes, or a file), the distance
// field, the start / goal clearance check, toWorldSpec and the simulation built from it.
// Expected refusals: ScenarioError, MapLoadError and std::invalid_argument (the node turns each
// into exit 3); anything else is a finding.
#include <memory>
#include <stdexcept>

#include "coopnav/band/band_config.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/sim/band_human_adapter.hpp"
#include "coopnav/sim/simulation.hpp"
#include "fuzz_util.hpp"
#include "maps/map_loader.hpp"
#include "scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const world_sim::Scenario scenario =
        world_sim::parseScenario(text, "scenario.yaml", fuzz::scratch().path());
    LoadedMap map = world_sim::loadScenarioMap(scenario, fuzz::kMaxMapCells);
    auto field = std::make_shared<GridDistanceField>(std::move(map.grid), UnknownPolicy::kObstacle);
    world_sim::checkScenarioAgainstMap(scenario, *field);
    sim::Simulation sim(world_sim::toWorldSpec(scenario), field.get(),
                        sim::dualBandAdapterFactory(BandPlannerConfig{}, field));
    (void)sim.agents();
  } catch (const world_sim::ScenarioError&) {
  } catch (const MapLoadError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
