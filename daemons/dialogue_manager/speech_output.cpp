#include "speech_output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "config/config.hpp"
#include "coopnav/dialogue/speech_timing.hpp"
#include "runtime/log.hpp"

namespace coopnav {

std::string findExecutable(const std::string& program) {
  if (program.empty()) return "";
  if (program.find('/') != std::string::npos)
    return ::access(program.c_str(), X_OK) == 0 ? program : "";
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, end - start);
    std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    start = end + 1;
  }
  return "";
}

SpeechOutput::SpeechOutput(const SpeechConfig& config) : config_(config) {
  if (!config_.enabled) return;
  program_path_ = findExecutable(config_.program);
  if (program_path_.empty()) {
    disable("'" + config_.program +
            "' is not an executable on PATH (Debian: apt-get install espeak-ng); speech is off, "
            "the dialogue goes on without it");
    return;
  }
  if (!config_.wav_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(config_.wav_dir, ec);
    if (ec) {
      disable("cannot create speech.wav_dir '" + config_.wav_dir + "': " + ec.message());
      return;
    }
  }
  usable_ = true;
  log().info("dialogue_manager: speech with {} (voice {}, {} wpm{})", program_path_, config_.voice,
             config_.rate_wpm, config_.wav_dir.empty() ? "" : ", WAV files in " + config_.wav_dir);
}

// Children are not waited for: a stopping daemon must exit within a second; a finishing espeak-ng
// child is re-parented and reaped by init.
SpeechOutput::~SpeechOutput() = default;

void SpeechOutput::disable(const std::string& why) {
  if (usable_ || !why.empty()) log().warn("dialogue_manager: speech: {}", why);
  usable_ = false;
  queue_.clear();
}

std::vector<std::string> SpeechOutput::argumentsFor(const std::string& text,
                                                    const std::string& wav_stem) const {
  std::vector<std::string> args{program_path_.empty() ? config_.program : program_path_, "-v",
                                config_.voice, "-s", std::to_string(config_.rate_wpm)};
  if (!config_.wav_dir.empty()) {
    args.push_back("-w");
    args.push_back((std::filesystem::path(config_.wav_dir) / (wav_stem + ".wav")).string());
  }
  // "--" ends the options: a text that begins with '-' is still spoken, never parsed.
  args.push_back("--");
  args.push_back(text);
  return args;
}

void SpeechOutput::say(const std::string& text, const std::string& wav_stem) {
  if (!usable_) return;
  if (queue_.size() >= static_cast<std::size_t>(config_.max_queue)) {
    ++dropped_;
    log().warn("dialogue_manager: speech queue full ({}): dropping \"{}\"", config_.max_queue,
               queue_.front().text);
    queue_.pop_front();
  }
  queue_.push_back({text, wav_stem});
  if (child_ <= 0) startNext();
}

void SpeechOutput::poll() {
  if (child_ > 0) {
    int status = 0;
    const pid_t r = ::waitpid(child_, &status, WNOHANG);
    if (r == 0) return;  // still speaking
    child_ = -1;
    if (r == -1) {
      log().warn("dialogue_manager: speech: waitpid: {}", std::strerror(errno));
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
      ++failed_;
      disable("could not execute '" + program_path_ + "' (exit 127); speech is off");
      return;
    } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      ++failed_;
      log().warn("dialogue_manager: speech: {} ended with status {}", program_path_, status);
    }
  }
  if (usable_ && !queue_.empty()) startNext();
}

void SpeechOutput::startNext() {
  if (queue_.empty() || child_ > 0) return;
  const Item item = queue_.front();
  queue_.pop_front();
  const pid_t pid = spawn(argumentsFor(item.text, item.wav_stem));
  if (pid < 0) {
    ++failed_;
    log().warn("dialogue_manager: speech: fork: {}", std::strerror(errno));
    return;
  }
  child_ = pid;
  ++started_;
  log().debug("dialogue_manager: speech: started {} for \"{}\"", pid, item.text);
}

pid_t SpeechOutput::spawn(const std::vector<std::string>& args) {
  // Everything the child needs is built before fork: after it only async-signal-safe calls.
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Child: no inherited LCM socket or self-pipe, quiet stdin, default SIGPIPE, then exec.
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, STDIN_FILENO);
#ifdef SYS_close_range
    if (::syscall(SYS_close_range, 3U, ~0U, 0U) != 0)
#endif
      for (int fd = 3; fd < 4096; ++fd) ::close(fd);
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    ::sigaction(SIGPIPE, &dfl, nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

std::vector<std::optional<double>> SpeechOutput::measure(const std::vector<std::string>& texts) {
  std::vector<std::optional<double>> seconds(texts.size());
  if (!usable_) return seconds;
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) return seconds;
  // One child per text, all at once: start-up waits for the slowest, not for the sum.
  std::vector<std::pair<pid_t, std::filesystem::path>> children;
  for (std::size_t i = 0; i < texts.size(); ++i) {
    const std::filesystem::path wav =
        dir /
        ("coopnav_speech_measure_" + std::to_string(::getpid()) + "_" + std::to_string(i) + ".wav");
    const pid_t pid = spawn({program_path_, "-v", config_.voice, "-s",
                             std::to_string(config_.rate_wpm), "-w", wav.string(), "--", texts[i]});
    children.emplace_back(pid, wav);
  }
  for (std::size_t i = 0; i < children.size(); ++i) {
    const auto& [pid, wav] = children[i];
    if (pid < 0) continue;
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      std::ifstream in(wav, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      seconds[i] = dialogue::wavDurationSeconds(bytes);
    }
    std::filesystem::remove(wav, ec);
  }
  return seconds;
}

}  // namespace coopnav
