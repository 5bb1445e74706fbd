#pragma once
/// @file Replay of a recorded LCM log (coopnav_record, lcm-logger) into the viewer's scene, with
/// a timeline: play, pause, speed, seek to any time. No bus: the log is read once at start
/// (daemons/common/logfile, the reader of every tool), and every event gets the scene time in force
/// when it was recorded (the newest agent-states utime before it, so daemon statuses, stamped with
/// the wall clock, fall in their place). Seeking restores the nearest earlier checkpoint (a copy of
/// the scene every checkpoint_s of scene time, at most max_checkpoints of them, thinned and spaced
/// further on a long log) and applies the events from there, the same handlers as live.

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene_model.hpp"

namespace coopnav::viewer {

class Replay {
 public:
  /// Reads the whole log; throws std::runtime_error when it cannot be opened or holds no
  /// agent states (nothing to place on a timeline), or is not a regular file. `scene` is the
  /// empty scene to start from (options and map set).
  Replay(const std::string& path, const SceneModel& scene, double checkpoint_s = 2.0,
         int max_checkpoints = 16);

  /// [s] scene time of the first and last agent states of the log.
  double startS() const { return start_s_; }
  double endS() const { return end_s_; }
  /// [s] the playback position.
  double positionS() const { return position_s_; }
  bool playing() const { return playing_; }
  double speed() const { return speed_; }
  void setSpeed(double speed) { speed_ = speed; }
  void play();
  void pause() { playing_ = false; }
  /// Moves the position to t_s (clamped to the log) and the scene with it.
  void seek(double t_s);
  /// Moves the position by wall_dt_s * speed while playing (stops at the end).
  void advance(double wall_dt_s);

  const SceneModel& scene() const { return scene_; }
  std::size_t events() const { return events_.size(); }
  /// Messages of the log the scene did not take, over the whole log (the scene counts those up
  /// to the position).
  std::int64_t rejectedInLog() const { return rejected_in_log_; }
  std::size_t checkpoints() const { return checkpoints_.size(); }
  /// What the reader met (events, bad headers, skipped bytes, ...; LogReadCounts::describe).
  const std::string& readCounts() const { return read_counts_; }
  /// {"file", "start", "end", "t", "playing", "speed", "events", "rejected_in_log", "read"} for
  /// the page's timeline.
  nlohmann::json timelineJson() const;

 private:
  struct Event {
    double t_s;
    std::string channel;
    std::vector<std::uint8_t> data;
    std::int64_t received_utime{0};  ///< the logger's receive time (daemon statuses' clock)
  };
  struct Checkpoint {
    double t_s;        ///< the scene holds every event at or before this time
    std::size_t next;  ///< index of the first event not applied
    SceneModel scene;
  };
  /// Applies the events up to position_s_ (counting those the scene rejects).
  void applyUpToPosition();
  static void applyTo(SceneModel& scene, const Event& e);

  std::string path_;
  std::vector<Event> events_;
  std::vector<Checkpoint> checkpoints_;
  SceneModel initial_;  ///< the empty scene (options and map), for a seek before any checkpoint
  SceneModel scene_;
  std::size_t next_{0};
  double start_s_{0.0};
  double end_s_{0.0};
  double position_s_{0.0};
  bool playing_{false};
  double speed_{1.0};
  std::int64_t rejected_in_log_{0};
  std::string read_counts_;
};

}  // namespace coopnav::viewer
