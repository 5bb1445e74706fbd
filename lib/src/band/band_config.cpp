#include "coopnav/band/band_config.hpp"

#include <cmath>
#include <limits>

namespace coopnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

class Checker {
 public:
  explicit Checker(std::vector<BandPlannerConfig::Error>* out) : out_(out) {}
  /// value must lie in [lo, hi] (open ends when lo_open / hi_open).
  void range(const std::string& key, double v, double lo, double hi, bool lo_open = false) {
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok) {
      std::string allowed = (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
      out_->push_back({key, v, allowed});
    }
  }

 private:
  static std::string fmt(double v) {
    if (v == kInf) return "inf";
    std::string s = std::to_string(v);
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  }
  std::vector<BandPlannerConfig::Error>* out_;
};

void checkKinematics(Checker& c, const std::string& p, const AgentKinematics& k) {
  c.range(p + ".max_vel_x_m_s", k.max_vel_x_m_s, 0.0, 10.0, true);
  c.range(p + ".max_vel_x_backwards_m_s", k.max_vel_x_backwards_m_s, 0.0, 10.0);
  c.range(p + ".max_vel_y_m_s", k.max_vel_y_m_s, 0.0, 10.0);
  c.range(p + ".max_vel_theta_rad_s", k.max_vel_theta_rad_s, 0.0, 20.0, true);
  c.range(p + ".acc_lim_x_m_s2", k.acc_lim_x_m_s2, 0.0, 20.0, true);
  c.range(p + ".acc_lim_y_m_s2", k.acc_lim_y_m_s2, 0.0, 20.0, true);
  c.range(p + ".acc_lim_theta_rad_s2", k.acc_lim_theta_rad_s2, 0.0, 50.0, true);
  c.range(p + ".min_nominal_vel_m_s", k.min_nominal_vel_m_s, 0.0, 10.0);
  c.range(p + ".radius_m", k.radius_m, 0.0, 5.0, true);
}

void checkWeights(Checker& c, const std::string& p, const BandWeights& w) {
  const std::pair<const char*, double> all[] = {
      {"max_vel_x", w.max_vel_x},
      {"max_vel_y", w.max_vel_y},
      {"max_vel_theta", w.max_vel_theta},
      {"acc_lim_x", w.acc_lim_x},
      {"acc_lim_y", w.acc_lim_y},
      {"acc_lim_theta", w.acc_lim_theta},
      {"nominal_vel", w.nominal_vel},
      {"optimaltime", w.optimaltime},
      {"viapoint", w.viapoint},
      {"obstacle", w.obstacle},
      {"kinematics_nh", w.kinematics_nh},
      {"kinematics_nh_diff_drive", w.kinematics_nh_diff_drive},
      {"kinematics_forward_drive", w.kinematics_forward_drive}};
  for (const auto& [k, v] : all) c.range(p + "." + k, v, 0.0, 1e6);
}

}  // namespace

std::vector<BandPlannerConfig::Error> BandPlannerConfig::validate() const {
  std::vector<Error> errors;
  Checker c(&errors);
  c.range("dt_ref_s", dt_ref_s, 0.0, 2.0, true);
  c.range("dt_hysteresis_s", dt_hysteresis_s, 0.0, dt_ref_s);
  c.range("min_samples", min_samples, 2, 10000);
  c.range("max_samples", max_samples, std::max(min_samples, 2), 10000);
  c.range("dt_min_s", dt_min_s, 0.0, dt_ref_s, true);
  c.range("max_plan_length_m", max_plan_length_m, 0.0, 1000.0, true);
  c.range("other_horizon_s", other_horizon_s, -kInf, 600.0);
  c.range("max_planned_others", max_planned_others, 1, 1000);
  c.range("no_inner_iterations", no_inner_iterations, 1, 1000);
  c.range("no_outer_iterations", no_outer_iterations, 1, 100);
  c.range("weight_adapt_factor", weight_adapt_factor, 1.0, 100.0);
  c.range("initial_damping_scale", initial_damping_scale, 0.0, 1e6);
  c.range("penalty_epsilon", penalty_epsilon, 0.0, 1.0);
  c.range("warm_start_reset_dist_m", warm_start_reset_dist_m, 0.0, 100.0, true);
  if (solver != "sparse_lm" && solver != "ceres") {
    errors.push_back({"solver", std::numeric_limits<double>::quiet_NaN(), "sparse_lm | ceres"});
  }
  checkKinematics(c, "robot", robot);
  checkKinematics(c, "human", human);
  checkWeights(c, "planning_weights", planning_weights);
  checkWeights(c, "other_weights", other_weights);
  c.range("min_obstacle_dist_m", min_obstacle_dist_m, 0.0, 10.0);
  c.range("min_agent_robot_dist_m", min_agent_robot_dist_m, 0.0, 10.0);
  c.range("min_agent_agent_dist_m", min_agent_agent_dist_m, 0.0, 10.0);
  c.range("weight_agent_robot_safety", weight_agent_robot_safety, 0.0, 1e6);
  c.range("weight_agent_agent_safety", weight_agent_agent_safety, 0.0, 1e6);
  c.range("rel_vel_cost_threshold", rel_vel_cost_threshold, 0.0, 1e3);
  c.range("weight_agent_robot_rel_vel", weight_agent_robot_rel_vel, 0.0, 1e6);
  c.range("rel_vel_activation_dist_m", rel_vel_activation_dist_m, -kInf, 1e3);
  c.range("safety_activation_dist_m", safety_activation_dist_m, -kInf, 1e3);
  c.range("symmetry_break_offset_m", symmetry_break_offset_m, 0.0, 5.0);
  c.range("xy_goal_tolerance_m", xy_goal_tolerance_m, 0.0, 10.0, true);
  c.range("yaw_goal_tolerance_rad", yaw_goal_tolerance_rad, 0.0, M_PI, true);
  c.range("global_resolution_m", global_resolution_m, 0.01, 2.0);
  c.range("global_clearance_pref_m", global_clearance_pref_m, 0.0, 10.0);
  c.range("global_clearance_weight", global_clearance_weight, 0.0, 1e3);
  c.range("global_replan_dist_m", global_replan_dist_m, 0.0, 100.0, true);
  return errors;
}

}  // namespace coopnav
