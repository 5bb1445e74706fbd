#include "runtime/step_outputs.hpp"

#include "coopnav/step_ack_t.hpp"
#include "runtime/log.hpp"

namespace coopnav {

StepOutputs::StepOutputs(Runtime& runtime, std::size_t keep_steps)
    : runtime_(runtime), keep_steps_(std::max<std::size_t>(keep_steps, 2)) {}

void StepOutputs::publishBytes(std::int64_t step, const std::string& channel,
                               std::vector<std::uint8_t> bytes) {
  runtime_.publishRaw(channel, bytes);
  steps_[step].messages.emplace_back(channel, std::move(bytes));
}

void StepOutputs::ack(std::int64_t utime, std::int64_t step) {
  if (step < 0) return;  // free-running: nobody waits
  Step& s = steps_[step];
  step_ack_t a{};
  a.utime = utime;
  a.step = step;
  a.participant = runtime_.name();
  // Channels in first-published order, so that the same outputs give the same ack bytes.
  for (const auto& [channel, bytes] : s.messages) {
    (void)bytes;
    bool found = false;
    for (std::size_t i = 0; i < a.output_channels.size(); ++i) {
      if (a.output_channels[i] == channel) {
        ++a.output_counts[i];
        found = true;
      }
    }
    if (!found && a.output_channels.size() < static_cast<std::size_t>(step_ack_t::MAX_OUTPUTS)) {
      a.output_channels.push_back(channel);
      a.output_counts.push_back(1);
    }
  }
  a.num_outputs = static_cast<std::int16_t>(a.output_channels.size());
  runtime_.fillRestart(a);
  s.ack.assign(static_cast<std::size_t>(a.getEncodedSize()), 0);
  a.encode(s.ack.data(), 0, static_cast<int>(s.ack.size()));
  runtime_.publishRaw(channels::kStepAck, s.ack);
  if (step > last_acked_) last_acked_ = step;
  while (steps_.size() > keep_steps_) steps_.erase(steps_.begin());
}

bool StepOutputs::republish(std::int64_t step) {
  const auto it = steps_.find(step);
  if (it == steps_.end() || it->second.ack.empty()) return false;
  for (const auto& [channel, bytes] : it->second.messages) runtime_.publishRaw(channel, bytes);
  runtime_.publishRaw(channels::kStepAck, it->second.ack);
  if (republished_++ % 50 == 0)
    log().info("{}: step {} published again ({} repeats so far)", runtime_.name(), step,
               republished_);
  return true;
}

void StepOutputs::republishRecent(std::int64_t step) {
  if (step < 0) return;
  republish(step - 1);
  republish(step);
}

bool StepOutputs::acked(std::int64_t step) const {
  const auto it = steps_.find(step);
  return it != steps_.end() && !it->second.ack.empty();
}

}  // namespace coopnav
