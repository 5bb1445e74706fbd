#pragma once
/// @file Situation assessor (paper §II-B): for each bands message and each human band in it, the
/// crossing info against the robot band, the two half-plane distance queries (one batched request
/// to the obstacle distance server per bands message), and the three predicates; publishes one
/// situation per human, then acknowledges the step. Bands messages are processed strictly in
/// arrival order: while one waits for its distance answers the next ones queue behind it (the
/// lockstep protocol needs the order; see docs/lockstep.md).

#include <chrono>
#include <cstdint>
#include <deque>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "coopnav/assessment/crossing.hpp"
#include "coopnav/assessment/situation.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "distance_client/distance_client.hpp"
#include "runtime/id_recency.hpp"
#include "runtime/limits.hpp"
#include "runtime/message_clock.hpp"
#include "runtime/runtime.hpp"
#include "runtime/step_node.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

struct SituationAssessorConfig {
  // The lib's own structs, read in place: their in-class initialisers are the only defaults.
  assessment::SituationThresholds situation;
  assessment::CrossingConfig crossing;
  /// [m] search range of the SIDE queries; an obstacle farther is "none" (+inf, not constrained).
  double query_range_m{10.0};
  /// [ms] wall time one distance request attempt may take (liveness only, never logic).
  int distance_timeout_ms{50};
  /// Attempts per bands message; the wait is bounded by distance_timeout_ms * distance_attempts.
  int distance_attempts{3};
  /// Free-running (step -1) bands messages waiting behind the one in progress beyond this are
  /// superseded by newer ones and dropped; lockstep messages are never dropped.
  int free_running_queue_max{2};
  /// [ms] lockstep: how long the bands of step k wait for band_source's ack of k (with the
  /// reference paths it published for k) before they are assessed without it (liveness only).
  int gate_timeout_ms{2000};

  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("tau_h_m", situation.tau_h_m, Range{0.0, 10.0});
    v("tau_oh_m", situation.tau_oh_m, Range{0.0, 10.0});
    v("tau_or_m", situation.tau_or_m, Range{0.0, 10.0});
    v("tau_hr_m", situation.tau_hr_m, Range{0.0, 10.0});
    v("robot_radius_m", situation.robot_radius_m, Range{0.0, 5.0});
    v("human_radius_m", situation.human_radius_m, Range{0.0, 5.0});
    v("coincident_tolerance_m", situation.coincident_tolerance_m, Range{1e-6, 1.0});
    v("grid_dt_s", crossing.grid_dt_s, Range{1e-3, 1.0});
    v("dir_tolerance_m", crossing.dir_tolerance_m, Range{0.0, 1.0});
    v("dir_lookahead_s", crossing.dir_lookahead_s, Range{0.0, 30.0});
    v("max_band_span_s", crossing.max_band_span_s, Range{1.0, 86400.0});
    v("max_grid_points", crossing.max_grid_points, Range{2, 10000000});
    v("query_range_m", query_range_m, Range{0.1, 100.0});
    v("distance_timeout_ms", distance_timeout_ms, Range{1, 5000});
    v("distance_attempts", distance_attempts, Range{1, 10});
    v("free_running_queue_max", free_running_queue_max, Range{1, 1000});
    v("gate_timeout_ms", gate_timeout_ms, Range{1, 600000});
    v("limits", limits);
  }

  const assessment::SituationThresholds& thresholds() const { return situation; }
  const assessment::CrossingConfig& crossingConfig() const { return crossing; }
};

class SituationAssessorNode {
 public:
  using Config = SituationAssessorConfig;
  SituationAssessorNode(const Config& config, Runtime& runtime);

  /// Bands messages received and not yet published (the head may be waiting for distances).
  std::size_t queued() const { return waiting_.size(); }
  /// Humans whose reference path is kept (at most limits.max_ids; tests, diagnostics).
  std::size_t referencesKept() const { return references_.size(); }

 private:
  /// Bands whose step's work started, waiting in arrival order for their turn at the distance
  /// server (the head may be waiting for its answers).
  struct BandsToAssess {
    StepNode::Step step;
    BandsSnapshot bands;
  };
  struct Reference {
    std::int32_t revision{0};
    std::int64_t utime{0};  ///< of the message that brought it (the stale-revision check)
    Path2 path;
  };
  /// Per human of the job at the head of the queue, between the request and the answer.
  struct HumanWork {
    std::int32_t id{0};
    assessment::CrossingInfo crossing;
    std::optional<assessment::HalfPlaneQueries> queries;
    int first_query{-1};  ///< index of the d_OH query in the batch (d_OR follows); -1 none
    std::string extra_reason;
  };

  void onBands(const bands_t& msg);
  void onReferencePaths(const reference_paths_t& msg);
  void storeReferencePaths(const reference_paths_t& msg);
  /// Forgets the reference paths not stored for limits.forget_after_s of message time, then the
  /// least recently stored beyond limits.max_ids; one log line for the lot. Only the forgotten
  /// are visited, so a message costs O(its paths + forgotten).
  void forgetReferences();
  void enqueue(BandsToAssess bands);
  /// Assesses the waiting bands in order until one waits for the distance server.
  void assessWaiting();
  void finish(const DistanceClient::Outcome* outcome);

  Config config_;
  Runtime& runtime_;
  assessment::SituationThresholds thresholds_;
  assessment::CrossingConfig crossing_config_;
  DistanceClient client_;
  /// The reference paths' time (messages stamped far off it are rejected, not followed).
  /// Bands keep no time: each is assessed on its own, whatever its stamp.
  MessageClock clock_;
  std::map<std::int32_t, Reference> references_;
  IdRecency recency_;  ///< ids of references_ by when last stored (ages them out)
  std::deque<BandsToAssess> waiting_;
  bool busy_{false};  ///< the head of waiting_ waits for its distance answers
  std::vector<HumanWork> work_;
  /// Last: steps still held when the node goes away are not acknowledged.
  std::unique_ptr<StepNode> steps_;
};

}  // namespace coopnav
