#include "trace.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <map>

#include "coopnav/assessment/path_assessment.hpp"
#include "maps/map_loader.hpp"
#include "summary.hpp"
#include "wire/conversions.hpp"

namespace coopnav::ctl {
namespace {

Json tristate(std::int8_t pred) {
  if (pred == situation_t::PRED_TRUE) return true;
  if (pred == situation_t::PRED_FALSE) return false;
  return nullptr;
}

Json states(const std::vector<double>& t, const std::vector<double>& x,
            const std::vector<double>& y, const std::vector<double>& theta, double radius_m) {
  Json o = Json::object();
  Json jt = Json::array(), jx = Json::array(), jy = Json::array(), jth = Json::array();
  for (std::size_t i = 0; i < t.size(); ++i) {
    jt.push_back(numberOrNull(t[i]));
    jx.push_back(numberOrNull(x[i]));
    jy.push_back(numberOrNull(y[i]));
    jth.push_back(numberOrNull(theta[i]));
  }
  o["t_s"] = std::move(jt);
  o["x_m"] = std::move(jx);
  o["y_m"] = std::move(jy);
  o["theta_rad"] = std::move(jth);
  o["radius_m"] = numberOrNull(radius_m);
  return o;
}

struct Track {
  std::vector<double> t, x, y, theta;
  double radius_m{std::nan("")};
  void add(double t_s, const agent_state_t& a) {
    t.push_back(t_s);
    x.push_back(a.x_m);
    y.push_back(a.y_m);
    theta.push_back(a.theta_rad);
    radius_m = a.radius_m;
  }
};

// [s] Time of each sample of the last interaction's CA: sample k was taken at the utime of the
// first assessment whose interaction count reached k + 1 (the assessor publishes each sample).
// Samples no message announced (a lost message) are placed linearly between their neighbours.
std::vector<double> sampleTimes(const RunLog& run, std::int32_t human_id, std::size_t n) {
  std::map<std::int64_t, double> at;  // interaction_samples -> t [s]
  std::int64_t previous = -1;
  for (const auto& p : run.assessments) {
    if (p.human_id != human_id) continue;
    if (p.interaction_samples < previous) at.clear();  // a new interaction began
    previous = p.interaction_samples;
    if (p.interaction_samples > 0) at.emplace(p.interaction_samples, utimeToS(p.utime));
  }
  std::vector<double> t(n, std::nan(""));
  if (at.empty()) return t;
  for (std::size_t k = 0; k < n; ++k) {
    const auto key = static_cast<std::int64_t>(k) + 1;
    const auto hi = at.lower_bound(key);
    if (hi != at.end() && hi->first == key) {
      t[k] = hi->second;
    } else if (hi != at.end() && hi != at.begin()) {
      const auto lo = std::prev(hi);
      const double f =
          static_cast<double>(key - lo->first) / static_cast<double>(hi->first - lo->first);
      t[k] = lo->second + f * (hi->second - lo->second);
    }
  }
  return t;
}

Json humanAssessment(const RunLog& run, const HumanAnalysis& h) {
  Json o = Json::object();
  o["id"] = h.id;
  Json t = Json::array(), cm = Json::array(), cmi = Json::array(), contributing = Json::array(),
       tau = Json::array(), p = Json::array();
  for (const auto& a : run.assessments) {
    if (a.human_id != h.id) continue;
    t.push_back(numberOrNull(utimeToS(a.utime)));
    cm.push_back(numberOrNull(a.cm_m));
    cmi.push_back(numberOrNull(a.cm_interaction_m));
    contributing.push_back(tristate(a.is_contributing));
    tau.push_back(numberOrNull(a.tau_m));
    p.push_back(numberOrNull(a.p_contributing));
  }
  o["t_s"] = std::move(t);
  o["cm_m"] = std::move(cm);
  o["cm_interaction_m"] = std::move(cmi);
  o["is_contributing"] = std::move(contributing);
  o["tau_m"] = std::move(tau);
  o["p_contributing"] = std::move(p);
  if (h.last_assessment) {
    const auto& last = run.assessments[*h.last_assessment];
    o["gamma"] = numberOrNull(last.gamma);
    o["tau_fixed_m"] = numberOrNull(last.tau_fixed_m);
    o["profile"] = last.profile;
  } else {
    o["gamma"] = nullptr;
    o["tau_fixed_m"] = nullptr;
    o["profile"] = nullptr;
  }

  // CA: the whole interaction when it could be rebuilt, else the last window alone (its samples
  // are the newest of the interaction).
  std::vector<double> ca;
  std::size_t offset = 0;
  const bool interaction = h.interaction_ca_complete && !h.interaction_ca_m.empty();
  if (interaction) {
    ca = h.interaction_ca_m;
  } else if (h.last_assessment) {
    const auto& last = run.assessments[*h.last_assessment];
    ca = last.ca_m;
    offset = static_cast<std::size_t>(std::max<std::int64_t>(
        0, std::int64_t{last.interaction_samples} - static_cast<std::int64_t>(ca.size())));
  }
  const auto times = sampleTimes(run, h.id, offset + ca.size());
  Json ca_t = Json::array(), ca_m = Json::array(), starts = Json::array();
  for (std::size_t k = 0; k < ca.size(); ++k) {
    ca_t.push_back(numberOrNull(times[offset + k]));
    ca_m.push_back(numberOrNull(ca[k]));
  }
  if (interaction)
    for (const std::size_t s : h.window_starts)
      if (s < times.size()) starts.push_back(numberOrNull(times[s]));
  Json jca = Json::object();
  jca["whole_interaction"] = interaction;
  jca["t_s"] = std::move(ca_t);
  jca["ca_m"] = std::move(ca_m);
  jca["window_start_t_s"] = std::move(starts);
  o["ca"] = std::move(jca);

  // CM against γ over that CA, by the path assessor's own formula (paper §II-C).
  Json gammas = Json::array(), cms = Json::array();
  for (int k = 0; k <= 50; ++k) {
    const double gamma = 0.5 + 0.01 * k;
    gammas.push_back(numberOrNull(gamma));
    cms.push_back(numberOrNull(assessment::discountedMean(ca, gamma)));
  }
  o["cm_by_gamma"] = Json::object({{"gamma", std::move(gammas)}, {"cm_m", std::move(cms)}});

  if (h.first_round_situation) {
    const auto& s = run.situations[*h.first_round_situation];
    o["first_round"] = Json::object(
        {{"t_s", numberOrNull(utimeToS(s.utime))},
         {"t_cross_s", numberOrNull(s.t_cross_s)},
         {"cp_h_m", Json::array({numberOrNull(s.cp_h_x_m), numberOrNull(s.cp_h_y_m)})},
         {"cp_r_m", Json::array({numberOrNull(s.cp_r_x_m), numberOrNull(s.cp_r_y_m)})}});
  } else {
    o["first_round"] = nullptr;
  }
  return o;
}

Json segments(const YAML::Node& list, const char* const (&keys)[4]) {
  Json out = Json::array();
  if (!list || !list.IsSequence()) return out;
  for (const auto& item : list) {
    Json seg = Json::array();
    for (const char* k : keys) seg.push_back(numberOrNull(item[k].as<double>()));
    out.push_back(std::move(seg));
  }
  return out;
}

}  // namespace

Json traceMap(const std::string& map_path) {
  MapLoadOptions options;
  options.build_tree = false;
  const LoadedMap loaded = loadMap(map_path, options);
  const OccupancyGrid2& g = loaded.grid;
  Json o = Json::object();
  o["path"] = std::filesystem::absolute(map_path).lexically_normal().string();
  o["source"] = loaded.source;

  // What the scenario (or map file) says: the map file it names, or its own walls and boxes.
  const YAML::Node doc = YAML::LoadFile(map_path);
  const YAML::Node section = doc["map"] ? doc["map"] : doc;
  if (section["file"]) {
    const auto base = std::filesystem::path(map_path).parent_path();
    o["file"] = (base / section["file"].as<std::string>()).lexically_normal().string();
  } else {
    o["file"] = nullptr;
  }
  static const char* const kWallKeys[] = {"x0_m", "y0_m", "x1_m", "y1_m"};
  static const char* const kBoxKeys[] = {"min_x_m", "min_y_m", "max_x_m", "max_y_m"};
  o["walls"] = segments(section["walls"], kWallKeys);
  o["boxes"] = segments(section["boxes"], kBoxKeys);

  // The grid the daemons use: every cell that is not free (walls; unknown cells of a ROS map
  // count as walls, as for world_sim), as runs [row j, first column, end column) per row.
  o["resolution_m"] = numberOrNull(g.resolution_m());
  o["origin_m"] = Json::array({numberOrNull(g.origin_m().x()), numberOrNull(g.origin_m().y())});
  o["width"] = g.width();
  o["height"] = g.height();
  Json runs = Json::array();
  for (int j = 0; j < g.height(); ++j) {
    int i = 0;
    while (i < g.width()) {
      if (g.at(i, j) == CellState::kFree) {
        ++i;
        continue;
      }
      const int start = i;
      while (i < g.width() && g.at(i, j) != CellState::kFree) ++i;
      runs.push_back(Json::array({j, start, i}));
    }
  }
  o["obstacle_runs"] = std::move(runs);
  return o;
}

Json traceDocument(const RunLog& run, const RunAnalysis& analysis, const std::string& log_path,
                   const std::string& map_path) {
  Json doc = Json::object();
  doc["format"] = "coopnav-trace";
  doc["version"] = kTraceVersion;
  doc["scenario"] = analysis.scenario;
  doc["log"] = std::filesystem::path(log_path).filename().string();

  Track robot;
  std::map<std::int32_t, Track> humans;
  for (const auto& s : run.agent_states) {
    const double t = utimeToS(s.utime);
    robot.add(t, s.robot);
    for (const auto& h : s.humans) humans[h.id].add(t, h);
  }
  doc["robot"] = states(robot.t, robot.x, robot.y, robot.theta, robot.radius_m);
  Json jh = Json::array();
  for (const auto& [id, tr] : humans) {
    Json o = states(tr.t, tr.x, tr.y, tr.theta, tr.radius_m);
    o["id"] = id;
    jh.push_back(std::move(o));
  }
  doc["humans"] = std::move(jh);

  Json assessments = Json::array();
  for (const auto& h : analysis.humans)
    if (h.last_assessment || h.first_round_situation)
      assessments.push_back(humanAssessment(run, h));
  doc["assessments"] = std::move(assessments);

  Json utterances = Json::array();
  for (const auto& u : run.utterances) {
    Json o = Json::object();
    o["t_s"] = numberOrNull(utimeToS(u.utime));
    o["human_id"] = u.human_id;
    o["act"] = speechActName(u.speech_act);
    o["round"] = u.round;
    o["direction"] = directionName(u.direction);
    o["t_cross_s"] = numberOrNull(u.t_cross_s);
    o["text"] = u.text;
    o["delivery"] = deliveryName(u.delivery);
    o["said"] = wasSaid(u.delivery);
    o["speech_start_s"] = numberOrNull(u.speech_start_s);
    o["speech_duration_s"] = numberOrNull(u.speech_duration_s);
    utterances.push_back(std::move(o));
  }
  doc["utterances"] = std::move(utterances);

  Json actions = Json::array();
  for (const auto& a : run.actions)
    actions.push_back(Json::object({{"t_s", numberOrNull(utimeToS(a.utime))},
                                    {"action", robotActionName(a.action)},
                                    {"human_id", a.human_id},
                                    {"reason", a.reason}}));
  doc["actions"] = std::move(actions);

  // The band source's mode, as each change first appears in its commands.
  Json modes = Json::array();
  bool first = true;
  std::int8_t previous = 0;
  for (const auto& c : run.commands) {
    if (!first && c.mode == previous) continue;
    modes.push_back(Json::object(
        {{"t_s", numberOrNull(utimeToS(c.utime))}, {"mode", commandModeName(c.mode)}}));
    previous = c.mode;
    first = false;
  }
  doc["modes"] = std::move(modes);

  Json recorder = Json::array();
  for (const auto& c : run.controls)
    recorder.push_back(Json::object({{"t_s", numberOrNull(utimeToS(c.utime))},
                                     {"command", recorderCommandName(c.command)},
                                     {"human_id", c.human_id}}));
  doc["recorder"] = std::move(recorder);

  if (analysis.final_status) {
    const auto& s = run.sim_status[*analysis.final_status];
    doc["outcome"] = Json::object({{"t_s", numberOrNull(utimeToS(s.utime))},
                                   {"state", simStateName(s.state)},
                                   {"min_clearance_m", numberOrNull(s.min_clearance_m)},
                                   {"robot_time_to_goal_s", numberOrNull(s.robot_time_to_goal_s)},
                                   {"detail", s.detail}});
  } else {
    doc["outcome"] = nullptr;
  }
  doc["map"] = map_path.empty() ? Json() : traceMap(map_path);
  return doc;
}

}  // namespace coopnav::ctl
