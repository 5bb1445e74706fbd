// How long the robot's words take and when they are said (lib/dialogue/speech_timing.hpp): the
// estimate against espeak-ng's measured durations, one voice without overlap, no cue after the
// crossing, WAV durations.
#include "coopnav/dialogue/speech_timing.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace coopnav::dialogue {
namespace {

// espeak-ng 1.51, en-us, 175 wpm, durations of its WAV files (short corridor phrases and the
// dialogue manager's templates), measured with `espeak-ng -s 175 -w`.
TEST(SpeechDuration, EstimateIsWithinFourTenthsOfASecondOfEspeak) {
  const struct {
    const char* text;
    double measured_s;
  } kMeasured[] = {
      {"Thank you.", 0.888},
      {"I will pass on your left.", 1.557},
      {"I am passing on your left.", 1.611},
      {"I will wait here for you to pass.", 1.929},
      {"Could you move a little more to your right, please?", 2.621},
      {"It is narrow here. I will wait at the side if needed.", 3.303},
      {"It is narrow here. Could you move to your left, please?", 3.337},
      {"I will stop here. Please pass carefully.", 2.749},
  };
  for (const auto& m : kMeasured)
    EXPECT_NEAR(estimateSpeechDuration(m.text, 175.0), m.measured_s, 0.4) << m.text;
  // A sentence said faster takes less time; no words take none.
  EXPECT_NEAR(estimateSpeechDuration("I will pass on your left.", 350.0),
              estimateSpeechDuration("I will pass on your left.", 175.0) / 2.0, 1e-12);
  EXPECT_EQ(estimateSpeechDuration("  ", 175.0), 0.0);
}

TEST(SpeechTimeline, OneVoiceNeverOverlaps) {
  SpeechTimeline voice;
  const SpeechSlot a = voice.plan(10.0, 3.0, 20.0, false);
  EXPECT_EQ(a.delivery, Delivery::kSaid);
  EXPECT_DOUBLE_EQ(a.start_s, 0.0);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 13.0);
  // Decided 1 s later (e.g. for a second human): it starts when the first has ended.
  const SpeechSlot b = voice.plan(11.0, 1.5, 20.0, false);
  EXPECT_EQ(b.delivery, Delivery::kSaid);
  EXPECT_DOUBLE_EQ(b.start_s, 2.0);
  EXPECT_DOUBLE_EQ(b.end_s(), 3.5);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 14.5);
  // Decided after the voice is free: at once.
  EXPECT_DOUBLE_EQ(voice.plan(15.0, 1.0, std::nullopt, false).start_s, 0.0);
}

TEST(SpeechTimeline, ACueThatWouldEndAfterTheCrossingIsNotSaid) {
  SpeechTimeline voice;
  // Crossing at 12 s: a 3 s sentence decided at 10 s would end at 13 s.
  const SpeechSlot late = voice.plan(10.0, 3.0, 12.0, false);
  EXPECT_EQ(late.delivery, Delivery::kTooLate);
  EXPECT_DOUBLE_EQ(10.0 + late.end_s() - 12.0, 1.0);  // how far past the crossing
  // It does not take the voice: a short one still fits.
  EXPECT_EQ(voice.plan(10.0, 1.5, 12.0, false).delivery, Delivery::kSaid);
  // Waiting for the voice can make a cue too late as well.
  EXPECT_EQ(voice.plan(10.5, 1.5, 12.5, false).delivery, Delivery::kTooLate);
  // Thanks have no deadline.
  EXPECT_EQ(voice.plan(10.5, 1.0, std::nullopt, false).delivery, Delivery::kSaid);
}

TEST(SpeechTimeline, MutedSaysNothingAndKeepsTheVoiceFree) {
  SpeechTimeline voice;
  const SpeechSlot m = voice.plan(5.0, 2.0, 20.0, true);
  EXPECT_EQ(m.delivery, Delivery::kMuted);
  EXPECT_DOUBLE_EQ(m.duration_s, 2.0);  // what it would have taken, for the log
  EXPECT_EQ(voice.plan(5.0, 2.0, 20.0, false).start_s, 0.0);
}

TEST(SpeechTimeline, ShortOfTimeTheShorterWordingIsSaidRatherThanNothing) {
  SpeechTimeline voice;
  // Crossing at 12 s, decided at 10 s: the 3 s wording would end after it, the 1 s one fits.
  const auto fits = voice.planFirstFitting(10.0, {3.0, 1.0}, 12.0, false);
  EXPECT_EQ(fits.index, 1U);
  EXPECT_EQ(fits.slot.delivery, Delivery::kSaid);
  EXPECT_DOUBLE_EQ(fits.slot.duration_s, 1.0);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 11.0);  // only the wording said takes the voice
  // With time enough, the full wording.
  const auto full = voice.planFirstFitting(20.0, {3.0, 1.0}, 30.0, false);
  EXPECT_EQ(full.index, 0U);
  EXPECT_EQ(full.slot.delivery, Delivery::kSaid);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 23.0);
  // Neither fits (the voice is busy until 23 s): the full one is recorded as too late, and the
  // voice stays as it was.
  const auto none = voice.planFirstFitting(22.0, {3.0, 1.0}, 23.5, false);
  EXPECT_EQ(none.index, 0U);
  EXPECT_EQ(none.slot.delivery, Delivery::kTooLate);
  EXPECT_DOUBLE_EQ(none.slot.duration_s, 3.0);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 23.0);
  // Muted: the full wording, muted, whatever the time.
  const auto muted = voice.planFirstFitting(40.0, {3.0, 1.0}, 41.0, true);
  EXPECT_EQ(muted.index, 0U);
  EXPECT_EQ(muted.slot.delivery, Delivery::kMuted);
  // No wording at all: nothing said, and it says so.
  EXPECT_EQ(voice.planFirstFitting(50.0, {}, 60.0, false).slot.delivery, Delivery::kTooLate);
}

// Words announcing a change of what the robot does ("I will wait here." after "I am passing on
// your right.") interrupt what is being said when they fit only from now; other words wait, or
// are too late, as before.
TEST(SpeechTimeline, WordsOfAChangeOfActionInterruptTheVoice) {
  SpeechTimeline voice;
  ASSERT_EQ(voice.plan(10.0, 2.0, 20.0, false).delivery, Delivery::kSaid);  // busy until 12 s
  // Decided at 10.5 s, crossing at 12.0 s: neither wording fits after 12 s.
  const auto waits = voice.planFirstFitting(10.5, {3.0, 1.0}, 12.0, false);
  EXPECT_EQ(waits.slot.delivery, Delivery::kTooLate);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 12.0);
  // Interrupting: the short wording fits from 10.5 s; the voice stops 1.5 s before its end.
  const auto cut = voice.planFirstFitting(10.5, {3.0, 1.0}, 12.0, false, true);
  EXPECT_EQ(cut.index, 1U);
  EXPECT_EQ(cut.slot.delivery, Delivery::kSaid);
  EXPECT_DOUBLE_EQ(cut.slot.start_s, 0.0);
  EXPECT_DOUBLE_EQ(cut.slot.interrupts_s, 1.5);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 11.5);
  // A wording that fits after the voice is free does not interrupt it.
  const auto after = voice.planFirstFitting(11.0, {0.5}, 20.0, false, true);
  EXPECT_DOUBLE_EQ(after.slot.start_s, 0.5);
  EXPECT_DOUBLE_EQ(after.slot.interrupts_s, 0.0);
  // Nothing fits even from now: too late, the voice as it was.
  const auto none = voice.planFirstFitting(11.5, {3.0}, 12.0, false, true);
  EXPECT_EQ(none.slot.delivery, Delivery::kTooLate);
  EXPECT_DOUBLE_EQ(voice.freeAt(), 12.0);
}

std::string le32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i)
    s[static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}

/// A mono 16-bit PCM WAV at `rate_hz` with `samples` samples; `data_size` as written in the header
/// (a streaming writer leaves 0x7fffffff there).
std::string wav(std::uint32_t rate_hz, std::uint32_t samples, std::uint32_t data_size) {
  std::string fmt = le32(16) + std::string("\x01\x00\x01\x00", 4) + le32(rate_hz) +
                    le32(rate_hz * 2) + std::string("\x02\x00\x10\x00", 4);
  std::string data(samples * 2, '\0');
  return "RIFF" + le32(36 + samples * 2) + "WAVE" + "fmt " + fmt + "LIST" + le32(3) + "abc" +
         std::string(1, '\0') + "data" + le32(data_size) + data;
}

TEST(WavDuration, DataOverByteRateAndOnlyTheBytesPresent) {
  const auto d = wavDurationSeconds(wav(22050, 22050, 44100));
  ASSERT_TRUE(d.has_value());
  EXPECT_DOUBLE_EQ(*d, 1.0);  // (a padded odd-sized chunk before "data" is skipped)
  const auto streamed = wavDurationSeconds(wav(22050, 11025, 0x7fffffff));
  ASSERT_TRUE(streamed.has_value());
  EXPECT_DOUBLE_EQ(*streamed, 0.5);
  EXPECT_FALSE(wavDurationSeconds("RIFF....WAVE").has_value());
  EXPECT_FALSE(wavDurationSeconds("not a wav file at all").has_value());
  EXPECT_FALSE(wavDurationSeconds("").has_value());
}

}  // namespace
}  // namespace coopnav::dialogue
