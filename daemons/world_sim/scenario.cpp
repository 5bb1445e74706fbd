#include "scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "config/config.hpp"
#include "config/file_read.hpp"

namespace coopnav::world_sim {

Scenario parseScenario(const std::string& yaml_text, const std::string& source,
                       const std::string& base_dir) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(source + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                        ": " + e.msg);
  }
  if (!root || !root.IsMap()) throw ScenarioError(source + ": a scenario must be a YAML mapping");

  Scenario sc;
  sc.source = source;
  ConfigReader r(root, source);
  sc.visit(r);
  MapSpec& map = sc.map;
  if (!map.file.empty() && map.walls.empty() && map.boxes.empty()) {
    std::filesystem::path p(map.file);
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    map.file = p.lexically_normal().string();
    // Not the throwing overload: a name the system refuses (ENAMETOOLONG) is a missing file.
    // The map loader reads the file itself through readFileCapped (a regular file under a cap).
    std::error_code ec;
    const auto status = std::filesystem::status(p, ec);
    if (!std::filesystem::exists(status)) {
      r.require(
          false, "map.file",
          "= '" + map.file + "' does not exist" + (ec ? " (" + ec.message() + ")" : std::string()));
    } else if (!std::filesystem::is_regular_file(status)) {
      r.require(false, "map.file", "= '" + map.file + "' is not a regular file");
    }
  }
  r.rejectUnknownKeys();
  if (!r.errors().empty()) {
    std::string all;
    for (const auto& e : r.errors()) all += e + "\n";
    all.pop_back();
    throw ScenarioError(all);
  }
  return sc;
}

Scenario loadScenario(const std::string& path) {
  std::string text;
  try {
    text = readFileCapped(path, kMaxYamlFileBytes, "scenario file");
  } catch (const FileReadError& e) {
    throw ScenarioError(e.what());
  }
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parseScenario(text, path, dir.empty() ? "." : dir);
}

void checkScenarioAgainstMap(const Scenario& sc, const DistanceMap& map) {
  std::vector<std::string> errors;
  auto check = [&](const std::string& key, const Eigen::Vector2d& p, double radius_m) {
    const DistanceResult r = map.nearest(p);
    std::ostringstream s;
    s << sc.source << ": key '" << key << "' = (" << p.x() << ", " << p.y() << ") ";
    if (r.status == DistanceStatus::kOk && r.distance_m >= radius_m) return;
    if (r.status == DistanceStatus::kOk) {
      s << "is " << r.distance_m << " m from a wall, closer than the agent's radius " << radius_m
        << " m";
    } else if (r.status == DistanceStatus::kNotFound) {
      return;  // no obstacle in range: free
    } else {
      s << "is not in free space (" << toString(r.status) << ")";
    }
    errors.push_back(s.str());
  };
  check("robot.start", sc.robot.start.position(), sc.robot.radius_m);
  check("robot.goal", sc.robot.goal.position(), sc.robot.radius_m);
  for (std::size_t i = 0; i < sc.humans.size(); ++i) {
    const auto& h = sc.humans[i];
    const std::string k = "humans[" + std::to_string(i) + "].";
    check(k + "start", h.start.position(), h.radius_m);
    check(k + "goal", h.goal.position(), h.radius_m);
    for (std::size_t j = 0; j < h.via.size(); ++j)
      check(k + "via[" + std::to_string(j) + "]", h.via[j], h.radius_m);
  }
  if (!errors.empty()) {
    std::string all;
    for (const auto& e : errors) all += e + "\n";
    all.pop_back();
    throw ScenarioError(all);
  }
}

LoadedMap loadScenarioMap(const Scenario& sc, std::int64_t max_cells) {
  // The loader reads YAML; rebuilding the validated section keeps one walls rasteriser for the
  // distance server and the simulator, so both see the same cells.
  YAML::Node node(YAML::NodeType::Map);
  if (!sc.map.file.empty()) {
    node["file"] = sc.map.file;
  } else {
    node["resolution_m"] = sc.map.resolution_m;
    for (const WallSegment& w : sc.map.walls) {
      YAML::Node n;
      n["x0_m"] = w.x0_m;
      n["y0_m"] = w.y0_m;
      n["x1_m"] = w.x1_m;
      n["y1_m"] = w.y1_m;
      n["thickness_m"] = w.thickness_m;
      node["walls"].push_back(n);
    }
    for (const BoxObstacle& b : sc.map.boxes) {
      YAML::Node n;
      n["min_x_m"] = b.min_x_m;
      n["min_y_m"] = b.min_y_m;
      n["max_x_m"] = b.max_x_m;
      n["max_y_m"] = b.max_y_m;
      node["boxes"].push_back(n);
    }
  }
  MapLoadOptions options;
  options.max_cells = max_cells;
  options.build_tree = false;  // the simulator needs the grid only
  return loadMapFromNode(node, ".", options, sc.source + ": map");
}

sim::WorldSpec toWorldSpec(const Scenario& sc) {
  sim::WorldSpec w;
  w.seed = sc.seed;
  w.settings.physics_dt_s = 1.0 / sc.rates.physics_hz;
  w.settings.substeps_per_step =
      static_cast<int>(std::lround(sc.rates.physics_hz / sc.rates.publish_hz));
  w.settings.time_limit_s = sc.time_limit_s;
  w.settings.standstill_time_s = sc.standstill_time_s;
  w.settings.standstill_distance_m = sc.standstill_distance_m;
  w.robot = sc.robot;
  w.humans = sc.humans;
  return w;
}

}  // namespace coopnav::world_sim
