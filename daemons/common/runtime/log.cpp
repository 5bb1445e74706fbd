#include "runtime/log.hpp"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <unordered_map>

namespace coopnav {
namespace {

/// Length of the valid UTF-8 sequence at s[i] (1..4), or 0 when it is not one; C1 controls
/// (U+0080..U+009F, which some terminals read as escapes) count as not valid here.
std::size_t utf8Length(std::string_view s, std::size_t i) {
  const auto b0 = static_cast<unsigned char>(s[i]);
  std::size_t n = 0;
  std::uint32_t cp = 0;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
    cp = b0 & 0x1Fu;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    cp = b0 & 0x0Fu;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    cp = b0 & 0x07u;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if ((b & 0xC0u) != 0x80u) return 0;
    cp = (cp << 6) | (b & 0x3Fu);
  }
  const bool overlong = (n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000);
  const bool surrogate = cp >= 0xD800 && cp <= 0xDFFF;
  if (overlong || surrogate || cp > 0x10FFFF || (cp >= 0x80 && cp <= 0x9F)) return 0;
  return n;
}

/// The pattern a line is rate-limited by: its text without digits (the same message about
/// another step, id or time is the same line), at most 80 bytes of it.
std::string patternOf(std::string_view text) {
  std::string key;
  for (const char c : text) {
    if (c >= '0' && c <= '9') continue;
    key.push_back(c);
    if (key.size() >= 80) break;
  }
  return key;
}

/// Escapes, caps and rate-limits, then hands the line to the terminal sink.
class SafeSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit SafeSink(std::shared_ptr<spdlog::sinks::sink> out) : out_(std::move(out)) {}

  void setCaps(std::size_t max_text_bytes, int lines_per_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    max_text_bytes_ = max_text_bytes;
    lines_per_s_ = lines_per_s;
  }

  void flushSuppressions() {
    std::lock_guard<std::mutex> lock(mutex_);
    reportSuppressed(std::chrono::steady_clock::now(), true);
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    const std::string_view text(msg.payload.data(), msg.payload.size());
    const auto now = std::chrono::steady_clock::now();
    reportSuppressed(now, false);
    // Errors at start-up and critical lines are never held back: they say why a daemon stops.
    if (msg.level < spdlog::level::critical) {
      Pattern& p = patterns_[patternOf(text)];
      if (p.lines_this_second >= lines_per_s_) {
        if (p.suppressed++ == 0) p.example = escapeLogText(text, 120);
        p.level = msg.level;
        return;
      }
      ++p.lines_this_second;
    }
    // Critical lines are the project's own start-up verdicts (a config's list of problems, one
    // per line): their line breaks stay, their length is not capped.
    if (msg.level >= spdlog::level::critical) {
      write(msg, escapeLogText(text, text.size() * 4 + 8, true));
    } else {
      write(msg, escapeLogText(text, max_text_bytes_));
    }
  }
  void flush_() override { out_->flush(); }
  // The terminal sink formats: the logger's pattern goes to it.
  void set_pattern_(const std::string& pattern) override { out_->set_pattern(pattern); }
  void set_formatter_(std::unique_ptr<spdlog::formatter> f) override {
    out_->set_formatter(std::move(f));
  }

 private:
  struct Pattern {
    int lines_this_second{0};
    long suppressed{0};
    std::string example;
    spdlog::level::level_enum level{spdlog::level::info};
  };

  void write(const spdlog::details::log_msg& msg, const std::string& text) {
    spdlog::details::log_msg safe(msg);
    safe.payload = spdlog::string_view_t(text.data(), text.size());
    out_->log(safe);
  }

  /// At the turn of a second (or when forced): one line per pattern that was held back, then a
  /// new second for every pattern (the table never holds more than one second's patterns).
  void reportSuppressed(std::chrono::steady_clock::time_point now, bool force) {
    if (!force && now - window_start_ < std::chrono::seconds(1)) return;
    window_start_ = now;
    for (auto& [key, p] : patterns_) {
      if (p.suppressed == 0) continue;
      const std::string line = "suppressed " + std::to_string(p.suppressed) +
                               " lines in the last second like: " + p.example;
      spdlog::details::log_msg m(spdlog::source_loc{}, "coopnav", p.level,
                                 spdlog::string_view_t(line.data(), line.size()));
      out_->log(m);
    }
    patterns_.clear();
  }

  std::shared_ptr<spdlog::sinks::sink> out_;
  std::size_t max_text_bytes_{1024};
  int lines_per_s_{20};
  std::unordered_map<std::string, Pattern> patterns_;
  std::chrono::steady_clock::time_point window_start_{std::chrono::steady_clock::now()};
};

std::shared_ptr<SafeSink>& safeSink() {
  static std::shared_ptr<SafeSink> sink =
      std::make_shared<SafeSink>(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  return sink;
}

}  // namespace

std::string escapeLogText(std::string_view text, std::size_t max_bytes, bool keep_newlines) {
  std::string out;
  out.reserve(std::min(text.size(), max_bytes) + 8);
  for (std::size_t i = 0; i < text.size();) {
    const auto b = static_cast<unsigned char>(text[i]);
    std::size_t n = 1;
    char piece[8];
    std::string_view add;
    if ((b >= 0x20 && b < 0x7F) || (keep_newlines && b == '\n')) {
      add = std::string_view(&text[i], 1);
    } else if (b >= 0x80 && (n = utf8Length(text, i)) > 0) {
      add = std::string_view(&text[i], n);
    } else {
      n = 1;
      std::snprintf(piece, sizeof piece, "\\x%02X", b);
      add = piece;
    }
    if (out.size() + add.size() > max_bytes) {
      out += "...";
      return out;
    }
    out.append(add.data(), add.size());
    i += n;
  }
  return out;
}

spdlog::logger& log() {
  static std::shared_ptr<spdlog::logger> logger = [] {
    auto l = std::make_shared<spdlog::logger>("coopnav", safeSink());
    l->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%n:%P] [%^%l%$] %v");
    return l;
  }();
  return *logger;
}

bool setLogLevel(const std::string& level) {
  const auto lvl = spdlog::level::from_str(level);
  // from_str maps unknown names to "off": accept "off" only when asked for explicitly.
  if (lvl == spdlog::level::off && level != "off") return false;
  log().set_level(lvl);
  return true;
}

void setLogCaps(std::size_t max_text_bytes, int lines_per_pattern_per_s) {
  safeSink()->setCaps(max_text_bytes, lines_per_pattern_per_s);
}

void flushLogSuppressions() { safeSink()->flushSuppressions(); }

}  // namespace coopnav
