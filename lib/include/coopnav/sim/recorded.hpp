#pragma once
/// @file Recorded humans: a track of timed positions (e.g. a walker of the UCY / ETH pedestrian
/// data) replayed in the simulator, placed into the map by a time offset and a rigid transform,
/// linearly interpolated between samples. The replayed human ignores the robot. Pure: parsing
/// takes the text (the caller reads the file), no clock.

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav::sim {

class HumanBehaviour;

/// One sample of a recorded track, in the recording's own clock and frame.
struct TrackSample {
  double t_s{0.0};  ///< [s] recording time
  double x_m{0.0};  ///< [m] recording frame
  double y_m{0.0};
};

/// A track that cannot be used; what() names the source and, for text, the line.
class TrackError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses a track in CSV: one `t x y` row per line, separated by commas and/or whitespace; a
/// first line that is not numeric is a header; blank lines and lines starting with '#' are
/// skipped. Throws TrackError "<source>:<line>: <what>" for a row without three finite numbers
/// (or with more), a time not after the previous row's, or no rows at all.
std::vector<TrackSample> parseTrackCsv(const std::string& text, const std::string& source);

/// Checks a track built elsewhere (e.g. from JSON): at least one sample, finite values, times
/// strictly increasing. Throws TrackError "<source>: <what>" naming the sample index.
void checkTrack(const std::vector<TrackSample>& track, const std::string& source);

/// Parameters of a `recorded` human.
struct RecordedParams {
  /// [s] sim time at which the track's first sample is played (< 0: the replay starts part-way
  /// into the track). Sim time s plays recording time t_first + (s - time_offset_s).
  double time_offset_s{0.0};
  /// Recording frame -> world: p_W = R(theta_rad) p_rec + (x_m, y_m).
  Pose2 transform;
  std::vector<TrackSample> track;  ///< as recorded; >= 1 sample, times strictly increasing
};

/// World position of the recorded human at sim time t_s: linear interpolation between samples;
/// before the first sample it stands at the first, after the last at the last.
Eigen::Vector2d recordedPosition(const RecordedParams& params, double t_s);
/// Its start pose: the position at sim time 0, facing where it first moves (> 5 cm away; the
/// transform's heading when it never does).
Pose2 recordedStart(const RecordedParams& params);
/// Its goal: the track's last point, facing along its last move.
Pose2 recordedGoal(const RecordedParams& params);
/// [s] sim time of the track's last sample.
double recordedEnd_s(const RecordedParams& params);

/// The behaviour replaying the track: desires the velocity that brings it onto the track's
/// position one physics step later (the track's own velocity plus a correction of the error,
/// limited to what its acceleration limit can stop). Throws std::invalid_argument for an empty
/// track.
std::unique_ptr<HumanBehaviour> makeRecordedBehaviour(const RecordedParams& params);

}  // namespace coopnav::sim
