#pragma once
/// @file YAML views of the band planner's and the dock mode machine's lib/ configs. lib/ stays free
/// of YAML and of the config visitor, so these adapters visit the lib structs' own fields: the lib
/// structs' in-class initialisers stay the only defaults, and the planner's own validate() is the
/// only range check of its keys (its errors are reported through the visitor's require(), under
/// the same dotted key names as in the YAML).
///
///   struct MyDaemonConfig {
///     BandPlannerConfigYaml planner;  // planner.config is a coopnav::BandPlannerConfig
///     template <class V> void visit(V& v) { v("planner", planner); }
///   };

#include <sstream>
#include <string>

#include "config/config.hpp"
#include "coopnav/band/band_config.hpp"
#include "coopnav/planning/dock.hpp"
#include "coopnav/planning/safety_guard.hpp"

namespace coopnav {

/// Visits an AgentKinematics it points to (keys as the field names).
struct AgentKinematicsYaml {
  AgentKinematics* k{nullptr};
  template <class V>
  void visit(V& v) {
    v("holonomic", k->holonomic);
    v("max_vel_x_m_s", k->max_vel_x_m_s);
    v("max_vel_x_backwards_m_s", k->max_vel_x_backwards_m_s);
    v("max_vel_y_m_s", k->max_vel_y_m_s);
    v("max_vel_theta_rad_s", k->max_vel_theta_rad_s);
    v("acc_lim_x_m_s2", k->acc_lim_x_m_s2);
    v("acc_lim_y_m_s2", k->acc_lim_y_m_s2);
    v("acc_lim_theta_rad_s2", k->acc_lim_theta_rad_s2);
    v("min_nominal_vel_m_s", k->min_nominal_vel_m_s);
    v("radius_m", k->radius_m);
  }
};

/// Visits a BandWeights it points to (keys as the field names).
struct BandWeightsYaml {
  BandWeights* w{nullptr};
  template <class V>
  void visit(V& v) {
    v("max_vel_x", w->max_vel_x);
    v("max_vel_y", w->max_vel_y);
    v("max_vel_theta", w->max_vel_theta);
    v("acc_lim_x", w->acc_lim_x);
    v("acc_lim_y", w->acc_lim_y);
    v("acc_lim_theta", w->acc_lim_theta);
    v("nominal_vel", w->nominal_vel);
    v("optimaltime", w->optimaltime);
    v("viapoint", w->viapoint);
    v("obstacle", w->obstacle);
    v("kinematics_nh", w->kinematics_nh);
    v("kinematics_nh_diff_drive", w->kinematics_nh_diff_drive);
    v("kinematics_forward_drive", w->kinematics_forward_drive);
  }
};

/// The whole planner config as a nested YAML mapping. Owns the lib struct, default-constructed.
struct BandPlannerConfigYaml {
  BandPlannerConfig config{};

  template <class V>
  void visit(V& v) {
    BandPlannerConfig& c = config;
    v("dt_ref_s", c.dt_ref_s);
    v("dt_hysteresis_s", c.dt_hysteresis_s);
    v("min_samples", c.min_samples);
    v("max_samples", c.max_samples);
    v("dt_min_s", c.dt_min_s);
    v("max_plan_length_m", c.max_plan_length_m);
    v("other_horizon_s", c.other_horizon_s);
    v("max_planned_others", c.max_planned_others);
    v("no_inner_iterations", c.no_inner_iterations);
    v("no_outer_iterations", c.no_outer_iterations);
    v("weight_adapt_factor", c.weight_adapt_factor);
    v("initial_damping_scale", c.initial_damping_scale);
    v("penalty_epsilon", c.penalty_epsilon);
    v("warm_start", c.warm_start);
    v("solver", c.solver, OneOf{{"sparse_lm", "ceres"}});
    v("warm_start_reset_dist_m", c.warm_start_reset_dist_m);
    AgentKinematicsYaml robot{&c.robot};
    AgentKinematicsYaml human{&c.human};
    v("robot", robot);
    v("human", human);
    BandWeightsYaml planning{&c.planning_weights};
    BandWeightsYaml other{&c.other_weights};
    v("planning_weights", planning);
    v("other_weights", other);
    v("min_obstacle_dist_m", c.min_obstacle_dist_m);
    v("min_agent_robot_dist_m", c.min_agent_robot_dist_m);
    v("min_agent_agent_dist_m", c.min_agent_agent_dist_m);
    v("weight_agent_robot_safety", c.weight_agent_robot_safety);
    v("weight_agent_agent_safety", c.weight_agent_agent_safety);
    v("rel_vel_cost_threshold", c.rel_vel_cost_threshold);
    v("weight_agent_robot_rel_vel", c.weight_agent_robot_rel_vel);
    v("rel_vel_activation_dist_m", c.rel_vel_activation_dist_m);
    v("safety_activation_dist_m", c.safety_activation_dist_m);
    v("symmetry_break_offset_m", c.symmetry_break_offset_m);
    v("init_planning_band_aside", c.init_planning_band_aside);
    v("xy_goal_tolerance_m", c.xy_goal_tolerance_m);
    v("yaw_goal_tolerance_rad", c.yaw_goal_tolerance_rad);
    v("free_goal_heading", c.free_goal_heading);
    v("global_resolution_m", c.global_resolution_m);
    v("global_clearance_pref_m", c.global_clearance_pref_m);
    v("global_clearance_weight", c.global_clearance_weight);
    v("global_replan_dist_m", c.global_replan_dist_m);
    for (const auto& e : c.validate()) {
      v.require(false, e.key,
                "= " + formatValue(e.value) + " is outside the allowed range " + e.allowed);
    }
  }

 private:
  static std::string formatValue(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
};

/// The dock / hold / retreat / resume machine's options and the room decision's, except those a
/// daemon derives so they cannot disagree: the goal tolerance (= planner xy_goal_tolerance_m: the
/// planner stops there, so a smaller tolerance would never be met) and the robot radius (the
/// agent state's, else planner robot.radius_m). Ranges here: lib/ has no validate() for these.
struct ModeMachineOptionsYaml {
  ModeMachineOptions options{};

  template <class V>
  void visit(V& v) {
    ModeMachineOptions& o = options;
    v("human_passed_margin_m", o.human_passed_margin_m, Range{0.0, 10.0});
    v("human_far_m", o.human_far_m, Range{0.5, 100.0});
    v("human_receding_m", o.human_receding_m, Range{0.0, 100.0});
    v("hold_timeout_s", o.hold_timeout_s, Range{0.1, 3600.0});
    v("wall_margin_m", o.dock.margin_m, Range{0.0, 2.0});
    v("search_range_m", o.dock.search_range_m, Range{0.1, 50.0});
    v("max_ahead_m", o.dock.max_ahead_m, Range{0.0, 20.0});
    v("candidate_step_m", o.dock.step_m, Range{0.01, 5.0});
    v("reached_tolerance_m", o.dock_reached_tolerance_m, Range{0.01, 1.0});
    v("passage_margin_m", o.room.passage_margin_m, Range{0.0, 2.0});
    v("wider_search_m", o.room.wider_search_m, Range{0.0, 100.0});
    v("wider_step_m", o.room.wider_step_m, Range{0.05, 5.0});
    v("reach_margin_s", o.room.reach_margin_s, Range{0.0, 30.0});
    v("closing_speed_m_s", o.room.closing_speed_m_s, Range{0.0, 2.0});
    v("retreat_lookahead_m", o.room.retreat_lookahead_m, Range{0.1, 10.0});
    v("retreat_min_room_m", o.room.retreat_min_room_m, Range{0.05, 5.0});
  }
};

/// The safety guard's options (lib/planning/safety_guard.hpp). Ranges here, as above.
struct GuardOptionsYaml {
  GuardOptions options{};

  template <class V>
  void visit(V& v) {
    GuardOptions& o = options;
    v("min_clearance_m", o.min_clearance_m, Range{0.0, 2.0});
    v("horizon_s", o.horizon_s, Range{0.1, 10.0});
    v("sample_dt_s", o.sample_dt_s, Range{0.01, 1.0});
    v("evade_gap_m", o.evade_gap_m, Range{0.0, 2.0});
    v("evade_wall_margin_m", o.evade_wall_margin_m, Range{0.0, 1.0});
    v.require(o.sample_dt_s <= o.horizon_s, "sample_dt_s", "must not exceed horizon_s");
  }
};

}  // namespace coopnav
