#pragma once
/// @file The one logger of a coopnav process (spdlog). Included only by .cpp files.

#include <spdlog/spdlog.h>

#include <string>

namespace coopnav {

/// The process-wide logger; created on first use, writes to stderr.
spdlog::logger& log();

/// Sets the level from "trace|debug|info|warn|error|critical|off"; returns false if unknown.
bool setLogLevel(const std::string& level);

}  // namespace coopnav
