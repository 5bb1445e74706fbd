#include "coopnav/dialogue/stand_off.hpp"

#include <algorithm>
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
    case StandOff::kBackingOff:
      return "backing_off";
  }
  return "?";
}

void StandOffWatch::restart() {
  wait_since_s_.reset();
  wait_best_t_cross_s_.reset();
  wait_robot_path_m_ = 0.0;
  dock_since_s_.reset();
  mutual_wait_s_ = 0.0;
  dock_wait_s_ = 0.0;
  backing_since_s_.reset();
  backing_off_s_ = 0.0;
}

StandOff StandOffWatch::update(const StandOffInput& in, bool docked) {
  const bool finite = std::isfinite(in.t_s) && std::isfinite(in.robot_speed_m_s) &&
                      std::isfinite(in.human_speed_m_s) && std::isfinite(in.centre_distance_m) &&
                      std::isfinite(in.gap_m) && std::isfinite(in.robot_receding_m_s) &&
                      std::isfinite(in.human_closing_m_s);
  if (!finite) {
    backing_since_s_.reset();
    backing_off_s_ = 0.0;
    wait_since_s_.reset();
    wait_best_t_cross_s_.reset();
    wait_robot_path_m_ = 0.0;
    last_t_s_.reset();
    mutual_wait_s_ = 0.0;
    return StandOff::kNone;
  }
  const double dt_s = last_t_s_ && in.t_s > *last_t_s_ ? in.t_s - *last_t_s_ : 0.0;
  last_t_s_ = in.t_s;
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

  // Both still and near: a wait, unless the crossing gets closer. The robot is still at a step
  // below robot_still_m_s; once a wait began, also while it dithers in place: its mean speed since
  // then below robot_still_m_s, no step above robot_dither_m_s. (Judged step by step, a robot whose
  // planner and guard take turns in front of a person never waits 3 s on end, and the stand-off is
  // never seen.)
  bool robot_still = in.robot_speed_m_s < config_.robot_still_m_s;
  // Docked, the robot holds still: what moves it there is the guard evading a person closing
  // in (squeezing past), which is no wait.
  if (!docked && wait_since_s_ && !robot_still && in.robot_speed_m_s < config_.robot_dither_m_s) {
    // The mean over at least mutual_wait_s: one step of dithering just after the wait began
    // does not end it.
    const double over_s = std::max(in.t_s - *wait_since_s_, config_.mutual_wait_s);
    robot_still = wait_robot_path_m_ + in.robot_speed_m_s * dt_s < config_.robot_still_m_s * over_s;
  }
  const bool waiting =
      robot_still && in.human_speed_m_s < config_.human_still_m_s && in.gap_m <= config_.near_gap_m;
  if (!waiting) {
    wait_since_s_.reset();
    wait_best_t_cross_s_.reset();
    wait_robot_path_m_ = 0.0;
  } else if (!wait_since_s_) {
    wait_since_s_ = in.t_s;
    wait_best_t_cross_s_ = t_cross;
    wait_robot_path_m_ = 0.0;
  } else {
    wait_robot_path_m_ += in.robot_speed_m_s * dt_s;
  }
  if (waiting && wait_since_s_ && *wait_since_s_ < in.t_s && t_cross) {
    if (!wait_best_t_cross_s_) {
      wait_best_t_cross_s_ = t_cross;
    } else if (*t_cross < *wait_best_t_cross_s_ - config_.t_cross_progress_s) {
      wait_since_s_ = in.t_s;  // the crossing got closer: a new wait, if any, from here
      wait_best_t_cross_s_ = t_cross;
      wait_robot_path_m_ = 0.0;
    }
  }
  mutual_wait_s_ = wait_since_s_ ? in.t_s - *wait_since_s_ : 0.0;
  // Backing off, judged on the means since it began (a chase at 0.2 m/s is as fast as a tracked
  // person's velocity noise step by step): it begins at a step where the robot moves away from
  // the person, and goes on while the person is near and in front of the robot; it is a
  // stand-off once it has lasted backing_off_s with the robot's mean speed away from them at
  // robot_still_m_s or more and the person, on average, coming after it. A docked robot's
  // retreat is a move it announced, watched as a dock.
  const bool near_ahead = !docked && in.human_ahead && in.gap_m <= config_.near_gap_m;
  if (!near_ahead) {
    backing_since_s_.reset();
  } else if (!backing_since_s_) {
    if (in.robot_receding_m_s >= config_.robot_still_m_s) {
      backing_since_s_ = in.t_s;
      backing_robot_m_ = backing_human_m_ = 0.0;
    }
  } else {
    backing_robot_m_ += in.robot_receding_m_s * dt_s;
    backing_human_m_ += in.human_closing_m_s * dt_s;
    const double over_s = in.t_s - *backing_since_s_;
    // Past its time, a robot no longer backing away on average ends it (one that stopped).
    if (over_s >= config_.backing_off_s && backing_robot_m_ < config_.robot_still_m_s * over_s)
      backing_since_s_.reset();
  }
  backing_off_s_ = backing_since_s_ ? in.t_s - *backing_since_s_ : 0.0;
  const bool backing_off = backing_since_s_ && backing_off_s_ >= config_.backing_off_s &&
                           backing_human_m_ > config_.robot_still_m_s * backing_off_s_;

  if (wait_since_s_ && mutual_wait_s_ >= config_.mutual_wait_s) return StandOff::kMutualWait;
  if (dock_since_s_ && dock_wait_s_ >= config_.dock_wait_s) return StandOff::kDockNoShow;
  if (backing_off) return StandOff::kBackingOff;
  return StandOff::kNone;
}

}  // namespace coopnav::dialogue
