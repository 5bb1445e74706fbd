#pragma once
/// @file The one place where lcmtypes meet lib/ types. `fromLcm` validates what it converts
/// (counts within the type's MAX_*, finite numbers, unique ids) and throws RejectedMessage with
/// the reason; `toLcm` sets every count from the vector it describes (LCM's encoder trusts them).

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/distance/distance_map.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/goal_estimates_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// Seconds <-> LCM utime (microseconds). Rounds to the nearest microsecond.
double utimeToSeconds(std::int64_t utime);
std::int64_t secondsToUtime(double t_s);
/// [s] later - earlier. In double, so that no pair of stamps overflows (a hostile stamp may be
/// INT64_MIN or INT64_MAX); exact, like the integer difference, while both are below 2^53 us.
double utimeDiffSeconds(std::int64_t later_utime, std::int64_t earlier_utime);

/// All agents at one instant (coopnav_agent_states_t).
struct AgentStatesSnapshot {
  std::int64_t utime{0};
  std::int64_t step{-1};
  AgentState robot;
  std::vector<AgentState> humans;
  /// The human with `id`, or nullptr.
  const AgentState* human(std::int32_t id) const;
};

AgentStatesSnapshot fromLcm(const agent_states_t& msg);
agent_states_t toLcm(const AgentStatesSnapshot& s);

/// One planning cycle's bands (coopnav_bands_t). Per-band validity is NOT enforced here: a band
/// of length 0/1 or with NaN is kept, and the assessors report it as unknown for that human.
struct BandsSnapshot {
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::int8_t status{bands_t::STATUS_OK};
  std::int8_t robot_mode{0};
  std::int32_t iterations{0};
  double final_cost{0.0};
  double solve_time_ms{0.0};
  std::int32_t robot_id{0};
  Band robot;
  std::vector<std::pair<std::int32_t, Band>> humans;
  /// bands_t.ROOM_* per entry of humans (same order and size; filled with ROOM_UNKNOWN when
  /// shorter on the way out).
  std::vector<std::int8_t> room_plans;
  const Band* humanBand(std::int32_t id) const;
  /// bands_t.ROOM_* for that human; ROOM_UNKNOWN when it has no band here.
  std::int8_t roomPlan(std::int32_t id) const;
};

BandsSnapshot fromLcm(const bands_t& msg);
bands_t toLcm(const BandsSnapshot& s);

/// Human reference paths (coopnav_reference_paths_t).
struct ReferencePaths {
  std::int64_t utime{0};
  std::int64_t step{-1};
  struct Entry {
    std::int32_t agent_id{0};
    std::int32_t revision{0};
    Path2 path;
  };
  std::vector<Entry> paths;
};

ReferencePaths fromLcm(const reference_paths_t& msg);
reference_paths_t toLcm(const ReferencePaths& r);

/// Goals (coopnav_goals_t).
struct Goal {
  std::int32_t agent_id{0};
  AgentKind kind{AgentKind::kHuman};
  Pose2 pose;  ///< theta NaN = any heading
};
struct GoalsSnapshot {
  std::int64_t utime{0};
  std::vector<Goal> goals;
};
GoalsSnapshot fromLcm(const goals_t& msg);
goals_t toLcm(const GoalsSnapshot& g);

/// The inferred goals (goal_estimates_t): the candidates and each inferred human's posterior.
struct GoalEstimates {
  struct Human {
    std::int32_t agent_id{0};
    int most_likely{-1};  ///< index into goals; -1 = none
    double walked_m{0.0};
    std::int32_t observations{0};
    std::vector<double> probability;  ///< one per goal
  };
  std::int64_t utime{0};
  std::int64_t step{-1};
  std::vector<Eigen::Vector2d> goals;
  std::vector<Human> humans;
};
/// Keeps at most MAX_GOALS candidates and MAX_HUMANS humans (the first ones; a most likely goal
/// beyond the kept candidates becomes -1).
goal_estimates_t toLcm(const GoalEstimates& e);
/// Rejects counts out of bounds or unequal, non-finite goals, probabilities outside [0, 1], a
/// most_likely outside [-1, num_goals) and duplicate ids.
GoalEstimates fromLcm(const goal_estimates_t& msg);

/// Velocity command (body frame).
struct VelocityCommand {
  std::int64_t utime{0};
  std::int64_t step{-1};
  Velocity2 body;  ///< vx forward, vy left, omega yaw rate (robot body frame)
  std::int8_t mode{velocity_command_t::MODE_IDLE};
  std::int8_t guard{velocity_command_t::GUARD_NONE};
};
VelocityCommand fromLcm(const velocity_command_t& msg);
velocity_command_t toLcm(const VelocityCommand& c);
/// A command mode's name as logs and JSON give it ("navigating", "goal_reached", ...);
/// "unknown" for a value that is none of velocity_command_t's MODE_ constants.
const char* commandModeName(std::int8_t mode);

/// Distance queries: one query of the server's three kinds.
enum class DistanceQueryKind : std::int8_t { kNearest = 0, kSide = 1, kRay = 2 };
struct DistanceQuery {
  DistanceQueryKind kind{DistanceQueryKind::kNearest};
  Eigen::Vector2d point{0.0, 0.0};
  Eigen::Vector2d vector{0.0, 0.0};  ///< SIDE: normal; RAY: direction
  double max_range_m{10.0};
};
/// Request header fields are passed separately; queries are validated per query by the server
/// (a NaN point is answered STATUS_INVALID_QUERY, not a rejected request).
std::vector<DistanceQuery> queriesFromLcm(const distance_request_t& msg);
distance_request_t toLcm(std::int64_t utime, std::int64_t request_id,
                         const std::string& reply_channel,
                         const std::vector<DistanceQuery>& queries);
std::vector<DistanceResult> resultsFromLcm(const distance_reply_t& msg);
distance_reply_t toLcm(std::int64_t utime, std::int64_t request_id,
                       const std::vector<DistanceResult>& results);

/// Answers one query against a map (the server's per-query logic; also used in-process).
DistanceResult answerQuery(const DistanceMap& map, const DistanceQuery& q);

}  // namespace coopnav
