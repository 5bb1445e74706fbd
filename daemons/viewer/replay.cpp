#include "replay.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <utility>

#include "coopnav/channels.hpp"
#include "logfile/log_reader.hpp"
#include "runtime/runtime.hpp"

namespace coopnav::viewer {

void Replay::applyTo(SceneModel& scene, const Event& e) {
  try {
    scene.applyRaw(e.channel, e.data.data(), e.data.size(), e.received_utime);
  } catch (const RejectedMessage&) {
    scene.countRejected(e.channel);
  } catch (const DroppedMessage&) {
    // Well-formed but not for the scene (older than it): as live, nothing to draw.
  }
}

Replay::Replay(const std::string& path, const SceneModel& scene, double checkpoint_s,
               int max_checkpoints)
    : path_(path), initial_(scene), scene_(scene) {
  // The tools' one reader (daemons/common/logfile): a bad header is skipped and the reader
  // resynchronises, a device or FIFO is refused, nothing past the file's size is read.
  logfile::LogEventReader log(path);
  // One pass: every event of a channel the scene draws, placed at the scene time in force.
  SceneModel scratch = scene;
  std::optional<double> first_t;
  std::vector<std::size_t> before_first;  // events before the first agent states
  double next_checkpoint = 0.0;
  logfile::RawEvent ev;
  while (log.next(ev)) {
    Event e;
    e.channel = std::move(ev.channel);
    e.data = std::move(ev.data);
    e.received_utime = ev.timestamp_us;
    try {
      if (!scratch.applyRaw(e.channel, e.data.data(), e.data.size(), e.received_utime))
        continue;  // not drawn
    } catch (const RejectedMessage&) {
      ++rejected_in_log_;
      scratch.countRejected(e.channel);
    } catch (const DroppedMessage&) {
    }
    if (scratch.utime()) {
      const double t = utimeToSeconds(*scratch.utime());
      if (!first_t) {
        first_t = t;
        for (std::size_t i : before_first) events_[i].t_s = t;
        next_checkpoint = t + checkpoint_s;
      }
      // A log spanning two runs (a resync) goes back in time: keep the timeline monotonic.
      e.t_s = events_.empty() ? t : std::max(t, events_.back().t_s);
    } else {
      before_first.push_back(events_.size());
    }
    events_.push_back(std::move(e));
    if (first_t && events_.back().t_s >= next_checkpoint) {
      checkpoints_.push_back({events_.back().t_s, events_.size(), scratch});
      // At most max_checkpoints copies of the scene (each bounded by SceneOptions): beyond,
      // every other one goes and the spacing doubles, so a long log costs a bounded memory.
      if (static_cast<int>(checkpoints_.size()) > std::max(max_checkpoints, 2)) {
        std::vector<Checkpoint> kept;
        for (std::size_t i = 1; i < checkpoints_.size(); i += 2)
          kept.push_back(std::move(checkpoints_[i]));
        checkpoints_ = std::move(kept);
        checkpoint_s *= 2.0;
      }
      next_checkpoint = events_.back().t_s + checkpoint_s;
    }
  }
  read_counts_ = log.counts().describe();
  if (!first_t)
    throw std::runtime_error("the LCM log " + path + " holds no agent states (" + read_counts_ +
                             ")");
  start_s_ = *first_t;
  end_s_ = events_.back().t_s;
  position_s_ = start_s_;
  applyUpToPosition();
}

void Replay::play() {
  if (position_s_ >= end_s_) seek(start_s_);
  playing_ = true;
}

void Replay::seek(double t_s) {
  const double target = std::clamp(t_s, start_s_, end_s_);
  const Checkpoint* from = nullptr;  // the latest checkpoint at or before the target
  for (const Checkpoint& c : checkpoints_) {
    if (c.t_s > target) break;
    from = &c;
  }
  if (target < position_s_) {
    // Backwards: from that checkpoint, else from the empty scene.
    scene_ = from ? from->scene : initial_;
    next_ = from ? from->next : 0;
  } else if (from && from->next > next_) {
    // Far forwards: skip to the checkpoint.
    scene_ = from->scene;
    next_ = from->next;
  }
  position_s_ = target;
  applyUpToPosition();
}

void Replay::advance(double wall_dt_s) {
  if (!playing_) return;
  position_s_ = std::min(end_s_, position_s_ + wall_dt_s * speed_);
  applyUpToPosition();
  if (position_s_ >= end_s_) playing_ = false;
}

void Replay::applyUpToPosition() {
  while (next_ < events_.size() && events_[next_].t_s <= position_s_) {
    applyTo(scene_, events_[next_]);
    ++next_;
  }
}

nlohmann::json Replay::timelineJson() const {
  return {{"file", path_},
          {"start", start_s_},
          {"end", end_s_},
          {"t", position_s_},
          {"playing", playing_},
          {"speed", speed_},
          {"events", events_.size()},
          {"rejected_in_log", rejected_in_log_},
          {"read", read_counts_}};
}

}  // namespace coopnav::viewer
