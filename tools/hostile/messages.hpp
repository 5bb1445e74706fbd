#pragma once
/// @file Valid messages of every input type, in the corridors of config/maps/open.yaml, that the
/// probes then bend one way (a stamp, an id, a size, a text) to make them hostile. Everything
/// else in them is what a well-behaved publisher sends, so that a daemon's answer is about the
/// one hostile property.

#include <cstdint>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/situation_t.hpp"

namespace coopnav::hostile {

/// Message time of the probes' normal traffic [us]: any epoch; daemons run on message time.
inline constexpr std::int64_t kEpoch_us = 1'000'000'000;
/// Period of the normal traffic [us] (10 Hz, as world_sim and a tracker publish).
inline constexpr std::int64_t kPeriod_us = 100'000;

/// The robot and `num_humans` humans in the 6 m corridor of open.pgm (y = 6.5 m), the robot
/// walking east from x = 6.5 m, humans west from x = 20.5 m in rows; `k` is the message index.
agent_states_t corridorStates(std::int64_t utime, std::int64_t step, int num_humans, int k);
/// Goals of the robot (x = 20.5 m) and of humans 1..num_humans (x = 6.5 m).
goals_t corridorGoals(std::int64_t utime, int num_humans);

/// A straight band from (x0, y0) to (x1, y1): `num_poses` poses, `duration_s` long.
band_t straightBand(std::int32_t id, std::int8_t kind, double x0, double y0, double x1, double y1,
                    int num_poses, double duration_s);
/// Bands of the bottom corridor of open.pgm: the robot east along y = 1.5 m, humans 1..n west
/// along y = 1.9 m; each band `num_poses` poses over 8 s.
bands_t corridorBands(std::int64_t utime, std::int64_t step, int num_humans, int num_poses);

/// Reference paths of humans first_id.. first_id + num_paths - 1: straight, `num_points`
/// points from x = 20 m to 12 m along y = 2.3 m (the bottom corridor).
reference_paths_t referencePaths(std::int64_t utime, std::int64_t step, std::int32_t first_id,
                                 int num_paths, int num_points);

/// A situation of `human_id` as the situation assessor sends it: crossing known, the human
/// needs to contribute, the robot is constrained.
situation_t situation(std::int64_t utime, std::int64_t step, std::int32_t human_id,
                      double t_cross_s, std::string reason);

robot_action_t robotAction(std::int64_t utime, std::int8_t action, std::int32_t human_id,
                           std::string reason);

/// One NEAREST query in the corridor, replied to on `reply_channel`.
distance_request_t distanceRequest(std::int64_t request_id, std::string reply_channel);

}  // namespace coopnav::hostile
