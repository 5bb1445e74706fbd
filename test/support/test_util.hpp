#pragma once
// Helpers shared by node and end-to-end style tests: the isolated LCM URL of this test
// executable, a scratch directory of its own, a child-process runner for daemons, and polling
// waits.

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "test_paths.hpp"

namespace coopnav::test {

/// The udpm URL CTest gave this executable (its own port), or a fallback port for manual runs.
inline std::string testLcmUrl() {
  const char* url = std::getenv("COOPNAV_TEST_LCM_URL");
  return url ? url : "udpm://239.255.76.67:7799?ttl=0&recv_buf_size=4194304";
}

/// A directory of this test process's own in the temp directory (coopnav_test_XXXXXX), made at
/// first use and removed with everything in it when the process exits: the maps, configs and
/// logs a test writes go here, so that test runs leave nothing behind in /tmp (ctest runs each
/// test as a process of its own). Children started with ChildProcess exec and remove nothing.
inline const std::filesystem::path& scratchDir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      std::string tmpl = (std::filesystem::temp_directory_path() / "coopnav_test_XXXXXX").string();
      if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("cannot make " + tmpl);
      path = tmpl;
    }
    Dir(const Dir&) = delete;
    Dir& operator=(const Dir&) = delete;
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

/// A band_source config for node tests (the open.pgm test map, a short step gate timeout) in the
/// scratch directory, named after `test_name`; returns its path.
inline std::string writeBandSourceTestConfig(const std::string& test_name) {
  const auto p = scratchDir() / (test_name + ".yaml");
  std::ofstream(p) << "map_file: " << ::coopnav::test::testDataDir() << "/maps/open.yaml\n"
                   << "step_gate_timeout_s: 0.5\n";
  return p.string();
}

inline std::string daemonPath(const std::string& name) {
  return ::coopnav::test::binaryDir() + "/daemons/" + name + "/coopnav_" + name;
}

/// Polls `pred` until true or `timeout`; returns pred's last value.
inline bool waitFor(
    const std::function<bool()>& pred, std::chrono::milliseconds timeout,
    const std::function<void()>& between = [] {}) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    between();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

/// A daemon started as a child process; killed (SIGKILL) on destruction if still running.
class ChildProcess {
 public:
  ChildProcess(const std::string& exe, const std::vector<std::string>& args) {
    pid_ = ::fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(exe.c_str()));
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(exe.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~ChildProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      int st = 0;
      ::waitpid(pid_, &st, 0);
    }
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int sig) { ::kill(pid_, sig); }

  /// Waits up to `timeout` for exit; returns the exit code, -1 on timeout, 128+sig on a signal.
  int waitExit(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      int st = 0;
      const pid_t r = ::waitpid(pid_, &st, WNOHANG);
      if (r == pid_) {
        exited_ = true;
        if (WIFEXITED(st)) return WEXITSTATUS(st);
        if (WIFSIGNALED(st)) return 128 + WTERMSIG(st);
        return -2;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return -1;
  }
  bool running() {
    if (exited_) return false;
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) {
      exited_ = true;
      return false;
    }
    return true;
  }

 private:
  pid_t pid_{-1};
  bool exited_{false};
};

}  // namespace coopnav::test
