#include "runtime/daemon_main.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>

namespace coopnav {

std::string configBaseDir(const std::string& config_path) {
  if (config_path.empty()) return ".";
  const auto parent = std::filesystem::path(config_path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

std::string resolvePath(const std::string& base_dir, const std::string& path) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(base_dir) / path).lexically_normal().string();
}

namespace {

void addCommonOptions(CLI::App& app, CommonOptions& opts) {
  app.add_option("-c,--config", opts.config_path,
                 "YAML config file (default: built-in defaults; see config/<daemon>.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("--lcm-url", opts.lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--log-level", opts.log_level, "trace|debug|info|warn|error|critical|off")
      ->capture_default_str();
  app.add_option(
      "--set", opts.overrides,
      "override a setting of the config: key=value (dotted keys for nested; repeatable)");
  app.add_option("--state-dir", opts.state_dir,
                 "restart journal directory, one per run: a daemon started again with it "
                 "rebuilds its state (docs/lockstep.md)");
  app.add_flag("--print-config", opts.print_config, "print the effective config as YAML and exit");
}

}  // namespace

std::optional<int> parseCommandLine(int argc, char** argv, const std::string& name,
                                    const std::string& description, CommonOptions& opts) {
  CLI::App app{description, "coopnav_" + name};
  addCommonOptions(app, opts);
  app.footer(exitCodeHelp());
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? kExitOk : kExitUsage;
  }
  return std::nullopt;
}

const char* exitCodeHelp() {
  return "Exit codes: 0 clean stop (SIGINT/SIGTERM), 1 LCM unavailable or fatal error,\n"
         "            2 bad command line or config, 3 bad map or scenario file.";
}

}  // namespace coopnav
