#include "coopnav/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::sim {

namespace {

/// Below this speed a human keeps its heading: slower than a slow walk a person shuffles, steps
/// aside or back without turning round, and the direction of such a velocity is noise. At
/// 0.05 m/s a planner-backed human stopping in the narrow corridor crept back at 0.06 m/s for one
/// step, turned to face away from the robot, and round 3 took that for the agents having crossed.
constexpr double kHeadingMinSpeed_m_s = 0.3;

double clampAbs(double x, double limit) { return std::clamp(x, -limit, limit); }

/// Moves `current` towards `target` by at most max_step (per-axis acceleration limit).
double approach(double current, double target, double max_step) {
  return current + clampAbs(target - current, max_step);
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("invalid world spec: " + what);
}

/// The behaviours that step aside of their own accord at some time (AvoidanceTiming).
bool yieldsOfItsOwn(BehaviourType t) {
  return t == BehaviourType::kFacilitating || t == BehaviourType::kLateFacilitating ||
         t == BehaviourType::kResponsive;
}

}  // namespace

double drawOnset(const RealisticOnsetParams& p, Rng& rng) {
  return std::min(p.max_s, p.median_s * std::exp(p.log_sd * rng.normal(0.0, 1.0)));
}

std::vector<std::optional<double>> Simulation::onsets() const {
  std::vector<std::optional<double>> out;
  out.reserve(humans_.size());
  for (const Human& h : humans_) out.push_back(h.spec.behaviour.onset_s);
  return out;
}

const char* toString(SimStatus s) {
  switch (s) {
    case SimStatus::kRunning:
      return "RUNNING";
    case SimStatus::kGoalsReached:
      return "GOALS_REACHED";
    case SimStatus::kCollision:
      return "COLLISION";
    case SimStatus::kTimeLimit:
      return "TIME_LIMIT";
    case SimStatus::kStandstill:
      return "STANDSTILL";
  }
  return "?";
}

double robotSpeedTowards(const AgentState& robot, const AgentState& human) {
  const Eigen::Vector2d d = human.pose.position() - robot.pose.position();
  const double n = d.norm();
  if (!(n > 0.0)) return 0.0;
  return Eigen::Vector2d{robot.velocity.vx_m_s, robot.velocity.vy_m_s}.dot(d / n);
}

Simulation::Simulation(const WorldSpec& spec, const DistanceMap* map,
                       const PlannerAdapterFactory& planner_factory)
    : spec_(spec), map_(map) {
  const SimSettings& st = spec.settings;
  require(st.physics_dt_s > 0.0 && st.physics_dt_s <= 0.05, "physics_dt_s must be in (0, 0.05]");
  require(st.substeps_per_step >= 1, "substeps_per_step must be >= 1");
  require(st.time_limit_s > 0.0, "time_limit_s must be > 0");
  require(st.contact_fault_speed_m_s >= 0.0, "contact_fault_speed_m_s must be >= 0");
  require(st.standstill_time_s >= 0.0 && st.standstill_distance_m >= 0.0,
          "standstill_time_s and standstill_distance_m must be >= 0");
  require(spec.robot.radius_m > 0.0, "robot radius must be > 0");
  require(isFinite(spec.robot.start) && isFinite(spec.robot.goal), "robot start/goal not finite");
  std::set<std::int32_t> ids;
  for (const HumanSpec& h : spec.humans) {
    require(h.id >= 1, "human id " + std::to_string(h.id) + " must be >= 1");
    require(ids.insert(h.id).second, "duplicate human id " + std::to_string(h.id));
    require(h.radius_m > 0.0 && h.speed_m_s >= 0.0 && h.max_acc_m_s2 > 0.0,
            "human " + std::to_string(h.id) + ": radius, speed, acceleration");
    require(isFinite(h.start) && isFinite(h.goal), "human start/goal not finite");
  }

  robot_.id = kRobotId;
  robot_.kind = AgentKind::kRobot;
  robot_.pose = spec.robot.start;
  robot_.radius_m = spec.robot.radius_m;

  humans_.reserve(spec.humans.size());
  for (const HumanSpec& hs : spec.humans) {
    Human h;
    h.spec = hs;
    h.state.id = hs.id;
    h.state.kind = AgentKind::kHuman;
    h.state.pose = hs.start;
    h.state.radius_m = hs.radius_m;
    h.path.push_back(hs.start.position());
    for (const auto& w : hs.via) h.path.push_back(w);
    h.path.push_back(hs.goal.position());
    // One stream per human, derived from (seed, id): adding a human does not change the draws
    // of the others.
    h.rng = Rng::forStream(spec.seed, static_cast<std::uint64_t>(hs.id));
    // A stream of its own: the draws of what it hears never shift its walking noise.
    constexpr std::uint64_t kCueStreams = std::uint64_t{1} << 40;
    h.cue_rng = Rng::forStream(spec.seed, kCueStreams + static_cast<std::uint64_t>(hs.id));
    h.preferred_speed_m_s = hs.speed_m_s;
    if (hs.speed_stddev_m_s > 0.0)
      h.preferred_speed_m_s = std::max(0.1, h.rng.normal(hs.speed_m_s, hs.speed_stddev_m_s));
    BehaviourConfig behaviour = hs.behaviour;
    if (spec.avoidance_timing == AvoidanceTiming::kRealistic && yieldsOfItsOwn(behaviour.type)) {
      constexpr std::uint64_t kOnsetStreams = std::uint64_t{1} << 41;
      Rng onset_rng = Rng::forStream(spec.seed, kOnsetStreams + static_cast<std::uint64_t>(hs.id));
      behaviour.onset_s = drawOnset(spec.onset, onset_rng);
      h.spec.behaviour.onset_s = behaviour.onset_s;
    }
    h.behaviour = makeBehaviour(behaviour, planner_factory);
    humans_.push_back(std::move(h));
  }
  const std::size_t n = humans_.size() + 2;  // robot, humans, wall
  in_contact_.assign(n, std::vector<bool>(n, false));
  summary_.human_goal_time_s.assign(humans_.size(), -1.0);
  still_at_.push_back(robot_.pose.position());
  for (const Human& h : humans_) still_at_.push_back(h.state.pose.position());
}

void Simulation::addCue(const Cue& cue) {
  for (Human& h : humans_) {
    if (h.spec.id != cue.human_id) continue;
    auto it = std::upper_bound(h.pending.begin(), h.pending.end(), cue.t_s,
                               [](double t, const Cue& c) { return t < c.t_s; });
    h.pending.insert(it, cue);
  }
}

std::size_t Simulation::pendingCues(std::int32_t human_id) const {
  for (const Human& h : humans_)
    if (h.spec.id == human_id) return h.pending.size();
  return 0;
}

void Simulation::hearCues(Human& h, std::vector<CueOutcome>& out) {
  std::size_t n = 0;
  for (; n < h.pending.size() && h.pending[n].t_s <= t_s_; ++n) {
    CueOutcome o;
    o.cue = h.pending[n];
    o.distance_m = (h.state.pose.position() - robot_.pose.position()).norm();
    o.responds = h.spec.behaviour.type == BehaviourType::kResponsive;
    if (o.responds) {
      const ResponsiveParams& p = h.spec.behaviour.responsive;
      // Both draws are made for every cue, heard or not, so that one cue's fate never shifts
      // the next one's.
      const double u = h.cue_rng.uniform01();
      const double z = h.cue_rng.normal(0.0, 1.0);
      o.heard = o.distance_m <= p.hearing_range_m;
      const double compliance = o.cue.kind == CueKind::kMoveToSide ? p.compliance_request
                                : o.cue.kind == CueKind::kKeepSide ? p.compliance_statement
                                                                   : 1.0;
      o.complies = o.heard && u < compliance;
      const double reaction_s = std::min(
          p.reaction_time_max_s, p.reaction_time_median_s * std::exp(p.reaction_time_log_sd * z));
      o.act_s = t_s_ + reaction_s;
      if (o.complies) {
        Cue act = o.cue;
        act.t_s = o.act_s;
        auto it = std::upper_bound(h.acting.begin(), h.acting.end(), act.t_s,
                                   [](double t, const Cue& c) { return t < c.t_s; });
        h.acting.insert(it, act);
      }
    }
    out.push_back(o);
  }
  h.pending.erase(h.pending.begin(), h.pending.begin() + static_cast<std::ptrdiff_t>(n));
}

void Simulation::setRobotBand(const Band& band, double stamp_s) {
  robot_band_ = band;
  robot_band_stamp_s_ = stamp_s;
  has_band_ = true;
}

std::vector<AgentState> Simulation::agents() const {
  std::vector<AgentState> out;
  out.reserve(humans_.size() + 1);
  out.push_back(robot_);
  for (const Human& h : humans_) out.push_back(h.state);
  return out;
}

std::vector<BehaviourStatus> Simulation::behaviourStatus() const {
  std::vector<BehaviourStatus> out;
  for (const Human& h : humans_) out.push_back(h.behaviour->status());
  return out;
}

StepResult Simulation::step(const Velocity2& robot_cmd_body) {
  StepResult r;
  for (int i = 0; i < spec_.settings.substeps_per_step && status_ == SimStatus::kRunning; ++i)
    physicsStep(robot_cmd_body, r);
  r.t_s = t_s_;
  r.agents = agents();
  r.status = status_;
  return r;
}

void Simulation::integrateRobot(const Velocity2& cmd, double dt_s) {
  const RobotLimits& lim = spec_.robot.limits;
  const bool holonomic = spec_.robot.kinematics == Kinematics::kHolonomic;
  // Clamp the command to the velocity limits, then move towards it under the acceleration limits.
  const double vx_cmd = std::clamp(cmd.vx_m_s, -lim.max_backward_m_s, lim.max_forward_m_s);
  const double vy_cmd = holonomic ? clampAbs(cmd.vy_m_s, lim.max_lateral_m_s) : 0.0;
  const double w_cmd = clampAbs(cmd.omega_rad_s, lim.max_omega_rad_s);
  Velocity2& v = robot_body_vel_;
  v.vx_m_s = approach(v.vx_m_s, vx_cmd, lim.max_acc_forward_m_s2 * dt_s);
  v.vy_m_s = approach(v.vy_m_s, vy_cmd, lim.max_acc_lateral_m_s2 * dt_s);
  v.omega_rad_s = approach(v.omega_rad_s, w_cmd, lim.max_acc_omega_rad_s2 * dt_s);
  // Midpoint heading: second-order accurate for arcs, exact for straight lines.
  const double th_mid = robot_.pose.theta_rad + 0.5 * v.omega_rad_s * dt_s;
  const double c = std::cos(th_mid), s = std::sin(th_mid);
  const double vx_w = c * v.vx_m_s - s * v.vy_m_s;
  const double vy_w = s * v.vx_m_s + c * v.vy_m_s;
  robot_.pose.x_m += vx_w * dt_s;
  robot_.pose.y_m += vy_w * dt_s;
  robot_.pose.theta_rad = wrapAngle(robot_.pose.theta_rad + v.omega_rad_s * dt_s);
  robot_.velocity = {vx_w, vy_w, v.omega_rad_s};
}

void Simulation::physicsStep(const Velocity2& cmd_body, StepResult& out) {
  std::vector<SimEvent>& events = out.events;
  const double dt_s = spec_.settings.physics_dt_s;
  // Every human decides on the same snapshot, so the result does not depend on update order.
  std::vector<AgentState> snapshot;
  snapshot.reserve(humans_.size());
  for (const Human& h : humans_) snapshot.push_back(h.state);
  const AgentState robot_snapshot = robot_;

  std::vector<AgentState> others;
  for (std::size_t i = 0; i < humans_.size(); ++i) {
    Human& h = humans_[i];
    others.clear();
    for (std::size_t j = 0; j < snapshot.size(); ++j)
      if (j != i) others.push_back(snapshot[j]);
    hearCues(h, out.cues);
    // Only what it has started acting on is visible, each cue once, in the step it starts: the
    // behaviour keeps what it made of it, and the simulator only the cues still to come (kept
    // all run long, a flood of words made every step scan them all).
    const auto started =
        std::find_if(h.acting.begin(), h.acting.end(), [&](const Cue& c) { return c.t_s > t_s_; });
    std::vector<Cue> heard(h.acting.begin(), started);
    h.acting.erase(h.acting.begin(), started);
    BehaviourContext ctx;
    ctx.t_s = t_s_;
    ctx.dt_s = dt_s;
    ctx.self = &snapshot[i];
    ctx.goal = h.spec.goal;
    ctx.reference_path = &h.path;
    ctx.preferred_speed_m_s = h.preferred_speed_m_s;
    ctx.goal_tolerance_m = h.spec.goal_tolerance_m;
    ctx.max_acc_m_s2 = h.spec.max_acc_m_s2;
    ctx.robot = &robot_snapshot;
    ctx.robot_band = has_band_ ? &robot_band_ : nullptr;
    ctx.robot_band_stamp_s = robot_band_stamp_s_;
    ctx.other_humans = &others;
    ctx.map = map_;
    ctx.cues = &heard;
    Velocity2 want = h.behaviour->desiredVelocity(ctx);
    if (h.spec.velocity_noise_m_s > 0.0) {
      want.vx_m_s += h.rng.normal(0.0, h.spec.velocity_noise_m_s);
      want.vy_m_s += h.rng.normal(0.0, h.spec.velocity_noise_m_s);
    }
    // Acceleration limit on the velocity vector (not per axis: walking has no preferred axes).
    const Eigen::Vector2d v{h.state.velocity.vx_m_s, h.state.velocity.vy_m_s};
    Eigen::Vector2d dv = Eigen::Vector2d{want.vx_m_s, want.vy_m_s} - v;
    const double max_dv = h.spec.max_acc_m_s2 * dt_s;
    if (dv.norm() > max_dv) dv *= max_dv / dv.norm();
    const Eigen::Vector2d v_new = v + dv;
    AgentState& s = h.state;
    s.pose.x_m += v_new.x() * dt_s;
    s.pose.y_m += v_new.y() * dt_s;
    const double th_old = s.pose.theta_rad;
    if (v_new.norm() > kHeadingMinSpeed_m_s) s.pose.theta_rad = std::atan2(v_new.y(), v_new.x());
    s.velocity = {v_new.x(), v_new.y(), wrapAngle(s.pose.theta_rad - th_old) / dt_s};
  }
  integrateRobot(cmd_body, dt_s);
  ++physics_steps_;
  // Time from the step count, not by accumulation, so that it never drifts.
  t_s_ = static_cast<double>(physics_steps_) * dt_s;

  // Goals.
  if (!robot_at_goal_ && (robot_.pose.position() - spec_.robot.goal.position()).norm() <
                             spec_.robot.goal_tolerance_m) {
    robot_at_goal_ = true;
    summary_.robot_goal_time_s = t_s_;
    events.push_back({SimEvent::Kind::kGoalReached, t_s_, kRobotId, kRobotId, 0.0});
  }
  for (std::size_t i = 0; i < humans_.size(); ++i) {
    Human& h = humans_[i];
    if (!h.at_goal &&
        (h.state.pose.position() - h.spec.goal.position()).norm() < h.spec.goal_tolerance_m) {
      h.at_goal = true;
      summary_.human_goal_time_s[i] = t_s_;
      events.push_back({SimEvent::Kind::kGoalReached, t_s_, h.spec.id, h.spec.id, 0.0});
    }
  }
  checkCollisions(events);
  summary_.t_s = t_s_;
  if (status_ != SimStatus::kRunning) return;

  const bool all_goals = robot_at_goal_ && std::all_of(humans_.begin(), humans_.end(),
                                                       [](const Human& h) { return h.at_goal; });
  const bool still = standingStill();
  if (spec_.settings.end_on_goals && all_goals) {
    end(SimStatus::kGoalsReached, events);
  } else if (still && !all_goals) {
    end(SimStatus::kStandstill, events);
  } else if (t_s_ >= spec_.settings.time_limit_s - 1e-9) {
    end(SimStatus::kTimeLimit, events);
  }
}

bool Simulation::standingStill() {
  const SimSettings& st = spec_.settings;
  bool moved = (robot_.pose.position() - still_at_[0]).norm() > st.standstill_distance_m;
  for (std::size_t i = 0; i < humans_.size() && !moved; ++i)
    moved = (humans_[i].state.pose.position() - still_at_[i + 1]).norm() > st.standstill_distance_m;
  if (moved) {
    // A move of anyone restarts the clock for everyone: the encounter is still being resolved.
    still_at_[0] = robot_.pose.position();
    for (std::size_t i = 0; i < humans_.size(); ++i)
      still_at_[i + 1] = humans_[i].state.pose.position();
    still_since_s_ = t_s_;
    return false;
  }
  return st.standstill_time_s > 0.0 && t_s_ - still_since_s_ >= st.standstill_time_s - 1e-9;
}

void Simulation::checkCollisions(std::vector<SimEvent>& events) {
  const std::size_t wall = humans_.size() + 1;
  bool robot_collided = false;
  // Edge-triggered: one event when a contact starts, none while it lasts.
  auto contact = [&](std::size_t a, std::size_t b, bool touching, std::int32_t id_a,
                     std::int32_t id_b, double gap_m) {
    if (touching && !in_contact_[a][b]) {
      events.push_back({SimEvent::Kind::kCollision, t_s_, id_a, id_b, gap_m});
      ++summary_.collisions;
      if (a == 0) robot_collided = true;
    }
    in_contact_[a][b] = touching;
  };
  auto wallGap = [&](const AgentState& s) {
    if (map_ == nullptr) return std::numeric_limits<double>::infinity();
    const DistanceResult r = map_->nearest(s.pose.position());
    if (r.status == DistanceStatus::kOk || r.status == DistanceStatus::kInObstacle)
      return r.distance_m - s.radius_m;
    return std::numeric_limits<double>::infinity();
  };

  const Eigen::Vector2d pr = robot_.pose.position();
  for (std::size_t i = 0; i < humans_.size(); ++i) {
    const AgentState& h = humans_[i].state;
    const double gap_m = (h.pose.position() - pr).norm() - h.radius_m - robot_.radius_m;
    if (gap_m < summary_.min_robot_human_clearance_m) {
      summary_.min_robot_human_clearance_m = gap_m;
      summary_.min_robot_human_clearance_t_s = t_s_;
    }
    if (gap_m < 0.0 && !in_contact_[0][i + 1] && !summary_.first_contact) {
      // Who touched whom: the robot's velocity of this physics step, in which contact began.
      RobotHumanContact c;
      c.human_id = h.id;
      c.t_s = t_s_;
      c.robot_speed_towards_m_s = robotSpeedTowards(robot_, h);
      c.robot_at_fault = c.robot_speed_towards_m_s > spec_.settings.contact_fault_speed_m_s;
      summary_.first_contact = c;
    }
    contact(0, i + 1, gap_m < 0.0, kRobotId, h.id, gap_m);
  }
  const double robot_wall_gap_m = wallGap(robot_);
  contact(0, wall, robot_wall_gap_m < 0.0, kRobotId, kWallId, robot_wall_gap_m);
  for (std::size_t i = 0; i < humans_.size(); ++i) {
    const AgentState& a = humans_[i].state;
    for (std::size_t j = i + 1; j < humans_.size(); ++j) {
      const AgentState& b = humans_[j].state;
      const double gap_m = (a.pose.position() - b.pose.position()).norm() - a.radius_m - b.radius_m;
      contact(i + 1, j + 1, gap_m < 0.0, a.id, b.id, gap_m);
    }
    const double wall_gap_m = wallGap(a);
    contact(i + 1, wall, wall_gap_m < 0.0, a.id, kWallId, wall_gap_m);
  }
  if (robot_collided && spec_.settings.end_on_robot_collision) end(SimStatus::kCollision, events);
}

void Simulation::end(SimStatus s, std::vector<SimEvent>& events) {
  status_ = s;
  summary_.status = s;
  SimEvent e;
  e.kind = SimEvent::Kind::kEnded;
  e.t_s = t_s_;
  e.status = s;
  events.push_back(e);
}

}  // namespace coopnav::sim
