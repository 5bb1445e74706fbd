#include "situation_assessor_node.hpp"

#include <algorithm>
#include <utility>

#include "coopnav/situation_t.hpp"
#include "runtime/log.hpp"
#include "wire/assessment.hpp"

namespace coopnav {
namespace {

const char* bandsStatusName(std::int8_t s) {
  switch (s) {
    case bands_t::STATUS_OK:
      return "OK";
    case bands_t::STATUS_NO_PATH:
      return "NO_PATH";
    case bands_t::STATUS_INVALID_INPUT:
      return "INVALID_INPUT";
    case bands_t::STATUS_SOLVER_FAILED:
      return "SOLVER_FAILED";
    case bands_t::STATUS_GOAL_REACHED:
      return "GOAL_REACHED";
    default:
      return "unknown status";
  }
}

void prependReason(std::string& reason, const std::string& what) {
  if (what.empty()) return;
  reason = reason.empty() ? what : what + "; " + reason;
}

}  // namespace

SituationAssessorNode::SituationAssessorNode(const Config& config, Runtime& runtime)
    : config_(config),
      runtime_(runtime),
      thresholds_(config.thresholds()),
      crossing_config_(config.crossingConfig()),
      client_(runtime, "situation_assessor",
              DistanceClient::Options{std::chrono::milliseconds(config.distance_timeout_ms),
                                      config.distance_attempts}),
      clock_(runtime.limits().max_time_jump_s, runtime.limits().time_resync_messages) {
  // Lockstep: the bands of step k are assessed with every reference path published up to k (a
  // lost one holds the step until the world publishes it again). Without a band source that
  // acknowledges (a log replay), nothing is waited for.
  StepNodeOptions steps;
  steps.requirements = {{"band_source",
                         0,
                         {channels::kReferencePaths, channels::kBands},
                         /*optional_until_seen=*/true}};
  steps.timeout = std::chrono::milliseconds(config_.gate_timeout_ms);
  // Every bands message is assessed in arrival order, an old step's too; a repeat is the same
  // bytes for the same step (the band source re-published it because the world waits for
  // someone downstream): the kept answers go out again, nothing is assessed twice.
  steps.repeat = StepNodeOptions::Repeat::kSameBytes;
  steps_ = std::make_unique<StepNode>(runtime_, steps);
  runtime_.setLostStateNote(
      "the humans' reference paths until the band source publishes them again (d_h unknown "
      "meanwhile)");
  runtime_.setRunning();
  runtime_.subscribe<reference_paths_t>(
      channels::kReferencePaths,
      [this](const reference_paths_t& m, std::int64_t) { onReferencePaths(m); });
  // Bands are not journaled: a restarted assessor assesses a re-published step afresh, with the
  // same references and distances, which gives the same answer.
  runtime_.subscribe<bands_t>(
      channels::kBands, [this](const bands_t& m, std::int64_t) { onBands(m); }, 0, false);
}

void SituationAssessorNode::onReferencePaths(const reference_paths_t& msg) {
  steps_->input("band_source", channels::kReferencePaths, msg.step, "refs",
                [&] { storeReferencePaths(msg); });
}

void SituationAssessorNode::storeReferencePaths(const reference_paths_t& msg) {
  const ReferencePaths paths = fromLcm(msg);  // throws RejectedMessage (NaN, bad counts)
  // A jump is rejected: one message stamped INT64_MAX must not make every later path look stale,
  // nor keep its paths for ever (they would age against its own time). Reordered ones are
  // stored: the revision check decides.
  clock_.take(paths.utime, "reference paths", [&] {
    // A new time line (a new run, a restarted band source, or a clock one bad message had set):
    // paths stamped on the old one can be neither compared nor aged against it.
    log().info(
        "situation_assessor: reference paths' time resynced to {}: forgetting the {} paths "
        "stored on the previous time",
        paths.utime, references_.size());
    references_.clear();
    recency_.clear();
  });
  const std::int64_t now_utime = *clock_.now();
  for (const auto& e : paths.paths) {
    auto it = references_.find(e.agent_id);
    if (it != references_.end() && e.revision < it->second.revision) {
      if (paths.utime <= it->second.utime) {
        log().debug(
            "situation_assessor: ignoring stale reference path of human {} (revision {} "
            "< {})",
            e.agent_id, e.revision, it->second.revision);
        continue;
      }
      // A newer message with a lower revision: the band source restarted.
      log().info(
          "situation_assessor: reference path revision of human {} went back from {} to "
          "{} (band source restarted?)",
          e.agent_id, it->second.revision, e.revision);
    }
    if (it == references_.end()) it = references_.emplace(e.agent_id, Reference{}).first;
    recency_.touch(e.agent_id, now_utime);
    Reference& r = it->second;
    r.revision = e.revision;
    r.utime = paths.utime;
    r.path = e.path;
  }
  forgetReferences();
}

void SituationAssessorNode::forgetReferences() {
  // The band source republishes every known human's path each second: a path not refreshed for
  // limits.forget_after_s (a minute) of message time belongs to someone who left, and ids beyond
  // limits.max_ids are a flood. Kept, they grew with every id ever sent (docs/soak.md).
  const InputLimits& limits = runtime_.limits();
  const auto max_ids = static_cast<std::size_t>(std::max(limits.max_ids, 1));
  const IdRecency::Forgotten n =
      recency_.forgetOld(*clock_.now(), limits.forget_after_s, max_ids,
                         [&](std::int32_t id) { references_.erase(id); });
  if (n.aged + n.over > 0)
    log().info(
        "situation_assessor: forgot the reference paths of {} humans ({} not republished for "
        "{} s, {} beyond limits.max_ids = {})",
        n.aged + n.over, n.aged, limits.forget_after_s, n.over, max_ids);
}

void SituationAssessorNode::onBands(const bands_t& msg) {
  steps_->open("band_source", channels::kBands, msg, [&]() -> StepNode::Work {
    BandsToAssess b{{}, fromLcm(msg)};  // throws RejectedMessage
    return [this, b](StepNode::Step& step) mutable {
      b.step = step;
      enqueue(std::move(b));
    };
  });
}

void SituationAssessorNode::enqueue(BandsToAssess b) {
  const bool free_running = b.step.step() < 0;
  waiting_.push_back(std::move(b));
  if (free_running) {
    // Free-running bands supersede each other: keep the newest waiting ones only. The head is
    // never touched while its request is in flight.
    std::size_t waiting = 0;
    for (std::size_t i = busy_ ? 1 : 0; i < waiting_.size(); ++i)
      if (waiting_[i].step.step() < 0) ++waiting;
    for (std::size_t i = busy_ ? 1 : 0;
         waiting > static_cast<std::size_t>(config_.free_running_queue_max) &&
         i + 1 < waiting_.size();) {
      if (waiting_[i].step.step() < 0) {
        log().debug("situation_assessor: free-running bands of utime {} superseded, dropped",
                    waiting_[i].step.utime());
        waiting_.erase(waiting_.begin() + static_cast<std::ptrdiff_t>(i));
        runtime_.countDropped();
        --waiting;
      } else {
        ++i;
      }
    }
  }
  assessWaiting();
}

void SituationAssessorNode::assessWaiting() {
  while (!busy_ && !waiting_.empty()) {
    BandsToAssess& head = waiting_.front();
    runtime_.noteLogicTime(head.step.utime());
    const BandsSnapshot& bands = head.bands;
    work_.clear();
    std::vector<DistanceQuery> queries;
    for (const auto& [id, band] : bands.humans) {
      HumanWork w;
      w.id = id;
      if (bands.status != bands_t::STATUS_OK) {
        w.crossing.status = assessment::CrossingStatus::kBadBands;
        w.crossing.reason = std::string("bands status ") + bandsStatusName(bands.status) +
                            ": the bands are not a plan";
      } else {
        // Paper §II-B: crossing info of this human band against the robot band.
        w.crossing = assessment::computeCrossing(bands.robot, band, crossing_config_);
      }
      if (w.crossing.status == assessment::CrossingStatus::kOk) {
        w.queries = assessment::halfPlaneQueries(w.crossing, thresholds_);
        if (w.queries) {
          w.first_query = static_cast<int>(queries.size());
          DistanceQuery q;
          q.kind = DistanceQueryKind::kSide;
          q.max_range_m = config_.query_range_m;
          q.point = w.queries->human.point;
          q.vector = w.queries->human.normal;
          queries.push_back(q);
          q.point = w.queries->robot.point;
          q.vector = w.queries->robot.normal;
          queries.push_back(q);
        } else {
          w.extra_reason =
              "CP_h and CP_r coincide and Dir is undefined: no side for the d_OH / d_OR "
              "half-planes";
        }
      }
      work_.push_back(std::move(w));
    }
    if (queries.empty()) {
      finish(nullptr);
      continue;
    }
    busy_ = true;
    client_.query(queries, head.step.utime(), [this](const DistanceClient::Outcome& o) {
      finish(&o);
      busy_ = false;
      assessWaiting();
    });
  }
}

void SituationAssessorNode::finish(const DistanceClient::Outcome* outcome) {
  BandsToAssess done = std::move(waiting_.front());
  waiting_.pop_front();
  if (outcome) {
    if (!outcome->ok) {
      runtime_.setDegraded("distance server: " +
                           keptText(outcome->error, runtime_.limits().maxTextBytes()));
      log().warn("situation_assessor: step {}: {}; d_OH / d_OR unknown", done.step.step(),
                 outcome->error);
    } else {
      runtime_.setRunning();
    }
  }
  const BandsSnapshot& bands = done.bands;
  for (const HumanWork& w : work_) {
    std::optional<double> d_oh_m;
    std::optional<double> d_or_m;
    std::string reason = w.extra_reason;
    if (w.first_query >= 0 && outcome) {
      if (outcome->ok) {
        const DistanceResult& rh = outcome->results[static_cast<std::size_t>(w.first_query)];
        const DistanceResult& rr = outcome->results[static_cast<std::size_t>(w.first_query) + 1];
        d_oh_m = assessment::obstacleDistanceFrom(rh, thresholds_.human_radius_m);
        d_or_m = assessment::obstacleDistanceFrom(rr, thresholds_.robot_radius_m);
        if (!d_oh_m) prependReason(reason, std::string("d_OH query: ") + toString(rh.status));
        if (!d_or_m) {
          const std::string r = std::string("d_OR query: ") + toString(rr.status);
          reason = reason.empty() ? r : reason + "; " + r;
        }
      } else {
        prependReason(reason, "distance server: " +
                                  keptText(outcome->error, runtime_.limits().maxTextBytes()));
      }
    }
    const auto ref = references_.find(w.id);
    static const Path2 kNoPath;
    const Path2& path = ref == references_.end() ? kNoPath : ref->second.path;
    SituationRecord rec;
    rec.utime = bands.utime;
    rec.step = bands.step;
    rec.human_id = w.id;
    rec.crossing = w.crossing;
    rec.has_reference = !path.empty();
    rec.thresholds = thresholds_;
    rec.room_plan = bands.roomPlan(w.id);
    rec.robot_mode = bands.robot_mode;
    // Paper §II-B: d_h, d_OH, d_OR, d_HR and the three predicates.
    rec.assessment = assessment::assessSituation(w.crossing, path, d_oh_m, d_or_m, thresholds_);
    prependReason(rec.assessment.reason, reason);
    done.step.publish(channels::kSituation, toLcm(rec));
  }
  work_.clear();
  done.step.finish();
}

}  // namespace coopnav
