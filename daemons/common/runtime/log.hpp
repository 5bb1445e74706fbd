#pragma once
/// @file The one logger of a coopnav process (spdlog). Included only by .cpp files.
///
/// Every line goes through one sink that makes text from the bus safe to log: control
/// characters and bytes that are not UTF-8 are escaped as \xNN (a reason holding "\n[critical]"
/// cannot forge a line, an ANSI escape cannot reach a terminal), a line's text is cut to a length
/// cap, and lines of one pattern (the text with its digits removed) beyond a rate are counted and
/// reported once a second instead of written (a flood of bad messages cannot flood the disk).

#include <spdlog/spdlog.h>

#include <cstddef>
#include <string>
#include <string_view>

namespace coopnav {

/// The process-wide logger; created on first use, writes to stderr.
spdlog::logger& log();

/// Sets the level from "trace|debug|info|warn|error|critical|off"; returns false if unknown.
bool setLogLevel(const std::string& level);

/// The caps of every line (InputLimits::max_text_bytes and log_lines_per_s).
void setLogCaps(std::size_t max_text_bytes, int lines_per_pattern_per_s);

/// Writes the "suppressed N lines like: ..." summaries of rate-limited lines now (the runtime
/// calls it once a second; a line of a new second does it too).
void flushLogSuppressions();

/// `text` with every control character, C1 control and byte that is not UTF-8 written as \xNN,
/// cut to `max_bytes` (plus "...") at a character boundary: what a log line may hold of text that
/// came from a message. `keep_newlines`: "\n" stays (the project's own multi-line messages).
std::string escapeLogText(std::string_view text, std::size_t max_bytes, bool keep_newlines = false);

}  // namespace coopnav
