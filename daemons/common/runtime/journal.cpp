#include "runtime/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "runtime/log.hpp"

namespace coopnav {
namespace {

constexpr char kMagic[4] = {'C', 'N', 'J', '1'};
constexpr std::size_t kHeader = 4 + 4 + 4 + 8;
/// A record claiming more is corrupt (LCM messages are < 2^28 bytes, channels < 64).
constexpr std::uint32_t kMaxData = 1u << 28;
constexpr std::uint32_t kMaxChannel = 256;
/// The channel of the record that ends a full journal (no LCM channel of ours starts with '#').
constexpr char kFullChannel[] = "#journal-full";

void putU32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void putI64(std::vector<std::uint8_t>& b, std::int64_t v) {
  const auto u = static_cast<std::uint64_t>(v);
  for (int i = 7; i >= 0; --i) b.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
}
std::uint64_t getBE(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

Journal::Journal(Runtime& runtime, const std::string& state_dir) : runtime_(runtime) {
  if (::mkdir(state_dir.c_str(), 0755) != 0 && errno != EEXIST)
    throw std::runtime_error("state dir " + state_dir + ": " + std::strerror(errno));
  path_ = state_dir + "/" + runtime_.name() + ".journal";
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("journal " + path_ + ": " + std::strerror(errno));
  std::vector<std::uint8_t> all;
  std::uint8_t buf[65536];
  for (;;) {
    const ssize_t n = ::pread(fd_, buf, sizeof buf, static_cast<off_t>(all.size()));
    if (n <= 0) break;
    all.insert(all.end(), buf, buf + n);
  }
  std::size_t pos = 0;
  while (pos + kHeader <= all.size()) {
    const std::uint8_t* p = all.data() + pos;
    if (std::memcmp(p, kMagic, 4) != 0) break;
    const auto clen = static_cast<std::uint32_t>(getBE(p + 4, 4));
    const auto dlen = static_cast<std::uint32_t>(getBE(p + 8, 4));
    const auto recv = static_cast<std::int64_t>(getBE(p + 12, 8));
    if (clen > kMaxChannel || dlen > kMaxData || pos + kHeader + clen + dlen > all.size()) break;
    Record r;
    r.channel.assign(reinterpret_cast<const char*>(p + kHeader), clen);
    if (r.channel == kFullChannel) {
      full_ = true;
      pos += kHeader + clen + dlen;
      break;
    }
    r.data.assign(p + kHeader + clen, p + kHeader + clen + dlen);
    r.recv_utime = recv;
    records_.push_back(std::move(r));
    pos += kHeader + clen + dlen;
  }
  size_bytes_ = pos;
  if (full_) {
    records_.clear();
  } else if (pos != all.size()) {
    // The process was killed in the middle of a write: drop the cut-off tail, so that the next
    // record starts on a record boundary.
    log().warn("{}: journal {}: ignoring {} bytes of a cut-off last record", runtime_.name(), path_,
               all.size() - pos);
    if (::ftruncate(fd_, static_cast<off_t>(pos)) != 0)
      throw std::runtime_error("journal " + path_ + ": truncate: " + std::strerror(errno));
  }
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t Journal::replayAndRecord() {
  if (full_) {
    // What it holds stops at the cap: a replay would rebuild a state that is not the one lost.
    runtime_.setRestarted(false, "its journal " + path_ + " had reached limits.journal_max_mib");
    return 0;
  }
  const std::size_t n = records_.size();
  if (n > 0) {
    log().warn("{}: restarted: replaying {} journaled messages from {}", runtime_.name(), n, path_);
    runtime_.setMuted(true);
    // The handlers log as they did the first time; only the summary below matters now.
    const auto level = log().level();
    log().set_level(spdlog::level::warn);
    for (const Record& r : records_)
      runtime_.dispatchRaw(r.channel, r.data.data(), r.data.size(), r.recv_utime);
    log().set_level(level);
    runtime_.setMuted(false);
    runtime_.setRestarted(
        true, "state recovered from its journal (" + std::to_string(n) + " messages replayed)");
    log().warn("{}: state recovered from its journal ({} messages)", runtime_.name(), n);
  }
  records_.clear();
  records_.shrink_to_fit();
  runtime_.setReceiveHook(
      [this](const std::string& channel, const void* data, std::size_t size,
             std::int64_t recv_utime) { append(channel, data, size, recv_utime); });
  return n;
}

void Journal::append(const std::string& channel, const void* data, std::size_t size,
                     std::int64_t recv_utime) {
  if (write_failed_ || full_) return;
  const std::uint64_t cap_bytes =
      static_cast<std::uint64_t>(runtime_.limits().journal_max_mib) * 1024u * 1024u;
  if (size_bytes_ + kHeader + channel.size() + size > cap_bytes) {
    full_ = true;
    writeRecord(kFullChannel, nullptr, 0, recv_utime);
    runtime_.setDegraded("journal " + path_ + " reached limits.journal_max_mib (" +
                         std::to_string(runtime_.limits().journal_max_mib) +
                         " MiB): a restart from now on loses the state");
    return;
  }
  writeRecord(channel, data, size, recv_utime);
}

void Journal::writeRecord(const std::string& channel, const void* data, std::size_t size,
                          std::int64_t recv_utime) {
  std::vector<std::uint8_t> b;
  b.reserve(kHeader + channel.size() + size);
  b.insert(b.end(), kMagic, kMagic + 4);
  putU32(b, static_cast<std::uint32_t>(channel.size()));
  putU32(b, static_cast<std::uint32_t>(size));
  putI64(b, recv_utime);
  b.insert(b.end(), channel.begin(), channel.end());
  const auto* d = static_cast<const std::uint8_t*>(data);
  if (size > 0) b.insert(b.end(), d, d + size);
  // One write of the whole record (O_APPEND): a kill -9 cannot interleave half records; the page
  // cache keeps what was written when only the process dies.
  const ssize_t w = ::write(fd_, b.data(), b.size());
  if (w > 0) size_bytes_ += static_cast<std::uint64_t>(w);
  if (w != static_cast<ssize_t>(b.size())) {
    write_failed_ = true;
    log().error("{}: journal {}: write failed ({}); a restart will not recover the state",
                runtime_.name(), path_, w < 0 ? std::strerror(errno) : "short write");
  }
}

}  // namespace coopnav
