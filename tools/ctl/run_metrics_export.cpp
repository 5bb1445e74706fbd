#include "run_metrics_export.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "coopnav/channels.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/planning/global_planner.hpp"

namespace coopnav::ctl {
namespace {

metrics::AgentSample sampleOf(const agent_state_t& a) {
  metrics::AgentSample s;
  s.id = a.id;
  s.p_m = {a.x_m, a.y_m};
  s.v_m_s = {a.vx_m_s, a.vy_m_s};
  s.theta_rad = a.theta_rad;
  s.radius_m = a.radius_m;
  return s;
}

bool finiteAgent(const agent_state_t& a) {
  return std::isfinite(a.x_m) && std::isfinite(a.y_m) && std::isfinite(a.vx_m_s) &&
         std::isfinite(a.vy_m_s) && std::isfinite(a.theta_rad) && std::isfinite(a.radius_m);
}

void putStat(Json& o, const std::string& key, const metrics::Stat3& s, const char* unit) {
  o["min_" + key + unit] = numberOrNull(s.min);
  o["avg_" + key + unit] = numberOrNull(s.avg);
  o["max_" + key + unit] = numberOrNull(s.max);
}

Json tristate(std::int8_t pred) {
  if (pred == situation_t::PRED_TRUE) return true;
  if (pred == situation_t::PRED_FALSE) return false;
  return nullptr;
}

std::string csvCell(const Json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
  if (v.is_number()) return jsonNumber(v.get<double>());
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::optional<Eigen::Vector2d> robotGoalFromLog(const std::string& path) {
  logfile::LogEventReader reader(path);
  logfile::RawEvent e;
  std::optional<Eigen::Vector2d> goal;
  while (reader.next(e)) {
    if (e.channel != channels::kGoals) continue;
    goals_t g;
    const auto size = static_cast<int>(e.data.size());
    try {
      if (g.decode(e.data.data(), 0, size) != size) continue;
    } catch (const std::exception&) {
      continue;
    }
    for (const auto& one : g.goals)
      if (one.kind == agent_state_t::KIND_ROBOT && std::isfinite(one.x_m) && std::isfinite(one.y_m))
        goal = Eigen::Vector2d{one.x_m, one.y_m};
  }
  return goal;
}

metrics::RunInput metricsInput(const RunLog& run, const RunAnalysis& analysis,
                               const std::optional<Eigen::Vector2d>& robot_goal,
                               const DistanceMap* map) {
  metrics::RunInput in;
  in.robot_goal = robot_goal;
  // Lockstep steps in time order; a step published again is read once (the reader), a state that
  // does not move time forward or has a non-finite robot is left out.
  for (const auto& s : run.agent_states) {
    const double t = utimeToS(s.utime);
    if (!in.frames.empty() && !(t > in.frames.back().t_s)) continue;
    if (!finiteAgent(s.robot)) continue;
    metrics::Frame f;
    f.t_s = t;
    f.robot = sampleOf(s.robot);
    for (const auto& h : s.humans)
      if (finiteAgent(h)) f.humans.push_back(sampleOf(h));
    in.frames.push_back(std::move(f));
  }
  if (analysis.final_status) {
    const sim_status_t& st = run.sim_status[*analysis.final_status];
    in.outcome =
        st.state >= sim_status_t::STATE_RUNNING && st.state <= sim_status_t::STATE_STANDSTILL
            ? static_cast<metrics::Outcome>(st.state)
            : metrics::Outcome::kUnknown;
    if (std::isfinite(st.robot_time_to_goal_s)) in.goal_time_s = st.robot_time_to_goal_s;
  }
  if (map && !in.frames.empty()) {
    for (const auto& f : in.frames) {
      const DistanceResult r = map->nearest(f.robot.p_m);
      const bool known = r.status == DistanceStatus::kOk || r.status == DistanceStatus::kInObstacle;
      in.wall_clearance_m.push_back(known ? r.distance_m - f.robot.radius_m : metrics::kNaN);
    }
    if (robot_goal) {
      // The shortest path a disc of the robot's size has (no clearance preference): SPL's ℓ.
      GridPathPlanner::Options po;
      po.resolution_m = std::max(0.05, map->resolution_m());
      po.clearance_weight = 0.0;
      const GridPathPlanner planner(
          std::shared_ptr<const DistanceMap>(map, [](const DistanceMap*) {}), po);
      const PathResult p =
          planner.plan(in.frames.front().robot.p_m, *robot_goal, in.frames.front().robot.radius_m);
      if (p.status == PathStatus::kOk) in.shortest_path_m = p.length_m;
    }
  }
  return in;
}

Json metricsEntry(const RunLog& run, const RunAnalysis& analysis, const metrics::RunMetrics& m,
                  const std::string& log_name, bool with_map) {
  Json o = Json::object();
  o["scenario"] = analysis.scenario;
  o["log"] = log_name;
  o["outcome"] = analysis.final_status ? simStateName(run.sim_status[*analysis.final_status].state)
                                       : std::string("UNKNOWN");
  o["map"] = with_map;
  o["success"] = m.success;
  o["collision"] = m.collision;
  o["person_collisions"] = m.person_collisions;
  o["robot_on_person_collisions"] = m.robot_on_person_collisions;
  o["person_on_robot_collisions"] = m.person_on_robot_collisions;
  o["wall_collisions"] = with_map ? Json(m.wall_collisions) : Json(nullptr);
  o["timeout"] = m.timeout;
  o["failure_to_progress"] = m.failure_to_progress;
  o["longest_no_progress_s"] = numberOrNull(m.longest_no_progress_s);
  o["stalled_s"] = numberOrNull(m.stalled_s);
  o["time_to_goal_s"] = numberOrNull(m.time_to_goal_s);
  o["duration_s"] = numberOrNull(m.duration_s);
  o["path_length_m"] = numberOrNull(m.path_length_m);
  o["shortest_path_m"] = numberOrNull(m.shortest_path_m);
  o["path_length_ratio"] = numberOrNull(m.path_length_ratio);
  o["goal_traversal_ratio"] = numberOrNull(m.goal_traversal_ratio);
  o["spl"] = numberOrNull(m.spl);
  o["final_distance_to_goal_m"] = numberOrNull(m.final_distance_to_goal_m);
  o["cumulative_heading_change_rad"] = numberOrNull(m.cumulative_heading_change_rad);
  o["path_irregularity_rad"] = numberOrNull(m.path_irregularity_rad);
  o["path_irregularity_rad_per_m"] = numberOrNull(m.path_irregularity_rad_per_m);
  putStat(o, "speed", m.speed_m_s, "_m_s");
  putStat(o, "acceleration", m.acceleration_m_s2, "_m_s2");
  putStat(o, "jerk", m.jerk_m_s3, "_m_s3");
  o["motion_energy_m2_s"] = numberOrNull(m.motion_energy_m2_s);
  putStat(o, "clearing_distance", m.clearing_distance_m, "_m");
  o["space_compliance"] = numberOrNull(m.space_compliance);
  o["min_distance_to_person_m"] = numberOrNull(m.min_distance_to_person_m);
  o["avg_closest_person_distance_m"] = numberOrNull(m.closest_person_distance_m.avg);
  o["max_closest_person_distance_m"] = numberOrNull(m.closest_person_distance_m.max);
  o["min_ttc_s"] = numberOrNull(m.min_ttc_s);
  o["intimate_s"] = numberOrNull(m.intimate_s);
  o["personal_s"] = numberOrNull(m.personal_s);
  o["social_s"] = numberOrNull(m.social_s);
  o["intimate_share"] = numberOrNull(m.intimate_share);
  o["personal_share"] = numberOrNull(m.personal_share);
  o["social_share"] = numberOrNull(m.social_share);
  o["discomfort_frequency"] = numberOrNull(m.discomfort_frequency);
  o["personal_space_cost_s"] = numberOrNull(m.personal_space_cost_s);
  o["social_work"] = numberOrNull(m.social_work);
  o["obstacle_work"] = with_map ? numberOrNull(m.obstacle_work) : Json(nullptr);
  Json persons = Json::array();
  for (const auto& p : m.persons) {
    Json q = Json::object();
    q["id"] = p.id;
    q["min_distance_m"] = numberOrNull(p.min_distance_m);
    q["min_ttc_s"] = numberOrNull(p.min_ttc_s);
    q["intimate_s"] = numberOrNull(p.intimate_s);
    q["personal_s"] = numberOrNull(p.personal_s);
    q["social_s"] = numberOrNull(p.social_s);
    q["collisions"] = p.collisions;
    q["robot_on_person_collisions"] = p.robot_on_person_collisions;
    q["person_on_robot_collisions"] = p.person_on_robot_collisions;
    q["max_conflict_intensity"] = numberOrNull(p.conflict.max_intensity);
    q["robot_responsibility"] = numberOrNull(p.conflict.robot_responsibility);
    q["person_responsibility"] = numberOrNull(std::isnan(p.conflict.robot_responsibility)
                                                  ? metrics::kNaN
                                                  : 1.0 - p.conflict.robot_responsibility);
    q["robot_engagement"] = numberOrNull(p.conflict.robot_engagement);
    q["person_engagement"] =
        numberOrNull(std::isnan(p.conflict.robot_engagement) ? metrics::kNaN
                                                             : 1.0 - p.conflict.robot_engagement);
    q["resolved_by_robot"] = numberOrNull(p.conflict.resolved_by_robot);
    q["resolved_by_person"] = numberOrNull(p.conflict.resolved_by_person);
    q["escalated_by_robot"] = numberOrNull(p.conflict.escalated_by_robot);
    q["escalated_by_person"] = numberOrNull(p.conflict.escalated_by_person);
    q["conflict_change_by_time"] = numberOrNull(p.conflict.by_time);
    // The path assessor's judgement of the same person (its last message), for comparison.
    const HumanAnalysis* h = analysis.human(p.id);
    const path_assessment_t* last =
        h && h->last_assessment ? &run.assessments[*h->last_assessment] : nullptr;
    q["cm_interaction_m"] = last ? numberOrNull(last->cm_interaction_m) : Json(nullptr);
    q["cm_window_m"] = last ? numberOrNull(last->cm_m) : Json(nullptr);
    q["is_contributing_interaction"] =
        last ? tristate(last->is_contributing_interaction) : Json(nullptr);
    q["p_contributing"] = last ? numberOrNull(last->p_contributing) : Json(nullptr);
    q["docked"] = h ? h->docked : false;
    persons.push_back(std::move(q));
  }
  o["persons"] = std::move(persons);
  return o;
}

Json metricsDocument(const std::vector<Json>& entries) {
  Json doc = Json::object();
  doc["format"] = kMetricsFormat;
  doc["runs"] = Json::array();
  for (const auto& e : entries) doc["runs"].push_back(e);
  return doc;
}

std::string metricsCsv(const std::vector<Json>& entries) {
  std::vector<std::string> columns;
  std::map<std::string, std::size_t> index;
  std::vector<std::map<std::string, std::string>> rows;
  auto put = [&](std::map<std::string, std::string>& row, const std::string& key, const Json& v) {
    if (!index.count(key)) {
      index[key] = columns.size();
      columns.push_back(key);
    }
    row[key] = csvCell(v);
  };
  for (const auto& e : entries) {
    std::map<std::string, std::string> row;
    for (const auto& [key, v] : e.items()) {
      if (key == "persons") continue;
      put(row, key, v);
    }
    for (const auto& p : elements(member(e, "persons"))) {
      const std::string prefix =
          "person" + std::to_string(static_cast<std::int64_t>(numberValue(member(p, "id")))) + "_";
      for (const auto& [key, v] : p.items())
        if (key != "id") put(row, prefix + key, v);
    }
    rows.push_back(std::move(row));
  }
  std::ostringstream out;
  for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << "\n";
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const auto it = row.find(columns[i]);
      out << (i ? "," : "") << (it == row.end() ? "" : it->second);
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace coopnav::ctl
