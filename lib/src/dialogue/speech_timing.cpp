#include "coopnav/dialogue/speech_timing.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>

namespace coopnav::dialogue {

const char* toString(Delivery d) {
  switch (d) {
    case Delivery::kSaid:
      return "said";
    case Delivery::kMuted:
      return "muted";
    case Delivery::kTooLate:
      return "too_late";
    case Delivery::kToldToGroup:
      return "told_to_group";
    case Delivery::kContradicts:
      return "contradicts";
  }
  return "?";
}

double estimateSpeechDuration(const std::string& text, double rate_wpm) {
  // Coefficients of the fit described in the header (espeak-ng 1.51, en-us, 175 wpm).
  constexpr double kBase_s = 0.58;
  constexpr double kPerLetter_s = 0.013;
  constexpr double kPerWord_s = 0.13;
  constexpr double kPerPause_s = 0.45;
  constexpr double kFitRate_wpm = 175.0;
  int letters = 0, words = 0, pauses = 0;
  bool in_word = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (std::isalnum(c) != 0) ++letters;
    const bool space = std::isspace(c) != 0;
    if (!space && !in_word) ++words;
    in_word = !space;
    // A pause is a comma, or a sentence end with more text after it (the final stop is silence
    // the synthesiser does not add).
    if (c == ',' || ((c == '.' || c == '!' || c == '?') && i + 1 < text.size() &&
                     std::isspace(static_cast<unsigned char>(text[i + 1])) != 0 &&
                     text.find_first_not_of(" \t\n", i + 1) != std::string::npos))
      ++pauses;
  }
  if (words == 0) return 0.0;
  const double at_fit_s =
      kBase_s + kPerLetter_s * letters + kPerWord_s * words + kPerPause_s * pauses;
  return at_fit_s * kFitRate_wpm / std::max(rate_wpm, 1.0);
}

std::optional<double> wavDurationSeconds(const std::string& bytes) {
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i)
      v = (v << 8) | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
    return v;
  };
  if (bytes.size() < 12 || bytes.compare(0, 4, "RIFF") != 0 || bytes.compare(8, 4, "WAVE") != 0)
    return std::nullopt;
  std::optional<std::uint32_t> byte_rate;
  std::size_t at = 12;
  while (at + 8 <= bytes.size()) {
    const std::string id = bytes.substr(at, 4);
    const std::uint64_t size = u32(at + 4);
    const std::size_t body = at + 8;
    if (id == "fmt " && size >= 16 && body + 16 <= bytes.size()) {
      byte_rate = u32(body + 8);
    } else if (id == "data") {
      if (!byte_rate || *byte_rate == 0) return std::nullopt;
      const std::uint64_t present = std::min<std::uint64_t>(size, bytes.size() - body);
      return static_cast<double>(present) / static_cast<double>(*byte_rate);
    }
    at = body + static_cast<std::size_t>(size) + (size % 2);  // chunks are word-aligned
  }
  return std::nullopt;
}

SpeechSlot SpeechTimeline::plan(double t_s, double duration_s, std::optional<double> deadline_s,
                                bool muted) {
  SpeechSlot slot;
  slot.duration_s = std::max(duration_s, 0.0);
  slot.start_s = std::max(0.0, free_at_s_ - t_s);
  if (muted) {
    slot.delivery = Delivery::kMuted;
  } else if (deadline_s && t_s + slot.end_s() > *deadline_s) {
    slot.delivery = Delivery::kTooLate;
  } else {
    slot.delivery = Delivery::kSaid;
    free_at_s_ = t_s + slot.end_s();
  }
  return slot;
}

SpeechTimeline::Choice SpeechTimeline::planFirstFitting(double t_s,
                                                        const std::vector<double>& durations_s,
                                                        std::optional<double> deadline_s,
                                                        bool muted, bool may_interrupt) {
  if (durations_s.empty()) {
    Choice none;
    none.slot.delivery = muted ? Delivery::kMuted : Delivery::kTooLate;
    none.slot.start_s = std::max(0.0, free_at_s_ - t_s);
    return none;
  }
  if (!muted) {
    for (std::size_t i = 0; i < durations_s.size(); ++i) {
      // plan() occupies the voice only for a slot that is said: trying does not change it.
      const SpeechSlot slot = plan(t_s, durations_s[i], deadline_s, false);
      if (slot.delivery == Delivery::kSaid) return {i, slot};
    }
    const double busy_s = free_at_s_ - t_s;
    if (may_interrupt && busy_s > 0.0) {
      for (std::size_t i = 0; i < durations_s.size(); ++i) {
        if (deadline_s && t_s + std::max(durations_s[i], 0.0) > *deadline_s) continue;
        free_at_s_ = t_s;  // what is being said stops here
        SpeechSlot slot = plan(t_s, durations_s[i], deadline_s, false);
        slot.interrupts_s = busy_s;
        return {i, slot};
      }
    }
  }
  return {0, plan(t_s, durations_s[0], deadline_s, muted)};
}

}  // namespace coopnav::dialogue
