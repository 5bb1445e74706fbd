#pragma once
/// @file The field's social-navigation metrics of one run, from timed tracks of the robot and of
/// each person (docs/metrics.md defines each one with its source): Francis et al., "Principles
/// and Guidelines for Evaluating Social Robot Navigation Algorithms" (ACM THRI 2025); HuNavSim's
/// evaluator (Pérez-Higueras et al.); SocNavBench (Biswas et al., THRI 2022); CrowdNav's
/// discomfort frequency (Chen et al., ICRA 2019); and the Responsibility / Engagement shares of
/// conflict resolution (Wenzel & Probst, arXiv 2509.12912; Probst, Wenzel & Dasi, arXiv
/// 2509.12890), in the reading docs/metrics.md states.
///
/// Pure functions: no I/O, no clock. Distances between agents are surface to surface (centre
/// distance minus both radii): our discs are the agents' footprints, so a centre distance of
/// 0.45 m would already be a collision for a 0.47 m robot and a 0.3 m person.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace coopnav::metrics {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// One agent at one instant, world frame.
struct AgentSample {
  std::int32_t id{0};
  Eigen::Vector2d p_m{0.0, 0.0};    ///< [m] position
  Eigen::Vector2d v_m_s{0.0, 0.0};  ///< [m/s] velocity (world frame)
  double theta_rad{0.0};            ///< [rad] heading
  double radius_m{0.3};             ///< [m] footprint disc
};

/// Everyone at one instant (one lockstep step of the log).
struct Frame {
  double t_s{0.0};  ///< [s] simulated time, strictly increasing from frame to frame
  AgentSample robot;
  std::vector<AgentSample> humans;  ///< those present at t_s
};

/// How the run ended, as the simulator judged it (sim_status_t.STATE_*); kUnknown without one.
enum class Outcome : std::int8_t {
  kUnknown = -1,
  kRunning = 0,
  kGoalReached = 1,
  kCollision = 2,
  kTimeLimit = 3,
  kParticipantTimeout = 4,
  kError = 5,
  kStandstill = 6,
};

/// Thresholds and model constants. Each default is the value of the metric's source
/// (docs/metrics.md names it); the only defaults there are.
struct MetricsOptions {
  double goal_tolerance_m{0.3};        ///< robot at its goal within this distance (no sim time)
  double stalled_speed_m_s{0.05};      ///< Francis "stalled": slower than this
  double progress_m{0.5};              ///< "progress": the best distance to goal falls this much
  double failure_to_progress_s{10.0};  ///< no progress for this long = failure to progress
  double space_compliance_m{0.5};      ///< Francis space compliance: a person nearer than this
  double intimate_m{0.45};             ///< Hall / HuNavSim zones
  double personal_m{1.2};
  double social_m{3.6};
  double discomfort_m{0.2};         ///< CrowdNav discomfort distance
  double contact_m{0.0};            ///< a gap at or below this is a collision
  double ran_into_speed_m_s{0.05};  ///< closing faster than this at contact = ran into
  double ttc_horizon_s{std::numeric_limits<double>::infinity()};  ///< TTC beyond: none
  double sfm_a_m_s2{2.1};        ///< social-force strength (Helbing & Molnár)
  double sfm_b_m{0.3};           ///< social-force range
  double sfm_wall_a_m_s2{10.0};  ///< obstacle-force strength
  double sfm_wall_b_m{0.2};      ///< obstacle-force range
  /// Personal-space cost (Kirby 2009, SocNavBench): the Gaussian's width ahead of a person is
  /// max(front_s × speed, min_sigma_m), behind it a third, to the sides a quarter.
  double personal_space_front_s{2.0};
  double personal_space_min_sigma_m{0.5};
  double conflict_sigma_m{0.5};    ///< conflict intensity: width over the predicted gap
  double conflict_tau_s{2.0};      ///< conflict intensity: decay over the time to it
  double conflict_horizon_s{8.0};  ///< conflict intensity: closest approach looked for within
  /// A pair whose conflict intensity never reached this had no conflict to share: no
  /// Responsibility or Engagement (intensity 0.1: a surface gap of 1.07 m predicted now, or a
  /// contact predicted 4.6 s ahead).
  double conflict_min_intensity{0.1};
  double min_motion_m{0.01};  ///< a step shorter than this has no motion direction
};

/// What the run's metrics are computed from besides the frames.
struct RunInput {
  std::vector<Frame> frames;
  std::optional<Eigen::Vector2d> robot_goal;  ///< unknown: no distance-to-goal metrics
  Outcome outcome{Outcome::kUnknown};
  /// [s] simulated time the robot reached its goal (the simulator's); NaN: take the first frame
  /// within goal_tolerance_m of robot_goal, if any.
  double goal_time_s{kNaN};
  /// [m] the shortest collision-free path from the robot's start to its goal (the map's
  /// geodesic); NaN: the straight line.
  double shortest_path_m{kNaN};
  /// [m] per frame, the robot's surface gap to the nearest obstacle; empty: no map, no wall
  /// metrics.
  std::vector<double> wall_clearance_m;
};

/// Min / mean / max of a series; NaN when it is empty.
struct Stat3 {
  double min{kNaN};
  double avg{kNaN};
  double max{kNaN};
};

/// The shares of resolving and of escalating one robot-person conflict (responsibility.cpp).
struct ConflictShares {
  double resolved_by_robot{0.0};    ///< Σ intensity decreases attributed to the robot's actions
  double resolved_by_person{0.0};   ///< ... to the person's
  double escalated_by_robot{0.0};   ///< Σ intensity increases attributed to the robot's actions
  double escalated_by_person{0.0};  ///< ... to the person's
  double by_time{0.0};              ///< Σ |change| with both keeping their velocity
  double max_intensity{0.0};        ///< highest conflict intensity of the encounter, 0..1
  /// resolved_by_robot / (resolved_by_robot + resolved_by_person); NaN when nothing resolved or
  /// there was no conflict (max_intensity below conflict_min_intensity).
  double robot_responsibility{kNaN};
  /// escalated_by_robot / (escalated_by_robot + escalated_by_person); NaN when nothing escalated.
  double robot_engagement{kNaN};
};

struct PersonMetrics {
  std::int32_t id{0};
  double min_distance_m{kNaN};  ///< min surface gap to the robot
  double min_ttc_s{kNaN};       ///< min constant-velocity time to contact (NaN: never closing)
  double intimate_s{0.0};       ///< time with the gap below intimate_m
  double personal_s{0.0};
  double social_s{0.0};
  int collisions{0};                  ///< contact onsets (gap at or below contact_m)
  int robot_on_person_collisions{0};  ///< contacts begun with the robot closing on the person
  int person_on_robot_collisions{0};  ///< contacts begun with the person closing on the robot
  ConflictShares conflict;
};

struct RunMetrics {
  // Outcome (Francis et al.)
  bool success{false};       ///< goal reached, no collision
  bool collision{false};     ///< any collision (person, or wall when known, or the sim's)
  int person_collisions{0};  ///< contact onsets with people, over all people
  int robot_on_person_collisions{0};
  int person_on_robot_collisions{0};
  int wall_collisions{0};  ///< clearance onsets at or below contact_m (needs wall clearance)
  bool timeout{false};
  bool failure_to_progress{false};
  double longest_no_progress_s{kNaN};
  double stalled_s{0.0};
  double time_to_goal_s{kNaN};
  double duration_s{0.0};  ///< first to last frame evaluated (to the goal when reached)
  // Path (Francis; SocNavBench; HuNavSim)
  double path_length_m{0.0};
  double shortest_path_m{kNaN};
  double path_length_ratio{kNaN};     ///< path / straight start-goal distance (SocNavBench)
  double goal_traversal_ratio{kNaN};  ///< final / initial distance to the goal (SocNavBench)
  double spl{0.0};                    ///< success × shortest / max(path, shortest)
  double final_distance_to_goal_m{kNaN};
  double cumulative_heading_change_rad{0.0};
  double path_irregularity_rad{kNaN};
  double path_irregularity_rad_per_m{kNaN};  ///< the same per metre of path (SocNavBench)
  // Motion
  Stat3 speed_m_s;
  Stat3 acceleration_m_s2;
  Stat3 jerk_m_s3;
  double motion_energy_m2_s{0.0};  ///< ∫ |v|² dt
  // Clearance and people
  Stat3 clearing_distance_m;      ///< to obstacles (needs wall clearance)
  double space_compliance{kNaN};  ///< share of time with a person nearer than space_compliance_m
  double min_distance_to_person_m{kNaN};
  Stat3 closest_person_distance_m;  ///< per frame, the nearest person's gap (HuNavSim)
  double min_ttc_s{kNaN};
  double intimate_s{0.0};  ///< time with the nearest person in the intimate zone
  double personal_s{0.0};
  double social_s{0.0};
  double intimate_share{kNaN};
  double personal_share{kNaN};
  double social_share{kNaN};
  double discomfort_frequency{kNaN};  ///< share of frames with a gap below discomfort_m
  double personal_space_cost_s{0.0};  ///< ∫ Σ_persons personalSpaceCost dt
  /// ∫ social-force magnitudes dt [m/s]: the people's on the robot, the robot's on each person
  /// and (with wall clearance) the obstacles' on the robot, as HuNavSim's W_r + Σ W_p.
  double social_work{0.0};
  double obstacle_work{0.0};           ///< the obstacles' part of social_work
  std::vector<PersonMetrics> persons;  ///< ascending id
};

// ---- the building blocks, each one metric (unit-tested on hand-computed tracks) ----

/// Surface gap between two discs [m] (negative: overlapping).
double surfaceGap(const AgentSample& a, const AgentSample& b);

/// Smallest t >= 0 at which two discs moving at constant velocity touch (|dp + dv t| = r_a + r_b);
/// 0 when already touching; NaN when they never touch or only after horizon_s.
double timeToCollision(const AgentSample& a, const AgentSample& b,
                       double horizon_s = std::numeric_limits<double>::infinity());

/// Σ |p_{k+1} - p_k|.
double pathLength(const std::vector<Eigen::Vector2d>& points);

/// Σ |wrap(θ_{k+1} - θ_k)| (HuNavSim's CHC).
double cumulativeHeadingChange(const std::vector<double>& headings_rad);

/// Turning beyond what the straight path needs: Σ |wrap(Δφ)| over the directions of motion (steps
/// of at least min_motion_m), starting from the initial heading, minus |wrap(bearing to the goal
/// - initial heading)|, at least 0.
double pathIrregularity(const std::vector<Eigen::Vector2d>& points, double initial_heading_rad,
                        const Eigen::Vector2d& goal, double min_motion_m);

/// Personal-space cost of the robot's position to one person, 0..1 (Kirby 2009, as SocNavBench):
/// an asymmetric Gaussian centred on the person, along its direction of motion (its heading when
/// still) of width σ = max(front_s·speed, min_sigma) ahead and σ/3 behind, σ/4 to the sides,
/// evaluated at the robot's centre.
double personalSpaceCost(const AgentSample& robot, const AgentSample& person,
                         const MetricsOptions& o);

/// Longest span [s] in which the best distance to the goal so far did not fall by progress_m.
double longestNoProgress(const std::vector<double>& t_s, const std::vector<double>& distance_m,
                         double progress_m);

/// Min / time-weighted mean / max of finite-difference derivatives of a velocity series: the
/// acceleration |Δv/Δt| (order 1) or the jerk |Δa/Δt| (order 2), at the midpoints.
Stat3 derivativeStats(const std::vector<double>& t_s, const std::vector<Eigen::Vector2d>& v,
                      int order);

/// Conflict intensity between two agents, 0..1: exp(-max(d*,0)²/2σ²)·exp(-t*/τ), t* the time of
/// their closest approach at constant velocity (clamped to [0, horizon]) and d* their surface gap
/// then.
double conflictIntensity(const AgentSample& robot, const AgentSample& person,
                         const MetricsOptions& o);

/// Responsibility and Engagement of one robot-person pair over aligned samples (same times).
ConflictShares conflictShares(const std::vector<AgentSample>& robot,
                              const std::vector<AgentSample>& person, const MetricsOptions& o);

/// Every metric of one run.
RunMetrics computeRunMetrics(const RunInput& in, const MetricsOptions& o = {});

}  // namespace coopnav::metrics
