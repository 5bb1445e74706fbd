#include "messages.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace coopnav::hostile {
namespace {

constexpr double kCorridorY_m = 6.5;
constexpr double kRobotSpeed_m_s = 0.7;
constexpr double kHumanSpeed_m_s = 1.0;

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double theta,
                    double vx) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = theta;
  a.vx_m_s = vx;
  a.radius_m = kind == agent_state_t::KIND_ROBOT ? 0.34 : 0.3;
  return a;
}

goal_t goal(std::int32_t id, std::int8_t kind, double x, double y) {
  goal_t g{};
  g.agent_id = id;
  g.kind = kind;
  g.x_m = x;
  g.y_m = y;
  g.theta_rad = std::numeric_limits<double>::quiet_NaN();
  return g;
}

}  // namespace

agent_states_t corridorStates(std::int64_t utime, std::int64_t step, int num_humans, int k) {
  const double t_s = 0.1 * k;
  agent_states_t m{};
  m.utime = utime;
  m.step = step;
  m.robot = agent(0, agent_state_t::KIND_ROBOT, 6.5 + kRobotSpeed_m_s * t_s, kCorridorY_m, 0.0,
                  kRobotSpeed_m_s);
  // Rows of 8 across the corridor (0.6 m apart), one row every 0.9 m behind the first.
  for (int h = 0; h < num_humans; ++h) {
    const int row = h / 8;
    const double x = 20.5 + 0.9 * row - kHumanSpeed_m_s * t_s;
    const double y = num_humans == 1 ? kCorridorY_m : 4.4 + 0.6 * (h % 8);
    m.humans.push_back(agent(h + 1, agent_state_t::KIND_HUMAN, x, y, M_PI, -kHumanSpeed_m_s));
  }
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  return m;
}

goals_t corridorGoals(std::int64_t utime, int num_humans) {
  goals_t g{};
  g.utime = utime;
  g.goals.push_back(goal(0, agent_state_t::KIND_ROBOT, 20.5, kCorridorY_m));
  for (int h = 0; h < num_humans; ++h)
    g.goals.push_back(goal(h + 1, agent_state_t::KIND_HUMAN, 6.5, kCorridorY_m));
  g.num_goals = static_cast<std::int16_t>(g.goals.size());
  return g;
}

band_t straightBand(std::int32_t id, std::int8_t kind, double x0, double y0, double x1, double y1,
                    int num_poses, double duration_s) {
  band_t b{};
  b.agent_id = id;
  b.kind = kind;
  for (int i = 0; i < num_poses; ++i) {
    const double s = num_poses > 1 ? static_cast<double>(i) / (num_poses - 1) : 0.0;
    timed_pose_t p{};
    p.t_s = s * duration_s;
    p.x_m = x0 + s * (x1 - x0);
    p.y_m = y0 + s * (y1 - y0);
    p.theta_rad = std::atan2(y1 - y0, x1 - x0);
    b.poses.push_back(p);
  }
  b.num_poses = static_cast<std::int16_t>(b.poses.size());
  return b;
}

bands_t corridorBands(std::int64_t utime, std::int64_t step, int num_humans, int num_poses) {
  bands_t m{};
  m.utime = utime;
  m.step = step;
  m.status = bands_t::STATUS_OK;
  m.robot = straightBand(0, agent_state_t::KIND_ROBOT, 12.0, 1.5, 20.0, 1.5, num_poses, 8.0);
  for (int h = 0; h < num_humans; ++h)
    m.humans.push_back(straightBand(h + 1, agent_state_t::KIND_HUMAN, 20.0 + 0.5 * h, 1.9, 12.0,
                                    1.9, num_poses, 8.0));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  m.room_plans.assign(m.humans.size(), bands_t::ROOM_UNKNOWN);
  return m;
}

reference_paths_t referencePaths(std::int64_t utime, std::int64_t step, std::int32_t first_id,
                                 int num_paths, int num_points) {
  reference_paths_t r{};
  r.utime = utime;
  r.step = step;
  for (int i = 0; i < num_paths; ++i) {
    path_t p{};
    p.agent_id = first_id + i;
    for (int j = 0; j < num_points; ++j) {
      const double s = num_points > 1 ? static_cast<double>(j) / (num_points - 1) : 0.0;
      p.x_m.push_back(20.0 - 8.0 * s);
      p.y_m.push_back(2.3);
    }
    p.num_points = static_cast<std::int16_t>(p.x_m.size());
    r.paths.push_back(std::move(p));
    r.revision.push_back(1);
  }
  r.num_paths = static_cast<std::int16_t>(r.paths.size());
  return r;
}

situation_t situation(std::int64_t utime, std::int64_t step, std::int32_t human_id,
                      double t_cross_s, std::string reason) {
  situation_t m{};
  m.utime = utime;
  m.step = step;
  m.human_id = human_id;
  m.crossing_status = situation_t::CROSSING_OK;
  m.i_star = 10;
  m.t_cross_s = t_cross_s;
  m.cp_h_x_m = 13.5;
  m.cp_h_y_m = 6.5;
  m.cp_r_x_m = 13.5;
  m.cp_r_y_m = 7.2;
  m.dir = situation_t::DIR_LEFT;
  m.d_h_m = 0.6;
  m.d_oh_m = 1.0;
  m.d_or_m = 1.0;
  m.d_hr_m = 0.7;
  m.human_needs_to_contribute = situation_t::PRED_TRUE;
  m.human_is_constrained = situation_t::PRED_FALSE;
  m.robot_is_constrained = situation_t::PRED_TRUE;
  m.tau_h_m = 0.3;
  m.tau_oh_m = 1.0;
  m.tau_or_m = 0.3;
  m.tau_hr_m = 1.2;
  m.reason = std::move(reason);
  return m;
}

robot_action_t robotAction(std::int64_t utime, std::int8_t action, std::int32_t human_id,
                           std::string reason) {
  robot_action_t a{};
  a.utime = utime;
  a.step = -1;
  a.action = action;
  a.human_id = human_id;
  a.reason = std::move(reason);
  return a;
}

distance_request_t distanceRequest(std::int64_t request_id, std::string reply_channel) {
  distance_request_t r{};
  r.utime = kEpoch_us;
  r.request_id = request_id;
  r.reply_channel = std::move(reply_channel);
  distance_query_t q{};
  q.kind = distance_query_t::KIND_NEAREST;
  q.px_m = 10.0;
  q.py_m = 6.5;
  q.nx = 1.0;
  q.max_range_m = 5.0;
  r.queries = {q};
  r.num_queries = 1;
  return r;
}

}  // namespace coopnav::hostile
