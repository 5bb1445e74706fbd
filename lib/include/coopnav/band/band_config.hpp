#pragma once
/// @file Configuration of the dual time-elastic-band planner (CoHAN-style, Singamaneni et al.
/// 2021, arXiv 2106.09971; TEB: Rösmann et al. 2013/2015). In-class defaults are CoHAN 2.0's
/// simulation values (`LAAS-HRI/CoHAN2.0`, `config/robot/hateb_local_planner_params.yaml`;
/// HATEB's `hateb_config.h` defaults where it sets none) unless a comment says why we differ.
/// Defaults live here and only here; the daemon's YAML overrides them key by key.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// The allowed values of a numeric key: [lo, hi], or (lo, hi] when lo_open.
struct KeyRange {
  double lo;
  double hi;
  bool lo_open{false};
};
/// The allowed values of a string key.
struct KeyChoices {
  std::vector<std::string> values;
};

// Every key of the planner's configuration is declared once, in forEachKey below: its name, its
// field and, for a number, its allowed range. validate() checks the ranges; the daemons' YAML
// adapter (daemons/common/config/band_config_yaml.hpp) reads the keys. `f` is called, in the
// YAML's order, as f(name, field) for a flag, f(name, field, KeyRange) for a number,
// f(name, field, KeyChoices) for a string and f(name, nested) for a nested mapping
// (AgentKinematics, BandWeights). `Self` is the struct, const or not.

/// Kinematic limits of one agent kind. Body frame: x forward, y left.
struct AgentKinematics {
  bool holonomic{true};       ///< false: differential drive (vy = 0, non-holonomic term)
  double max_vel_x_m_s{0.7};  ///< forward speed limit
  double max_vel_x_backwards_m_s{0.4};
  double max_vel_y_m_s{0.7};  ///< lateral speed limit (holonomic only)
  double max_vel_theta_rad_s{1.2};
  double acc_lim_x_m_s2{0.3};
  double acc_lim_y_m_s2{0.3};
  double acc_lim_theta_rad_s2{0.4};
  /// The nominal-speed term pulls an anticipated band to max(this, tracked speed) (CoHAN:
  /// max(0.3, 5-sample average), ros.cpp l.771).
  double min_nominal_vel_m_s{0.3};
  double radius_m{0.34};  ///< default disc radius when the request gives none (<= 0)

  template <class Self, class F>
  static void forEachKey(Self& k, F&& f) {
    f("holonomic", k.holonomic);
    f("max_vel_x_m_s", k.max_vel_x_m_s, KeyRange{0.0, 10.0, true});
    f("max_vel_x_backwards_m_s", k.max_vel_x_backwards_m_s, KeyRange{0.0, 10.0});
    f("max_vel_y_m_s", k.max_vel_y_m_s, KeyRange{0.0, 10.0});
    f("max_vel_theta_rad_s", k.max_vel_theta_rad_s, KeyRange{0.0, 20.0, true});
    f("acc_lim_x_m_s2", k.acc_lim_x_m_s2, KeyRange{0.0, 20.0, true});
    f("acc_lim_y_m_s2", k.acc_lim_y_m_s2, KeyRange{0.0, 20.0, true});
    f("acc_lim_theta_rad_s2", k.acc_lim_theta_rad_s2, KeyRange{0.0, 50.0, true});
    f("min_nominal_vel_m_s", k.min_nominal_vel_m_s, KeyRange{0.0, 10.0});
    f("radius_m", k.radius_m, KeyRange{0.0, 5.0, true});
  }
};

/// CoHAN 2.0 sim agent (human) limits: 1.3 / 0.4 / 1.1 m/s, acc 0.6 / 0.3 / 0.8, radius 0.30.
inline AgentKinematics defaultHumanKinematics() {
  AgentKinematics k;
  k.holonomic = true;
  k.max_vel_x_m_s = 1.3;
  k.max_vel_x_backwards_m_s = 0.2;  // not in CoHAN's table; a small step back is human
  k.max_vel_y_m_s = 0.4;
  k.max_vel_theta_rad_s = 1.1;
  k.acc_lim_x_m_s2 = 0.6;
  k.acc_lim_y_m_s2 = 0.3;
  k.acc_lim_theta_rad_s2 = 0.8;
  k.radius_m = 0.30;
  return k;
}

/// Cost weights of one band (g2o information = weight, i.e. cost = weight * e^2).
struct BandWeights {
  double max_vel_x{2.0};
  double max_vel_y{2.0};
  double max_vel_theta{1.0};
  double acc_lim_x{1.0};
  double acc_lim_y{1.0};
  double acc_lim_theta{1.0};
  double nominal_vel{0.0};  ///< CoHAN `weight_agent_nominal_vel` (humans: 2)
  double optimaltime{1.0};
  double viapoint{0.05};
  double obstacle{50.0};
  /// Non-holonomic term. CoHAN 2.0 sim uses 1.0 for its omni PR2; for a differential-drive agent
  /// the planner uses `kinematics_nh_diff_drive` instead (with 1.0 a differential-drive band
  /// jumps sideways, where the velocity term does not see it: segments reach 5 m/s).
  double kinematics_nh{1.0};
  double kinematics_nh_diff_drive{1000.0};
  double kinematics_forward_drive{100.0};  ///< diff drive only (CoHAN code default)

  template <class Self, class F>
  static void forEachKey(Self& w, F&& f) {
    const KeyRange weight{0.0, 1e6};
    f("max_vel_x", w.max_vel_x, weight);
    f("max_vel_y", w.max_vel_y, weight);
    f("max_vel_theta", w.max_vel_theta, weight);
    f("acc_lim_x", w.acc_lim_x, weight);
    f("acc_lim_y", w.acc_lim_y, weight);
    f("acc_lim_theta", w.acc_lim_theta, weight);
    f("nominal_vel", w.nominal_vel, weight);
    f("optimaltime", w.optimaltime, weight);
    f("viapoint", w.viapoint, weight);
    f("obstacle", w.obstacle, weight);
    f("kinematics_nh", w.kinematics_nh, weight);
    f("kinematics_nh_diff_drive", w.kinematics_nh_diff_drive, weight);
    f("kinematics_forward_drive", w.kinematics_forward_drive, weight);
  }
};

/// CoHAN 2.0 sim agent weights: max_vel 4, acc 2, nominal 2, optimaltime 3, viapoint 0.5.
inline BandWeights defaultOtherWeights() {
  BandWeights w;
  w.max_vel_x = 4.0;
  w.max_vel_y = 4.0;
  w.acc_lim_x = 2.0;
  w.acc_lim_y = 2.0;
  w.acc_lim_theta = 2.0;
  w.nominal_vel = 2.0;
  w.optimaltime = 3.0;
  w.viapoint = 0.5;
  return w;
}

/// Whole planner configuration. Names carry units; weights are dimensionless.
struct BandPlannerConfig {
  // --- band resolution (CoHAN 2.0 sim) ---
  double dt_ref_s{0.125};
  double dt_hysteresis_s{0.0125};
  int min_samples{3};
  int max_samples{500};
  /// Smallest ΔT the optimiser may use (TEB keeps ΔT > 0 by a bound; we use a penalty + clamp).
  double dt_min_s{0.01};

  // --- horizon ---
  /// Robot plan cut (CoHAN 2.0: 0.9 * costmap half-size = 6.75 m).
  double max_plan_length_m{6.75};
  /// Anticipated agents' bands cover this many seconds; <= 0: the planning agent's band duration
  /// (poses past the other band's end pair with nothing, so they would only cost time).
  double other_horizon_s{0.0};
  /// Others planned jointly per cycle, the nearest first (clearance, ties by id); the rest get no
  /// band this cycle (PlanResult::unplanned_ids) and so no assessment. The joint factorisation
  /// grows faster than the number of bands it couples (bench_band: 5 humans take 4.6x the time
  /// of one; 64 take over 2 min a cycle), so a crowd must not stall the robot's planner. CoHAN
  /// predicts at most 2 moving humans per cycle.
  int max_planned_others{5};

  // --- optimisation (CoHAN 2.0 sim: 8 inner x 4 outer, weight_adapt_factor 2) ---
  int no_inner_iterations{8};
  int no_outer_iterations{4};
  double weight_adapt_factor{2.0};
  /// sparse_lm's first damping of each outer iteration, λ₀ = this · max diag(JᵀJ) (Madsen,
  /// Nielsen & Tingleff 2004, eq. 3.14); 0: λ₀ = 1 whatever the problem's scale (Ceres' start,
  /// the default). The band problem's accepted damping is ~1e-2 of its largest diagonal entry
  /// (bench_band), so from λ₀ = 1 the first 3 of every 8 solves are rejected while λ climbs; a
  /// scale-aware start takes more steps per budget but changes the narrow-corridor bands enough
  /// to move the paper's round-2 decision there.
  double initial_damping_scale{0.0};
  double penalty_epsilon{0.01};
  /// Last cycle's bands as a second candidate beside fresh ones, the cheaper kept (twice the
  /// solves; DualBandPlanner::plan says why). CoHAN 2.0 disables warm starts.
  bool warm_start{true};
  /// Least-squares solver: "sparse_lm" (ours, sparse_lm.hpp: single-threaded, deterministic)
  /// or "ceres" (Ceres' sparse normal Cholesky LM, tuned as band_optimizer.cpp says). Same
  /// residual blocks; bench_band compares the two.
  std::string solver{"sparse_lm"};
  /// Re-initialise a warm band whose start is farther than this from the agent [m].
  double warm_start_reset_dist_m{1.0};

  // --- agents: limits by kind (AgentState::kind), weights by role in the plan ---
  AgentKinematics robot{};  ///< CoHAN 2.0 sim PR2 (omni): 0.7 / 0.4 / 0.7 / 1.2, acc 0.3 / 0.4
  AgentKinematics human{defaultHumanKinematics()};
  /// Weights of the planning agent's band (the robot in band_source; the simulated human when
  /// world_sim runs the planner for a "facilitating" human, the robot then being an "other").
  BandWeights planning_weights{};
  /// Weights of anticipated agents' bands: held to their path 10x harder, time 3x, nominal
  /// speed 2 -> "minimal human contribution" (paper §II-A).
  BandWeights other_weights{defaultOtherWeights()};

  // --- obstacles ---
  double min_obstacle_dist_m{0.2};  ///< clearance from the agent's disc edge

  // --- coupling (CoHAN 2.0 sim) ---
  double min_agent_robot_dist_m{0.6};  ///< disc edge to disc edge
  double min_agent_agent_dist_m{0.4};
  double weight_agent_robot_safety{5.0};
  double weight_agent_agent_safety{2.0};
  double rel_vel_cost_threshold{1.5};
  double weight_agent_robot_rel_vel{5.0};
  /// The relative-velocity term acts on a time-paired pose pair only while the pair's
  /// edge-to-edge distance is below this [m] (<= 0: at any range). Why: CoHAN's cost
  /// c = closing speed + (|v_r| + 1)/|d| exceeds the 1.5 threshold head-on at ANY range
  /// (0.7 + 1.0 m/s closing), so ungated it makes the robot crawl from 14 m away (measured:
  /// first band 6.75 m over 17.9 s instead of 11.3 s, closed-loop speed ~0.3 m/s), while the
  /// paper's CoHAN robot keeps moving and bends aside. Gated like CoHAN's 2.0 m safety gate, but
  /// per pair (we pair by time), so the term still shapes the bands where they meet.
  double rel_vel_activation_dist_m{2.0};
  /// Safety term only while agents are closer than this now [m]; CoHAN hard-codes 2.0 because
  /// it pairs by index. We pair by time, so the term is safe to keep always (<= 0: always).
  double safety_activation_dist_m{0.0};
  /// Lateral offset given to the planning band at a predicted head-on meeting, to break the
  /// exact symmetry (two poses on one point: no lateral gradient, and the relative-velocity
  /// term's 1/|d| blows up) [m].
  double symmetry_break_offset_m{0.3};
  /// On a cold start, place the planning band aside by the full safety separation at the
  /// predicted meeting (within the free room): the optimum under "minimal human contribution"
  /// lies there, and LM from the centre line ends in a local minimum where both bands bend.
  bool init_planning_band_aside{true};

  // --- goal / command ---
  double xy_goal_tolerance_m{0.2};
  double yaw_goal_tolerance_rad{0.2};
  bool free_goal_heading{true};  ///< goal heading follows the path, not the requested theta

  // --- global planner ---
  double global_resolution_m{0.1};
  double global_clearance_pref_m{0.5};  ///< beyond radius: clearance the path likes to keep
  double global_clearance_weight{2.0};
  double global_replan_dist_m{0.75};  ///< re-plan when the agent strays this far from its path

  /// Errors found by validate(): key, offending value and allowed range, one per problem.
  struct Error {
    std::string key;
    double value;
    std::string allowed;
  };
  /// Checks every key; empty when the configuration is usable.
  std::vector<Error> validate() const;

  template <class Self, class F>
  static void forEachKey(Self& c, F&& f) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    f("dt_ref_s", c.dt_ref_s, KeyRange{0.0, 2.0, true});
    f("dt_hysteresis_s", c.dt_hysteresis_s, KeyRange{0.0, c.dt_ref_s});
    f("min_samples", c.min_samples, KeyRange{2, 10000});
    f("max_samples", c.max_samples,
      KeyRange{static_cast<double>(std::max(c.min_samples, 2)), 10000});
    f("dt_min_s", c.dt_min_s, KeyRange{0.0, c.dt_ref_s, true});
    f("max_plan_length_m", c.max_plan_length_m, KeyRange{0.0, 1000.0, true});
    f("other_horizon_s", c.other_horizon_s, KeyRange{-kInf, 600.0});
    f("max_planned_others", c.max_planned_others, KeyRange{1, 1000});
    f("no_inner_iterations", c.no_inner_iterations, KeyRange{1, 1000});
    f("no_outer_iterations", c.no_outer_iterations, KeyRange{1, 100});
    f("weight_adapt_factor", c.weight_adapt_factor, KeyRange{1.0, 100.0});
    f("initial_damping_scale", c.initial_damping_scale, KeyRange{0.0, 1e6});
    f("penalty_epsilon", c.penalty_epsilon, KeyRange{0.0, 1.0});
    f("warm_start", c.warm_start);
    f("solver", c.solver, KeyChoices{{"sparse_lm", "ceres"}});
    f("warm_start_reset_dist_m", c.warm_start_reset_dist_m, KeyRange{0.0, 100.0, true});
    f("robot", c.robot);
    f("human", c.human);
    f("planning_weights", c.planning_weights);
    f("other_weights", c.other_weights);
    f("min_obstacle_dist_m", c.min_obstacle_dist_m, KeyRange{0.0, 10.0});
    f("min_agent_robot_dist_m", c.min_agent_robot_dist_m, KeyRange{0.0, 10.0});
    f("min_agent_agent_dist_m", c.min_agent_agent_dist_m, KeyRange{0.0, 10.0});
    f("weight_agent_robot_safety", c.weight_agent_robot_safety, KeyRange{0.0, 1e6});
    f("weight_agent_agent_safety", c.weight_agent_agent_safety, KeyRange{0.0, 1e6});
    f("rel_vel_cost_threshold", c.rel_vel_cost_threshold, KeyRange{0.0, 1e3});
    f("weight_agent_robot_rel_vel", c.weight_agent_robot_rel_vel, KeyRange{0.0, 1e6});
    f("rel_vel_activation_dist_m", c.rel_vel_activation_dist_m, KeyRange{-kInf, 1e3});
    f("safety_activation_dist_m", c.safety_activation_dist_m, KeyRange{-kInf, 1e3});
    f("symmetry_break_offset_m", c.symmetry_break_offset_m, KeyRange{0.0, 5.0});
    f("init_planning_band_aside", c.init_planning_band_aside);
    f("xy_goal_tolerance_m", c.xy_goal_tolerance_m, KeyRange{0.0, 10.0, true});
    f("yaw_goal_tolerance_rad", c.yaw_goal_tolerance_rad, KeyRange{0.0, M_PI, true});
    f("free_goal_heading", c.free_goal_heading);
    f("global_resolution_m", c.global_resolution_m, KeyRange{0.01, 2.0});
    f("global_clearance_pref_m", c.global_clearance_pref_m, KeyRange{0.0, 10.0});
    f("global_clearance_weight", c.global_clearance_weight, KeyRange{0.0, 1e3});
    f("global_replan_dist_m", c.global_replan_dist_m, KeyRange{0.0, 100.0, true});
  }

  /// Limits of an agent of this kind.
  const AgentKinematics& kinematics(AgentKind kind) const {
    return kind == AgentKind::kRobot ? robot : human;
  }
};

}  // namespace coopnav
