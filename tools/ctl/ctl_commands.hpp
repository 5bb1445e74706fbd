#pragma once
// Further coopnav_ctl subcommands (log reading, transcripts, summaries) live beside main.cpp.
#include <CLI/CLI.hpp>
#include <string>

namespace coopnav {
void addCtlCommands(CLI::App& app);
int runCtlCommands(CLI::App& app, const std::string& lcm_url);
}  // namespace coopnav
