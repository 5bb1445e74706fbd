#pragma once
// The worked example of docs/architecture.md: a whole daemon on the step harness. Each lockstep
// step k it publishes the band source's velocity command of k, scaled down while a human is
// within `slow_radius_m` of the robot. test/node/example_daemon_test.cpp runs it.
#include <chrono>
#include <iterator>
#include <map>

#include "config/config.hpp"
#include "runtime/step_node.hpp"
#include "wire/conversions.hpp"

namespace coopnav::example {

struct SpeedLimiterConfig {
  double slow_radius_m{1.5};  ///< [m] a human this close slows the robot down
  double slow_factor{0.5};    ///< the command is multiplied by this meanwhile
  int gate_timeout_ms{2000};  ///< [ms] wait for the band source's command of a step
  template <class V>
  void visit(V& v) {
    v("slow_radius_m", slow_radius_m, Range{0.0, 20.0});
    v("slow_factor", slow_factor, Range{0.0, 1.0});
    v("gate_timeout_ms", gate_timeout_ms, Range{1, 600000});
  }
};

class SpeedLimiterNode {
 public:
  using Config = SpeedLimiterConfig;
  static constexpr const char* kOutput = "COOPNAV_ROBOT_CMD_LIMITED";

  SpeedLimiterNode(const Config& config, Runtime& runtime)
      : config_(config),
        // Step k runs once the band source acknowledged k with its command of k (not waited for
        // until the band source is heard from: a replay without it still runs).
        steps_(runtime, StepNodeOptions{{{"band_source", 0, {channels::kRobotCmd}, true}},
                                        std::chrono::milliseconds(config.gate_timeout_ms)}) {
    runtime.subscribe<velocity_command_t>(
        channels::kRobotCmd, [this](const velocity_command_t& m, std::int64_t) {
          steps_.input("band_source", channels::kRobotCmd, m.step, "cmd",
                       [&] { commands_[m.step] = fromLcm(m); });  // throws RejectedMessage
        });
    runtime.subscribe<agent_states_t>(
        channels::kAgentStates, [this](const agent_states_t& m, std::int64_t) {
          steps_.open("world_sim", channels::kAgentStates, m, [&]() -> StepNode::Work {
            const AgentStatesSnapshot states = fromLcm(m);  // throws RejectedMessage
            return [this, states](StepNode::Step& step) { limit(states, step); };
          });
        });
    runtime.setRunning();
  }

 private:
  /// Inputs of step k -> outputs of step k. The harness acknowledges the step afterwards.
  void limit(const AgentStatesSnapshot& states, StepNode::Step& step) {
    const auto it = commands_.find(step.step());
    if (it == commands_.end()) return;  // no command of this step: nothing to limit
    VelocityCommand c = it->second;
    commands_.erase(commands_.begin(), std::next(it));
    for (const AgentState& h : states.humans) {
      if ((h.pose.position() - states.robot.pose.position()).norm() < config_.slow_radius_m) {
        c.body.vx_m_s *= config_.slow_factor;
        c.body.vy_m_s *= config_.slow_factor;
        c.body.omega_rad_s *= config_.slow_factor;
        break;
      }
    }
    step.publish(kOutput, toLcm(c));
  }

  Config config_;
  std::map<std::int64_t, VelocityCommand> commands_;  ///< by step, until their step runs
  StepNode steps_;  ///< last: a step still held when the node goes away is not acknowledged
};

}  // namespace coopnav::example
