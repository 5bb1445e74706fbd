#include "coopnav/dialogue/stand_off.hpp"

#include <cmath>

namespace coopnav::dialogue {

const char* toString(StandOff s) {
  switch (s) {
    case StandOff::kNone:
      return "none";
    case StandOff::kMutualWait:
      return "mutual_wait";
    case StandOff::kDockNoShow:
      return "dock_no_show";
  }
  return "?";
}

void StandOffWatch::restart() {
  wait_since_s_.reset();
  wait_best_t_cross_s_.reset();
  dock_since_s_.reset();
  mutual_wait_s_ = 0.0;
  dock_wait_s_ = 0.0;
}

StandOff StandOffWatch::update(const StandOffInput& in, bool docked) {
  const bool finite = std::isfinite(in.t_s) && std::isfinite(in.robot_speed_m_s) &&
                      std::isfinite(in.human_speed_m_s) && std::isfinite(in.centre_distance_m) &&
                      std::isfinite(in.gap_m);
  if (!finite) {
    wait_since_s_.reset();
    wait_best_t_cross_s_.reset();
    mutual_wait_s_ = 0.0;
    return StandOff::kNone;
  }
  const std::optional<double> t_cross =
      in.t_cross_s && std::isfinite(*in.t_cross_s) ? in.t_cross_s : std::nullopt;

  // Docked: the person coming nearer is the crossing going on.
  if (!docked) {
    dock_since_s_.reset();
    dock_wait_s_ = 0.0;
  } else if (!dock_since_s_ ||
             in.centre_distance_m < dock_best_distance_m_ - config_.dock_progress_m) {
    // The reference distance moves only with progress, so that a person creeping nearer by
    // less than dock_progress_m a step still makes progress once the creeping adds up.
    dock_since_s_ = in.t_s;
    dock_best_distance_m_ = in.centre_distance_m;
  }
  if (dock_since_s_) dock_wait_s_ = in.t_s - *dock_since_s_;

  // Both still and near: a wait, unless the crossing gets closer.
  const bool waiting = in.robot_speed_m_s < config_.robot_still_m_s &&
                       in.human_speed_m_s < config_.human_still_m_s &&
                       in.gap_m <= config_.near_gap_m;
  if (!waiting) {
    wait_since_s_.reset();
    wait_best_t_cross_s_.reset();
  } else if (!wait_since_s_) {
    wait_since_s_ = in.t_s;
    wait_best_t_cross_s_ = t_cross;
  } else if (t_cross) {
    if (!wait_best_t_cross_s_) {
      wait_best_t_cross_s_ = t_cross;
    } else if (*t_cross < *wait_best_t_cross_s_ - config_.t_cross_progress_s) {
      wait_since_s_ = in.t_s;  // the crossing got closer: a new wait, if any, from here
      wait_best_t_cross_s_ = t_cross;
    }
  }
  mutual_wait_s_ = wait_since_s_ ? in.t_s - *wait_since_s_ : 0.0;

  if (wait_since_s_ && mutual_wait_s_ >= config_.mutual_wait_s) return StandOff::kMutualWait;
  if (dock_since_s_ && dock_wait_s_ >= config_.dock_wait_s) return StandOff::kDockNoShow;
  return StandOff::kNone;
}

}  // namespace coopnav::dialogue
