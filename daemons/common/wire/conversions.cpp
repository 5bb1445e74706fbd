#include "wire/conversions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

[[noreturn]] void reject(const std::string& why) { throw RejectedMessage(why); }

void requireFinite(double v, const char* what) {
  if (!std::isfinite(v)) reject(std::string(what) + " is not finite");
}

template <class Count>
void requireCount(Count n, std::size_t actual, int max, const char* what) {
  if (n < 0 || n > max)
    reject(std::string(what) + " count " + std::to_string(n) + " outside [0, " +
           std::to_string(max) + "]");
  if (static_cast<std::size_t>(n) != actual) reject(std::string(what) + " count mismatch");
}

AgentState agentFromLcm(const agent_state_t& a, const char* what) {
  requireFinite(a.x_m, what);
  requireFinite(a.y_m, what);
  requireFinite(a.theta_rad, what);
  requireFinite(a.vx_m_s, what);
  requireFinite(a.vy_m_s, what);
  requireFinite(a.omega_rad_s, what);
  if (!(a.radius_m > 0.0) || !std::isfinite(a.radius_m))
    reject(std::string(what) + " radius must be > 0");
  if (a.kind != agent_state_t::KIND_ROBOT && a.kind != agent_state_t::KIND_HUMAN)
    reject(std::string(what) + " has an unknown kind " + std::to_string(a.kind));
  AgentState s;
  s.id = a.id;
  s.kind = a.kind == agent_state_t::KIND_ROBOT ? AgentKind::kRobot : AgentKind::kHuman;
  s.pose = {a.x_m, a.y_m, a.theta_rad};
  s.velocity = {a.vx_m_s, a.vy_m_s, a.omega_rad_s};
  s.radius_m = a.radius_m;
  return s;
}

agent_state_t agentToLcm(const AgentState& s) {
  agent_state_t a;
  a.id = s.id;
  a.kind = s.kind == AgentKind::kRobot ? agent_state_t::KIND_ROBOT : agent_state_t::KIND_HUMAN;
  a.x_m = s.pose.x_m;
  a.y_m = s.pose.y_m;
  a.theta_rad = s.pose.theta_rad;
  a.vx_m_s = s.velocity.vx_m_s;
  a.vy_m_s = s.velocity.vy_m_s;
  a.omega_rad_s = s.velocity.omega_rad_s;
  a.radius_m = s.radius_m;
  return a;
}

Band bandFromLcm(const band_t& b) {
  requireCount(b.num_poses, b.poses.size(), band_t::MAX_POSES, "band poses");
  Band out;
  out.poses.reserve(b.poses.size());
  for (const auto& p : b.poses) out.poses.push_back({p.t_s, {p.x_m, p.y_m, p.theta_rad}});
  return out;
}

band_t bandToLcm(std::int32_t id, std::int8_t kind, const Band& band) {
  band_t b;
  b.agent_id = id;
  b.kind = kind;
  const std::size_t n = std::min<std::size_t>(band.poses.size(), band_t::MAX_POSES);
  b.num_poses = static_cast<std::int16_t>(n);
  b.poses.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = band.poses[i];
    b.poses[i].t_s = p.t_s;
    b.poses[i].x_m = p.pose.x_m;
    b.poses[i].y_m = p.pose.y_m;
    b.poses[i].theta_rad = p.pose.theta_rad;
  }
  return b;
}

}  // namespace

double utimeToSeconds(std::int64_t utime) { return static_cast<double>(utime) * 1e-6; }
double utimeDiffSeconds(std::int64_t later_utime, std::int64_t earlier_utime) {
  return (static_cast<double>(later_utime) - static_cast<double>(earlier_utime)) * 1e-6;
}
std::int64_t secondsToUtime(double t_s) {
  return static_cast<std::int64_t>(std::llround(t_s * 1e6));
}

const AgentState* AgentStatesSnapshot::human(std::int32_t id) const {
  for (const auto& h : humans)
    if (h.id == id) return &h;
  return nullptr;
}

AgentStatesSnapshot fromLcm(const agent_states_t& msg) {
  requireCount(msg.num_humans, msg.humans.size(), agent_states_t::MAX_HUMANS, "humans");
  AgentStatesSnapshot s;
  s.utime = msg.utime;
  s.step = msg.step;
  s.robot = agentFromLcm(msg.robot, "robot state");
  if (s.robot.kind != AgentKind::kRobot) reject("robot state has kind HUMAN");
  std::set<std::int32_t> ids;
  for (const auto& h : msg.humans) {
    s.humans.push_back(agentFromLcm(h, "human state"));
    if (s.humans.back().kind != AgentKind::kHuman) reject("human state has kind ROBOT");
    if (!ids.insert(h.id).second) reject("duplicate human id " + std::to_string(h.id));
  }
  return s;
}

agent_states_t toLcm(const AgentStatesSnapshot& s) {
  agent_states_t m;
  m.utime = s.utime;
  m.step = s.step;
  m.robot = agentToLcm(s.robot);
  for (const auto& h : s.humans) m.humans.push_back(agentToLcm(h));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  return m;
}

const Band* BandsSnapshot::humanBand(std::int32_t id) const {
  for (const auto& [hid, band] : humans)
    if (hid == id) return &band;
  return nullptr;
}

std::int8_t BandsSnapshot::roomPlan(std::int32_t id) const {
  for (std::size_t i = 0; i < humans.size() && i < room_plans.size(); ++i)
    if (humans[i].first == id) return room_plans[i];
  return bands_t::ROOM_UNKNOWN;
}

BandsSnapshot fromLcm(const bands_t& msg) {
  requireCount(msg.num_humans, msg.humans.size(), bands_t::MAX_HUMANS, "human bands");
  BandsSnapshot s;
  s.utime = msg.utime;
  s.step = msg.step;
  s.status = msg.status;
  s.robot_mode = msg.robot_mode;
  s.iterations = msg.iterations;
  s.final_cost = msg.final_cost;
  s.solve_time_ms = msg.solve_time_ms;
  s.robot_id = msg.robot.agent_id;
  s.robot = bandFromLcm(msg.robot);
  std::set<std::int32_t> ids;
  for (const auto& h : msg.humans) {
    if (!ids.insert(h.agent_id).second) reject("duplicate human band id");
    s.humans.emplace_back(h.agent_id, bandFromLcm(h));
  }
  if (msg.room_plans.size() != msg.humans.size()) reject("room_plans count differs from humans");
  for (const std::int8_t p : msg.room_plans) {
    if (p < bands_t::ROOM_UNKNOWN || p > bands_t::ROOM_NONE)
      reject("room plan " + std::to_string(p) + " unknown");
  }
  s.room_plans = msg.room_plans;
  return s;
}

bands_t toLcm(const BandsSnapshot& s) {
  bands_t m;
  m.utime = s.utime;
  m.step = s.step;
  m.status = s.status;
  m.robot_mode = s.robot_mode;
  m.iterations = s.iterations;
  m.final_cost = s.final_cost;
  m.solve_time_ms = s.solve_time_ms;
  m.robot = bandToLcm(s.robot_id, agent_state_t::KIND_ROBOT, s.robot);
  for (const auto& [id, band] : s.humans)
    m.humans.push_back(bandToLcm(id, agent_state_t::KIND_HUMAN, band));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  m.room_plans = s.room_plans;
  m.room_plans.resize(m.humans.size(), bands_t::ROOM_UNKNOWN);
  return m;
}

ReferencePaths fromLcm(const reference_paths_t& msg) {
  requireCount(msg.num_paths, msg.paths.size(), reference_paths_t::MAX_PATHS, "paths");
  ReferencePaths r;
  r.utime = msg.utime;
  r.step = msg.step;
  for (std::size_t i = 0; i < msg.paths.size(); ++i) {
    const auto& p = msg.paths[i];
    requireCount(p.num_points, p.x_m.size(), path_t::MAX_POINTS, "path points");
    if (p.y_m.size() != p.x_m.size()) reject("path x/y size mismatch");
    ReferencePaths::Entry e;
    e.agent_id = p.agent_id;
    e.revision = msg.revision.size() > i ? msg.revision[i] : 0;
    for (std::size_t k = 0; k < p.x_m.size(); ++k) {
      requireFinite(p.x_m[k], "path point");
      requireFinite(p.y_m[k], "path point");
      e.path.emplace_back(p.x_m[k], p.y_m[k]);
    }
    r.paths.push_back(std::move(e));
  }
  return r;
}

reference_paths_t toLcm(const ReferencePaths& r) {
  reference_paths_t m;
  m.utime = r.utime;
  m.step = r.step;
  for (const auto& e : r.paths) {
    path_t p;
    p.agent_id = e.agent_id;
    const std::size_t n = std::min<std::size_t>(e.path.size(), path_t::MAX_POINTS);
    for (std::size_t k = 0; k < n; ++k) {
      p.x_m.push_back(e.path[k].x());
      p.y_m.push_back(e.path[k].y());
    }
    p.num_points = static_cast<std::int16_t>(n);
    m.paths.push_back(std::move(p));
    m.revision.push_back(e.revision);
  }
  m.num_paths = static_cast<std::int16_t>(m.paths.size());
  return m;
}

GoalsSnapshot fromLcm(const goals_t& msg) {
  requireCount(msg.num_goals, msg.goals.size(), goals_t::MAX_GOALS, "goals");
  GoalsSnapshot g;
  g.utime = msg.utime;
  std::set<std::int32_t> ids;
  for (const auto& x : msg.goals) {
    requireFinite(x.x_m, "goal");
    requireFinite(x.y_m, "goal");
    if (std::isinf(x.theta_rad)) reject("goal heading is infinite");
    if (!ids.insert(x.agent_id).second) reject("duplicate goal id");
    if (x.kind != agent_state_t::KIND_ROBOT && x.kind != agent_state_t::KIND_HUMAN)
      reject("goal of agent " + std::to_string(x.agent_id) + " has an unknown kind " +
             std::to_string(x.kind));
    Goal goal;
    goal.agent_id = x.agent_id;
    goal.kind = x.kind == agent_state_t::KIND_ROBOT ? AgentKind::kRobot : AgentKind::kHuman;
    goal.pose = {x.x_m, x.y_m, x.theta_rad};
    g.goals.push_back(goal);
  }
  return g;
}

goals_t toLcm(const GoalsSnapshot& g) {
  goals_t m;
  m.utime = g.utime;
  for (const auto& x : g.goals) {
    goal_t t;
    t.agent_id = x.agent_id;
    t.kind = x.kind == AgentKind::kRobot ? agent_state_t::KIND_ROBOT : agent_state_t::KIND_HUMAN;
    t.x_m = x.pose.x_m;
    t.y_m = x.pose.y_m;
    t.theta_rad = x.pose.theta_rad;
    m.goals.push_back(t);
  }
  m.num_goals = static_cast<std::int16_t>(m.goals.size());
  return m;
}

goal_estimates_t toLcm(const GoalEstimates& e) {
  goal_estimates_t m;
  m.utime = e.utime;
  m.step = e.step;
  const std::size_t ng = std::min<std::size_t>(e.goals.size(), goal_estimates_t::MAX_GOALS);
  for (std::size_t i = 0; i < ng; ++i) {
    m.goal_x_m.push_back(e.goals[i].x());
    m.goal_y_m.push_back(e.goals[i].y());
  }
  m.num_goals = static_cast<std::int16_t>(ng);
  for (const auto& h : e.humans) {
    if (m.humans.size() >= static_cast<std::size_t>(goal_estimates_t::MAX_HUMANS)) break;
    goal_estimate_t t;
    t.agent_id = h.agent_id;
    t.most_likely = static_cast<std::int16_t>(
        h.most_likely >= 0 && static_cast<std::size_t>(h.most_likely) < ng ? h.most_likely : -1);
    t.walked_m = h.walked_m;
    t.observations = h.observations;
    for (std::size_t i = 0; i < ng; ++i)
      t.probability.push_back(
          static_cast<float>(i < h.probability.size() ? h.probability[i] : 0.0));
    t.num_goals = static_cast<std::int16_t>(ng);
    m.humans.push_back(std::move(t));
  }
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  return m;
}

GoalEstimates fromLcm(const goal_estimates_t& msg) {
  requireCount(msg.num_goals, msg.goal_x_m.size(), goal_estimates_t::MAX_GOALS, "goals");
  requireCount(msg.num_goals, msg.goal_y_m.size(), goal_estimates_t::MAX_GOALS, "goals");
  requireCount(msg.num_humans, msg.humans.size(), goal_estimates_t::MAX_HUMANS, "humans");
  GoalEstimates e;
  e.utime = msg.utime;
  e.step = msg.step;
  for (std::size_t i = 0; i < msg.goal_x_m.size(); ++i) {
    requireFinite(msg.goal_x_m[i], "goal");
    requireFinite(msg.goal_y_m[i], "goal");
    e.goals.emplace_back(msg.goal_x_m[i], msg.goal_y_m[i]);
  }
  std::set<std::int32_t> ids;
  for (const auto& h : msg.humans) {
    if (!ids.insert(h.agent_id).second) reject("duplicate goal estimate id");
    if (h.num_goals != msg.num_goals || h.probability.size() != msg.goal_x_m.size())
      reject("goal estimate of agent " + std::to_string(h.agent_id) +
             " has a probability count other than num_goals");
    if (h.most_likely < -1 || h.most_likely >= msg.num_goals)
      reject("most_likely " + std::to_string(h.most_likely) + " outside [-1, num_goals)");
    requireFinite(h.walked_m, "walked_m");
    GoalEstimates::Human x;
    x.agent_id = h.agent_id;
    x.most_likely = h.most_likely;
    x.walked_m = h.walked_m;
    x.observations = h.observations;
    for (float p : h.probability) {
      if (!(p >= 0.0F && p <= 1.0F)) reject("a goal probability is outside [0, 1]");
      x.probability.push_back(p);
    }
    e.humans.push_back(std::move(x));
  }
  return e;
}

VelocityCommand fromLcm(const velocity_command_t& msg) {
  requireFinite(msg.vx_m_s, "command vx");
  requireFinite(msg.vy_m_s, "command vy");
  requireFinite(msg.omega_rad_s, "command omega");
  VelocityCommand c;
  c.utime = msg.utime;
  c.step = msg.step;
  c.body = {msg.vx_m_s, msg.vy_m_s, msg.omega_rad_s};
  c.mode = msg.mode;
  c.guard = msg.guard;
  return c;
}

velocity_command_t toLcm(const VelocityCommand& c) {
  velocity_command_t m;
  m.utime = c.utime;
  m.step = c.step;
  m.vx_m_s = c.body.vx_m_s;
  m.vy_m_s = c.body.vy_m_s;
  m.omega_rad_s = c.body.omega_rad_s;
  m.mode = c.mode;
  m.guard = c.guard;
  return m;
}

std::vector<DistanceQuery> queriesFromLcm(const distance_request_t& msg) {
  if (msg.num_queries < 1 || msg.num_queries > distance_request_t::MAX_QUERIES ||
      static_cast<std::size_t>(msg.num_queries) != msg.queries.size())
    reject("num_queries " + std::to_string(msg.num_queries) + " outside [1, " +
           std::to_string(distance_request_t::MAX_QUERIES) + "]");
  std::vector<DistanceQuery> out;
  out.reserve(msg.queries.size());
  for (const auto& q : msg.queries) {
    DistanceQuery d;
    d.kind = static_cast<DistanceQueryKind>(q.kind);
    d.point = {q.px_m, q.py_m};
    d.vector = {q.nx, q.ny};
    d.max_range_m = q.max_range_m;
    out.push_back(d);
  }
  return out;
}

distance_request_t toLcm(std::int64_t utime, std::int64_t request_id,
                         const std::string& reply_channel,
                         const std::vector<DistanceQuery>& queries) {
  distance_request_t m;
  m.utime = utime;
  m.request_id = request_id;
  m.reply_channel = reply_channel;
  for (const auto& q : queries) {
    distance_query_t t;
    t.kind = static_cast<std::int8_t>(q.kind);
    t.px_m = q.point.x();
    t.py_m = q.point.y();
    t.nx = q.vector.x();
    t.ny = q.vector.y();
    t.max_range_m = q.max_range_m;
    m.queries.push_back(t);
  }
  m.num_queries = static_cast<std::int16_t>(m.queries.size());
  return m;
}

std::vector<DistanceResult> resultsFromLcm(const distance_reply_t& msg) {
  requireCount(msg.num_results, msg.results.size(), distance_request_t::MAX_QUERIES, "results");
  std::vector<DistanceResult> out;
  for (const auto& r : msg.results) {
    DistanceResult d;
    if (r.status < 0 || r.status > distance_result_t::STATUS_INVALID_QUERY)
      reject("unknown distance status " + std::to_string(r.status));
    d.status = static_cast<DistanceStatus>(r.status);
    d.distance_m = r.distance_m;
    d.obstacle = {r.obstacle_x_m, r.obstacle_y_m};
    if ((d.status == DistanceStatus::kOk) && !std::isfinite(d.distance_m))
      reject("OK distance result is not finite");
    out.push_back(d);
  }
  return out;
}

distance_reply_t toLcm(std::int64_t utime, std::int64_t request_id,
                       const std::vector<DistanceResult>& results) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  distance_reply_t m;
  m.utime = utime;
  m.request_id = request_id;
  m.status = distance_reply_t::STATUS_OK;
  for (const auto& r : results) {
    distance_result_t t;
    t.status = static_cast<std::int8_t>(r.status);
    const bool has_distance = r.status == DistanceStatus::kOk ||
                              r.status == DistanceStatus::kInObstacle ||
                              r.status == DistanceStatus::kNotFound;
    t.distance_m = has_distance ? r.distance_m : kNaN;
    const bool has_point = r.status == DistanceStatus::kOk;
    t.obstacle_x_m = has_point ? r.obstacle.x() : kNaN;
    t.obstacle_y_m = has_point ? r.obstacle.y() : kNaN;
    m.results.push_back(t);
  }
  m.num_results = static_cast<std::int16_t>(m.results.size());
  return m;
}

DistanceResult answerQuery(const DistanceMap& map, const DistanceQuery& q) {
  DistanceResult invalid;
  invalid.status = DistanceStatus::kInvalidQuery;
  invalid.distance_m = std::numeric_limits<double>::quiet_NaN();
  if (!q.point.allFinite()) return invalid;
  switch (q.kind) {
    case DistanceQueryKind::kNearest:
      return map.nearest(q.point);
    case DistanceQueryKind::kSide:
      if (!q.vector.allFinite() || q.vector.norm() < 1e-9 || !(q.max_range_m > 0.0) ||
          !std::isfinite(q.max_range_m))
        return invalid;
      return map.nearestInHalfPlane(q.point, q.vector, q.max_range_m);
    case DistanceQueryKind::kRay:
      if (!q.vector.allFinite() || q.vector.norm() < 1e-9 || !(q.max_range_m > 0.0) ||
          !std::isfinite(q.max_range_m))
        return invalid;
      return map.ray(q.point, q.vector, q.max_range_m);
  }
  return invalid;
}

const char* commandModeName(std::int8_t mode) {
  switch (mode) {
    case velocity_command_t::MODE_IDLE:
      return "idle";
    case velocity_command_t::MODE_NAVIGATING:
      return "navigating";
    case velocity_command_t::MODE_DOCKING:
      return "docking";
    case velocity_command_t::MODE_HOLDING:
      return "holding";
    case velocity_command_t::MODE_RESUMING:
      return "resuming";
    case velocity_command_t::MODE_GOAL_REACHED:
      return "goal_reached";
    case velocity_command_t::MODE_STOPPED:
      return "stopped";
    case velocity_command_t::MODE_RETREATING:
      return "retreating";
    default:
      return "unknown";
  }
}

}  // namespace coopnav
