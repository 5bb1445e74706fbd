#pragma once
/// @file What a people tracker would publish from the simulated humans' true states: position
/// noise, velocity and heading estimated from the noisy positions, missed detections, dropped
/// tracks that come back under a new id, id switches at random times, and a detection range
/// around the robot. Pure and deterministic: its draws come from streams of its own derived from
/// the scenario's seed, so switching it on never changes the humans' own random draws. The robot's
/// state is never touched (localisation is out of scope).

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/geometry/types.hpp"
#include "coopnav/sim/random.hpp"

namespace coopnav::sim {

/// Tracker model parameters. With every key at its default the tracker is off (active() false):
/// the true states are published unchanged, under the scenario's ids.
struct TrackerParams {
  double position_sigma_m{0.0};  ///< [m] Gaussian noise per axis on each published position
  /// [samples] velocity = difference of the track's noisy positions over its last n published
  /// samples (fewer at a track's start), divided by their time span. Used when active().
  int velocity_window_steps{3};
  double miss_probability{0.0};  ///< [-] per person and step: absent from that message
  /// [s] a person not detected for longer than this has lost its track: when it is detected again
  /// it gets a new id (as real trackers do).
  double drop_after_s{1.0};
  int id_switches{0};  ///< per run: at that many random times a person gets a new id from then on
  /// [s] the switch times are uniform in (0, id_switch_window_s]; 0 = (0, horizon of the run].
  /// A switch scheduled after the run has ended does not happen.
  double id_switch_window_s{0.0};
  double range_m{0.0};  ///< [m] persons whose centre is farther from the robot's are not
                        ///< published; 0 = unlimited

  /// True when any of noise, misses, switches or range is on.
  bool active() const;
  /// Every problem, one message per key ("tracker.<key> = ... must be ..."); empty when valid.
  std::vector<std::string> validate() const;
};

/// First id a tracker gives a new track: new ids never collide with the robot's or any scenario
/// id (they start above the largest of those too).
inline constexpr std::int32_t kFirstNewTrackId = 1000;

/// One published human and the person (index into the true humans) behind it.
struct TrackedHuman {
  AgentState state;       ///< id = the track's id; velocity and heading estimated when active
  std::size_t person{0};  ///< index of the true human
};

/// Counters of a run, for logs and tests.
struct TrackerStats {
  std::int64_t published{0};     ///< human entries published
  std::int64_t missed{0};        ///< detections lost to miss_probability
  std::int64_t out_of_range{0};  ///< person-steps beyond range_m
  std::int64_t dropped{0};       ///< tracks that came back under a new id after a drop
  std::int64_t switches{0};      ///< id switches done
};

class Tracker {
 public:
  /// `person_ids`: the true humans' ids, in the order observe() receives them (>= 1, distinct).
  /// `horizon_s`: the run's length (time limit), for id_switch_window_s = 0. Throws
  /// std::invalid_argument when params.validate() reports a problem.
  Tracker(const TrackerParams& params, std::uint64_t seed, std::vector<std::int32_t> person_ids,
          double horizon_s);

  /// The humans a tracker publishes at sim time t_s (one call per published step, t_s
  /// increasing), from the true robot and the true humans (same order and count as person_ids).
  std::vector<TrackedHuman> observe(double t_s, const AgentState& robot,
                                    const std::vector<AgentState>& humans);

  /// The person an id was ever published (or announced) under; nullopt for an id never used.
  std::optional<std::size_t> personOf(std::int32_t id) const;
  /// The id a person is currently tracked under (its last one; its scenario id before any).
  std::int32_t currentId(std::size_t person) const { return persons_[person].id; }
  /// Scheduled switches (time, person), sorted by time.
  const std::vector<std::pair<double, std::size_t>>& switchSchedule() const { return switches_; }
  const TrackerStats& stats() const { return stats_; }
  const TrackerParams& params() const { return params_; }

 private:
  struct Sample {
    double t_s{0.0};
    Eigen::Vector2d p{0.0, 0.0};
  };
  struct Person {
    std::int32_t id{0};
    Rng rng;
    bool tracked{false};          ///< has a live track (seen, not yet dropped or switched)
    double last_seen_s{0.0};      ///< time of its last detection
    std::vector<Sample> history;  ///< the live track's last published positions, oldest first
    double theta_rad{0.0};        ///< the live track's last published heading
  };

  std::int32_t newId(std::size_t person);

  TrackerParams params_;
  std::vector<Person> persons_;
  std::vector<std::pair<double, std::size_t>> switches_;
  std::size_t next_switch_{0};
  std::int32_t next_id_{kFirstNewTrackId};
  std::map<std::int32_t, std::size_t> person_of_id_;
  TrackerStats stats_;
};

}  // namespace coopnav::sim
