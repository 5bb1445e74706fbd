#include "pedestrians_daemon.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "runtime/runtime.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"

namespace coopnav::ctl {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kDaemonName = "path_assessor";
// [us] where the daemon's message time starts, and the pause between two walker-runs on it. The
// runs come from sequences with clocks of their own: each run is shifted to start kRunGapUs
// after the previous one ended, so the daemon's time runs forward in steps far below its
// limits.max_time_jump_s (a jump would be refused) while a run keeps its own time spacing.
constexpr std::int64_t kFirstUtime = 1'000'000'000'000;
constexpr std::int64_t kRunGapUs = 1'000'000;
constexpr double kStopWaitS = 3.0;

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error(why); }

std::string describeStatus(int status) {
  if (WIFEXITED(status)) return "exited with code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "stopped (status " + std::to_string(status) + ")";
}

// fork + execv of args; the child's stdout goes to stdout_fd when >= 0. Exec failure: exit 127.
pid_t spawn(const std::vector<std::string>& args, int stdout_fd) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) fail(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    // The daemon goes when this tool goes, however it ends: an orphan would keep the port busy
    // and the output pipe of whoever ran the tool (a test runner) open.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (stdout_fd >= 0) ::dup2(stdout_fd, STDOUT_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// The daemon process: stopped (SIGTERM, SIGKILL after kStopWaitS) and reaped when it goes.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    pid_ = spawn(args, null_fd);
    if (null_fd >= 0) ::close(null_fd);
  }
  ~Child() { stop(); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }

  // The way it ended, if it has.
  std::optional<std::string> ended() {
    if (status_) return describeStatus(*status_);
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) {
      status_ = st;
      return describeStatus(st);
    }
    return std::nullopt;
  }

  // Stops it; returns how it ended.
  std::string stop() {
    if (const auto e = ended()) return *e;
    ::kill(pid_, SIGTERM);
    const auto end = Clock::now() + std::chrono::duration<double>(kStopWaitS);
    while (Clock::now() < end) {
      if (const auto e = ended()) return *e;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(pid_, SIGKILL);
    int st = 0;
    ::waitpid(pid_, &st, 0);
    status_ = st;
    return describeStatus(st) + " (did not stop on SIGTERM within 3 s)";
  }

 private:
  pid_t pid_{-1};
  std::optional<int> status_;
};

// Runs args to the end and returns its stdout; throws unless it exits 0.
std::string captureOutput(const std::vector<std::string>& args) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) fail(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = spawn(args, fds[1]);
  ::close(fds[1]);
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      out.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
    std::string cmd;
    for (const auto& a : args) cmd += (cmd.empty() ? "" : " ") + a;
    fail(cmd + ": " + describeStatus(st) +
         (WIFEXITED(st) && WEXITSTATUS(st) == 127 ? " (cannot execute it)" : ""));
  }
  return out;
}

std::string existing(const std::vector<fs::path>& candidates) {
  for (const auto& c : candidates)
    if (fs::exists(c)) return c.lexically_normal().string();
  return "";
}

std::string buildDirOfThisExe() {
  if (const char* env = std::getenv("COOPNAV_BUILD_DIR")) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  // <build>/tools/coopnav_ctl (or <build>/test/<test> for the tests).
  return exe.parent_path().parent_path().string();
}

std::string defaultConfig(const std::string& profile) {
  const std::string name =
      profile == "calibrated" ? "path_assessor_calibrated.yaml" : "path_assessor.yaml";
  const std::string build = buildDirOfThisExe();
  std::vector<fs::path> candidates{fs::path("config") / name};
  if (!build.empty()) candidates.push_back(fs::path(build).parent_path() / "config" / name);
  std::string found = existing(candidates);
  if (found.empty())
    fail("no config/" + name + " in the working directory or beside the build tree: give --config");
  return found;
}

// The recorder settings the daemon runs with, from its --print-config.
assessment::PathAssessorConfig parseRecorderConfig(const std::string& yaml, std::string& profile,
                                                   double& max_time_jump_s) {
  const YAML::Node n = YAML::Load(yaml);
  assessment::PathAssessorConfig c;
  const auto num = [&](const char* key, double& v) {
    if (!n[key]) fail(std::string("path assessor --print-config: no ") + key);
    v = n[key].as<double>();
  };
  num("sample_period_s", c.sample_period_s);
  num("gamma", c.gamma);
  num("tau_m", c.tau_m);
  num("room_fraction", c.room_fraction);
  num("room_tau_floor_m", c.room_tau_floor_m);
  num("side_deadband_m", c.side_deadband_m);
  num("history_s", c.history_s);
  const auto tau_mode = assessment::tauModeFromString(n["tau_mode"].as<std::string>(""));
  const auto side_rule = assessment::sideRuleFromString(n["side_rule"].as<std::string>(""));
  if (!tau_mode || !side_rule) fail("path assessor --print-config: bad tau_mode or side_rule");
  c.tau_mode = *tau_mode;
  c.side_rule = *side_rule;
  profile = n["profile"].as<std::string>("");
  max_time_jump_s = n["limits"]["max_time_jump_s"].as<double>(60.0);
  return c;
}

// Plays the tracker and the dialogue manager for the daemon, one walker-run at a time.
class DaemonDriver {
 public:
  DaemonDriver(Runtime& rt, Child& child, double reply_timeout_s)
      : rt_(rt), child_(child), reply_timeout_s_(reply_timeout_s) {
    rt_.subscribe<path_assessment_t>(channels::kPathAssessment,
                                     [this](const path_assessment_t& m, std::int64_t) {
                                       if (m.human_id != human_id_) return;
                                       last_ = m;
                                       ++received_;
                                     });
  }

  // The daemon's final assessment of the run, after its STOP.
  path_assessment_t run(const WalkerRun& run, std::int32_t human_id, std::int64_t offset_us) {
    human_id_ = human_id;
    received_ = 0;
    const auto utime = [&](double t_s) { return offset_us + secondsToUtime(t_s); };
    // Stamped at the run's first time (its reference time t0_s: the first observation).
    ReferencePaths refs;
    refs.utime = utime(std::min(run.walker.window_start_s, run.observations.front().t_s));
    refs.paths.push_back({human_id, 0, run.reference});
    publish(channels::kReferencePaths, toLcm(refs));
    std::size_t sent_states = 0;
    for (std::size_t i = 0; i < run.observations.size(); ++i) {
      const auto& o = run.observations[i];
      sendStates(utime(o.t_s), o.human_m, o.robot_m);
      waitForAssessments(++sent_states, "observation at t " + std::to_string(o.t_s) + " s");
      if (i == run.start_after)
        control(utime(run.walker.window_start_s), dialogue::RecorderCommand::kStart);
    }
    control(utime(run.stop_t_s), dialogue::RecorderCommand::kStop);
    // The daemon publishes on agent states only: one more at the last observation's time (not
    // after it, so it adds no observation and no sample) brings the assessment after the STOP.
    const auto& last = run.observations.back();
    sendStates(utime(last.t_s), last.human_m, last.robot_m);
    waitForAssessments(++sent_states, "the assessment after STOP");
    if (last_.recording != path_assessment_t::REC_STOPPED)
      fail("the path assessor's last assessment of human " + std::to_string(human_id) +
           " is not STOPPED (recording " + std::to_string(last_.recording) +
           "): its START or STOP was not applied");
    return last_;
  }

  std::size_t messagesSent() const { return sent_; }

 private:
  template <class Msg>
  void publish(const char* channel, const Msg& msg) {
    if (!rt_.publish(channel, msg)) fail(std::string("cannot publish on ") + channel);
    ++sent_;
  }

  void sendStates(std::int64_t utime, const Eigen::Vector2d& human_m,
                  const Eigen::Vector2d& robot_m) {
    AgentStatesSnapshot s;
    s.utime = utime;
    s.step = -1;
    s.robot.id = 0;
    s.robot.kind = AgentKind::kRobot;
    s.robot.pose = {robot_m.x(), robot_m.y(), 0.0};
    AgentState h;
    h.id = human_id_;
    h.kind = AgentKind::kHuman;
    h.pose = {human_m.x(), human_m.y(), 0.0};
    s.humans.push_back(h);
    publish(channels::kAgentStates, toLcm(s));
  }

  void control(std::int64_t utime, dialogue::RecorderCommand command) {
    RecorderControl c;
    c.utime = utime;
    c.step = -1;
    c.human_id = human_id_;
    c.command = command;
    c.reason = "coopnav_ctl pedestrians";
    publish(channels::kPathAssessorControl, toLcm(c));
  }

  void waitForAssessments(std::size_t count, const std::string& what) {
    const auto end = Clock::now() + std::chrono::duration<double>(reply_timeout_s_);
    while (received_ < count) {
      if (const auto e = child_.ended()) fail("the path assessor " + *e);
      const auto left_ms =
          std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      if (left_ms <= 0)
        fail("no path assessment of human " + std::to_string(human_id_) + " for " + what +
             " within " + std::to_string(reply_timeout_s_) + " s");
      // Through the runtime (it queues what LCM receives and hands it to the subscriptions), in
      // 1 ms slices: spinFor runs to its deadline, and a reply is waited for one at a time.
      rt_.spinFor(1);
    }
  }

  Runtime& rt_;
  Child& child_;
  double reply_timeout_s_;
  std::int32_t human_id_{0};
  std::size_t received_{0};
  std::size_t sent_{0};
  path_assessment_t last_{};
};

void waitReady(Runtime& rt, Child& child, const std::string& url, double timeout_s) {
  // The subscription outlives this call (Runtime has no unsubscribe) and later status messages
  // still reach it: the flag it sets must too.
  auto ready = std::make_shared<bool>(false);
  const pid_t pid = child.pid();
  rt.subscribe<daemon_status_t>(channels::kStatus, [ready, pid](const daemon_status_t& s,
                                                                std::int64_t) {
    if (s.name == kDaemonName && s.pid == pid &&
        (s.state == daemon_status_t::STATE_RUNNING || s.state == daemon_status_t::STATE_DEGRADED))
      *ready = true;
  });
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (!*ready) {
    if (const auto e = child.ended()) fail("the path assessor " + *e + " before it was ready");
    if (Clock::now() >= end)
      fail("no status from the path assessor (pid " + std::to_string(child.pid()) + ") within " +
           std::to_string(timeout_s) + " s on " + url);
    rt.spinFor(100);
  }
}

}  // namespace

std::string defaultPathAssessorBinary() {
  const std::string build = buildDirOfThisExe();
  return (fs::path(build) / "daemons" / "path_assessor" / "coopnav_path_assessor").string();
}

DaemonRunResult runPedestriansThroughDaemon(const std::vector<PedestrianPair>& pairs,
                                            const WindowSetting& window,
                                            const DaemonRunOptions& options) {
  DaemonRunResult r;
  r.path_assessor =
      options.path_assessor.empty() ? defaultPathAssessorBinary() : options.path_assessor;
  if (::access(r.path_assessor.c_str(), X_OK) != 0)
    fail(r.path_assessor +
         ": not an executable (build coopnav_path_assessor, or give --path-assessor)");
  r.config_path =
      options.config_path.empty() ? defaultConfig(options.profile) : options.config_path;
  std::vector<std::string> args{r.path_assessor, "-c", r.config_path};
  for (const auto& o : options.overrides) {
    args.emplace_back("--set");
    args.push_back(o);
  }
  // The in-process replay uses exactly what the daemon runs with.
  std::vector<std::string> print = args;
  print.emplace_back("--print-config");
  double max_time_jump_s = 60.0;
  r.config = parseRecorderConfig(captureOutput(print), r.profile, max_time_jump_s);
  if (static_cast<double>(kRunGapUs) * 1e-6 >= max_time_jump_s)
    fail("the path assessor's limits.max_time_jump_s is below the gap between runs");

  args.insert(args.end(), {"--lcm-url", options.lcm_url, "--log-level", "warn"});
  std::vector<WalkerRun> runs = planWalkerRuns(pairs, window);
  r.daemon.config = r.config;
  r.in_process.config = r.config;
  {
    Child child(args);
    Runtime rt("coopnav_ctl_pedestrians", options.lcm_url);
    waitReady(rt, child, options.lcm_url, options.ready_timeout_s);
    DaemonDriver driver(rt, child, options.reply_timeout_s);
    std::int64_t cursor_us = kFirstUtime;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      WalkerRun& run = runs[i];
      const RunOutcome mine = replayRun(run, r.config);
      WalkerResult in_process = run.walker;
      in_process.cm_m = mine.cm_m;
      in_process.samples = mine.samples;
      WalkerResult from_daemon = run.walker;
      if (!run.observations.empty()) {
        const double first_t_s = std::min(run.walker.window_start_s, run.observations.front().t_s);
        const std::int64_t offset_us = cursor_us - secondsToUtime(first_t_s);
        const path_assessment_t final =
            driver.run(run, static_cast<std::int32_t>(i + 1), offset_us);
        cursor_us = offset_us +
                    secondsToUtime(std::max(run.stop_t_s, run.observations.back().t_s)) + kRunGapUs;
        if (final.interaction_samples > 0 && std::isfinite(final.cm_interaction_m))
          from_daemon.cm_m = final.cm_interaction_m;
        from_daemon.samples = static_cast<std::size_t>(std::max(0, final.interaction_samples));
      }
      if (from_daemon.samples != in_process.samples ||
          from_daemon.cm_m.has_value() != in_process.cm_m.has_value())
        ++r.sample_mismatches;
      if (from_daemon.cm_m && in_process.cm_m)
        r.max_abs_dcm_m = std::max(r.max_abs_dcm_m, std::abs(*from_daemon.cm_m - *in_process.cm_m));
      r.daemon.walkers.push_back(std::move(from_daemon));
      r.in_process.walkers.push_back(std::move(in_process));
    }
    r.messages_sent = driver.messagesSent();
    const std::string how = child.stop();
    if (how != describeStatus(0)) fail("the path assessor " + how + " on SIGTERM");
  }
  scoreEvaluation(r.daemon);
  scoreEvaluation(r.in_process);
  return r;
}

std::string formatDaemonRun(const DaemonRunResult& r, const WindowSetting& window) {
  std::ostringstream o;
  char buf[96];
  o << "path assessor " << r.path_assessor << " -c " << r.config_path << " (profile "
    << (r.profile.empty() ? "?" : r.profile) << ")\n";
  o << formatPedestrianEvaluation(r.daemon,
                                  std::pow(r.config.gamma, 1.0 / r.config.sample_period_s), window);
  std::snprintf(buf, sizeof buf, "%.3g", r.max_abs_dcm_m);
  o << "daemon vs in-process: " << r.daemon.walkers.size() << " walkers, max |dCM| " << buf
    << " m, sample count mismatches " << r.sample_mismatches << " (" << r.messages_sent
    << " messages sent)\n";
  std::snprintf(buf, sizeof buf, "%.3e", r.max_abs_dcm_m);
  o << "RESULT pedestrians_daemon_max_abs_dcm_m " << buf << "\n";
  o << "RESULT pedestrians_daemon_sample_mismatches " << r.sample_mismatches << "\n";
  return o.str();
}

}  // namespace coopnav::ctl
