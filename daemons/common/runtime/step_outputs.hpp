#pragma once
/// @file The outputs of a daemon's lockstep steps, kept so that a step can be answered again
/// (docs/lockstep.md "Loss and restarts"). A node publishes its outputs of step k through
/// publish(k, ...) and ends the step with ack(utime, k): the ack carries how many messages went
/// out on each channel, so a consumer knows when it has them all. When the world re-publishes a
/// step (an ack or an output was lost, or a participant restarted), the node calls
/// republishRecent(k): the cached bytes of steps k-1 and k go out again, identical, ack included;
/// nothing is recomputed, so a repeat can never differ from the first answer.
/// Free-running messages (step -1) are published as they are and never kept.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "runtime/runtime.hpp"

namespace coopnav {

class StepOutputs {
 public:
  /// Keeps the outputs of the latest `keep_steps` steps.
  explicit StepOutputs(Runtime& runtime, std::size_t keep_steps = 8);

  template <class Msg>
  void publish(std::int64_t step, const std::string& channel, const Msg& msg) {
    if (step < 0) {
      runtime_.publish(channel, msg);
      return;
    }
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    if (msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0) return;
    publishBytes(step, channel, std::move(bytes));
  }

  /// Acknowledges `step` with the counts of what was published for it, and keeps the ack.
  void ack(std::int64_t utime, std::int64_t step);

  /// Sends the kept outputs and ack of `step` again; false when the step is not (or no longer)
  /// kept or not yet acknowledged.
  bool republish(std::int64_t step);
  /// republish(step - 1) and republish(step): what a consumer of step `step` may still miss.
  void republishRecent(std::int64_t step);

  bool acked(std::int64_t step) const;
  /// Latest acknowledged step; -1 when none.
  std::int64_t lastAcked() const { return last_acked_; }

 private:
  struct Step {
    std::vector<std::pair<std::string, std::vector<std::uint8_t>>> messages;
    std::vector<std::uint8_t> ack;  ///< empty until acknowledged
  };
  void publishBytes(std::int64_t step, const std::string& channel, std::vector<std::uint8_t> bytes);

  Runtime& runtime_;
  std::size_t keep_steps_;
  std::map<std::int64_t, Step> steps_;
  std::int64_t last_acked_{-1};
  std::int64_t republished_{0};
};

}  // namespace coopnav
