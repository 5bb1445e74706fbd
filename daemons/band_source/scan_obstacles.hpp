#pragma once
/// @file The band source's obstacles of the moment (issue 45): the laser scans of COOPNAV_SCAN
/// (world_sim's simulated laser, or the robot's through coopnav_ros2_bridge) turned into map-frame
/// points for the safety guard (all of them, people's legs too) and the planner's obstacle term
/// (less the returns of tracked people, who are planned as agents).
///
/// Lockstep: the scan of step k is published by the world before the agent states of k and
/// counted in its ack of k, so the step gate holds step k until it is here (StepRequirement on
/// world_sim's COOPNAV_SCAN): step k always plans with the scan of k, whatever the arrival order.
/// A world without a laser counts none, and nothing waits. Free-running (step -1): the newest
/// scan, if it is no older than max_age_s in message time.

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "config/config.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "wire/conversions.hpp"
#include "wire/scan.hpp"

namespace coopnav {

struct ScanObstaclesConfig {
  /// Points farther than this from the robot are left out (they cannot matter within the
  /// guard's horizon or the band's first seconds, and each costs the solver) [m].
  double max_range_m{4.0};
  /// Free-running: a scan older than the agent states by more than this is not used [s].
  double max_age_s{0.5};
  /// Planner only: returns within a tracked human's radius plus this are that human's body and
  /// left to the agent terms; the guard keeps them [m].
  double people_margin_m{0.3};
  /// Returns within this of an obstacle of the static map are that obstacle (a wall the planner
  /// and the mode machine already know, docking included) and left out [m]: a few map cells plus
  /// the laser's noise.
  double map_margin_m{0.15};

  template <class V>
  void visit(V& v) {
    v("max_range_m", max_range_m, Range{0.1, 100.0});
    v("max_age_s", max_age_s, Range{0.0, 60.0});
    v("people_margin_m", people_margin_m, Range{0.0, 5.0});
    v("map_margin_m", map_margin_m, Range{0.0, 5.0});
  }
};

class ScanObstacles {
 public:
  explicit ScanObstacles(const ScanObstaclesConfig& config) : config_(config) {}

  /// A scan of step `r.step` (or the newest free-running one). Lockstep scans are kept until
  /// their step is planned; at most max_steps of them (the harness's own pending bound).
  void store(const LaserScanRecord& r, std::int64_t max_steps);

  /// The points for the states `s` (their step's scan, or the newest fresh one when free-running)
  /// within max_range_m of the robot and not on the static `map`; forgets the scans of steps up
  /// to s.step.
  struct Points {
    std::vector<Eigen::Vector2d> guard;    ///< every return near the robot
    std::vector<Eigen::Vector2d> planner;  ///< less the tracked people's
  };
  Points take(const AgentStatesSnapshot& s, const DistanceMap& map);

 private:
  ScanObstaclesConfig config_;
  std::map<std::int64_t, LaserScanRecord> by_step_;
  std::optional<LaserScanRecord> latest_free_;
};

}  // namespace coopnav
