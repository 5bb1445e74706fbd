#include "progress_metrics.hpp"

#include <cmath>
#include <iterator>
#include <limits>
#include <map>

#include "run_analysis.hpp"

namespace coopnav::ctl {

ProgressMetrics progressMetrics(const RunLog& run) {
  ProgressMetrics m;
  m.max_mutual_wait_start_s = std::numeric_limits<double>::quiet_NaN();
  // The command in force at each step: the band source's command of the latest step at or
  // before it (commands carry the step they answer).
  std::map<std::int64_t, std::int8_t> mode_at_step;
  for (const auto& c : run.commands) mode_at_step[c.step] = c.mode;
  auto modeAt = [&](std::int64_t step) -> std::int8_t {
    auto it = mode_at_step.upper_bound(step);
    if (it == mode_at_step.begin()) return velocity_command_t::MODE_IDLE;
    return std::prev(it)->second;
  };

  const agent_states_t* previous = nullptr;
  std::map<std::int32_t, double> waiting_since;  // per human: start of the current mutual wait
  for (const auto& s : run.agent_states) {
    const agent_state_t* robot = &s.robot;
    const double t_s = utimeToS(s.utime);
    const double dt_s = previous ? t_s - utimeToS(previous->utime) : 0.0;
    previous = &s;
    const std::int8_t mode = modeAt(s.step);
    const double speed = std::hypot(robot->vx_m_s, robot->vy_m_s);
    const bool at_goal = mode == velocity_command_t::MODE_GOAL_REACHED;
    const bool making_room = mode == velocity_command_t::MODE_DOCKING ||
                             mode == velocity_command_t::MODE_HOLDING ||
                             mode == velocity_command_t::MODE_RETREATING;
    const bool still = speed < kStalledSpeed_m_s && !at_goal;
    if (still && !making_room && dt_s > 0.0) m.stalled_s += dt_s;

    std::map<std::int32_t, double> next;
    for (const auto& a : s.humans) {
      if (!still) break;
      const double gap =
          std::hypot(a.x_m - robot->x_m, a.y_m - robot->y_m) - a.radius_m - robot->radius_m;
      if (gap > kMutualWaitGap_m || std::hypot(a.vx_m_s, a.vy_m_s) >= kHumanWaitingSpeed_m_s)
        continue;
      const auto it = waiting_since.find(a.id);
      const double since = it != waiting_since.end() ? it->second : t_s;
      next[a.id] = since;
      if (t_s - since > m.max_mutual_wait_s) {
        m.max_mutual_wait_s = t_s - since;
        m.max_mutual_wait_start_s = since;
        m.max_mutual_wait_human = a.id;
      }
    }
    waiting_since = std::move(next);
  }
  return m;
}

}  // namespace coopnav::ctl
