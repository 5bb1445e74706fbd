#pragma once
/// @file Track continuity across tracker id switches. A people tracker that loses a
/// person for a moment, or swaps labels in a crowd, publishes the same person under a new id.
/// Every daemon that keeps an interaction per id (the dialogue manager's rounds, the path
/// assessor's recording) would restart it: the robot would announce round 1 again to someone it
/// already spoke to. A new id that appears where a recently lost one was heading continues it.
/// Pure logic: positions and times come from the caller, so every daemon decides alike.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace coopnav {

/// A track the tracker stopped publishing, as last seen.
struct LostTrack {
  std::int32_t id{0};
  double t_s{0.0};                         ///< [s] last seen (message time)
  Eigen::Vector2d position_m{0.0, 0.0};    ///< [m] world frame
  Eigen::Vector2d velocity_m_s{0.0, 0.0};  ///< [m/s] world frame
};

struct TrackContinuityOptions {
  double max_gap_s{2.0};  ///< [s] a track lost longer ago is gone, not switched
  /// [m] gate around the constant-velocity prediction at a gap of 0: tracker noise and the
  /// body's own extent (two people are rarely nearer than this, centre to centre).
  double gate_m{0.5};
  /// [m/s] the gate grows with the gap: a walker can change speed and heading meanwhile.
  double gate_growth_m_s{0.5};
};

/// The lost track a new track (first seen at t_s at position_m) continues: of the tracks lost
/// at most max_gap_s before t_s, the one whose constant-velocity prediction is nearest, if within
/// gate_m + gate_growth_m_s · gap (ties: the lower id). nullopt when none qualifies, or when a
/// non-finite input makes the question meaningless.
std::optional<std::int32_t> continuedTrack(const std::vector<LostTrack>& lost, double t_s,
                                           const Eigen::Vector2d& position_m,
                                           const TrackContinuityOptions& options = {});

}  // namespace coopnav
