#pragma once
/// @file When the robot's words are heard: how long an utterance takes to say, and one voice's
/// timeline (an utterance starts only once the previous one has ended, and a cue whose speech would
/// end after the crossing is not said). Pure: time is an input.
///
/// A cue is useful only if the person hears it with time left to act on it (t_cue_start ≥
/// t_cross − (T_utterance + T_react + T_maneuver): our reading, no published rule); the decision
/// pipeline of paper §II-D fires its rounds at t_CROSS thresholds and does not say how long the
/// words take. So every utterance carries its start and its duration, and the person model of the
/// simulator and the round-2 check (decision.hpp) both count from when the words have been heard.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace coopnav::dialogue {

/// What became of a decided utterance; values mirror coopnav_utterance_t.DELIVERY_*.
enum class Delivery : std::int8_t {
  kSaid = 1,
  kMuted = 2,        ///< the robot is muted: decided and logged, not said
  kTooLate = 3,      ///< its speech would end after the crossing: not said
  kToldToGroup = 4,  ///< already said to the human's group (crowd.hpp): not said again
  kContradicts = 5,  ///< would contradict what the robot said or does (crowd.hpp): not said
};
const char* toString(Delivery d);

/// Time to say `text` at `rate_wpm` with espeak-ng's en-us voice, for when no synthesiser measures
/// it [s]: 0.58 s + 0.013 s per letter or digit + 0.13 s per word + 0.45 s per internal pause
/// (comma, or a sentence end followed by more text), scaled by 175 / rate_wpm. Least-squares fit
/// to espeak-ng 1.51 at 175 wpm over the 17 template texts and short corridor phrases ("Thank
/// you." 0.89 s, "I will pass on your left." 1.56 s; 0.89–3.34 s, largest error 0.38 s, typically
/// 0.1 s).
double estimateSpeechDuration(const std::string& text, double rate_wpm);

/// Duration of a PCM WAV file given as its bytes [s]: the data chunk's size over the format
/// chunk's byte rate (a data size past the end of the file, as a streaming writer leaves it, is
/// cut to the bytes present). nullopt when it is not a RIFF/WAVE file with both chunks.
std::optional<double> wavDurationSeconds(const std::string& bytes);

/// When one utterance is spoken, relative to its decision time.
struct SpeechSlot {
  Delivery delivery{Delivery::kSaid};
  double start_s{0.0};     ///< [s] after the decision: > 0 while an earlier one is being spoken
  double duration_s{0.0};  ///< [s] how long saying it takes
  /// [s] Said by cutting the utterance being spoken this long before its end (0: none cut).
  double interrupts_s{0.0};
  /// [s] end of the speech after the decision (start + duration); for kTooLate, how far past the
  /// crossing it would have ended is end_s − the deadline given.
  double end_s() const { return start_s + duration_s; }
};

/// The robot's one voice. Not thread-safe; one per dialogue manager.
class SpeechTimeline {
 public:
  /// Plans an utterance decided at `t_s` that takes `duration_s`: it starts when the voice is
  /// free. `deadline_s` (absolute, e.g. the crossing's time) when its words are useless after it;
  /// a slot that would end later is kTooLate. kMuted and kTooLate slots do not occupy the voice.
  SpeechSlot plan(double t_s, double duration_s, std::optional<double> deadline_s, bool muted);
  /// Plans the first of several wordings of one utterance (longest first, `durations_s` in that
  /// order) whose speech ends before `deadline_s`: with little time left a shorter sentence is
  /// said rather than nothing. When none fits, the first is returned as kTooLate (the transcript
  /// records the full sentence as not said, and why). Muted: the first, kMuted. Empty
  /// `durations_s`: index 0 with a kTooLate slot of zero duration.
  struct Choice {
    std::size_t index{0};  ///< which wording was planned
    SpeechSlot slot;
  };
  /// `may_interrupt`: words that announce a change of what the robot does (it makes room where it
  /// said it passes) must not be lost to the words before them. When no wording fits after what
  /// is being said but one fits from now, the voice stops what it says and says it now
  /// (SpeechSlot::interrupts_s > 0).
  Choice planFirstFitting(double t_s, const std::vector<double>& durations_s,
                          std::optional<double> deadline_s, bool muted, bool may_interrupt = false);
  /// Absolute time at which the voice is free again.
  double freeAt() const { return free_at_s_; }

 private:
  double free_at_s_{-1e300};
};

}  // namespace coopnav::dialogue
