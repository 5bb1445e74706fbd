#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "runtime/daemon_main.hpp"
#include "viewer_node.hpp"

// `--log FILE` (replay a recorded run) is `--set log_file=<FILE, absolute>` plus, unless an LCM
// URL is given, `--lcm-url memq://`: a replay needs no bus, and its own status stays in-process.
int main(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  std::vector<std::string> out;
  bool replay = false;
  bool url_given = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string file;
    if (args[i] == "--log" && i + 1 < args.size()) {
      file = args[++i];
    } else if (args[i].rfind("--log=", 0) == 0) {
      file = args[i].substr(6);
    } else if (args[i] == "--log") {
      std::cerr << "viewer: --log needs a file (a recorded LCM log)\n";
      return coopnav::kExitUsage;
    } else {
      if (args[i] == "--lcm-url" || args[i].rfind("--lcm-url=", 0) == 0) url_given = true;
      out.push_back(args[i]);
      continue;
    }
    replay = true;
    out.push_back("--set");
    out.push_back("log_file=" + std::filesystem::absolute(file).lexically_normal().string());
  }
  if (replay && !url_given) {
    out.push_back("--lcm-url");
    out.push_back("memq://");
  }
  std::vector<char*> cargs;
  cargs.reserve(out.size() + 1);
  for (std::string& a : out) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  return coopnav::runDaemon<coopnav::ViewerNode>(
      static_cast<int>(cargs.size() - 1), cargs.data(), "viewer",
      "Browser viewer: serves one page drawing the coopnav scene (map, agents, bands, crossing, "
      "distances, predicates, mode, utterances, CA/CM per human, every daemon's status) live "
      "from the bus, or `--log FILE` to replay a recorded LCM log with a timeline (no bus). "
      "Open http://127.0.0.1:8088/ (http_port, bind_address).");
}
