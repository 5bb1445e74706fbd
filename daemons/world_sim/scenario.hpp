#pragma once
/// @file Scenario files of the world simulator (format: docs/scenario-format.md): YAML -> a
/// validated Scenario struct -> a sim::WorldSpec. In-class initialisers here and in lib/sim are
/// the only defaults. Every problem of a file is reported at once, each naming the file, the key,
/// the value and what is allowed.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/map_loader.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/sim/simulation.hpp"

namespace coopnav::world_sim {

/// A scenario that cannot be run; what() lists every problem found, one per line.
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A straight wall of a synthetic map: the segment thickened by thickness_m.
struct WallSegment {
  double x0_m{0.0}, y0_m{0.0}, x1_m{0.0}, y1_m{0.0};
  double thickness_m{0.2};
};

/// An axis-aligned solid box of a synthetic map.
struct BoxObstacle {
  double min_x_m{0.0}, min_y_m{0.0}, max_x_m{0.0}, max_y_m{0.0};
};

/// Exactly one of file or (walls and/or boxes).
struct MapSpec {
  std::string file;  ///< resolved against the scenario's folder; empty for a synthetic map
  std::vector<WallSegment> walls;
  std::vector<BoxObstacle> boxes;
  double resolution_m{0.05};  ///< grid resolution for a synthetic map
};

struct RatesSpec {
  double physics_hz{20.0};       ///< >= 20 Hz (issue 4); an integer multiple of publish_hz
  double publish_hz{10.0};       ///< agent-state publication = one lockstep tick
  double real_time_factor{1.0};  ///< real-time mode only: sim seconds per wall second
};

struct LockstepSpec {
  bool enabled{true};
  std::vector<std::string> participants;  ///< daemon names that must finish each tick
  double step_timeout_s{10.0};  ///< wall time to wait for a participant before failing the run
};

struct Scenario {
  std::string name;
  std::uint64_t seed{0};
  double time_limit_s{60.0};
  MapSpec map;
  RatesSpec rates;
  LockstepSpec lockstep;
  sim::RobotSpec robot;
  std::vector<sim::HumanSpec> humans;
  std::string source;  ///< file the scenario came from (for messages)
};

/// Reads and validates a scenario file. Throws ScenarioError.
Scenario loadScenario(const std::string& path);
/// Same from text; `source` names it in messages, relative map paths resolve against base_dir.
Scenario parseScenario(const std::string& yaml_text, const std::string& source,
                       const std::string& base_dir);
/// Checks the scenario against its loaded map: every start and goal (and via point) lies in free
/// space with the agent's radius of clearance. Throws ScenarioError listing every offender.
void checkScenarioAgainstMap(const Scenario& scenario, const DistanceMap& map);
/// Loads the scenario's map section (its file, or its walls and boxes rasterised) with the
/// daemons' map loader. Throws MapLoadError naming the file or "<scenario>: map", also when the
/// map has more than max_cells cells or more than an OcTree holds. No OcTree is built (the
/// simulator needs the grid only): the result's tree is null.
LoadedMap loadScenarioMap(const Scenario& scenario, std::int64_t max_cells = kMaxMapCells);
/// The simulator's input for the scenario.
sim::WorldSpec toWorldSpec(const Scenario& scenario);

}  // namespace coopnav::world_sim
