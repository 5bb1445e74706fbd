// coopnav_ctl: the commands the scripts, the experiment layer and users need, in C++ so that they
// start in milliseconds and read logs with the one fuzzed reader (logfile/log_reader.hpp). The
// commands by job (command.hpp): bus operations, run analysis, research evaluation.
#include <CLI/CLI.hpp>
#include <iostream>

#include "command.hpp"
#include "runtime/log.hpp"

int main(int argc, char** argv) {
  CLI::App app{"coopnav command-line tools"};
  app.require_subcommand(1);
  std::string url;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL)");
  coopnav::ctl::CommandTable commands;
  coopnav::ctl::addBusCommands(app, commands);
  coopnav::ctl::addRunCommands(app, commands);
  coopnav::ctl::addResearchCommands(app, commands);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; any bad command line 2, as every coopnav program.
    return app.exit(e) == 0 ? 0 : 2;
  }
  coopnav::setLogLevel("warn");
  try {
    for (const auto& c : commands)
      if (*c.sub) return c.command->run(url);
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "coopnav_ctl: " << e.what() << "\n";
    return 1;
  }
}
