#pragma once
/// @file coopnav_ctl's subcommands, one source file per job:
///   bus operations     bus_commands.cpp       wait-ready, wait-step, query
///   run analysis       run_commands.cpp       transcript, summarize, merge-summaries, cm-table,
///                                             trace, metrics
///   research           research_commands.cpp  pedestrians, calibrate, forecast, goals,
///                                             goal-candidates (real pedestrian pairs, maps)
/// Each subcommand is an object holding its own options, bound to its CLI11 subcommand when it is
/// made; main.cpp keeps the one table of them and runs the one given on the command line.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace coopnav::ctl {

class Command {
 public:
  Command() = default;
  Command(const Command&) = delete;  // CLI11 holds pointers to the options
  Command& operator=(const Command&) = delete;
  Command(Command&&) = delete;
  Command& operator=(Command&&) = delete;
  virtual ~Command() = default;
  /// Runs the command; returns the exit status. lcm_url: coopnav_ctl's --lcm-url ("": LCM's
  /// default, $LCM_DEFAULT_URL).
  virtual int run(const std::string& lcm_url) = 0;
};

struct CommandEntry {
  CLI::App* sub{nullptr};
  std::unique_ptr<Command> command;
};
using CommandTable = std::vector<CommandEntry>;

/// Adds subcommand `name` to `app`, run by a C made with it (C declares its options on it).
template <class C>
void addCommand(CLI::App& app, CommandTable& table, const std::string& name,
                const std::string& help) {
  CLI::App* sub = app.add_subcommand(name, help);
  auto command = std::make_unique<C>(*sub);
  table.push_back({sub, std::move(command)});
}

void addBusCommands(CLI::App& app, CommandTable& table);
void addRunCommands(CLI::App& app, CommandTable& table);
void addResearchCommands(CLI::App& app, CommandTable& table);

}  // namespace coopnav::ctl
