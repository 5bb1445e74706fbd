#pragma once
/// @file Human path assessment of paper §II-C: the signed contribution array CA, its discounted
/// mean CM and the IsContributing predicate, for one human.
///
/// CA sign (design-readings, "CA sign"; our reading, decided at EACH sample): CA_i is the distance
/// of the human from its initial shortest path, positive when the human is on the side of that
/// path away from the robot. The robot's side is the side of the path the robot is on at that
/// sample (sign of its signed distance from the path). While the robot is within side_deadband_m
/// of the path (e.g. head-on, before it swerves) the last decided side is kept; if no side was
/// decided yet, the robot's side relative to the human across the path is used; if that too is
/// within the deadband, CA_i = 0 (no evidence either way). Per sample rather than at start because
/// at start a head-on robot stands on the human's path, where the side is undefined.

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/geometry/types.hpp"

namespace coopnav::assessment {

/// [m] Paper §II-C: CM = Σ γ^(N−i) CA_i / Σ γ^(N−i). Any γ > 0 (γ = 1 is the plain mean, γ > 1
/// weights early samples more, as in the paper's γ sweep); numerically safe for any N (no
/// overflow or underflow of γ^N). nullopt when ca_m is empty or γ is not finite and > 0.
std::optional<double> discountedMean(const std::vector<double>& ca_m, double gamma);

/// Paper §II-C: IsContributing = CM > τ; unknown when CM is (no samples).
Tristate isContributing(std::optional<double> cm_m, double tau_m);

/// Which threshold IsContributing compares CM with.
///  - kFixed: the paper's τ (§III), whatever room the human had.
///  - kRoom (beyond the paper, opt-in): τ shrunk to the room the human had. In a 1.8 m corridor
///    a facilitating human can move at most ~0.3 m from its path, below the paper's τ = 0.4 m,
///    so under kFixed every human there is "not contributing" whatever they do.
enum class TauMode : std::int8_t { kFixed = 0, kRoom = 1 };
const char* toString(TauMode m);
/// The mode named by toString(); nullopt for any other name.
std::optional<TauMode> tauModeFromString(const std::string& name);

/// [m] Lateral room the human had on the side away from the robot, measured from its reference
/// path at the crossing: d_OH (body clearance at CP_h, away from the robot, paper §II-B) plus d_h
/// (how far CP_h already lies from the reference path). CM is measured from the reference path,
/// so its room is the sum: a joint band that already moved CP_h aside has used part of the room
/// d_OH alone would not show. +inf when d_OH is (nothing within the server's range); nullopt
/// when either is unknown or negative.
std::optional<double> lateralRoom(std::optional<double> d_oh_m, std::optional<double> d_h_m);

/// [m] τ judged against the room (TauMode::kRoom): min(τ, max(floor, fraction · room)). With
/// fraction 0.5 the paper's narrow corridor (2.25 m, room ~0.8 m) keeps τ = 0.4 m and a wide one
/// keeps it too; a human with less room is contributing once CM exceeds that fraction of what
/// they had. The floor keeps shifts within tracking noise from counting. τ when room is unknown.
double roomTau(double tau_m, std::optional<double> room_m, double room_fraction, double floor_m);

/// Which side of the human the robot is taken to be on when CA is signed.
///  - kPathSide (the paper's reading, @file): the side of the reference path the robot is on.
///  - kHumanSide (beyond the paper): the side of the HUMAN the robot is on, measured across the
///    reference path's direction at each sample (robot offset minus human offset), with the same
///    deadband and memory. Real walkers meet in open space where the other is often already off
///    the human's initial line on the side the human steps to: the path side then calls a step
///    away from the other "towards the robot" (ETH/UCY head-on pairs).
enum class SideRule : std::int8_t { kPathSide = 0, kHumanSide = 1 };
const char* toString(SideRule r);
/// The rule named by toString(); nullopt for any other name.
std::optional<SideRule> sideRuleFromString(const std::string& name);

/// One CA evaluation.
struct ContributionSample {
  double ca_m{0.0};                   ///< [m] signed contribution (0 when robot_side undefined)
  double human_offset_m{0.0};         ///< [m] human's signed distance from the path, > 0 = left
  Side robot_side{Side::kUndefined};  ///< side of the path (along its direction) the robot is on
  bool side_from_path{false};  ///< robot_side is the robot's own side of the path (memory-able)
};

/// Paper §II-C, CA_i for one sample (see @file for the sign reading, SideRule for the other).
/// previous_robot_side: the robot's side decided at an earlier sample (kUndefined if none).
/// nullopt when the path is empty or a position is non-finite.
std::optional<ContributionSample> contributionAt(const Path2& reference_path,
                                                 const Eigen::Vector2d& human_m,
                                                 const Eigen::Vector2d& robot_m,
                                                 Side previous_robot_side, double side_deadband_m,
                                                 SideRule rule = SideRule::kPathSide);

/// Path assessor tuning. Defaults in this one place.
struct PathAssessorConfig {
  double sample_period_s{0.1};        ///< CA sampling period (10 Hz, CoHAN's control rate), > 0
  double gamma{0.98};                 ///< γ, paper §III
  double tau_m{0.4};                  ///< [m] τ on CM, paper §III
  TauMode tau_mode{TauMode::kFixed};  ///< which threshold IsContributing uses (see TauMode)
  double room_fraction{0.5};          ///< kRoom: share of the lateral room CM must exceed, (0, 1]
  double room_tau_floor_m{0.1};       ///< [m] kRoom: lowest threshold (the side deadband's 0.1 m)
  double side_deadband_m{0.1};  ///< [m] robot this close to the path: side undecided (see @file)
  SideRule side_rule{SideRule::kPathSide};  ///< how CA is signed (SideRule)
  double history_s{2.0};  ///< [s] observations kept for commands stamped in the past
  /// [s] observations farther apart are a tracking gap (or a clock jump): the grid times inside it
  /// get no sample instead of positions interpolated over the gap, and skipping them costs O(1)
  /// however long the gap.
  double max_gap_s{5.0};
};

enum class RecorderState : std::int8_t { kIdle = 0, kRecording = 1, kStopped = 2 };

struct CaSample {
  double t_s{0.0};  ///< [s] grid time of the sample (message time base)
  double ca_m{0.0};
  Side robot_side{Side::kUndefined};
};

/// What the path assessor publishes for one human.
struct PathAssessmentSnapshot {
  RecorderState state{RecorderState::kIdle};
  std::size_t window_samples{0};      ///< samples since the last reset (or start)
  std::optional<double> cm_window_m;  ///< [m] CM over them (decisions); nullopt = no samples
  Tristate is_contributing_window{Tristate::kUnknown};
  std::size_t interaction_samples{0};      ///< samples since start (no reset)
  std::optional<double> cm_interaction_m;  ///< [m] CM since start (Table I reporting)
  Tristate is_contributing_interaction{Tristate::kUnknown};
  double tau_m{0.4};             ///< [m] threshold in force (config τ, or τ_room in kRoom)
  double tau_fixed_m{0.4};       ///< [m] the paper's τ (config)
  std::optional<double> room_m;  ///< [m] lateral room given at start; nullopt = unknown
  double tau_room_m{0.4};        ///< [m] roomTau() of it (= tau_fixed_m when room unknown)
  TauMode tau_mode{TauMode::kFixed};
};

/// Per-human CA recorder (paper §II-C). Fed observations (time, human and robot positions) at any
/// rate; samples CA on a fixed grid t_start + k * sample_period_s from MESSAGE time, with positions
/// linearly interpolated between the bracketing observations, so γ keeps its meaning whatever the
/// tracker's rate. Commands take effect from their time stamp, also slightly in the past (within
/// history_s). No clock: time is a parameter throughout.
class PathRecorder {
 public:
  explicit PathRecorder(const PathAssessorConfig& config = {});

  /// Starts a new interaction at t_s against reference_path (the human's INITIAL shortest path,
  /// kept until the next start). Clears both windows. room_m: the lateral room the human had
  /// (lateralRoom() of the decision's situation), used by TauMode::kRoom. Returns false (and
  /// stays as it was) when the path is empty or non-finite.
  bool start(double t_s, const Path2& reference_path, std::optional<double> room_m = std::nullopt);
  /// Stops sampling at t_s (samples after t_s are dropped). Data stay readable.
  void stop(double t_s);
  /// Starts a new decision window: samples at or before t_s leave the window (not the interaction).
  void reset(double t_s);
  /// Feeds one observation; returns false (ignored) for non-finite input or t_s not after the
  /// previous observation.
  bool observe(double t_s, const Eigen::Vector2d& human_m, const Eigen::Vector2d& robot_m);

  PathAssessmentSnapshot snapshot() const;
  RecorderState state() const { return state_; }
  /// All samples since start, oldest first.
  const std::vector<CaSample>& interactionSamples() const { return samples_; }
  /// CA values since the last reset, oldest first.
  std::vector<double> windowCa() const;
  /// CA values since start, oldest first (feed to discountedMean() for a γ sweep).
  std::vector<double> interactionCa() const;
  const Path2& referencePath() const { return reference_; }
  const PathAssessorConfig& config() const { return config_; }

 private:
  struct Observation {
    double t_s;
    Eigen::Vector2d human_m;
    Eigen::Vector2d robot_m;
  };
  void sampleDue();
  std::size_t windowBegin() const;

  PathAssessorConfig config_;
  RecorderState state_{RecorderState::kIdle};
  Path2 reference_;
  std::optional<double> room_m_;
  std::deque<Observation> history_;
  std::vector<CaSample> samples_;
  double start_t_s_{0.0};
  long next_k_{0};
  std::optional<double> stop_t_s_;
  std::optional<double> reset_t_s_;
  Side robot_side_memory_{Side::kUndefined};
};

}  // namespace coopnav::assessment
