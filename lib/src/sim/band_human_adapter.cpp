#include "coopnav/sim/band_human_adapter.hpp"

#include <cmath>
#include <limits>

namespace coopnav::sim {

DualBandHumanAdapter::DualBandHumanAdapter(BandPlannerConfig config,
                                           std::shared_ptr<const DistanceMap> map,
                                           double replan_period_s)
    : planner_(std::move(config), std::move(map)), replan_period_s_(replan_period_s) {}

std::optional<Velocity2> DualBandHumanAdapter::plan(const BehaviourContext& ctx) {
  if (ctx.self == nullptr) return std::nullopt;
  if (last_world_ && ctx.t_s < next_plan_s_) return last_world_;
  PlanRequest req;
  req.stamp_s = ctx.t_s;
  req.agent = *ctx.self;
  req.goal = ctx.goal;
  if (ctx.robot != nullptr) {
    OtherAgentInput robot;
    robot.state = *ctx.robot;
    // The human does not know the robot's goal: constant-velocity anticipation.
    robot.goal = {std::numeric_limits<double>::quiet_NaN(),
                  std::numeric_limits<double>::quiet_NaN(), 0.0};
    req.others.push_back(robot);
  }
  last_result_ = planner_.plan(req);
  next_plan_s_ = ctx.t_s + replan_period_s_;
  if (last_result_.status != PlanStatus::kOk) {
    last_world_.reset();
    return std::nullopt;
  }
  // The planner commands in the body frame; the simulator wants a world-frame velocity.
  const Velocity2& b = last_result_.command_body;
  const double th = ctx.self->pose.theta_rad;
  const double c = std::cos(th), s = std::sin(th);
  last_world_ = Velocity2{c * b.vx_m_s - s * b.vy_m_s, s * b.vx_m_s + c * b.vy_m_s, 0.0};
  return last_world_;
}

PlannerAdapterFactory dualBandAdapterFactory(BandPlannerConfig config,
                                             std::shared_ptr<const DistanceMap> map) {
  return [config, map](const FacilitatingParams&) -> std::unique_ptr<HumanPlannerAdapter> {
    return std::make_unique<DualBandHumanAdapter>(config, map);
  };
}

}  // namespace coopnav::sim
