#pragma once
/// @file The planner-backed "facilitating" human (paper §III: "simulated by another CoHAN
/// instance"): the dual-band planner plans for the human, with the robot as the anticipated
/// other agent, and the human walks the first segment of its band.

#include <memory>
#include <optional>

#include "coopnav/band/dual_band_planner.hpp"
#include "coopnav/sim/behaviour.hpp"

namespace coopnav::sim {

/// HumanPlannerAdapter over DualBandPlanner. Replans every replan_period_s of sim time (CoHAN's
/// 10 Hz control rate) and holds the command in between; returns nullopt when the planner has no
/// plan (the facilitating behaviour then falls back to its analytic model).
class DualBandHumanAdapter final : public HumanPlannerAdapter {
 public:
  DualBandHumanAdapter(BandPlannerConfig config, std::shared_ptr<const DistanceMap> map,
                       double replan_period_s = 0.1);
  std::optional<Velocity2> plan(const BehaviourContext& ctx) override;
  /// Last planner result (for logs and tests).
  const PlanResult& lastResult() const { return last_result_; }

 private:
  DualBandPlanner planner_;
  double replan_period_s_;
  double next_plan_s_{-1.0};
  std::optional<Velocity2> last_world_;
  PlanResult last_result_;
};

/// A PlannerAdapterFactory building one DualBandHumanAdapter per facilitating human.
PlannerAdapterFactory dualBandAdapterFactory(BandPlannerConfig config,
                                             std::shared_ptr<const DistanceMap> map);

}  // namespace coopnav::sim
