#include "coopnav/band/velocity_command.hpp"

#include <algorithm>
#include <cmath>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav {

Velocity2 toBodyFrame(const Velocity2& w, double theta_rad) {
  const Eigen::Vector2d b = worldToBody({w.vx_m_s, w.vy_m_s}, theta_rad);
  return {b.x(), b.y(), w.omega_rad_s};
}

Velocity2 bandCommand(const TimedElasticBand& band, const AgentKinematics& k) {
  if (band.size() < 2) return {};
  const double dt = band.dt(0);
  if (!(dt > 0.0) || !std::isfinite(dt)) return {};
  const Pose2 a = band.pose(0);
  const Pose2 b = band.pose(1);
  const Velocity2 world{(b.x_m - a.x_m) / dt, (b.y_m - a.y_m) / dt,
                        wrapAngle(b.theta_rad - a.theta_rad) / dt};
  Velocity2 body = toBodyFrame(world, a.theta_rad);
  if (!k.holonomic) {
    // Signed speed along the heading; the band's sideways part is a kinematics residual.
    const double speed = std::hypot(world.vx_m_s, world.vy_m_s);
    body.vx_m_s = body.vx_m_s >= 0.0 ? speed : -speed;
    body.vy_m_s = 0.0;
  }
  body.vx_m_s = std::clamp(body.vx_m_s, -k.max_vel_x_backwards_m_s, k.max_vel_x_m_s);
  body.vy_m_s = k.holonomic ? std::clamp(body.vy_m_s, -k.max_vel_y_m_s, k.max_vel_y_m_s) : 0.0;
  body.omega_rad_s = std::clamp(body.omega_rad_s, -k.max_vel_theta_rad_s, k.max_vel_theta_rad_s);
  if (!std::isfinite(body.vx_m_s) || !std::isfinite(body.vy_m_s) ||
      !std::isfinite(body.omega_rad_s)) {
    return {};
  }
  return body;
}

}  // namespace coopnav
