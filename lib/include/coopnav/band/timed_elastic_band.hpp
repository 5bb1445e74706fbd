#pragma once
/// @file A timed elastic band (TEB): poses s_i = (x, y, θ) and time differences ΔT_i between
/// consecutive poses (Rösmann et al., "Trajectory modification considering dynamic constraints of
/// autonomous robots", ROBOTIK 2012; "Efficient trajectory optimization using a sparse model",
/// ECMR 2013). The storage is what Ceres optimises in place: one 3-vector per pose and one scalar
/// per ΔT, kept at stable addresses while a problem is solved.

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav {

class TimedElasticBand {
 public:
  /// Position of a time on the band: segment index and fraction in [0, 1].
  struct Locator {
    std::size_t segment{0};
    double fraction{0.0};
  };

  TimedElasticBand() = default;

  /// Band from `start` along `path` (path[0] is taken as the projection of start; it is
  /// replaced by the start pose). Poses are spaced speed_m_s * dt_ref_s along the path with
  /// ΔT = spacing / speed; headings follow the path; the last pose is the path end with
  /// `end_heading_rad` if given. A path shorter than one spacing gives two poses.
  /// Precondition: speed_m_s > 0, dt_ref_s > 0, finite inputs.
  static TimedElasticBand fromPath(const Pose2& start, const Path2& path, double speed_m_s,
                                   double dt_ref_s,
                                   std::optional<double> end_heading_rad = std::nullopt);

  /// Acceleration-limited speed profile for fromPath: speed ramps from start_speed_m_s to the
  /// cruise speed and, if stop_at_end, down to 0 at the path end (ΔT from the profile).
  struct SpeedProfile {
    double start_speed_m_s{0.0};
    double acc_m_s2{0.0};  ///< <= 0: constant cruise speed
    bool stop_at_end{false};
  };
  static TimedElasticBand fromPath(const Pose2& start, const Path2& path, double speed_m_s,
                                   double dt_ref_s, std::optional<double> end_heading_rad,
                                   const SpeedProfile& profile);

  /// A band of one pose (an agent standing at its goal).
  static TimedElasticBand single(const Pose2& pose);

  std::size_t size() const { return poses_.size(); }
  bool empty() const { return poses_.empty(); }
  Pose2 pose(std::size_t i) const { return {poses_[i][0], poses_[i][1], poses_[i][2]}; }
  void setPose(std::size_t i, const Pose2& p) { poses_[i] = {p.x_m, p.y_m, p.theta_rad}; }
  double dt(std::size_t i) const { return dts_[i]; }
  /// Raw storage for the optimiser (3 doubles per pose, 1 per ΔT).
  double* poseData(std::size_t i) { return poses_[i].data(); }
  double* dtData(std::size_t i) { return &dts_[i]; }

  /// Sum of all ΔT [s].
  double duration_s() const;
  /// Time of every pose from the band start [s] (size() entries, first 0).
  std::vector<double> times_s() const;
  /// Where time t_s falls; nullopt when t_s < 0, t_s > duration or the band has < 2 poses.
  std::optional<Locator> locate(double t_s) const;
  /// Linearly interpolated pose at time t_s, clamped to the band's ends. Precondition: !empty().
  Pose2 poseAt(double t_s) const;

  /// Inserts / removes poses so that every ΔT stays within dt_ref ± hysteresis where possible
  /// (TEB autoResize, own variant): a ΔT above dt_ref + hyst that holds >= 2 references is split
  /// into round(ΔT / dt_ref) parts; a ΔT below dt_ref - hyst is merged with its neighbour when
  /// the sum stays <= 1.5 dt_ref (merging further would only trigger a split again: the
  /// oscillation of teb_local_planner PR #263). The first and last poses are never removed.
  /// Returns true when poses were inserted or removed (storage addresses may have changed).
  bool autoResize(double dt_ref_s, double dt_hysteresis_s, int min_samples, int max_samples);

  /// Warm start: drops the poses the agent has already passed (the band pose nearest to
  /// `current` among those within elapsed_s + 1 s of the start) and makes `current` the first
  /// pose. Returns the number of poses removed.
  std::size_t pruneToStart(const Pose2& current, double elapsed_s);

  /// Replaces the last pose (new horizon end or goal) keeping the last ΔT's speed.
  void setEnd(const Pose2& end);

  /// Wraps every heading to (-pi, pi] and clamps ΔT to >= dt_min_s (after a solve).
  void normalize(double dt_min_s);

  /// Published form: poses with time from start.
  Band toBand() const;

 private:
  void insertAfter(std::size_t i, const std::array<double, 3>& p, double dt_before,
                   double dt_after);

  std::vector<std::array<double, 3>> poses_;
  std::vector<double> dts_;  ///< dts_[i] between pose i and i + 1 (size() - 1 entries)
};

}  // namespace coopnav
