#include "log_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <unordered_set>

#include "coopnav/channels.hpp"

namespace coopnav::logfile {
namespace {

constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::int64_t kHeaderBytes = 28;  // sync, event number, timestamp, two lengths
// LCM's own bounds: channel names are < 1000 bytes in any log the library writes, messages
// at most 2^28 bytes.
constexpr std::int64_t kMaxChannelBytes = 1000;
constexpr std::int64_t kMaxDataBytes = std::int64_t{1} << 28;

std::uint64_t readBe(const unsigned char* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

// Next sync word at or after `from` and before `end` (the size at open: a file that grows while
// read is read as it was); returns its offset (file positioned after it) or -1.
std::int64_t scanForSync(std::FILE* f, std::int64_t from, std::int64_t end) {
  if (fseeko(f, from, SEEK_SET) != 0) return -1;
  std::uint32_t window = 0;
  std::int64_t pos = from;
  int c = 0;
  int have = 0;
  while (pos < end && (c = std::getc(f)) != EOF) {
    window = (window << 8) | static_cast<std::uint32_t>(c);
    ++pos;
    if (++have >= 4 && window == kSyncWord) return pos - 4;
  }
  return -1;
}

template <class Msg>
bool decodeInto(const RawEvent& e, std::vector<Msg>& out) {
  Msg msg;
  const int size = static_cast<int>(e.data.size());
  if (size == 0) return false;
  int used = -1;
  try {
    // The generated decoder throws (std::length_error, std::bad_alloc) on a negative or absurd
    // array count, and returns < 0 on a fingerprint mismatch or short buffer.
    used = msg.decode(e.data.data(), 0, size);
  } catch (const std::exception&) {
    return false;
  }
  // Trailing bytes mean the payload is not this type either.
  if (used != size) return false;
  out.push_back(std::move(msg));
  return true;
}

bool isNotNeeded(const std::string& channel) {
  static const char* const kNames[] = {channels::kGoals, channels::kBands,
                                       channels::kDistanceRequest};
  for (const char* n : kNames)
    if (channel == n) return true;
  const std::string prefix = channels::kDistanceReplyPrefix;
  return channel.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

std::string LogReadCounts::describe() const {
  std::string s = "events " + std::to_string(events) + ", decoded " + std::to_string(decoded) +
                  ", not needed " + std::to_string(not_needed) + ", unknown channel " +
                  std::to_string(unknown_channel) + ", undecodable " + std::to_string(undecodable);
  for (const auto& [channel, n] : undecodable_by_channel)
    s += " (" + channel + ": " + std::to_string(n) + ")";
  if (bad_headers > 0) s += ", bad headers " + std::to_string(bad_headers);
  if (skipped_bytes > 0) s += ", skipped bytes " + std::to_string(skipped_bytes);
  if (repeats > 0) s += ", repeats " + std::to_string(repeats);
  if (truncated) s += ", truncated at the end";
  return s;
}

LogEventReader::LogEventReader(const std::string& path) {
  // Opened without blocking (a FIFO with no writer would block the open itself) and checked:
  // only a regular file has a size to bound the reads by; /dev/zero, a FIFO or a terminal would
  // be read forever, so they are refused at once.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open log " + path + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw std::runtime_error("log " + path +
                             " is not a regular file (a device, FIFO or directory cannot be "
                             "read as a log)");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  file_ = ::fdopen(fd, "rb");
  if (!file_) {
    ::close(fd);
    throw std::runtime_error("cannot open log " + path + ": " + std::strerror(errno));
  }
  file_size_ = static_cast<std::int64_t>(st.st_size);
}

LogEventReader::~LogEventReader() {
  if (file_) std::fclose(file_);
}

bool LogEventReader::next(RawEvent& out) {
  for (;;) {
    const std::int64_t pos = ftello(file_);
    const std::int64_t sync = scanForSync(file_, pos, file_size_);
    if (sync < 0) {
      counts_.skipped_bytes += file_size_ - pos;
      return false;
    }
    counts_.skipped_bytes += sync - pos;
    unsigned char h[kHeaderBytes - 4];
    if (std::fread(h, 1, sizeof h, file_) != sizeof h) {
      counts_.truncated = true;
      return false;
    }
    const auto event_number = static_cast<std::int64_t>(readBe(h, 8));
    const auto timestamp = static_cast<std::int64_t>(readBe(h + 8, 8));
    const auto channel_len = static_cast<std::int32_t>(readBe(h + 16, 4));
    const auto data_len = static_cast<std::int32_t>(readBe(h + 20, 4));
    const std::int64_t remaining = file_size_ - (sync + kHeaderBytes);
    const bool plausible = channel_len > 0 && channel_len < kMaxChannelBytes && data_len >= 0 &&
                           data_len <= kMaxDataBytes;
    if (!plausible || channel_len + std::int64_t{data_len} > remaining) {
      // A plausible header that runs past the end with no later sync word is a cut-off last
      // event (logger killed); anything else is corruption: resynchronise after this sync word.
      if (plausible && scanForSync(file_, sync + 1, file_size_) < 0) {
        counts_.truncated = true;
        fseeko(file_, 0, SEEK_END);
        return false;
      }
      ++counts_.bad_headers;
      fseeko(file_, sync + 1, SEEK_SET);
      continue;
    }
    out.event_number = event_number;
    out.timestamp_us = timestamp;
    out.channel.assign(static_cast<std::size_t>(channel_len), '\0');
    out.data.resize(static_cast<std::size_t>(data_len));
    if (std::fread(out.channel.data(), 1, out.channel.size(), file_) != out.channel.size() ||
        std::fread(out.data.data(), 1, out.data.size(), file_) != out.data.size()) {
      counts_.truncated = true;
      return false;
    }
    ++counts_.events;
    return true;
  }
}

void addEvent(const RawEvent& e, RunLog& run) {
  using Kind = RunLog::Kind;
  bool ok = false;
  Kind kind{};
  std::size_t index = 0;
  auto take = [&](Kind k, auto& vec) {
    kind = k;
    index = vec.size();
    ok = decodeInto(e, vec);
  };
  const std::string& ch = e.channel;
  if (ch == channels::kAgentStates) {
    take(Kind::kAgentStates, run.agent_states);
  } else if (ch == channels::kSituation) {
    take(Kind::kSituation, run.situations);
  } else if (ch == channels::kPathAssessment) {
    take(Kind::kPathAssessment, run.assessments);
  } else if (ch == channels::kUtterance) {
    take(Kind::kUtterance, run.utterances);
  } else if (ch == channels::kRobotAction) {
    take(Kind::kRobotAction, run.actions);
  } else if (ch == channels::kPathAssessorControl) {
    take(Kind::kRecorderControl, run.controls);
  } else if (ch == channels::kSimStatus) {
    take(Kind::kSimStatus, run.sim_status);
  } else if (ch == channels::kReferencePaths) {
    take(Kind::kReferencePaths, run.reference_paths);
  } else if (ch == channels::kGoalEstimates) {
    take(Kind::kGoalEstimates, run.goal_estimates);
  } else if (ch == channels::kStatus) {
    take(Kind::kDaemonStatus, run.daemon_status);
  } else if (ch == channels::kRobotCmd) {
    // Only the modes and the guard are used (summary counts). A command of an older shape does
    // not decode: not needed, not corrupt, as the acks below.
    take(Kind::kVelocityCommand, run.commands);
    if (!ok) {
      ++run.counts.not_needed;
      return;
    }
  } else if (ch == channels::kStepAck) {
    // Only a restart matters to the tools: its first ack, per daemon and restart step. Acks of an
    // older shape (logs before the restart fields) do not decode: not needed, not corrupt.
    std::vector<step_ack_t> acks;
    const bool decoded = decodeInto(e, acks);
    if (decoded && acks.front().step >= 0) {
      // Who answered how far: counted as the ack is (not needed), only its step is kept.
      const auto it = run.last_acked_step.find(acks.front().participant);
      if (it != run.last_acked_step.end())
        it->second = std::max(it->second, acks.front().step);
      else if (run.last_acked_step.size() < RunLog::kMaxAckParticipants)
        run.last_acked_step.emplace(acks.front().participant, acks.front().step);
    }
    if (!decoded || acks.front().restart == step_ack_t::RESTART_NONE) {
      ++run.counts.not_needed;
      return;
    }
    for (const auto& r : run.restarts) {
      if (r.participant == acks.front().participant &&
          r.restart_step == acks.front().restart_step) {
        ++run.counts.not_needed;
        return;
      }
    }
    kind = Kind::kRestart;
    index = run.restarts.size();
    run.restarts.push_back(std::move(acks.front()));
    ok = true;
  } else if (isNotNeeded(ch)) {
    ++run.counts.not_needed;
    return;
  } else {
    ++run.counts.unknown_channel;
    return;
  }
  if (!ok) {
    ++run.counts.undecodable;
    ++run.counts.undecodable_by_channel[ch];
    return;
  }
  ++run.counts.decoded;
  run.order.push_back({kind, index});
}

RunLog readRunLog(const std::string& path) {
  LogEventReader reader(path);
  RunLog run;
  RawEvent e;
  // A step published again (after a loss or a restart) is the same bytes: read it once.
  std::unordered_set<std::string> seen;
  std::int64_t repeats = 0;
  while (reader.next(e)) {
    if (e.channel != channels::kStatus) {
      std::string key = e.channel;
      key.push_back('\0');
      key.append(e.data.begin(), e.data.end());
      if (!seen.insert(std::move(key)).second) {
        ++repeats;
        continue;
      }
    }
    addEvent(e, run);
  }
  run.counts.repeats = repeats;
  // Framing counts come from the reader, decoding counts from addEvent.
  const LogReadCounts& framing = reader.counts();
  run.counts.events = framing.events;
  run.counts.bad_headers = framing.bad_headers;
  run.counts.skipped_bytes = framing.skipped_bytes;
  run.counts.truncated = framing.truncated;
  return run;
}

}  // namespace coopnav::logfile
