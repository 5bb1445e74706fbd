#pragma once
/// @file Optional spoken output: runs espeak-ng (or a compatible program) as a child process with
/// an argument vector, never through a shell, so the text of an utterance can never be run as a
/// command. Non-blocking: say() queues, poll() (called from a timer) reaps the child with
/// waitpid(WNOHANG) and starts the next one. One child at a time so that utterances do not talk
/// over each other. Nothing here feeds back into the decisions or the timing of the messages: the
/// node calls it only after it has published and acknowledged a step.

#include <sys/types.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace coopnav {

struct SpeechConfig {
  bool enabled{false};
  std::string program{"espeak-ng"};
  std::string voice{"en-us"};
  int rate_wpm{175};
  std::string wav_dir{""};
  int max_queue{8};

  template <class V>
  void visit(V& v);
};

class SpeechOutput {
 public:
  explicit SpeechOutput(const SpeechConfig& config);
  ~SpeechOutput();
  SpeechOutput(const SpeechOutput&) = delete;
  SpeechOutput& operator=(const SpeechOutput&) = delete;

  /// False when disabled by config or when the program cannot be run (warned once).
  bool usable() const { return usable_; }

  /// Queues `text`; `wav_stem` names the WAV file (without extension) when wav_dir is set.
  /// When the queue is full the oldest waiting utterance is dropped (counted, logged).
  void say(const std::string& text, const std::string& wav_stem);

  /// Reaps a finished child without blocking and starts the next queued utterance.
  void poll();

  /// Synthesises each text into a temporary WAV file, all at once, waits for the programs
  /// (start-up only: it blocks) and returns how long each takes to say [s], in order; nullopt
  /// for one whose program failed, all nullopt when speech is not usable. The decisions plan
  /// with these durations (lib/dialogue/speech_timing.hpp).
  std::vector<std::optional<double>> measure(const std::vector<std::string>& texts);

  /// The argument vector for one utterance (argv[0] = the resolved program). Public for tests.
  std::vector<std::string> argumentsFor(const std::string& text, const std::string& wav_stem) const;

  std::int64_t started() const { return started_; }
  std::int64_t failed() const { return failed_; }
  std::int64_t droppedFromQueue() const { return dropped_; }
  bool busy() const { return child_ > 0; }

 private:
  struct Item {
    std::string text;
    std::string wav_stem;
  };
  void startNext();
  /// fork + execv of `args` (stdin /dev/null, no inherited descriptors); the child's pid or -1.
  pid_t spawn(const std::vector<std::string>& args);
  void disable(const std::string& why);

  SpeechConfig config_;
  std::string program_path_;
  bool usable_{false};
  pid_t child_{-1};
  std::deque<Item> queue_;
  std::int64_t started_{0};
  std::int64_t failed_{0};
  std::int64_t dropped_{0};
};

/// Finds `program` on PATH (or checks it when it contains '/'); "" when not executable.
std::string findExecutable(const std::string& program);

template <class V>
void SpeechConfig::visit(V& v) {
  v("enabled", enabled);
  v("program", program);
  v("voice", voice);
  v("rate_wpm", rate_wpm, Range{80.0, 450.0});
  v("wav_dir", wav_dir);
  v("max_queue", max_queue, Range{1.0, 100.0});
  v.require(!program.empty(), "program", "must name a program");
  bool voice_ok = !voice.empty() && voice.front() != '-';
  for (char c : voice) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_' || c == '+' || c == '/';
    voice_ok = voice_ok && ok;
  }
  v.require(voice_ok, "voice", "must be an espeak-ng voice name such as en-us or en+f3");
}

}  // namespace coopnav
