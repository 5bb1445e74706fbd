// Scenario files load to the values they are meant to (the scenario loader reads through the
// daemons' ConfigReader). Every scenario of config/scenarios/ and test/data/scenarios/ is loaded
// and printed, every value to 17 significant digits (or the loader's error message), and compared
// with test/data/golden/scenarios_loaded.txt. In the world_sim_node library, hence a node-tier test
// although it opens no LCM (as world_sim_scenario_test). A scenario file added to either folder
// needs its entry there: the failure prints it. Change an entry only when a change of what a
// scenario loads to is intended.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "scenario.hpp"
#include "test_paths.hpp"

namespace coopnav::world_sim {
namespace {

// Every value of a loaded Scenario as text, one "key = value" line each (doubles to 17
// significant digits: two texts are equal only when the values are bit-identical).

std::string num(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// Prints lines "prefix key = value"; also the visitor of the lib/sim parameter structs.
class Printer {
 public:
  Printer(std::ostringstream& out, std::string prefix) : out_(out), prefix_(std::move(prefix)) {}
  void line(const std::string& key, const std::string& value) {
    out_ << prefix_ << key << " = " << value << "\n";
  }
  void number(const char* key, double& field, double, double) { line(key, num(field)); }
  void choice(const char* key, std::string& field, const std::vector<std::string>&) {
    line(key, "'" + field + "'");
  }
  template <class S>
  void nested(const char* key, S& sub) {
    Printer p(out_, prefix_ + key + ".");
    sub.visit(p);
  }
  void pose(const std::string& key, const Pose2& p) {
    line(key, "(" + num(p.x_m) + ", " + num(p.y_m) + ", " + num(p.theta_rad) + ")");
  }

 private:
  std::ostringstream& out_;
  std::string prefix_;
};

/// The scenario's values; `source_dir` (when not empty) is replaced by "<dir>" in paths.
std::string print(Scenario sc, const std::string& source_dir = "") {
  auto rel = [&](std::string s) {
    if (!source_dir.empty()) {
      for (auto pos = s.find(source_dir); pos != std::string::npos; pos = s.find(source_dir))
        s.replace(pos, source_dir.size(), "<dir>");
    }
    return s;
  };
  std::ostringstream out;
  Printer p(out, "");
  p.line("name", "'" + sc.name + "'");
  p.line("seed", std::to_string(sc.seed));
  p.line("time_limit_s", num(sc.time_limit_s));
  p.line("source", "'" + rel(sc.source) + "'");
  p.line("map.file", "'" + rel(sc.map.file) + "'");
  for (std::size_t i = 0; i < sc.map.walls.size(); ++i) {
    const WallSegment& w = sc.map.walls[i];
    p.line("map.walls[" + std::to_string(i) + "]", num(w.x0_m) + " " + num(w.y0_m) + " " +
                                                       num(w.x1_m) + " " + num(w.y1_m) + " " +
                                                       num(w.thickness_m));
  }
  for (std::size_t i = 0; i < sc.map.boxes.size(); ++i) {
    const BoxObstacle& b = sc.map.boxes[i];
    p.line("map.boxes[" + std::to_string(i) + "]",
           num(b.min_x_m) + " " + num(b.min_y_m) + " " + num(b.max_x_m) + " " + num(b.max_y_m));
  }
  p.line("map.resolution_m", num(sc.map.resolution_m));
  p.line("rates.physics_hz", num(sc.rates.physics_hz));
  p.line("rates.publish_hz", num(sc.rates.publish_hz));
  p.line("rates.real_time_factor", num(sc.rates.real_time_factor));
  p.line("lockstep.enabled", sc.lockstep.enabled ? "true" : "false");
  std::string parts;
  for (const auto& s : sc.lockstep.participants) parts += (parts.empty() ? "" : ", ") + s;
  p.line("lockstep.participants", "[" + parts + "]");
  p.line("lockstep.step_timeout_s", num(sc.lockstep.step_timeout_s));
  // The tracker and goal keys: printed only when not at their defaults, so that the entries of
  // the scenarios that do not set them stay short.
  if (!sc.publish_human_goals) p.line("publish_human_goals", "false");
  const sim::TrackerParams& tr = sc.tracker;
  const sim::TrackerParams tr0;
  if (tr.position_sigma_m != tr0.position_sigma_m ||
      tr.velocity_window_steps != tr0.velocity_window_steps ||
      tr.miss_probability != tr0.miss_probability || tr.drop_after_s != tr0.drop_after_s ||
      tr.id_switches != tr0.id_switches || tr.id_switch_window_s != tr0.id_switch_window_s ||
      tr.range_m != tr0.range_m) {
    p.line("tracker", num(tr.position_sigma_m) + " " + std::to_string(tr.velocity_window_steps) +
                          " " + num(tr.miss_probability) + " " + num(tr.drop_after_s) + " " +
                          std::to_string(tr.id_switches) + " " + num(tr.id_switch_window_s) + " " +
                          num(tr.range_m));
  }
  // Unmapped obstacles and the laser (issue 45): printed only when a scenario has them.
  for (std::size_t i = 0; i < sc.unmapped_obstacles.boxes.size(); ++i) {
    const BoxObstacle& b = sc.unmapped_obstacles.boxes[i];
    p.line("unmapped_obstacles.boxes[" + std::to_string(i) + "]",
           num(b.min_x_m) + " " + num(b.min_y_m) + " " + num(b.max_x_m) + " " + num(b.max_y_m));
  }
  for (std::size_t i = 0; i < sc.unmapped_obstacles.circles.size(); ++i) {
    const CircleObstacle& c = sc.unmapped_obstacles.circles[i];
    p.line("unmapped_obstacles.circles[" + std::to_string(i) + "]",
           num(c.x_m) + " " + num(c.y_m) + " " + num(c.radius_m));
  }
  if (sc.laser.enabled) {
    const LaserSpec& l = sc.laser;
    p.line("laser", num(l.range_min_m) + " " + num(l.range_max_m) + " " + num(l.fov_deg) + " " +
                        num(l.resolution_deg) + " " + num(l.noise_sigma_m) + " " +
                        num(l.mount_x_m) + " " + num(l.mount_y_m));
  }
  p.pose("robot.start", sc.robot.start);
  p.pose("robot.goal", sc.robot.goal);
  p.line("robot.radius_m", num(sc.robot.radius_m));
  p.line("robot.kinematics",
         sc.robot.kinematics == sim::Kinematics::kHolonomic ? "holonomic" : "differential");
  p.nested("robot.limits", sc.robot.limits);
  p.line("robot.goal_tolerance_m", num(sc.robot.goal_tolerance_m));
  for (std::size_t i = 0; i < sc.humans.size(); ++i) {
    sim::HumanSpec& h = sc.humans[i];
    Printer hp(out, "humans[" + std::to_string(i) + "].");
    hp.line("id", std::to_string(h.id));
    hp.pose("start", h.start);
    hp.pose("goal", h.goal);
    for (std::size_t j = 0; j < h.via.size(); ++j)
      hp.line("via[" + std::to_string(j) + "]", num(h.via[j].x()) + " " + num(h.via[j].y()));
    hp.line("behaviour", sim::toString(h.behaviour.type));
    hp.line("speed_m_s", num(h.speed_m_s));
    hp.line("speed_stddev_m_s", num(h.speed_stddev_m_s));
    hp.line("velocity_noise_m_s", num(h.velocity_noise_m_s));
    hp.line("radius_m", num(h.radius_m));
    hp.line("max_acc_m_s2", num(h.max_acc_m_s2));
    hp.line("goal_tolerance_m", num(h.goal_tolerance_m));
    // Every behaviour's parameters, also those of the behaviours not chosen (all defaults).
    hp.nested("minimal", h.behaviour.minimal);
    hp.nested("oblivious", h.behaviour.oblivious);
    hp.nested("social_force", h.behaviour.social_force);
    hp.nested("late_facilitating", h.behaviour.late_facilitating);
    hp.nested("responsive", h.behaviour.responsive);
    hp.nested("facilitating", h.behaviour.facilitating);
    if (h.behaviour.pause.duration_s > 0.0) hp.nested("pause", h.behaviour.pause);
    if (h.behaviour.type == sim::BehaviourType::kRecorded) {
      const sim::RecordedParams& r = h.behaviour.recorded;
      const RecordedSource& src = sc.recorded_sources[i];
      hp.line("recorded.file", "'" + rel(src.file) + "'");
      hp.line("recorded.pair", std::to_string(src.pair));
      hp.line("recorded.walker", "'" + src.walker + "'");
      hp.line("recorded.time_offset_s", num(r.time_offset_s));
      hp.pose("recorded.transform", r.transform);
      hp.line("recorded.samples", std::to_string(r.track.size()));
      if (!r.track.empty()) {
        hp.line("recorded.first", num(r.track.front().t_s) + " " + num(r.track.front().x_m) + " " +
                                      num(r.track.front().y_m));
        hp.line("recorded.last", num(r.track.back().t_s) + " " + num(r.track.back().x_m) + " " +
                                     num(r.track.back().y_m));
      }
    }
  }
  return out.str();
}

/// print() of the scenario file at `path`, or "ERROR\n" and the loader's message.
std::string printFile(const std::string& path, const std::string& source_dir = "") {
  try {
    return print(loadScenario(path), source_dir);
  } catch (const ScenarioError& e) {
    std::string msg = e.what();
    if (!source_dir.empty()) {
      for (auto pos = msg.find(source_dir); pos != std::string::npos; pos = msg.find(source_dir))
        msg.replace(pos, source_dir.size(), "<dir>");
    }
    return "ERROR\n" + msg + "\n";
  }
}

/// "=== <path>" -> the lines after it, from the golden file.
std::map<std::string, std::string> goldenEntries(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, std::string> out;
  std::string line, current;
  while (std::getline(in, line)) {
    if (line.rfind("=== ", 0) == 0) {
      current = line.substr(4);
      out[current];
    } else if (!current.empty()) {
      out[current] += line + "\n";
    }
  }
  return out;
}

TEST(ScenarioGolden, EveryScenarioLoadsToTheValuesItLoadedToBefore) {
  namespace fs = std::filesystem;
  const std::string root = ::coopnav::test::sourceDir();
  const auto golden = goldenEntries(root + "/test/data/golden/scenarios_loaded.txt");
  ASSERT_FALSE(golden.empty()) << "test/data/golden/scenarios_loaded.txt is missing or empty";
  std::vector<std::string> files;
  for (const char* dir : {"config/scenarios", "test/data/scenarios"})
    for (const auto& e : fs::directory_iterator(root + "/" + dir))
      if (e.path().extension() == ".yaml")
        files.push_back(std::string(dir) + "/" + e.path().filename().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 8u);
  for (const auto& rel : files) {
    SCOPED_TRACE(rel);
    const std::string now = printFile(root + "/" + rel, root);
    const auto it = golden.find(rel);
    if (it == golden.end()) {
      ADD_FAILURE() << "no golden entry; if this is what it should load to, add\n=== " << rel
                    << "\n"
                    << now;
      continue;
    }
    if (now == it->second) continue;
    // The first differing line, then the whole entry.
    std::istringstream a(it->second), b(now);
    std::string la, lb;
    while (std::getline(a, la) && std::getline(b, lb) && la == lb) {
    }
    ADD_FAILURE() << "loads differently: before '" << la << "', now '" << lb << "'\nnow:\n" << now;
  }
}

}  // namespace
}  // namespace coopnav::world_sim
