#pragma once
/// @file Scenario files of the world simulator (format: docs/scenario-format.md): YAML -> a
/// validated Scenario struct -> a sim::WorldSpec. In-class initialisers here and in lib/sim are
/// the only defaults. Every key is declared once, with its range, in a visit() below (or, for the
/// lib/sim parameter structs, in theirs), read by the daemons' config reader (config/config.hpp,
/// ConfigReader). Every problem of a file is reported at once, each naming the file, the key, the
/// value and what is allowed.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/sim/recorded.hpp"
#include "coopnav/sim/simulation.hpp"
#include "coopnav/sim/tracker.hpp"
#include "maps/map_loader.hpp"

namespace coopnav::world_sim {

/// Bound of every coordinate of a scenario [m]: far beyond any map, finite.
inline constexpr double kMaxCoordinate_m = 1e6;

/// Most humans a scenario may have: the fewest any message about them carries (agent states,
/// goals with the robot's, bands, reference paths; lcmtypes/). One more loaded and ran, and every
/// message of the run was rejected downstream for its count.
inline constexpr std::size_t kMaxScenarioHumans =
    std::min<std::size_t>({static_cast<std::size_t>(agent_states_t::MAX_HUMANS),
                           static_cast<std::size_t>(goals_t::MAX_GOALS - 1),
                           static_cast<std::size_t>(bands_t::MAX_HUMANS),
                           static_cast<std::size_t>(reference_paths_t::MAX_PATHS)});

/// A number as messages print it (ostream defaults: 1.5, 1e+15).
inline std::string scenarioNumber(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// A scenario that cannot be run; what() lists every problem found, one per line.
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A segment [m, world frame] given by its ends.
struct SegmentSpec {
  double x0_m{0.0}, y0_m{0.0}, x1_m{0.0}, y1_m{0.0};
  template <class V>
  void visit(V& v) {
    const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
    v("x0_m", x0_m, xy, Required{});
    v("y0_m", y0_m, xy, Required{});
    v("x1_m", x1_m, xy, Required{});
    v("y1_m", y1_m, xy, Required{});
  }
};

/// A straight wall of a synthetic map: the segment thickened by thickness_m.
struct WallSegment : SegmentSpec {
  double thickness_m{kDefaultWallThickness_m};
  template <class V>
  void visit(V& v) {
    SegmentSpec::visit(v);
    v("thickness_m", thickness_m, Range{0.01, 10.0});
  }
};

/// A place people walk to (maps/map_loader.hpp MapGoalRegion): read by the band source's goal
/// inference, checked here so that a scenario with a bad one stops every daemon alike.
using GoalRegionSpec = SegmentSpec;

/// An axis-aligned solid box of a synthetic map.
struct BoxObstacle {
  double min_x_m{0.0}, min_y_m{0.0}, max_x_m{0.0}, max_y_m{0.0};
  template <class V>
  void visit(V& v) {
    const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
    v("min_x_m", min_x_m, xy, Required{});
    v("min_y_m", min_y_m, xy, Required{});
    v("max_x_m", max_x_m, xy, Required{});
    v("max_y_m", max_y_m, xy, Required{});
    v.require(max_x_m > min_x_m && max_y_m > min_y_m, "",
              "must have max_x_m > min_x_m and max_y_m > min_y_m");
  }
};

/// Exactly one of file or (walls and/or boxes).
struct MapSpec {
  std::string file;  ///< resolved against the scenario's folder; empty for a synthetic map
  std::vector<WallSegment> walls;
  std::vector<BoxObstacle> boxes;
  std::vector<GoalRegionSpec> goal_regions;           ///< not used by the simulator
  double resolution_m{kDefaultWallsMapResolution_m};  ///< grid resolution for a synthetic map
  template <class V>
  void visit(V& v) {
    v("file", file);
    v("walls", walls);
    v("boxes", boxes);
    v("goal_regions", goal_regions);
    v("resolution_m", resolution_m, Range{0.01, 1.0});
    const bool synthetic = !walls.empty() || !boxes.empty();
    v.require(file.empty() == synthetic, "", "needs exactly one of 'file' or 'walls'/'boxes'");
  }
};

struct RatesSpec {
  double physics_hz{20.0};       ///< >= 20 Hz; an integer multiple of publish_hz
  double publish_hz{10.0};       ///< agent-state publication = one lockstep tick
  double real_time_factor{1.0};  ///< real-time mode only: sim seconds per wall second
  template <class V>
  void visit(V& v) {
    v("physics_hz", physics_hz, Range{20.0, 2000.0});
    v("publish_hz", publish_hz, Range{0.1, 1000.0});
    v("real_time_factor", real_time_factor, Range{0.01, 1000.0});
    const double ratio = physics_hz / publish_hz;
    if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-9)
      v.require(false, "physics_hz",
                "= " + scenarioNumber(physics_hz) +
                    " must be an integer multiple of publish_hz = " + scenarioNumber(publish_hz));
  }
};

/// A disc of the world that is not on the robot's map.
struct CircleObstacle {
  double x_m{0.0}, y_m{0.0}, radius_m{0.0};
  template <class V>
  void visit(V& v) {
    const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
    v("x_m", x_m, xy, Required{});
    v("y_m", y_m, xy, Required{});
    v("radius_m", radius_m, Range{0.01, 100.0}, Required{});
  }
};

/// Obstacles in the world but not on the robot's map (a chair, a trolley, an open door): the
/// simulator's physics and laser see them, the daemons' map (the `map:` section) does not.
struct UnmappedObstaclesSpec {
  std::vector<BoxObstacle> boxes;
  std::vector<CircleObstacle> circles;
  template <class V>
  void visit(V& v) {
    v("boxes", boxes);
    v("circles", circles);
  }
  bool empty() const { return boxes.empty() && circles.empty(); }
};

/// The robot's simulated planar laser (lib/sim/laser.hpp), published on COOPNAV_SCAN each step.
struct LaserSpec {
  bool enabled{false};
  double range_min_m{0.05};
  double range_max_m{8.0};
  double fov_deg{270.0};
  double resolution_deg{0.5};
  double noise_sigma_m{0.01};
  double mount_x_m{0.0};
  double mount_y_m{0.0};
  template <class V>
  void visit(V& v) {
    v("enabled", enabled);
    v("range_min_m", range_min_m, Range{0.0, 100.0});
    v("range_max_m", range_max_m, Range{0.1, 100.0});
    v("fov_deg", fov_deg, Range{1.0, 360.0});
    v("resolution_deg", resolution_deg, Range{0.05, 10.0});
    v("noise_sigma_m", noise_sigma_m, Range{0.0, 1.0});
    v("mount_x_m", mount_x_m, Range{-5.0, 5.0});
    v("mount_y_m", mount_y_m, Range{-5.0, 5.0});
    v.require(range_max_m > range_min_m, "range_max_m", "must be greater than range_min_m");
    // laser_scan_t carries at most MAX_RANGES rays.
    v.require(fov_deg / resolution_deg + 1.0 <= 4096.0, "resolution_deg",
              "gives more than 4096 rays over fov_deg (laser_scan_t::MAX_RANGES)");
  }
};

struct LockstepSpec {
  bool enabled{true};
  std::vector<std::string> participants;  ///< daemon names that must finish each tick
  double step_timeout_s{10.0};  ///< wall time to wait for a participant before failing the run
  template <class V>
  void visit(V& v) {
    v("enabled", enabled);
    v("participants", participants);
    for (std::size_t i = 0; i < participants.size(); ++i)
      v.require(!participants[i].empty(), "participants[" + std::to_string(i) + "]",
                "must be a daemon name");
    v("step_timeout_s", step_timeout_s, Range{0.01, 3600.0});
  }
};

// ---- YAML views of the lib/sim structs (lib/ knows no file format), as
// config/band_config_yaml.hpp does for the band planner's: they visit the lib structs' own fields,
// whose initialisers stay the only defaults.

/// A lib/sim parameter struct, whose visit() speaks v.number(key, field, min, max),
/// v.choice(key, field, {allowed...}) and v.nested(key, sub), seen as a config struct.
template <class Params>
struct SimParamsYaml {
  Params* params{nullptr};
  template <class V>
  struct Adapter {
    V& v;
    void number(const char* key, double& field, double min, double max) {
      v(key, field, Range{min, max});
    }
    void choice(const char* key, std::string& field, const std::vector<std::string>& allowed) {
      v(key, field, OneOf{allowed});
    }
    template <class Sub>
    void nested(const char* key, Sub& sub) {
      SimParamsYaml<Sub> yaml{&sub};
      v(key, yaml);
    }
  };
  template <class V>
  void visit(V& v) {
    Adapter<V> a{v};
    params->visit(a);
  }
};

/// A pose {x_m, y_m, theta_rad}; theta_rad may be left out.
struct PoseYaml {
  Pose2* pose{nullptr};
  template <class V>
  void visit(V& v) {
    const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
    v("x_m", pose->x_m, xy, Required{});
    v("y_m", pose->y_m, xy, Required{});
    v("theta_rad", pose->theta_rad, Range{-2.0 * M_PI, 2.0 * M_PI});
  }
};

/// A via point {x_m, y_m} of a human's reference path.
struct ViaPointYaml {
  double x_m{0.0}, y_m{0.0};
  template <class V>
  void visit(V& v) {
    const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
    v("x_m", x_m, xy, Required{});
    v("y_m", y_m, xy, Required{});
  }
};

/// Where a recorded human's track comes from (`params` of behaviour `recorded`); the loaded
/// samples go to sim::RecordedParams::track.
struct RecordedSource {
  /// CSV of `t x y` rows, or a pedestrians JSON ("headon_pairs/2", test/data/pedestrians) when it
  /// ends in .json. Resolved against the scenario's folder by parseScenario().
  std::string file;
  int pair{-1};        ///< JSON only: index into its `pairs` (required there)
  std::string walker;  ///< JSON only: "a" or "b", the walker of the pair (required there)
};

/// `params` of a `recorded` human: the source, the time offset and the rigid transform.
struct RecordedParamsYaml {
  sim::RecordedParams* params{nullptr};
  RecordedSource* source{nullptr};
  template <class V>
  void visit(V& v) {
    v("file", source->file, Required{});
    v("pair", source->pair, Range{-1.0, 1e9});
    v("walker", source->walker);
    v("time_offset_s", params->time_offset_s, Range{-86400.0, 86400.0});
    TransformYaml transform{&params->transform};
    v("transform", transform);
  }

 private:
  /// Recording frame -> world; each key may be left out (identity).
  struct TransformYaml {
    Pose2* pose{nullptr};
    template <class V>
    void visit(V& v) {
      const Range xy{-kMaxCoordinate_m, kMaxCoordinate_m};
      v("x_m", pose->x_m, xy);
      v("y_m", pose->y_m, xy);
      v("theta_rad", pose->theta_rad, Range{-2.0 * M_PI, 2.0 * M_PI});
    }
  };
};

/// The `tracker` section (scenario) over lib/sim's TrackerParams, whose initialisers are the
/// defaults; the ranges are TrackerParams::validate()'s.
struct TrackerParamsYaml {
  sim::TrackerParams* p{nullptr};
  template <class V>
  void visit(V& v) {
    v("position_sigma_m", p->position_sigma_m, Range{0.0, 2.0});
    v("velocity_window_steps", p->velocity_window_steps, Range{1.0, 100.0});
    v("miss_probability", p->miss_probability, Range{0.0, 0.99});
    v("drop_after_s", p->drop_after_s, Range{0.0, 3600.0});
    v("id_switches", p->id_switches, Range{0.0, 1000.0});
    v("id_switch_window_s", p->id_switch_window_s, Range{0.0, 86400.0});
    v("range_m", p->range_m, Range{0.0, 1e6});
  }
};

struct RobotSpecYaml {
  sim::RobotSpec* robot{nullptr};
  template <class V>
  void visit(V& v) {
    PoseYaml start{&robot->start};
    PoseYaml goal{&robot->goal};
    v("start", start, Required{});
    v("goal", goal, Required{});
    v("radius_m", robot->radius_m, Range{0.05, 2.0});
    std::string kinematics =
        robot->kinematics == sim::Kinematics::kHolonomic ? "holonomic" : "differential";
    v("kinematics", kinematics, OneOf{{"differential", "holonomic"}});
    robot->kinematics =
        kinematics == "holonomic" ? sim::Kinematics::kHolonomic : sim::Kinematics::kDifferential;
    SimParamsYaml<sim::RobotLimits> limits{&robot->limits};
    v("limits", limits);
    v("goal_tolerance_m", robot->goal_tolerance_m, Range{0.01, 5.0});
  }
};

/// One item of `humans`. Owns its spec (list items are built by the reader); the id is read as a
/// number and the behaviour as its name, both checked here.
struct HumanSpecYaml {
  sim::HumanSpec spec;
  double id{0.0};         ///< as read: must be an integer >= 1 (0: not read)
  std::string behaviour;  ///< as read: empty until read, then one of behaviourTypeNames()
  RecordedSource source;  ///< behaviour recorded: where its track comes from

  static HumanSpecYaml of(const sim::HumanSpec& h, const RecordedSource& source = {}) {
    return {h, static_cast<double>(h.id), sim::toString(h.behaviour.type), source};
  }

  template <class V>
  void visit(V& v) {
    v("id", id, Range{1.0, 2147483647.0}, Required{});
    if (id != std::floor(id))
      v.require(false, "id", "= " + scenarioNumber(id) + " must be an integer >= 1");
    spec.id = static_cast<std::int32_t>(id);
    v("behaviour", behaviour, OneOf{sim::behaviourTypeNames()}, Required{});
    const bool known = sim::parseBehaviourType(behaviour, spec.behaviour.type);
    // A recorded human's start and goal are its track's (parseScenario() sets them): for it
    // start, goal and via are no keys.
    if (!known || spec.behaviour.type != sim::BehaviourType::kRecorded) {
      PoseYaml start{&spec.start};
      PoseYaml goal{&spec.goal};
      v("start", start, Required{});
      v("goal", goal, Required{});
      std::vector<ViaPointYaml> via;
      for (const auto& p : spec.via) via.push_back({p.x(), p.y()});
      v("via", via);
      spec.via.clear();
      for (const auto& p : via) spec.via.emplace_back(p.x_m, p.y_m);
    }
    v("speed_m_s", spec.speed_m_s, Range{0.0, 3.0});
    v("speed_stddev_m_s", spec.speed_stddev_m_s, Range{0.0, 1.0});
    v("velocity_noise_m_s", spec.velocity_noise_m_s, Range{0.0, 1.0});
    v("radius_m", spec.radius_m, Range{0.05, 1.0});
    v("max_acc_m_s2", spec.max_acc_m_s2, Range{0.1, 10.0});
    v("goal_tolerance_m", spec.goal_tolerance_m, Range{0.01, 5.0});
    // Every behaviour's but oblivious's (which ignores it): lib/include/coopnav/sim/behaviour.hpp.
    SimParamsYaml<sim::BodyCheckParams> body_check{&spec.behaviour.body_check};
    v("body_check", body_check);
    // A pause stops a walker (lib/include/coopnav/sim/behaviour.hpp PauseParams); a recorded
    // human's track is what it is.
    if (!known || spec.behaviour.type != sim::BehaviourType::kRecorded) {
      SimParamsYaml<sim::PauseParams> pause{&spec.behaviour.pause};
      v("pause", pause);
    }
    if (known) {
      visitParams(v);
    } else {
      v.skip("params");  // reported through 'behaviour'; not also unknown
    }
  }

 private:
  template <class Params, class V>
  static void params(V& v, Params& p) {
    SimParamsYaml<Params> yaml{&p};
    v("params", yaml);
  }
  template <class V>
  void visitParams(V& v) {
    sim::BehaviourConfig& b = spec.behaviour;
    switch (b.type) {
      case sim::BehaviourType::kMinimal:
        return params(v, b.minimal);
      case sim::BehaviourType::kOblivious:
        return params(v, b.oblivious);
      case sim::BehaviourType::kSocialForce:
        return params(v, b.social_force);
      case sim::BehaviourType::kLateFacilitating:
        return params(v, b.late_facilitating);
      case sim::BehaviourType::kResponsive:
        return params(v, b.responsive);
      case sim::BehaviourType::kFacilitating:
        return params(v, b.facilitating);
      case sim::BehaviourType::kRecorded: {
        RecordedParamsYaml yaml{&b.recorded, &source};
        v("params", yaml, Required{});
        return;
      }
    }
  }
};

struct Scenario {
  std::string name;
  std::uint64_t seed{0};
  double time_limit_s{60.0};
  /// The run ends in STANDSTILL after this long without any agent moving more than
  /// standstill_distance_m (and not every goal reached); 0 = never. Defaults: lib/sim's.
  double standstill_time_s{sim::SimSettings{}.standstill_time_s};
  double standstill_distance_m{sim::SimSettings{}.standstill_distance_m};
  MapSpec map;
  RatesSpec rates;
  LockstepSpec lockstep;
  sim::RobotSpec robot;
  std::vector<sim::HumanSpec> humans;
  /// Per human (same order): where a recorded human's track came from; empty file for the others.
  std::vector<RecordedSource> recorded_sources;
  /// What a people tracker would make of the humans (off by default: the true states).
  sim::TrackerParams tracker;
  /// false: COOPNAV_GOALS carries only the robot's goal (the humans' goals are to be inferred).
  bool publish_human_goals{true};
  UnmappedObstaclesSpec unmapped_obstacles;
  LaserSpec laser;
  /// When the people who yield of their own accord start to: "trigger" (their behaviour's fixed
  /// trigger) or "realistic" (an onset drawn per person from real walkers; sim::AvoidanceTiming).
  std::string avoidance_timing{sim::toString(sim::AvoidanceTiming::kTrigger)};
  std::string source;  ///< file the scenario came from (for messages)

  /// Every key of a scenario file (format: docs/scenario-format.md). map.file is read as written;
  /// parseScenario() resolves it against the scenario's folder and checks that it exists.
  template <class V>
  void visit(V& v) {
    v("name", name, Required{});
    // Read as a number: seeds up to 2^53, so that every value is exact in YAML's double reading.
    double seed_value = static_cast<double>(seed);
    v("seed", seed_value, Range{0.0, 9007199254740992.0}, Required{});
    if (seed_value != std::floor(seed_value))
      v.require(false, "seed", "= " + scenarioNumber(seed_value) + " must be an integer >= 0");
    seed = static_cast<std::uint64_t>(seed_value);
    v("time_limit_s", time_limit_s, Range{0.1, 86400.0}, Required{});
    v("standstill_time_s", standstill_time_s, Range{0.0, 86400.0});
    v("standstill_distance_m", standstill_distance_m, Range{0.0, 10.0});
    v("map", map, Required{});
    v("rates", rates);
    v("lockstep", lockstep);
    TrackerParamsYaml tracker_yaml{&tracker};
    v("tracker", tracker_yaml);
    v("publish_human_goals", publish_human_goals);
    v("avoidance_timing", avoidance_timing, OneOf{{"trigger", "realistic"}});
    v("unmapped_obstacles", unmapped_obstacles);
    v("laser", laser);
    RobotSpecYaml robot_yaml{&robot};
    v("robot", robot_yaml, Required{});
    std::vector<HumanSpecYaml> items;
    for (std::size_t i = 0; i < humans.size(); ++i)
      items.push_back(HumanSpecYaml::of(
          humans[i], i < recorded_sources.size() ? recorded_sources[i] : RecordedSource{}));
    v("humans", items);
    if (items.size() > kMaxScenarioHumans)
      v.require(false, "humans",
                "has " + std::to_string(items.size()) + " humans, more than the " +
                    std::to_string(kMaxScenarioHumans) +
                    " a message carries (agent_states_t::MAX_HUMANS)");
    humans.clear();
    recorded_sources.clear();
    for (const auto& item : items) {
      humans.push_back(item.spec);
      recorded_sources.push_back(item.source);
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (!(items[i].id >= 1.0)) continue;  // not read (reported)
      for (std::size_t j = 0; j < i; ++j) {
        if (items[j].id >= 1.0 && items[j].spec.id == items[i].spec.id) {
          v.require(false, "humans[" + std::to_string(i) + "].id",
                    "= " + scenarioNumber(items[i].id) + " duplicates humans[" + std::to_string(j) +
                        "].id");
          break;
        }
      }
    }
  }
};

/// The samples of a recorded human's track (source.file already resolved): a CSV of `t x y` rows,
/// or walker `walker` of pair `pair` of a pedestrians JSON ("headon_pairs/2") when the file ends
/// in .json. Throws sim::TrackError naming the file (and the line of a CSV, the member of a JSON).
std::vector<sim::TrackSample> loadTrack(const RecordedSource& source);

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
/// The world's grid: marks every cell an unmapped obstacle overlaps occupied (what the robot's
/// map does not hold; the simulator's collisions and laser see it).
void addUnmappedObstacles(const UnmappedObstaclesSpec& obstacles, OccupancyGrid2& grid);
/// Robot-body clearance to the nearest unmapped obstacle [m] (+inf when there is none).
double unmappedClearance(const UnmappedObstaclesSpec& obstacles, const Eigen::Vector2d& centre,
                         double radius_m);
/// The simulator's input for the scenario.
sim::WorldSpec toWorldSpec(const Scenario& scenario);

}  // namespace coopnav::world_sim
