#pragma once
/// @file Progress of one crossing, watched per human: a mutual wait (robot and person both
/// still, near each other, the crossing not getting closer), a dock the person does not come
/// to pass, and the robot backing off before a person who follows it (giving way backwards, with
/// no crossing ahead: the planner's bands yield ground and nothing ever passes). Neither is in the
/// paper, whose rounds fire at t_CROSS thresholds and assume the crossing comes; this is the
/// freezing-robot stand-off (Trautman & Krause 2010) that issue 44 requires to be resolved within a
/// bounded time. Pure: time is an input; HumanDecision decides what to do about it (decision.hpp,
/// the cooperation assessment).

#include <optional>

namespace coopnav::dialogue {

/// Thresholds of the watch. Defaults in this one place.
struct StandOffConfig {
  /// [m/s] The robot is still below this speed (issue 44's stalled speed): a wait begins at a
  /// step below it, and goes on while the robot's mean speed since it began (over at least
  /// mutual_wait_s) stays below it.
  double robot_still_m_s{0.05};
  /// [m/s] ... and while no single step is above this: a robot that sets off ends the wait at
  /// once, one that dithers in place (its planner and guard taking turns, steps of a few cm/s
  /// either way) does not. Not while docked: a docked robot holds still, and what moves it is
  /// the guard evading a person who closes in to squeeze past.
  double robot_dither_m_s{0.15};
  /// [m/s] A person waits below this speed: well under a walk (≥ 0.5 m/s), above the velocity
  /// noise of a tracked person standing still.
  double human_still_m_s{0.2};
  /// [m] Near enough to be waiting for each other, surface to surface: about a corridor's width
  /// and a step, the room a passage is negotiated in.
  double near_gap_m{2.0};
  /// [s] The crossing got closer when t_CROSS fell by at least this since the wait began: a
  /// t_CROSS that creeps down by less (planned bands shifting while nobody moves) is no progress.
  double t_cross_progress_s{0.5};
  /// [s] Both still and near this long without the crossing getting closer is a mutual wait.
  /// Long enough to not take a person's pause to look, or the robot's stop at its dock pose,
  /// for a stand-off (a reaction is ≈ 1 s, notes §7); short enough that the stand-off is
  /// resolved long before the 10 s a population counts as a stalemate.
  double mutual_wait_s{3.0};
  /// [m] Docked for a person, the person came this much nearer (centre to centre): the
  /// crossing goes on.
  double dock_progress_m{0.3};
  /// [s] Docked, and the person has not come nearer by dock_progress_m for this long: they are
  /// not coming, and the robot goes on. Counted from the dock request, so it covers the drive to
  /// the dock pose (a few seconds) and a person's late start after hearing the dock's words.
  double dock_wait_s{8.0};
  /// [s] Not docked, the robot has backed off before a person near it and in front of it this
  /// long (on average moving away from them at robot_still_m_s or more, while they come after
  /// it): it is giving way backwards with no end, as the person keeps coming. Long enough for
  /// a step back that lets a person by; short enough that the robot does not back down a
  /// corridor before saying anything.
  double backing_off_s{3.0};
};

/// One step's view of the robot and one person, from the agent states and the situation.
struct StandOffInput {
  double t_s{0.0};                ///< [s] message time
  double robot_speed_m_s{0.0};    ///< [m/s]
  double human_speed_m_s{0.0};    ///< [m/s]
  double centre_distance_m{0.0};  ///< [m] robot centre to person centre
  double gap_m{0.0};              ///< [m] surface to surface (centre distance less the radii)
  /// [m/s] The robot's velocity along the direction from the person to the robot (> 0: moving
  /// away from them) and the person's along the same direction (> 0: coming at the robot).
  double robot_receding_m_s{0.0};
  double human_closing_m_s{0.0};
  /// The person is in front of the robot (along its heading): one coming from behind, as the
  /// robot drives on, is being followed, not backed off from.
  bool human_ahead{false};
  std::optional<double> t_cross_s;  ///< [s] nullopt = unknown
};

enum class StandOff {
  kNone = 0,
  kMutualWait = 1,  ///< both still and near for mutual_wait_s, the crossing no closer
  kDockNoShow = 2,  ///< docked, the person not nearer by dock_progress_m for dock_wait_s
  kBackingOff = 3,  ///< not docked, backing off before a person who follows for backing_off_s
};
const char* toString(StandOff s);

/// Per-human watch. Not thread-safe.
class StandOffWatch {
 public:
  explicit StandOffWatch(const StandOffConfig& config = {}) : config_(config) {}

  /// Advances with one step; `docked`: a dock for this person is requested and not resumed.
  /// Returns a stand-off once it is reached, and again at every later step until restart().
  /// Non-finite inputs count as no evidence: they end a wait being timed (never start one).
  StandOff update(const StandOffInput& in, bool docked);
  /// After a decision on a stand-off: every timer starts afresh from the next step.
  void restart();
  /// [s] How long the current mutual wait has lasted at the last update (0 when none).
  double mutualWait_s() const { return mutual_wait_s_; }
  /// [s] How long the dock has seen no progress at the last update (0 when not docked).
  double dockWait_s() const { return dock_wait_s_; }
  /// [s] How long the robot has been backing off before the person (0 when it is not).
  double backingOff_s() const { return backing_off_s_; }
  const StandOffConfig& config() const { return config_; }

 private:
  StandOffConfig config_;
  std::optional<double> wait_since_s_;  ///< both still and near since, the crossing no closer
  std::optional<double> wait_best_t_cross_s_;
  double wait_robot_path_m_{0.0};       ///< [m] the robot's path since the wait began (speed x dt)
  std::optional<double> last_t_s_;      ///< the previous update's time
  std::optional<double> dock_since_s_;  ///< docked, no progress since
  double dock_best_distance_m_{0.0};
  double mutual_wait_s_{0.0};
  double dock_wait_s_{0.0};
  std::optional<double> backing_since_s_;
  double backing_robot_m_{0.0};  ///< [m] the robot's way away from the person since then
  double backing_human_m_{0.0};  ///< [m] the person's way towards the robot since then
  double backing_off_s_{0.0};
};

}  // namespace coopnav::dialogue
