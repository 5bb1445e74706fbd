#pragma once
/// @file YAML views of the band planner's and the dock mode machine's lib/ configs. lib/ stays free
/// of YAML and of the config visitor; the planner's keys are declared once, in the lib structs'
/// forEachKey (name, field, range), which these adapters read and the planner's validate()
/// checks: the lib structs' in-class initialisers stay the only defaults, and validate() is the
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

/// Reads the keys the lib structs declare (forEachKey): a nested mapping through its own view,
/// a string with its choices; ranges are validate()'s (reported by BandPlannerConfigYaml).
template <class V>
struct BandKeysYaml;

/// Visits an AgentKinematics it points to (keys as the field names).
struct AgentKinematicsYaml {
  AgentKinematics* k{nullptr};
  template <class V>
  void visit(V& v) {
    AgentKinematics::forEachKey(*k, BandKeysYaml<V>{v});
  }
};

/// Visits a BandWeights it points to (keys as the field names).
struct BandWeightsYaml {
  BandWeights* w{nullptr};
  template <class V>
  void visit(V& v) {
    BandWeights::forEachKey(*w, BandKeysYaml<V>{v});
  }
};

template <class V>
struct BandKeysYaml {
  V& v;
  template <class T>
  void operator()(const char* key, T& field, const KeyRange& /*checked by validate()*/) const {
    v(key, field);
  }
  void operator()(const char* key, std::string& field, const KeyChoices& choices) const {
    v(key, field, OneOf{choices.values});
  }
  void operator()(const char* key, bool& flag) const { v(key, flag); }
  void operator()(const char* key, AgentKinematics& k) const {
    AgentKinematicsYaml view{&k};
    v(key, view);
  }
  void operator()(const char* key, BandWeights& w) const {
    BandWeightsYaml view{&w};
    v(key, view);
  }
};

/// The whole planner config as a nested YAML mapping. Owns the lib struct, default-constructed.
struct BandPlannerConfigYaml {
  BandPlannerConfig config{};

  template <class V>
  void visit(V& v) {
    BandPlannerConfig::forEachKey(config, BandKeysYaml<V>{v});
    for (const auto& e : config.validate()) {
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
    v("settle_tolerance_m", o.dock_settle_tolerance_m, Range{0.001, 1.0});
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
