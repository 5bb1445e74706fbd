#include "coopnav/sim/heard_words.hpp"

#include <algorithm>
#include <utility>

namespace coopnav::sim {

std::size_t HeardWords::unended(std::int32_t id, const Simulation& sim) const {
  return sim.pendingCues(id) + static_cast<std::size_t>(std::count_if(
                                   pending_.begin(), pending_.end(),
                                   [&](const Pending& p) { return p.cue.human_id == id; }));
}

HeardWords::Verdict HeardWords::offer(const Cue& cue, std::int64_t step,
                                      const std::vector<std::int32_t>& group, double now_s,
                                      double max_ahead_s, double forget_after_s,
                                      const Simulation& sim) {
  // Words are heard when they end, on the simulation's clock.
  if (!(cue.t_s <= now_s + max_ahead_s)) return Verdict::kEndsTooFarAhead;
  if (cue.t_s < now_s - forget_after_s) return Verdict::kEndedTooLongAgo;
  if (unended(cue.human_id, sim) >= max_unended_) return Verdict::kFull;
  pending_.push_back({cue, step});
  // Words to a group are heard by everyone in it (one plan, said once: dialogue crowd.hpp).
  for (const std::int32_t id : group) {
    if (unended(id, sim) >= max_unended_) continue;  // that person: full
    Pending p{cue, step};
    p.cue.human_id = id;
    pending_.push_back(p);
  }
  return Verdict::kKept;
}

std::vector<HeardWords::Pending> HeardWords::take(double now_s) {
  std::vector<Pending> out = std::move(pending_);
  pending_.clear();
  for (Pending& p : out) p.cue.t_s = std::max(p.cue.t_s, now_s);
  return out;
}

}  // namespace coopnav::sim
