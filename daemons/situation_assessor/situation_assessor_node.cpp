#include "situation_assessor_node.hpp"

#include <utility>

#include "common/conversions_assessment.hpp"
#include "common/log.hpp"
#include "coopnav/situation_t.hpp"

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
      outputs_(runtime) {
  // Lockstep: the bands of step k are assessed with every reference path published up to k (a
  // lost one holds the step until the world publishes it again). Without a band source that
  // acknowledges (a log replay), nothing is waited for.
  StepGateOptions gate;
  gate.requirements = {{"band_source",
                        0,
                        {channels::kReferencePaths, channels::kBands},
                        /*optional_until_seen=*/true}};
  gate.timeout = std::chrono::milliseconds(config_.gate_timeout_ms);
  gate_ = std::make_unique<StepGate>(runtime_, gate);
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
  if (!gate_->noteReceived("band_source", channels::kReferencePaths, msg.step, "refs")) return;
  struct Poke {
    StepGate& g;
    ~Poke() { g.poke(); }
  } poke{*gate_};
  const ReferencePaths paths = fromLcm(msg);  // throws RejectedMessage (NaN, bad counts)
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
    references_[e.agent_id] = Reference{e.revision, paths.utime, e.path};
  }
  // The band source republishes every known human's path each second: a path not refreshed for
  // a minute of message time belongs to someone who left. Forgetting it keeps a long-running
  // assessor's memory bounded (it grew with every person ever met; docs/soak.md).
  for (auto it = references_.begin(); it != references_.end();) {
    if (utimeDiffSeconds(paths.utime, it->second.utime) > kForgetHumanAfter_s) {
      it = references_.erase(it);
    } else {
      ++it;
    }
  }
}

void SituationAssessorNode::onBands(const bands_t& msg) {
  // A repeat is the same bytes for the same step (the band source re-published it because the
  // world waits for someone downstream): send our kept answers again, never assess twice. Other
  // bands of an old step (a clock or step going backwards) are assessed in arrival order.
  std::uint64_t hash = 1469598103934665603ull;
  if (msg.step >= 0) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    for (const auto b : bytes) hash = (hash ^ b) * 1099511628211ull;
    const auto seen = bands_hash_.find(msg.step);
    if (seen != bands_hash_.end() && seen->second == hash) {
      outputs_.republishRecent(msg.step);
      runtime_.countDropped();  // not assessed again: counted as a stale input
      return;
    }
    bands_hash_[msg.step] = hash;
    while (bands_hash_.size() > 64) bands_hash_.erase(bands_hash_.begin());
  }
  gate_->noteReceived("band_source", channels::kBands, msg.step, "bands");
  Job job;
  job.utime = msg.utime;
  job.step = msg.step;
  bool rejected = false;
  std::string why;
  try {
    job.bands = fromLcm(msg);
  } catch (const RejectedMessage& e) {
    // Still acknowledged, in its turn, so that a lockstep run goes on (docs/lockstep.md).
    rejected = true;
    why = e.what();
  }
  gate_->submit(job.step,
                [this, job](bool, const std::string&) mutable { enqueue(std::move(job)); });
  if (rejected) throw RejectedMessage(why);
}

void SituationAssessorNode::enqueue(Job job) {
  const bool free_running = job.step < 0;
  queue_.push_back(std::move(job));
  if (free_running) {
    // Free-running bands supersede each other: keep the newest waiting ones only. The head is
    // never touched while its request is in flight.
    std::size_t waiting = 0;
    for (std::size_t i = busy_ ? 1 : 0; i < queue_.size(); ++i)
      if (queue_[i].step < 0) ++waiting;
    for (std::size_t i = busy_ ? 1 : 0;
         waiting > static_cast<std::size_t>(config_.free_running_queue_max) &&
         i + 1 < queue_.size();) {
      if (queue_[i].step < 0) {
        log().debug("situation_assessor: free-running bands of utime {} superseded, dropped",
                    queue_[i].utime);
        queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(i));
        runtime_.countDropped();
        --waiting;
      } else {
        ++i;
      }
    }
  }
  pump();
}

void SituationAssessorNode::pump() {
  while (!busy_ && !queue_.empty()) {
    Job& job = queue_.front();
    if (!job.bands) {
      outputs_.ack(job.utime, job.step);
      queue_.pop_front();
      continue;
    }
    runtime_.noteLogicTime(job.utime);
    const BandsSnapshot& bands = *job.bands;
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
    client_.query(queries, job.utime, [this](const DistanceClient::Outcome& o) {
      finish(&o);
      busy_ = false;
      pump();
    });
  }
}

void SituationAssessorNode::finish(const DistanceClient::Outcome* outcome) {
  const Job job = std::move(queue_.front());
  queue_.pop_front();
  if (outcome) {
    if (!outcome->ok) {
      runtime_.setDegraded("distance server: " + outcome->error);
      log().warn("situation_assessor: step {}: {}; d_OH / d_OR unknown", job.step, outcome->error);
    } else {
      runtime_.setRunning();
    }
  }
  const BandsSnapshot& bands = *job.bands;
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
        prependReason(reason, "distance server: " + outcome->error);
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
    // Paper §II-B: d_h, d_OH, d_OR, d_HR and the three predicates.
    rec.assessment = assessment::assessSituation(w.crossing, path, d_oh_m, d_or_m, thresholds_);
    prependReason(rec.assessment.reason, reason);
    outputs_.publish(job.step, channels::kSituation, toLcm(rec));
  }
  work_.clear();
  outputs_.ack(job.utime, job.step);
}

}  // namespace coopnav
