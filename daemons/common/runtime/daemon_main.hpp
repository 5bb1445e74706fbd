#pragma once
/// @file The shared main() of every daemon: CLI (--help --config --lcm-url --log-level
/// --print-config), config loading and validation, LCM set-up, the node, the loop, exit codes.
///
/// A node type provides: `using Config = ...;` and a constructor `Node(const Config&, Runtime&)`
/// that subscribes and may throw StartupError (bad map, ...) to stop at start.
///
/// The command line is parsed in daemon_main.cpp, not here: CLI11 is header-only and costs about
/// half of a daemon main's compile time, in every build (release, sanitizers, fuzzing).

#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "config/config.hpp"
#include "runtime/journal.hpp"
#include "runtime/log.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {

/// Thrown by a node constructor when an input file (map, scenario) is unusable.
class StartupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CommonOptions {
  std::string config_path;
  std::string lcm_url;
  std::string log_level{"info"};
  bool print_config{false};
  std::vector<std::string> overrides;  ///< --set key=value, applied over the config file
  /// --state-dir: restart journal directory (journal.hpp); "" = none, a restart loses the state.
  std::string state_dir;
};

/// Parses the common options (--help, --config, --lcm-url, --log-level, --set, --state-dir,
/// --print-config) of daemon `name` into `opts`. Returns the exit code when the daemon must stop
/// now (help printed: kExitOk; bad command line: kExitUsage, the reason printed), else nothing.
std::optional<int> parseCommandLine(int argc, char** argv, const std::string& name,
                                    const std::string& description, CommonOptions& opts);

/// The exit-code paragraph shown at the end of every --help.
const char* exitCodeHelp();

namespace detail {
template <class T, class = void>
struct HasResolvePaths : std::false_type {};
template <class T>
struct HasResolvePaths<T, std::void_t<decltype(std::declval<T&>().resolvePaths(std::string()))>>
    : std::true_type {};
}  // namespace detail

/// Directory relative paths in a config are resolved against: the config file's, else ".".
std::string configBaseDir(const std::string& config_path);

/// Joins base and path unless path is absolute or empty.
std::string resolvePath(const std::string& base_dir, const std::string& path);

template <class Node>
int runDaemon(int argc, char** argv, const std::string& name, const std::string& description) {
  // A stop signal at any time from here on is answered within a second (runtime.hpp).
  Runtime::beginStartup();
  CommonOptions opts;
  if (const auto rc = parseCommandLine(argc, argv, name, description, opts)) return *rc;
  if (!setLogLevel(opts.log_level)) {
    std::cerr << name << ": unknown --log-level '" << opts.log_level << "'\n";
    return kExitUsage;
  }
  typename Node::Config config;
  try {
    config = loadConfig<typename Node::Config>(opts.config_path, opts.overrides);
  } catch (const ConfigError& e) {
    log().critical("{}: bad config:\n{}", name, e.what());
    return kExitUsage;
  }
  if constexpr (detail::HasResolvePaths<typename Node::Config>::value) {
    config.resolvePaths(configBaseDir(opts.config_path));
  }
  if (opts.print_config) {
    std::cout << configToYaml(config) << std::endl;
    return kExitOk;
  }
  try {
    Runtime runtime(name, opts.lcm_url);
    runtime.setLimits(config.limits);
    Node node(config, runtime);
    // After the node subscribed (its handlers rebuild the state), before the loop (no live
    // message is handled before the recorded ones).
    std::unique_ptr<Journal> journal;
    if (!opts.state_dir.empty()) {
      journal = std::make_unique<Journal>(runtime, opts.state_dir);
      journal->replayAndRecord();
    }
    return runtime.run();
  } catch (const LcmUnavailable& e) {
    log().critical("{}: {}", name, e.what());
    return kExitRuntime;
  } catch (const StartupError& e) {
    log().critical("{}: cannot start: {}", name, e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    log().critical("{}: fatal: {}", name, e.what());
    return kExitRuntime;
  }
}

}  // namespace coopnav
