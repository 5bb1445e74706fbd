#include "sensing.hpp"

#include <cmath>

#include "wire/conversions.hpp"
#include "wire/scan.hpp"

namespace coopnav::world_sim {
namespace {
/// The laser's own random stream of the scenario seed (sim::Rng::forStream): the humans' and the
/// tracker's draws are the same with the laser on or off.
constexpr std::uint64_t kLaserStream = 0x4c41534552ULL;  // "LASER"
constexpr double kDeg = M_PI / 180.0;
}  // namespace

WorldSensing::WorldSensing(const Scenario& scenario, bool laser_on)
    : unmapped_(scenario.unmapped_obstacles),
      rng_(sim::Rng::forStream(scenario.seed, kLaserStream)) {
  if (!laser_on || !scenario.laser.enabled) return;
  const LaserSpec& l = scenario.laser;
  sim::LaserOptions o;
  o.range_min_m = l.range_min_m;
  o.range_max_m = l.range_max_m;
  o.fov_rad = l.fov_deg * kDeg;
  o.angular_resolution_rad = l.resolution_deg * kDeg;
  o.noise_sigma_m = l.noise_sigma_m;
  o.mount_x_m = l.mount_x_m;
  o.mount_y_m = l.mount_y_m;
  laser_ = o;
}

laser_scan_t WorldSensing::scan(const DistanceMap& world, const std::vector<AgentState>& agents,
                                std::int64_t utime, std::int64_t step) {
  std::vector<sim::LaserDisc> discs;
  for (std::size_t i = 1; i < agents.size(); ++i)
    discs.push_back({agents[i].pose.position(), agents[i].radius_m});
  LaserScanRecord r;
  r.utime = utime;
  r.step = step;
  r.scan = sim::simulateLaser(world, discs, agents.front().pose, *laser_, rng_);
  return toLcm(r);
}

void WorldSensing::noteRobot(const AgentState& robot, double t_s) {
  if (unmapped_.empty()) return;
  const double c = unmappedClearance(unmapped_, robot.pose.position(), robot.radius_m);
  if (c < min_clearance_m_) {
    min_clearance_m_ = c;
    min_clearance_t_s_ = t_s;
  }
}

}  // namespace coopnav::world_sim
