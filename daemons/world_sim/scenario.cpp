#include "scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/config.hpp"
#include "config/file_read.hpp"

namespace coopnav::world_sim {

namespace {

/// Largest track file read [bytes]: the whole pedestrians JSON (0.6 MB) with room to spare.
constexpr std::size_t kMaxTrackFileBytes = std::size_t{64} << 20;

/// Walker `walker` of pair `pair` of a "headon_pairs/2" file.
std::vector<sim::TrackSample> pedestrianWalker(const std::string& text, const std::string& file,
                                               int pair, const std::string& walker) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw sim::TrackError(file + ": not JSON: " + e.what());
  }
  const std::string schema =
      root.is_object() && root.contains("schema") && root["schema"].is_string()
          ? root["schema"].get<std::string>()
          : std::string();
  if (schema != "headon_pairs/2")
    throw sim::TrackError(file + ": schema '" + schema +
                          "' is not 'headon_pairs/2' (test/data/pedestrians/README.md)");
  const auto& pairs = root["pairs"];
  if (!pairs.is_array() || pair < 0 || static_cast<std::size_t>(pair) >= pairs.size())
    throw sim::TrackError(file + ": pair " + std::to_string(pair) + " is not in its 'pairs' (" +
                          std::to_string(pairs.is_array() ? pairs.size() : 0) + " pairs)");
  const std::string where = file + ": pairs[" + std::to_string(pair) + "].traj_" + walker;
  const auto& pr = pairs[static_cast<std::size_t>(pair)];
  if (!pr.is_object() || !pr.contains("traj_" + walker) || !pr["traj_" + walker].is_object())
    throw sim::TrackError(where + " is missing");
  const auto& traj = pr["traj_" + walker];
  auto numbers = [&](const char* key) {
    std::vector<double> out;
    if (!traj.contains(key) || !traj[key].is_array())
      throw sim::TrackError(where + "." + key + " is missing or not a list");
    for (const auto& x : traj[key]) {
      if (!x.is_number())
        throw sim::TrackError(where + "." + key + " has an entry that is no number");
      out.push_back(x.get<double>());
    }
    return out;
  };
  const std::vector<double> t = numbers("t"), x = numbers("x"), y = numbers("y");
  if (t.size() != x.size() || t.size() != y.size())
    throw sim::TrackError(where + ": t, x and y differ in length");
  std::vector<sim::TrackSample> track;
  for (std::size_t i = 0; i < t.size(); ++i) track.push_back({t[i], x[i], y[i]});
  sim::checkTrack(track, where);
  return track;
}

bool endsWithJson(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".json";
}

/// Resolves each recorded human's file, loads its track and sets its start and goal from it.
void loadRecordedTracks(Scenario& sc, const std::string& base_dir, ConfigReader& r) {
  for (std::size_t i = 0; i < sc.humans.size() && i < sc.recorded_sources.size(); ++i) {
    sim::HumanSpec& h = sc.humans[i];
    RecordedSource& src = sc.recorded_sources[i];
    if (h.behaviour.type != sim::BehaviourType::kRecorded || src.file.empty()) continue;
    const std::string key = "humans[" + std::to_string(i) + "].params.";
    std::filesystem::path p(src.file);
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    src.file = p.lexically_normal().string();
    const bool json = endsWithJson(src.file);
    if (json) {
      if (src.pair < 0) r.require(false, key + "pair", "is missing (required for a .json track)");
      if (src.walker != "a" && src.walker != "b")
        r.require(false, key + "walker",
                  src.walker.empty() ? "is missing (required for a .json track: a or b)"
                                     : notOneOfMessage(src.walker, {"a", "b"}));
      if (src.pair < 0 || (src.walker != "a" && src.walker != "b")) continue;
    } else if (src.pair >= 0 || !src.walker.empty()) {
      r.require(false, key + (src.pair >= 0 ? "pair" : "walker"),
                "is for a .json track only; '" + src.file + "' is read as CSV (t x y)");
      continue;
    }
    try {
      h.behaviour.recorded.track = loadTrack(src);
    } catch (const sim::TrackError& e) {
      r.require(false, key + "file", std::string("could not be used: ") + e.what());
      continue;
    }
    h.start = sim::recordedStart(h.behaviour.recorded);
    h.goal = sim::recordedGoal(h.behaviour.recorded);
  }
}

}  // namespace

std::vector<sim::TrackSample> loadTrack(const RecordedSource& source) {
  std::string text;
  try {
    text = readFileCapped(source.file, kMaxTrackFileBytes, "track file");
  } catch (const FileReadError& e) {
    throw sim::TrackError(e.what());
  }
  if (endsWithJson(source.file))
    return pedestrianWalker(text, source.file, source.pair, source.walker);
  return sim::parseTrackCsv(text, source.file);
}

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
  loadRecordedTracks(sc, base_dir, r);
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
  sim::parseAvoidanceTiming(sc.avoidance_timing, w.avoidance_timing);  // validated on load
  return w;
}

}  // namespace coopnav::world_sim

namespace coopnav::world_sim {

namespace {
/// Distance from p to the axis-aligned box (0 inside).
double boxDistance(const BoxObstacle& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d c(std::clamp(p.x(), b.min_x_m, b.max_x_m),
                          std::clamp(p.y(), b.min_y_m, b.max_y_m));
  return (p - c).norm();
}
}  // namespace

void addUnmappedObstacles(const UnmappedObstaclesSpec& obstacles, OccupancyGrid2& grid) {
  if (obstacles.empty() || grid.empty()) return;
  const double res = grid.resolution_m();
  const double half = 0.5 * res;
  // A cell is occupied when the shape overlaps it: the distance from its centre to the shape is
  // within the cell (a box: per axis; a circle: from the nearest point of the cell).
  for (int j = 0; j < grid.height(); ++j) {
    for (int i = 0; i < grid.width(); ++i) {
      const Eigen::Vector2d c = grid.cellCenter_m(i, j);
      bool hit = false;
      for (const BoxObstacle& b : obstacles.boxes)
        hit = hit || (c.x() + half > b.min_x_m && c.x() - half < b.max_x_m &&
                      c.y() + half > b.min_y_m && c.y() - half < b.max_y_m);
      for (const CircleObstacle& k : obstacles.circles) {
        const Eigen::Vector2d o(k.x_m, k.y_m);
        const Eigen::Vector2d q(std::clamp(o.x(), c.x() - half, c.x() + half),
                                std::clamp(o.y(), c.y() - half, c.y() + half));
        hit = hit || (q - o).norm() < k.radius_m;
      }
      if (hit) grid.set(i, j, CellState::kOccupied);
    }
  }
}

double unmappedClearance(const UnmappedObstaclesSpec& obstacles, const Eigen::Vector2d& centre,
                         double radius_m) {
  double m = std::numeric_limits<double>::infinity();
  for (const BoxObstacle& b : obstacles.boxes) m = std::min(m, boxDistance(b, centre) - radius_m);
  for (const CircleObstacle& k : obstacles.circles)
    m = std::min(m, (centre - Eigen::Vector2d(k.x_m, k.y_m)).norm() - k.radius_m - radius_m);
  return m;
}

}  // namespace coopnav::world_sim
