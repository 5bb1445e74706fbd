#include "coopnav/band/timed_elastic_band.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav {
namespace {

std::array<double, 3> lerpPose(const std::array<double, 3>& a, const std::array<double, 3>& b,
                               double s) {
  const double dth = wrapAngle(b[2] - a[2]);
  return {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), wrapAngle(a[2] + s * dth)};
}

}  // namespace

TimedElasticBand TimedElasticBand::fromPath(const Pose2& start, const Path2& path, double speed_m_s,
                                            double dt_ref_s,
                                            std::optional<double> end_heading_rad) {
  return fromPath(start, path, speed_m_s, dt_ref_s, end_heading_rad, SpeedProfile{});
}

TimedElasticBand TimedElasticBand::fromPath(const Pose2& start, const Path2& path, double speed_m_s,
                                            double dt_ref_s, std::optional<double> end_heading_rad,
                                            const SpeedProfile& profile) {
  TimedElasticBand band;
  const double spacing_m = speed_m_s * dt_ref_s;
  band.poses_.push_back({start.x_m, start.y_m, start.theta_rad});
  // Poly-line from the start through path[1..]; path[0] stands for the start.
  Path2 pts;
  pts.push_back(start.position());
  for (std::size_t i = 1; i < path.size(); ++i) {
    if ((path[i] - pts.back()).norm() > 1e-9) pts.push_back(path[i]);
  }
  if (pts.size() == 1 && !path.empty() && (path.back() - pts.back()).norm() > 1e-9) {
    pts.push_back(path.back());
  }
  double total_m = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) total_m += (pts[i + 1] - pts[i]).norm();

  auto headingOf = [&](std::size_t seg) {
    const Eigen::Vector2d d = pts[seg + 1] - pts[seg];
    return std::atan2(d.y(), d.x());
  };
  const int n_inner = std::max(0, static_cast<int>(std::ceil(total_m / spacing_m)) - 1);
  // Speed at arc length s: cruise, limited by acceleration from the start speed and (when
  // stopping) by deceleration to the end; a floor keeps ΔT finite at a standstill end.
  auto speedAt = [&](double s_m) {
    if (profile.acc_m_s2 <= 0.0) return speed_m_s;
    const double v0 = std::max(profile.start_speed_m_s, 0.0);
    double v = std::min(speed_m_s, std::sqrt(v0 * v0 + 2.0 * profile.acc_m_s2 * s_m));
    if (profile.stop_at_end) {
      v = std::min(v, std::sqrt(2.0 * profile.acc_m_s2 * std::max(total_m - s_m, 0.0)));
    }
    return std::max(v, 0.1 * speed_m_s);
  };
  auto segmentTime = [&](double s0_m, double s1_m) {
    return (s1_m - s0_m) / (0.5 * (speedAt(s0_m) + speedAt(s1_m)));
  };
  std::size_t seg = 0;
  double seg_start_m = 0.0;
  double prev_s_m = 0.0;
  for (int k = 1; k <= n_inner; ++k) {
    const double s_m = k * total_m / (n_inner + 1);
    while (seg + 2 < pts.size() && seg_start_m + (pts[seg + 1] - pts[seg]).norm() < s_m) {
      seg_start_m += (pts[seg + 1] - pts[seg]).norm();
      ++seg;
    }
    const double len = (pts[seg + 1] - pts[seg]).norm();
    const double f = len > 0.0 ? std::clamp((s_m - seg_start_m) / len, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d p = pts[seg] + f * (pts[seg + 1] - pts[seg]);
    band.poses_.push_back({p.x(), p.y(), headingOf(seg)});
    band.dts_.push_back(std::max(segmentTime(prev_s_m, s_m), 1e-3));
    prev_s_m = s_m;
  }
  const Eigen::Vector2d end = pts.back();
  double end_th = start.theta_rad;
  if (end_heading_rad) {
    end_th = *end_heading_rad;
  } else if (pts.size() >= 2) {
    end_th = headingOf(pts.size() - 2);
  }
  band.poses_.push_back({end.x(), end.y(), end_th});
  band.dts_.push_back(total_m > prev_s_m ? std::max(segmentTime(prev_s_m, total_m), 1e-3)
                                         : dt_ref_s);
  return band;
}

TimedElasticBand TimedElasticBand::single(const Pose2& pose) {
  TimedElasticBand b;
  b.poses_.push_back({pose.x_m, pose.y_m, pose.theta_rad});
  return b;
}

double TimedElasticBand::duration_s() const {
  double t = 0.0;
  for (double d : dts_) t += d;
  return t;
}

std::vector<double> TimedElasticBand::times_s() const {
  std::vector<double> t(poses_.size(), 0.0);
  for (std::size_t i = 0; i < dts_.size(); ++i) t[i + 1] = t[i] + dts_[i];
  return t;
}

std::optional<TimedElasticBand::Locator> TimedElasticBand::locate(double t_s) const {
  if (poses_.size() < 2 || !(t_s >= 0.0)) return std::nullopt;
  double t0 = 0.0;
  for (std::size_t i = 0; i < dts_.size(); ++i) {
    const double t1 = t0 + dts_[i];
    if (t_s <= t1) {
      return Locator{i, dts_[i] > 0.0 ? std::clamp((t_s - t0) / dts_[i], 0.0, 1.0) : 0.0};
    }
    t0 = t1;
  }
  return std::nullopt;
}

Pose2 TimedElasticBand::poseAt(double t_s) const {
  if (poses_.size() == 1 || t_s <= 0.0) return pose(0);
  const auto loc = locate(t_s);
  if (!loc) return pose(poses_.size() - 1);
  const auto p = lerpPose(poses_[loc->segment], poses_[loc->segment + 1], loc->fraction);
  return {p[0], p[1], p[2]};
}

void TimedElasticBand::insertAfter(std::size_t i, const std::array<double, 3>& p, double dt_before,
                                   double dt_after) {
  poses_.insert(poses_.begin() + static_cast<std::ptrdiff_t>(i + 1), p);
  dts_[i] = dt_before;
  dts_.insert(dts_.begin() + static_cast<std::ptrdiff_t>(i + 1), dt_after);
}

bool TimedElasticBand::autoResize(double dt_ref_s, double dt_hysteresis_s, int min_samples,
                                  int max_samples) {
  if (poses_.size() < 2) return false;
  bool any = false;
  constexpr int kMaxSweeps = 100;  // as TEB: bounded so a pathological band cannot spin
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    bool changed = false;
    for (std::size_t i = 0; i < dts_.size(); ++i) {
      const double dt = dts_[i];
      if (dt > dt_ref_s + dt_hysteresis_s && static_cast<int>(poses_.size()) < max_samples) {
        const int parts = static_cast<int>(std::lround(dt / dt_ref_s));
        if (parts < 2) continue;
        const int room = max_samples - static_cast<int>(poses_.size());
        const int n_new = std::min(parts - 1, room);
        const auto a = poses_[i];
        const auto b = poses_[i + 1];
        const double sub = dt / (n_new + 1);
        for (int k = n_new; k >= 1; --k) {
          insertAfter(i, lerpPose(a, b, static_cast<double>(k) / (n_new + 1)), sub, sub);
        }
        dts_[i] = sub;
        i += static_cast<std::size_t>(n_new);
        changed = true;
      } else if (dt<dt_ref_s - dt_hysteresis_s&& static_cast<int>(poses_.size())> std::max(
                     min_samples, 2)) {
        if (i + 1 < dts_.size()) {
          // Remove pose i + 1; its two ΔT merge.
          if (dt + dts_[i + 1] > 1.5 * dt_ref_s) continue;
          dts_[i] += dts_[i + 1];
          poses_.erase(poses_.begin() + static_cast<std::ptrdiff_t>(i + 1));
          dts_.erase(dts_.begin() + static_cast<std::ptrdiff_t>(i + 1));
          changed = true;
        } else if (i > 0) {
          // Last ΔT: remove pose i (the last pose is fixed).
          if (dt + dts_[i - 1] > 1.5 * dt_ref_s) continue;
          dts_[i - 1] += dt;
          poses_.erase(poses_.begin() + static_cast<std::ptrdiff_t>(i));
          dts_.erase(dts_.begin() + static_cast<std::ptrdiff_t>(i));
          changed = true;
        }
      }
    }
    if (!changed) break;
    any = true;
  }
  return any;
}

std::size_t TimedElasticBand::pruneToStart(const Pose2& current, double elapsed_s) {
  if (poses_.empty()) return 0;
  const auto t = times_s();
  const Eigen::Vector2d c = current.position();
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < poses_.size() && t[i] <= elapsed_s + 1.0; ++i) {
    const double d = (Eigen::Vector2d(poses_[i][0], poses_[i][1]) - c).norm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  poses_.erase(poses_.begin(), poses_.begin() + static_cast<std::ptrdiff_t>(best));
  dts_.erase(dts_.begin(), dts_.begin() + static_cast<std::ptrdiff_t>(best));
  poses_[0] = {current.x_m, current.y_m, current.theta_rad};
  return best;
}

void TimedElasticBand::setEnd(const Pose2& end) {
  if (poses_.empty()) return;
  if (poses_.size() == 1) {
    poses_.push_back({end.x_m, end.y_m, end.theta_rad});
    dts_.push_back(0.1);
    return;
  }
  const std::size_t n = poses_.size();
  const Eigen::Vector2d prev(poses_[n - 2][0], poses_[n - 2][1]);
  const double old_len = (Eigen::Vector2d(poses_[n - 1][0], poses_[n - 1][1]) - prev).norm();
  const double new_len = (end.position() - prev).norm();
  if (old_len > 1e-6 && dts_[n - 2] > 0.0) {
    dts_[n - 2] *= std::max(new_len / old_len, 0.05);
  }
  poses_[n - 1] = {end.x_m, end.y_m, end.theta_rad};
}

void TimedElasticBand::normalize(double dt_min_s) {
  for (auto& p : poses_) p[2] = wrapAngle(p[2]);
  for (auto& d : dts_) d = std::max(d, dt_min_s);
}

Band TimedElasticBand::toBand() const {
  Band b;
  b.poses.reserve(poses_.size());
  const auto t = times_s();
  for (std::size_t i = 0; i < poses_.size(); ++i) b.poses.push_back({t[i], pose(i)});
  return b;
}

}  // namespace coopnav
