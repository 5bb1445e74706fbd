#include "scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/config.hpp"

namespace coopnav::world_sim {

namespace {

std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// Reads one YAML mapping, collecting errors into a shared list; remembers the keys it read so
/// that unknown keys can be reported. Also the visitor of the lib/sim parameter structs.
class Reader {
 public:
  Reader(YAML::Node node, std::string prefix, std::vector<std::string>& errors,
         const std::string& source)
      : node_(std::move(node)), prefix_(std::move(prefix)), errors_(errors), source_(source) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) error("", "must be a mapping");
  }
  ~Reader() { rejectUnknownKeys(); }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  void error(const std::string& key, const std::string& msg) {
    const std::string k = prefix_ + key;
    errors_.push_back(source_ + ": " + (k.empty() ? "" : "key '" + k + "' ") + msg);
  }
  std::string full(const std::string& key) const { return prefix_ + key; }

  /// The value node or an invalid node; records the key as known.
  YAML::Node get(const std::string& key, bool required) {
    seen_.insert(key);
    if (!node_ || !node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node v = node_[key];
    if (!v || v.IsNull()) {
      if (required) error(key, "is missing (required)");
      return YAML::Node(YAML::NodeType::Undefined);
    }
    return v;
  }

  template <class T>
  bool scalar(const std::string& key, const YAML::Node& v, T& out, const char* type_name) {
    if (!v.IsScalar()) {
      error(key, "must be " + std::string(type_name));
      return false;
    }
    try {
      out = v.as<T>();
      return true;
    } catch (const YAML::Exception&) {
      error(key, "= '" + v.Scalar() + "' has the wrong type: expected " + type_name + " (line " +
                     std::to_string(v.Mark().line + 1) + ")");
      return false;
    }
  }

  // ---- visitor protocol of lib/sim parameter structs (optional keys, in-class defaults)
  void number(const char* key, double& field, double lo, double hi, bool required = false) {
    const YAML::Node v = get(key, required);
    if (!v) return;
    double x = 0.0;
    if (!scalar(key, v, x, "a number")) return;
    if (!std::isfinite(x) || x < lo || x > hi) {
      error(key,
            "= " + v.Scalar() + " is outside the allowed range [" + fmt(lo) + ", " + fmt(hi) + "]");
      return;
    }
    field = x;
  }
  void choice(const char* key, std::string& field, const std::vector<std::string>& allowed,
              bool required = false) {
    const YAML::Node v = get(key, required);
    if (!v) return;
    std::string s;
    if (!scalar(key, v, s, "a string")) return;
    for (const auto& a : allowed)
      if (a == s) {
        field = s;
        return;
      }
    error(key, notOneOfMessage(s, allowed));
  }
  template <class S>
  void nested(const char* key, S& sub) {
    const YAML::Node v = get(key, false);
    if (!v) return;
    Reader r(v, full(key) + ".", errors_, source_);
    sub.visit(r);
  }

  void flag(const char* key, bool& field) {
    const YAML::Node v = get(key, false);
    if (v) scalar(key, v, field, "true or false");
  }
  void text(const char* key, std::string& field, bool required) {
    const YAML::Node v = get(key, required);
    if (v) scalar(key, v, field, "a string");
  }
  /// {x_m, y_m, theta_rad}; theta_rad optional.
  void pose(const char* key, Pose2& out, bool required) {
    const YAML::Node v = get(key, required);
    if (!v) return;
    Reader r(v, full(key) + ".", errors_, source_);
    constexpr double kBig = 1e6;
    r.number("x_m", out.x_m, -kBig, kBig, true);
    r.number("y_m", out.y_m, -kBig, kBig, true);
    r.number("theta_rad", out.theta_rad, -2.0 * M_PI, 2.0 * M_PI);
  }

  const YAML::Node& node() const { return node_; }

 private:
  // Called from the destructor: nothing in it may throw but allocation.
  void rejectUnknownKeys() {
    reportUnknownKeys(node_, seen_,
                      [this](const std::string& key, const std::string& msg) { error(key, msg); });
  }

  YAML::Node node_;
  std::string prefix_;
  std::vector<std::string>& errors_;
  const std::string& source_;
  std::set<std::string> seen_;
};

/// Calls fn(Reader&, index) for each mapping of a list key.
template <class Fn>
void forEachItem(Reader& parent, const char* key, bool required, std::vector<std::string>& errors,
                 const std::string& source, Fn fn) {
  const YAML::Node v = parent.get(key, required);
  if (!v) return;
  if (!v.IsSequence()) {
    parent.error(key, "must be a list");
    return;
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    Reader r(v[i], parent.full(key) + "[" + std::to_string(i) + "].", errors, source);
    fn(r, i);
  }
}

void readMap(Reader& root, MapSpec& map, const std::string& base_dir,
             std::vector<std::string>& errors, const std::string& source) {
  const YAML::Node m = root.get("map", true);
  if (!m) return;
  Reader r(m, "map.", errors, source);
  r.text("file", map.file, false);
  constexpr double kBig = 1e6;
  forEachItem(r, "walls", false, errors, source, [&](Reader& w, std::size_t) {
    WallSegment s;
    w.number("x0_m", s.x0_m, -kBig, kBig, true);
    w.number("y0_m", s.y0_m, -kBig, kBig, true);
    w.number("x1_m", s.x1_m, -kBig, kBig, true);
    w.number("y1_m", s.y1_m, -kBig, kBig, true);
    w.number("thickness_m", s.thickness_m, 0.01, 10.0);
    map.walls.push_back(s);
  });
  forEachItem(r, "boxes", false, errors, source, [&](Reader& b, std::size_t) {
    BoxObstacle o;
    b.number("min_x_m", o.min_x_m, -kBig, kBig, true);
    b.number("min_y_m", o.min_y_m, -kBig, kBig, true);
    b.number("max_x_m", o.max_x_m, -kBig, kBig, true);
    b.number("max_y_m", o.max_y_m, -kBig, kBig, true);
    if (o.max_x_m <= o.min_x_m || o.max_y_m <= o.min_y_m)
      b.error("", "must have max_x_m > min_x_m and max_y_m > min_y_m");
    map.boxes.push_back(o);
  });
  r.number("resolution_m", map.resolution_m, 0.01, 1.0);
  const bool synthetic = !map.walls.empty() || !map.boxes.empty();
  if (map.file.empty() == !synthetic) {
    r.error("", "needs exactly one of 'file' or 'walls'/'boxes'");
  } else if (!map.file.empty()) {
    std::filesystem::path p(map.file);
    if (p.is_relative()) p = std::filesystem::path(base_dir) / p;
    map.file = p.lexically_normal().string();
    // Not the throwing overload: a name the system refuses (ENAMETOOLONG) is a missing file.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      r.error("file", "= '" + map.file + "' does not exist" +
                          (ec ? " (" + ec.message() + ")" : std::string()));
  }
}

void readRobot(Reader& root, sim::RobotSpec& robot, std::vector<std::string>& errors,
               const std::string& source) {
  const YAML::Node v = root.get("robot", true);
  if (!v) return;
  Reader r(v, "robot.", errors, source);
  r.pose("start", robot.start, true);
  r.pose("goal", robot.goal, true);
  r.number("radius_m", robot.radius_m, 0.05, 2.0);
  std::string kin = robot.kinematics == sim::Kinematics::kHolonomic ? "holonomic" : "differential";
  r.choice("kinematics", kin, {"differential", "holonomic"});
  robot.kinematics =
      kin == "holonomic" ? sim::Kinematics::kHolonomic : sim::Kinematics::kDifferential;
  r.nested("limits", robot.limits);
  r.number("goal_tolerance_m", robot.goal_tolerance_m, 0.01, 5.0);
}

void readBehaviourParams(Reader& h, sim::BehaviourConfig& b) {
  using sim::BehaviourType;
  switch (b.type) {
    case BehaviourType::kMinimal:
      h.nested("params", b.minimal);
      break;
    case BehaviourType::kOblivious:
      h.nested("params", b.oblivious);
      break;
    case BehaviourType::kSocialForce:
      h.nested("params", b.social_force);
      break;
    case BehaviourType::kLateFacilitating:
      h.nested("params", b.late_facilitating);
      break;
    case BehaviourType::kResponsive:
      h.nested("params", b.responsive);
      break;
    case BehaviourType::kFacilitating:
      h.nested("params", b.facilitating);
      break;
  }
}

void readHumans(Reader& root, std::vector<sim::HumanSpec>& humans, std::vector<std::string>& errors,
                const std::string& source) {
  std::map<std::int32_t, std::size_t> first_index;
  forEachItem(root, "humans", false, errors, source, [&](Reader& h, std::size_t i) {
    sim::HumanSpec s;
    double id = 0.0;
    h.number("id", id, 1.0, 2147483647.0, true);
    if (id != std::floor(id)) h.error("id", "= " + fmt(id) + " must be an integer >= 1");
    s.id = static_cast<std::int32_t>(id);
    if (id >= 1.0) {
      auto [it, fresh] = first_index.emplace(s.id, i);
      if (!fresh)
        h.error("id", "= " + fmt(id) + " duplicates humans[" + std::to_string(it->second) + "].id");
    }
    h.pose("start", s.start, true);
    h.pose("goal", s.goal, true);
    forEachItem(h, "via", false, errors, source, [&](Reader& w, std::size_t) {
      Pose2 p;
      w.number("x_m", p.x_m, -1e6, 1e6, true);
      w.number("y_m", p.y_m, -1e6, 1e6, true);
      s.via.push_back(p.position());
    });
    std::string behaviour;
    const auto names = sim::behaviourTypeNames();
    h.choice("behaviour", behaviour, names, true);
    const bool known = sim::parseBehaviourType(behaviour, s.behaviour.type);
    h.number("speed_m_s", s.speed_m_s, 0.0, 3.0);
    h.number("speed_stddev_m_s", s.speed_stddev_m_s, 0.0, 1.0);
    h.number("velocity_noise_m_s", s.velocity_noise_m_s, 0.0, 1.0);
    h.number("radius_m", s.radius_m, 0.05, 1.0);
    h.number("max_acc_m_s2", s.max_acc_m_s2, 0.1, 10.0);
    h.number("goal_tolerance_m", s.goal_tolerance_m, 0.01, 5.0);
    if (known) {
      readBehaviourParams(h, s.behaviour);
    } else {
      h.get("params", false);  // reported through 'behaviour'; do not also call it unknown
    }
    humans.push_back(s);
  });
}

}  // namespace

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
  std::vector<std::string> errors;
  {
    Reader r(root, "", errors, source);
    r.text("name", sc.name, true);
    double seed = 0.0;
    // Seeds up to 2^53 so that every value is exact in YAML's double reading.
    r.number("seed", seed, 0.0, 9007199254740992.0, true);
    if (seed != std::floor(seed)) r.error("seed", "= " + fmt(seed) + " must be an integer >= 0");
    sc.seed = static_cast<std::uint64_t>(seed);
    r.number("time_limit_s", sc.time_limit_s, 0.1, 86400.0, true);
    readMap(r, sc.map, base_dir, errors, source);
    if (const YAML::Node v = r.get("rates", false)) {
      Reader rr(v, "rates.", errors, source);
      rr.number("physics_hz", sc.rates.physics_hz, 20.0, 2000.0);
      rr.number("publish_hz", sc.rates.publish_hz, 0.1, 1000.0);
      rr.number("real_time_factor", sc.rates.real_time_factor, 0.01, 1000.0);
      const double ratio = sc.rates.physics_hz / sc.rates.publish_hz;
      if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-9)
        rr.error("physics_hz",
                 "= " + fmt(sc.rates.physics_hz) +
                     " must be an integer multiple of publish_hz = " + fmt(sc.rates.publish_hz));
    }
    if (const YAML::Node v = r.get("lockstep", false)) {
      Reader rl(v, "lockstep.", errors, source);
      rl.flag("enabled", sc.lockstep.enabled);
      if (const YAML::Node p = rl.get("participants", false)) {
        if (!p.IsSequence()) {
          rl.error("participants", "must be a list of daemon names");
        } else {
          for (std::size_t i = 0; i < p.size(); ++i) {
            if (p[i].IsScalar() && !p[i].Scalar().empty()) {
              sc.lockstep.participants.push_back(p[i].Scalar());
            } else {
              rl.error("participants[" + std::to_string(i) + "]", "must be a daemon name");
            }
          }
        }
      }
      rl.number("step_timeout_s", sc.lockstep.step_timeout_s, 0.01, 3600.0);
    }
    readRobot(r, sc.robot, errors, source);
    readHumans(r, sc.humans, errors, source);
  }
  if (!errors.empty()) {
    std::string all;
    for (const auto& e : errors) all += e + "\n";
    all.pop_back();
    throw ScenarioError(all);
  }
  return sc;
}

Scenario loadScenario(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ScenarioError(path + ": is a directory, not a scenario file");
  std::ifstream in(path);
  if (!in) throw ScenarioError(path + ": cannot open the scenario file");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parseScenario(ss.str(), path, dir.empty() ? "." : dir);
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
  w.robot = sc.robot;
  w.humans = sc.humans;
  return w;
}

}  // namespace coopnav::world_sim
