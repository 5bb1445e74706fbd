#include "coopnav/band/dual_band_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "coopnav/band/velocity_command.hpp"
#include "coopnav/distance/point_obstacle_map.hpp"
#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

/// A cached path is re-used while its goal moved less than this [m].
constexpr double kSameGoal_m = 1e-3;

/// Whether `path` from arc length from_m on passes nearer than clear_m to one of `points`.
bool pathBlocked(const Path2& path, double from_m, const std::vector<Eigen::Vector2d>& points,
                 double clear_m) {
  if (points.empty()) return false;
  double arc = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) arc += (path[i] - path[i - 1]).norm();
    if (arc < from_m) continue;
    for (const Eigen::Vector2d& p : points)
      if ((p - path[i]).squaredNorm() < clear_m * clear_m) return true;
  }
  return false;
}

/// The agent's disc radius: its own when the request gives one, else its kind's default.
double radiusOf(const AgentState& st, const BandPlannerConfig& cfg) {
  return st.radius_m > 0.0 ? st.radius_m : cfg.kinematics(st.kind).radius_m;
}
/// Head-on test for the symmetry break: lateral offset of the other agent at closest approach
/// below which neither side is preferred by the geometry [m].
constexpr double kHeadOnLateral_m = 0.1;
/// Extra length given to anticipated bands beyond nominal speed × horizon (fraction).
constexpr double kOtherLengthMargin = 0.1;
/// Constant-velocity prediction horizon when an other agent's goal is unknown [s].
constexpr double kConstVelHorizon_s = 10.0;

/// Where a cold-started band begins across its path. A band laid on the path from a robot
/// beside it returns to the path within its first segment: its first segment, the command,
/// then points back to the path, and the optimiser, to keep that segment within the limits,
/// slows the band instead. A band that begins at the agent's offset and joins the path
/// further on (PathJoin) keeps its speed.
struct PathJoin {
  bool valid{false};
  Eigen::Vector2d left{0.0, 1.0};  ///< unit normal of the local path at its first point
  double offset_m{0.0};            ///< the agent's signed offset from the path along `left`
  double speed_m_s{0.0};           ///< its velocity along `left`
};

/// Moves the inner poses of a band laid on the path across it, so that their offset starts at
/// the robot's offset and lateral speed and returns to the path over blend_s: the cubic Hermite
/// h(u) = (2u³ − 3u² + 1)·o₀ + (u³ − 2u² + u)·T·v₀, added to the offset the band already has
/// (none, or a swerve whose up-ramp is a smoothstep over the same T: the sum is then the Hermite
/// from the robot to the swerve).
void applyJoin(const PathJoin& j, double blend_s, TimedElasticBand* band) {
  if (!j.valid || band->size() < 3 || !(blend_s > 0.0)) return;
  const auto t = band->times_s();
  for (std::size_t i = 1; i + 1 < band->size(); ++i) {
    const double u = t[i] / blend_s;
    if (u >= 1.0) break;
    Pose2 p = band->pose(i);
    const double h = (2.0 * u * u * u - 3.0 * u * u + 1.0) * j.offset_m +
                     (u * u * u - 2.0 * u * u + u) * blend_s * j.speed_m_s;
    p.x_m += h * j.left.x();
    p.y_m += h * j.left.y();
    band->setPose(i, p);
  }
}

/// Time a smoothstep or cubic ramp needs to move an agent sideways by offset_m within its
/// lateral acceleration limit: the ramp's peak acceleration is 6·offset/T².
double lateralRampTime_s(double offset_m, const AgentKinematics& kin) {
  const double a_lat = kin.holonomic ? kin.acc_lim_y_m_s2 : kin.acc_lim_theta_rad_s2;
  return std::sqrt(6.0 * std::abs(offset_m) / std::max(a_lat, 1e-3));
}

/// The blend time of a join that returns to the path: 1 s, or what the ramp needs.
double joinBlendTime(const PathJoin& j, const AgentKinematics& kin) {
  return std::max(1.0, lateralRampTime_s(j.offset_m, kin));
}

/// A cold band along `local` (its first point the agent's foot on it) for an agent that may stand
/// beside it: laid on the path from that foot, with the agent's own pose first, and `join` set
/// for applyJoin(). Without a usable path direction, the band is laid from the agent's pose.
TimedElasticBand layOnPath(const AgentState& st, const Path2& local, const AgentKinematics& kin,
                           double speed_m_s, double dt_ref_s, std::optional<double> end_th,
                           const TimedElasticBand::SpeedProfile& prof, PathJoin* join) {
  *join = PathJoin{};
  if (local.size() >= 2) {
    // The path's direction over its first half metre: its tangent where the agent meets it.
    std::size_t ahead = 1;
    while (ahead + 1 < local.size() && (local[ahead] - local.front()).norm() < 0.5) ++ahead;
    const Eigen::Vector2d d = local[ahead] - local.front();
    if (d.norm() > 1e-6) {
      join->left = Eigen::Vector2d(-d.y(), d.x()).normalized();
      join->offset_m = join->left.dot(st.pose.position() - local.front());
      const double v_max = kin.max_vel_x_m_s + kin.max_vel_y_m_s;
      join->speed_m_s = std::clamp(
          join->left.dot(Eigen::Vector2d(st.velocity.vx_m_s, st.velocity.vy_m_s)), -v_max, v_max);
      join->valid = true;
      const Pose2 foot{local.front().x(), local.front().y(), st.pose.theta_rad};
      TimedElasticBand band =
          TimedElasticBand::fromPath(foot, local, speed_m_s, dt_ref_s, end_th, prof);
      band.setPose(0, st.pose);
      return band;
    }
  }
  return TimedElasticBand::fromPath(st.pose, local, speed_m_s, dt_ref_s, end_th, prof);
}

PlanStatus fromPathStatus(PathStatus s) {
  switch (s) {
    case PathStatus::kOk:
      return PlanStatus::kOk;
    case PathStatus::kInvalidInput:
      return PlanStatus::kInvalidInput;
    case PathStatus::kStartOutsideMap:
    case PathStatus::kGoalOutsideMap:
      return PlanStatus::kOutsideMap;
    case PathStatus::kStartInObstacle:
      return PlanStatus::kStartInObstacle;
    case PathStatus::kGoalInObstacle:
      return PlanStatus::kGoalInObstacle;
    case PathStatus::kNoPath:
      return PlanStatus::kNoPath;
  }
  return PlanStatus::kNoPath;
}

double speedOf(const Velocity2& v) { return std::hypot(v.vx_m_s, v.vy_m_s); }

/// Heading of the path at arc length s (direction of the segment holding s).
double pathHeadingAtEnd(const Path2& p, double fallback) {
  if (p.size() < 2) return fallback;
  const Eigen::Vector2d d = p[p.size() - 1] - p[p.size() - 2];
  return d.norm() > 1e-9 ? std::atan2(d.y(), d.x()) : fallback;
}

}  // namespace

const char* toString(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk:
      return "ok";
    case PlanStatus::kGoalReached:
      return "goal_reached";
    case PlanStatus::kInvalidInput:
      return "invalid_input";
    case PlanStatus::kInvalidConfig:
      return "invalid_config";
    case PlanStatus::kOutsideMap:
      return "outside_map";
    case PlanStatus::kStartInObstacle:
      return "start_in_obstacle";
    case PlanStatus::kGoalInObstacle:
      return "goal_in_obstacle";
    case PlanStatus::kNoPath:
      return "no_path";
  }
  return "unknown";
}

DualBandPlanner::DualBandPlanner(BandPlannerConfig config, std::shared_ptr<const DistanceMap> map)
    : config_(std::move(config)), config_errors_(config_.validate()), map_(std::move(map)) {
  if (config_errors_.empty() && map_) {
    GridPathPlanner::Options o;
    o.resolution_m = config_.global_resolution_m;
    o.clearance_pref_m = config_.global_clearance_pref_m;
    o.clearance_weight = config_.global_clearance_weight;
    o.sample_spacing_m = 0.1;
    global_ = std::make_unique<GridPathPlanner>(map_, o);
  }
}

void DualBandPlanner::reset() {
  bands_.clear();
  paths_.clear();
}

// A warm band is the last cycle's solution moved on: it keeps whatever shape LM found then,
// including a local minimum in which the robot waits and the anticipated person walks round it
// (a narrow corridor with a person stepping aside: the robot band slows, then runs backwards,
// and each cycle's few iterations only deepen it). So the warm bands are one candidate beside
// the fresh ones laid on the paths, both optimised, and the cheaper joint solution is kept: the
// previous solution goes on while it is no worse than a fresh start, and a minimum the fresh
// start does not fall into is left as soon as it costs more. TEB's homotopy-class planner keeps its
// previous best trajectory beside new candidates in the same way (Rösmann et al. 2017).
PlanResult DualBandPlanner::plan(const PlanRequest& req) {
  if (!config_.warm_start) return planOnce(req, false, nullptr);
  // With a budget, each candidate gets half of it.
  PlanRequest half = req;
  if (half.time_budget_s > 0.0) half.time_budget_s *= 0.5;
  bool used_warm = false;
  PlanResult warm = planOnce(half, true, &used_warm);
  if (!used_warm || warm.status != PlanStatus::kOk) return warm;
  const auto warm_memory = bands_;
  PlanResult cold = planOnce(half, false, nullptr);
  PlanResult* kept = &warm;
  PlanResult* other = &cold;
  if (cold.status == PlanStatus::kOk && cold.final_cost < warm.final_cost) {
    std::swap(kept, other);
    // The reference paths were (re)planned by the first call: it alone saw them change.
    for (auto& o : cold.others) {
      for (const auto& w : warm.others) {
        if (w.id == o.id) o.reference_changed = o.reference_changed || w.reference_changed;
      }
    }
  } else {
    bands_ = warm_memory;
  }
  kept->warm_candidate = true;
  kept->iterations += other->iterations;
  kept->accepted_steps += other->accepted_steps;
  kept->solver_time_s += other->solver_time_s;
  kept->budget_exhausted = kept->budget_exhausted || other->budget_exhausted;
  return std::move(*kept);
}

PlanResult DualBandPlanner::planOnce(const PlanRequest& req, bool allow_warm, bool* used_warm) {
  PlanResult out;
  const BandPlannerConfig& cfg = config_;
  if (!config_errors_.empty() || !map_ || !global_) {
    out.status = PlanStatus::kInvalidConfig;
    return out;
  }
  const AgentState& me = req.agent;
  if (!isFinite(me.pose) || !std::isfinite(req.goal.x_m) || !std::isfinite(req.goal.y_m) ||
      !std::isfinite(req.stamp_s)) {
    out.status = PlanStatus::kInvalidInput;
    return out;
  }
  const AgentKinematics& my_kin = cfg.kinematics(me.kind);
  const double my_radius = radiusOf(me, cfg);
  const Eigen::Vector2d my_pos = me.pose.position();
  const Eigen::Vector2d goal_pos = req.goal.position();
  const double horizon_fallback_s = cfg.max_plan_length_m / my_kin.max_vel_x_m_s;

  // --- the planning agent's global path (cached while on it and the goal is unchanged) ---
  const bool at_goal = (goal_pos - my_pos).norm() < cfg.xy_goal_tolerance_m;
  Path2 my_path;
  if (!at_goal) {
    auto it = paths_.find(me.id);
    bool reuse = false;
    // A return nearer the path than the radius (less a grid cell: the path's points lie
    // between the cells it was planned on) blocks it; one planned round the returns keeps them
    // at least that far, so it is kept while they stay where they were.
    const double blocked_m = my_radius - cfg.global_resolution_m;
    if (it != paths_.end() && (it->second.goal - goal_pos).norm() < kSameGoal_m &&
        it->second.status == PathStatus::kOk) {
      const auto proj = projectOntoPath(it->second.path, my_pos);
      // The static map's path taken because the returns blocked every way is planned again
      // once they no longer block it (not at every cycle they still do: a search that fails
      // explores all the map can reach).
      // The first radius ahead is the search's own escape from where the agent stands.
      reuse = proj && proj->distance_m < cfg.global_replan_dist_m &&
              pathBlocked(it->second.path, proj->arc_length_m + my_radius, req.obstacle_points,
                          blocked_m) == it->second.blocked;
    }
    if (!reuse) {
      PathResult pr = global_->plan(my_pos, goal_pos, my_radius, req.obstacle_points);
      bool blocked = false;
      if (pr.status != PathStatus::kOk && !req.obstacle_points.empty()) {
        // No way round the returns: the static map's path, held short of them by the band's
        // obstacle term and the guard (safe; the returns may yet move or open a way).
        pr = global_->plan(my_pos, goal_pos, my_radius);
        blocked = pr.status == PathStatus::kOk;
      }
      if (pr.status != PathStatus::kOk) {
        paths_.erase(me.id);
        bands_.erase(me.id);
        out.status = fromPathStatus(pr.status);
        return out;
      }
      paths_[me.id] = {goal_pos, pr.path, pr.status, blocked};
      bands_.erase(me.id);  // a new path invalidates the warm band
    }
    my_path = paths_[me.id].path;
    out.path_blocked = paths_[me.id].blocked;
  }

  // --- the planning agent's band ---
  TimedElasticBand my_band;
  PathJoin join;
  bool my_end_is_goal = true;
  bool cold_start = true;
  if (at_goal) {
    my_band = TimedElasticBand::single(me.pose);
  } else {
    const auto proj = projectOntoPath(my_path, my_pos);
    const double from_m = proj ? proj->arc_length_m : 0.0;
    const Path2 local = subPath(my_path, from_m, cfg.max_plan_length_m);
    my_end_is_goal = from_m + cfg.max_plan_length_m >= pathLength(my_path) - 1e-6;
    const double end_th =
        my_end_is_goal && !cfg.free_goal_heading && std::isfinite(req.goal.theta_rad)
            ? req.goal.theta_rad
            : pathHeadingAtEnd(local, me.pose.theta_rad);
    const Pose2 end{local.back().x(), local.back().y(), end_th};
    auto mem = bands_.find(me.id);
    if (allow_warm && mem != bands_.end() && mem->second.band.size() >= 2) {
      TimedElasticBand warm = mem->second.band;
      warm.pruneToStart(me.pose, std::max(0.0, req.stamp_s - mem->second.stamp_s));
      const bool near = warm.size() >= 2 &&
                        (warm.pose(1).position() - my_pos).norm() < cfg.warm_start_reset_dist_m &&
                        (warm.pose(warm.size() - 1).position() - end.position()).norm() <
                            cfg.warm_start_reset_dist_m;
      if (near) {
        warm.setEnd(end);
        my_band = std::move(warm);
        cold_start = false;
        if (used_warm != nullptr) *used_warm = true;
      }
    }
    if (cold_start) {
      TimedElasticBand::SpeedProfile prof;
      prof.start_speed_m_s = speedOf(me.velocity);
      prof.acc_m_s2 = my_kin.acc_lim_x_m_s2;
      prof.stop_at_end = my_end_is_goal;
      my_band =
          layOnPath(me, local, my_kin, my_kin.max_vel_x_m_s, cfg.dt_ref_s, end_th, prof, &join);
    }
  }
  out.agent_path = my_path;
  out.warm_started = !cold_start;

  // --- anticipated agents ---
  const double other_T_s = cfg.other_horizon_s > 0.0
                               ? cfg.other_horizon_s
                               : (my_band.size() >= 2 ? my_band.duration_s() : horizon_fallback_s);
  struct OtherWork {
    const OtherAgentInput* in;
    TimedElasticBand band;
    bool end_is_goal;
    double nominal_m_s;
    double radius_m;
  };
  std::vector<OtherWork> work;
  std::vector<OtherAgentResult> predicted;  ///< beyond max_planned_others (not optimised)
  auto valid = [](const AgentState& st) {
    return isFinite(st.pose) && std::isfinite(st.velocity.vx_m_s) &&
           std::isfinite(st.velocity.vy_m_s);
  };
  // The nearest max_planned_others by clearance (ties by id, so the choice does not depend on
  // the order of the request) are planned; the rest wait for a cycle in which they are nearer.
  std::vector<bool> planned(req.others.size(), false);
  {
    std::vector<std::pair<std::pair<double, std::int32_t>, std::size_t>> by_clearance;
    for (std::size_t i = 0; i < req.others.size(); ++i) {
      const AgentState& st = req.others[i].state;
      if (!valid(st)) continue;
      by_clearance.push_back(
          {{(st.pose.position() - my_pos).norm() - radiusOf(st, cfg) - my_radius, st.id}, i});
    }
    std::sort(by_clearance.begin(), by_clearance.end());
    const std::size_t n = std::min(by_clearance.size(),
                                   static_cast<std::size_t>(std::max(cfg.max_planned_others, 0)));
    for (std::size_t k = 0; k < n; ++k) planned[by_clearance[k].second] = true;
  }
  for (std::size_t oi = 0; oi < req.others.size(); ++oi) {
    const OtherAgentInput& o = req.others[oi];
    const AgentState& st = o.state;
    if (!valid(st)) {
      out.skipped_ids.push_back(st.id);
      continue;
    }
    // Beyond the nearest max_planned_others: a band predicted, not planned jointly (walked along
    // its reference at its speed), so that the assessors still see where it goes; no A* for it
    // (a straight line to its goal unless a path is known), so a crowd costs little.
    const bool predicted_only = !planned[oi];
    if (predicted_only) {
      out.unplanned_ids.push_back(st.id);
      bands_.erase(st.id);  // its warm band would be stale by the time it is planned again
    }
    const AgentKinematics& k = cfg.kinematics(st.kind);
    const double radius = radiusOf(st, cfg);
    const double nominal =
        std::min(std::max(k.min_nominal_vel_m_s, speedOf(st.velocity)), k.max_vel_x_m_s);
    const Eigen::Vector2d pos = st.pose.position();
    OtherAgentResult res;
    res.id = st.id;
    Path2 ref;
    if (o.reference_path.size() >= 2) {
      ref = o.reference_path;
    } else if (std::isfinite(o.goal.x_m) && std::isfinite(o.goal.y_m)) {
      const Eigen::Vector2d g = o.goal.position();
      auto it = paths_.find(st.id);
      bool reuse = false;
      if (it != paths_.end() && (it->second.goal - g).norm() < kSameGoal_m) {
        const auto proj = projectOntoPath(it->second.path, pos);
        reuse = proj && proj->distance_m < cfg.global_replan_dist_m;
      }
      if (!reuse && predicted_only) {
        ref = resamplePath({pos, g}, 0.1);
        res.reference_changed = true;
      } else {
        if (!reuse) {
          PathResult pr = global_->plan(pos, g, radius);
          if (pr.status != PathStatus::kOk) pr.path = resamplePath({pos, g}, 0.1);
          paths_[st.id] = {g, pr.path, pr.status};
          res.reference_changed = true;
        }
        ref = paths_[st.id].path;
        res.reference_status = paths_[st.id].status;
      }
    } else {
      // Unknown goal: constant-velocity prediction (CoHAN's const_vel mode).
      const Eigen::Vector2d v(st.velocity.vx_m_s, st.velocity.vy_m_s);
      const Eigen::Vector2d dir =
          v.norm() > 1e-3 ? Eigen::Vector2d(v.normalized()) : headingVector(st.pose.theta_rad);
      ref = resamplePath({pos, pos + dir * nominal * kConstVelHorizon_s}, 0.1);
      res.reference_changed = true;
    }
    if ((ref.back() - pos).norm() < cfg.xy_goal_tolerance_m) ref = {pos};
    const auto proj = projectOntoPath(ref, pos);
    const double from_m = proj ? proj->arc_length_m : 0.0;
    const double len_m = nominal * other_T_s * (1.0 + kOtherLengthMargin);
    const Path2 local = ref.size() >= 2 ? subPath(ref, from_m, len_m) : ref;
    const bool end_is_goal = from_m + len_m >= pathLength(ref) - 1e-6;
    const Pose2 end{local.back().x(), local.back().y(), pathHeadingAtEnd(local, st.pose.theta_rad)};
    TimedElasticBand band;
    bool have = false;
    auto mem = bands_.find(st.id);
    if (!predicted_only && allow_warm && mem != bands_.end() && mem->second.band.size() >= 2 &&
        !res.reference_changed) {
      TimedElasticBand warm = mem->second.band;
      warm.pruneToStart(st.pose, std::max(0.0, req.stamp_s - mem->second.stamp_s));
      if (warm.size() >= 2 &&
          (warm.pose(1).position() - pos).norm() < cfg.warm_start_reset_dist_m &&
          (warm.pose(warm.size() - 1).position() - end.position()).norm() <
              cfg.warm_start_reset_dist_m) {
        warm.setEnd(end);
        band = std::move(warm);
        have = true;
        if (used_warm != nullptr) *used_warm = true;
      }
    }
    if (!have) {
      TimedElasticBand::SpeedProfile prof;
      prof.start_speed_m_s = speedOf(st.velocity);
      prof.acc_m_s2 = k.acc_lim_x_m_s2;
      prof.stop_at_end = end_is_goal;
      // Laid from the human's own pose, the hop to its reference path included (the robot's
      // band is joined to its path smoothly instead): the anticipated band starts where the
      // human is. Where a round-2 decision rests on CM ≈ d_h (a facilitating human in the
      // 2.25 m corridor), t_CROSS's small dependence on this start can decide it.
      band = TimedElasticBand::fromPath(st.pose, local, nominal, cfg.dt_ref_s, end.theta_rad, prof);
    }
    res.reference_path = ref;
    if (predicted_only) {
      res.band = band.toBand();
      res.predicted = true;
      predicted.push_back(std::move(res));
      continue;
    }
    out.others.push_back(res);
    work.push_back({&o, std::move(band), end_is_goal, nominal, radius});
  }
  // After the planned ones (whose order matches work's), whatever is returned below.
  const auto addPredicted = [&] {
    for (auto& p : predicted) out.others.push_back(std::move(p));
  };

  if (at_goal) {
    // Anticipated bands as initialised (nothing to negotiate with a standing agent).
    out.status = PlanStatus::kGoalReached;
    out.agent_band = my_band.toBand();
    for (std::size_t i = 0; i < work.size(); ++i) out.others[i].band = work[i].band.toBand();
    bands_.erase(me.id);
    addPredicted();
    return out;
  }

  bool joined = false;
  // --- symmetry break on a cold start: an exactly head-on pair has no lateral gradient ---
  if (cold_start && my_band.size() > 2) {
    for (const auto& w : work) {
      const auto pairs = pairByTime(my_band, w.band);
      double best = std::numeric_limits<double>::infinity();
      std::size_t bi = 0;
      Eigen::Vector2d other_at_best(0.0, 0.0);
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        if (!pairs[i]) continue;
        const double s = pairs[i]->fraction;
        const Eigen::Vector2d q = (1.0 - s) * w.band.pose(pairs[i]->segment).position() +
                                  s * w.band.pose(pairs[i]->segment + 1).position();
        const double d = (my_band.pose(i).position() - q).norm();
        if (d < best) {
          best = d, bi = i, other_at_best = q;
        }
      }
      const double needed = my_radius + w.radius_m + cfg.min_agent_robot_dist_m;
      if (!(best < needed) || bi == 0 || bi + 1 >= my_band.size()) continue;
      const Pose2 pm = my_band.pose(bi);
      const Eigen::Vector2d h = headingVector(pm.theta_rad);
      const Eigen::Vector2d left(-h.y(), h.x());
      const double lateral = cross2(h, other_at_best - pm.position());
      // Side away from the other; for a dead-on meeting the side with more room, a tie going
      // to the right (keep right).
      double side = lateral > 0.0 ? -1.0 : 1.0;
      const double room_l = map_->ray(pm.position(), left, 10.0).distance_m;
      const double room_r = map_->ray(pm.position(), -left, 10.0).distance_m;
      if (std::abs(lateral) <= kHeadOnLateral_m) side = room_l > room_r + 0.1 ? 1.0 : -1.0;
      // Amplitude: the planning agent is the one expected to make room ("minimal human
      // contribution"), so start it where the safety distance holds, within the free room.
      double amp = cfg.symmetry_break_offset_m;
      if (cfg.init_planning_band_aside) {
        amp = std::max(amp, needed + cfg.penalty_epsilon + 0.05 - std::abs(lateral));
      }
      // Others meeting the robot there too (people walking abreast, a group): the start goes
      // around all of them on that side, never between two of them, when the room allows;
      // else around them on the other side, if it fits there.
      const auto clearAll = [&](double sd, double a) {
        for (bool moved = true; moved;) {
          moved = false;
          for (const auto& w2 : work) {
            const auto loc = w2.band.locate(my_band.times_s()[bi]);
            if (!loc) continue;
            const Eigen::Vector2d at =
                (1.0 - loc->fraction) * w2.band.pose(loc->segment).position() +
                loc->fraction * w2.band.pose(loc->segment + 1).position();
            const double lat2 = cross2(h, at - pm.position());
            const double need2 = my_radius + w2.radius_m + cfg.min_agent_robot_dist_m;
            if (std::abs(sd * a - lat2) >= need2) continue;
            a = sd * lat2 + need2 + cfg.penalty_epsilon + 0.05;
            moved = true;
          }
        }
        return a;
      };
      const double room_side = (side > 0.0 ? room_l : room_r) - my_radius - cfg.min_obstacle_dist_m;
      const double around = clearAll(side, amp);
      if (around <= room_side) {
        amp = around;
      } else {
        const double room_other =
            (side > 0.0 ? room_r : room_l) - my_radius - cfg.min_obstacle_dist_m;
        const double around_other = clearAll(-side, needed + cfg.penalty_epsilon + 0.05);
        if (around_other <= room_other) {
          side = -side;
          amp = around_other;
        }
      }
      const double room = (side > 0.0 ? room_l : room_r) - my_radius - cfg.min_obstacle_dist_m;
      amp = std::clamp(amp, 0.0, std::max(room, 0.0));
      const auto t = my_band.times_s();
      // Smoothstep ramps (3u² − 2u³, peak lateral acceleration 6·amp/T²) long enough for the
      // lateral acceleration limit, full offset from half-way to the meeting until 1 s after
      // it: the optimiser usually slows the planning agent (relative-velocity term), which
      // moves the meeting earlier along its path than this constant-speed guess predicts.
      const double ramp_s = lateralRampTime_s(amp, my_kin);
      const double t_end = t.back();
      const double up_s = std::clamp(ramp_s, 1.0, std::max(1.0, 0.8 * t[bi]));
      const double t_hi = std::max(t[bi] + 1.0, up_s);
      const double down_s = std::clamp(t_end - t_hi, 0.5, ramp_s);
      auto smooth = [](double u) {
        u = std::clamp(u, 0.0, 1.0);
        return u * u * (3.0 - 2.0 * u);
      };
      for (std::size_t i = 1; i + 1 < my_band.size(); ++i) {
        const double w_up = smooth(t[i] / up_s);
        const double w_down = 1.0 - smooth((t[i] - t_hi) / down_s);
        const double off = side * amp * std::min(w_up, w_down);
        Pose2 p = my_band.pose(i);
        p.x_m += off * left.x();
        p.y_m += off * left.y();
        my_band.setPose(i, p);
      }
      // The join over the same up-ramp: with it the offset runs from where the robot is, at
      // the speed it has, to the swerve (a cubic Hermite: 1 - smoothstep and smoothstep).
      applyJoin(join, up_s, &my_band);
      joined = true;
      break;  // one offset suffices; the optimiser does the rest
    }
  }

  if (!joined) applyJoin(join, joinBlendTime(join, my_kin), &my_band);

  // --- joint optimisation ---
  std::vector<BandAgent> agents;
  agents.reserve(1 + work.size());
  {
    BandAgent a;
    a.id = me.id;
    a.is_robot = me.kind == AgentKind::kRobot;
    a.band = &my_band;
    a.weights = cfg.planning_weights;
    a.limits = makeMotionLimits(my_kin, a.weights, cfg.penalty_epsilon, 0.0);
    a.radius_m = my_radius;
    a.start_velocity_body = toBodyFrame(me.velocity, me.pose.theta_rad);
    a.end_is_goal = my_end_is_goal;
    a.reference = &out.agent_path;
    agents.push_back(a);
  }
  for (std::size_t i = 0; i < work.size(); ++i) {
    const AgentState& st = work[i].in->state;
    BandAgent a;
    a.id = st.id;
    a.is_robot = st.kind == AgentKind::kRobot;
    a.band = &work[i].band;
    a.weights = cfg.other_weights;
    a.limits = makeMotionLimits(cfg.kinematics(st.kind), a.weights, cfg.penalty_epsilon,
                                work[i].nominal_m_s);
    a.radius_m = work[i].radius_m;
    a.start_velocity_body = toBodyFrame(st.velocity, st.pose.theta_rad);
    a.end_is_goal = work[i].end_is_goal;
    a.reference = &out.others[i].reference_path;
    agents.push_back(a);
  }
  // Obstacles of the moment only where there are some: without them the solve is the static
  // map's, bit for bit.
  std::optional<PointObstacleMap> with_points;
  if (!req.obstacle_points.empty()) with_points.emplace(*map_, req.obstacle_points);
  const DistanceMap& obstacles =
      with_points ? static_cast<const DistanceMap&>(*with_points) : *map_;
  const OptimizeStats stats =
      optimizeBands(agents, obstacles, cfg, req.max_iterations, req.time_budget_s, req.clock_s);
  out.iterations = stats.iterations;
  out.accepted_steps = stats.accepted;
  out.final_cost = stats.final_cost;
  out.solver_time_s = stats.solver_time_s;
  out.budget_exhausted = stats.budget_exhausted;
  out.term_costs = stats.terms;

  // --- outputs and warm-start memory ---
  out.agent_band = my_band.toBand();
  out.command_body = bandCommand(my_band, my_kin);
  bands_[me.id] = {my_band, req.stamp_s};
  for (std::size_t i = 0; i < work.size(); ++i) {
    out.others[i].band = work[i].band.toBand();
    bands_[work[i].in->state.id] = {work[i].band, req.stamp_s};
  }
  addPredicted();
  out.status = PlanStatus::kOk;
  return out;
}

}  // namespace coopnav
