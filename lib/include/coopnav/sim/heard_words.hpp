#pragma once
/// @file Words said to the simulated people, kept until the step that applies them (world_sim):
/// pure (no LCM, no clock, no I/O). The node converts an utterance to a Cue (who hears what,
/// when its words end) and offers it here; at each step it takes the cues and adds them to the
/// simulation, which decides what each person does with them (lib/sim behaviours).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coopnav/sim/behaviour.hpp"
#include "coopnav/sim/simulation.hpp"

namespace coopnav::sim {

class HeardWords {
 public:
  struct Pending {
    Cue cue;
    std::int64_t step{-1};  ///< the step the words were decided on (-1: free-running)
  };
  enum class Verdict : std::uint8_t {
    kKept,             ///< kept for the addressee and every group member with room for it
    kEndsTooFarAhead,  ///< its words end more than max_ahead_s after now: they would wait all run
    kEndedTooLongAgo,  ///< ended more than forget_after_s before now: the encounter is long over
    kFull,             ///< the addressee has max_unended utterances whose words have not ended
  };

  /// max_unended_per_human: utterances to one person whose words have not ended (here and in the
  /// simulation): one person hears one sentence at a time, and the robot says one per round.
  explicit HeardWords(std::size_t max_unended_per_human = 16)
      : max_unended_(max_unended_per_human) {}

  /// The cue of an utterance to `cue.human_id` (a person's scenario id), decided on `step`, also
  /// heard by `group` (the other persons it was said to, already resolved; each gets it while it
  /// has room). now_s: the simulation's time; sim: for the cues it still holds per person.
  Verdict offer(const Cue& cue, std::int64_t step, const std::vector<std::int32_t>& group,
                double now_s, double max_ahead_s, double forget_after_s, const Simulation& sim);

  /// The cues to apply now, in the order they were offered, each heard no earlier than now_s
  /// (words that ended before the step they were decided on takes effect are heard now); emptied.
  std::vector<Pending> take(double now_s);

  std::size_t size() const { return pending_.size(); }
  std::size_t maxUnendedPerHuman() const { return max_unended_; }

 private:
  /// Utterances to `id` not yet ended: here and in the simulation.
  std::size_t unended(std::int32_t id, const Simulation& sim) const;

  std::size_t max_unended_;
  std::vector<Pending> pending_;
};

}  // namespace coopnav::sim
