#pragma once
/// @file What the world holds beyond the robot's map, and the robot's laser that sees it:
/// the scenario's unmapped obstacles (in the world's distance field, so collisions
/// and rays see them as walls) and its `laser` section, one scan per step on COOPNAV_SCAN.

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "coopnav/sim/laser.hpp"
#include "coopnav/sim/random.hpp"
#include "scenario.hpp"

namespace coopnav::world_sim {

class WorldSensing {
 public:
  /// `laser_on`: the scenario's laser.enabled, unless the config turned it off.
  WorldSensing(const Scenario& scenario, bool laser_on);

  bool laserOn() const { return laser_.has_value(); }
  /// The scan of the robot (agents.front()) among the others (agents[1..], discs of their
  /// radius), stamped utime / step. Precondition: laserOn(). Draws the step's noise.
  laser_scan_t scan(const DistanceMap& world, const std::vector<AgentState>& agents,
                    std::int64_t utime, std::int64_t step);
  /// Notes the robot's clearance to the unmapped obstacles at this step.
  void noteRobot(const AgentState& robot, double t_s);
  bool hasUnmapped() const { return !unmapped_.empty(); }
  /// Least robot-body clearance to an unmapped obstacle so far [m] (+inf: none, or none noted).
  double minUnmappedClearance_m() const { return min_clearance_m_; }
  double minUnmappedClearanceT_s() const { return min_clearance_t_s_; }

 private:
  UnmappedObstaclesSpec unmapped_;
  std::optional<sim::LaserOptions> laser_;
  sim::Rng rng_;
  double min_clearance_m_{std::numeric_limits<double>::infinity()};
  double min_clearance_t_s_{0.0};
};

}  // namespace coopnav::world_sim
