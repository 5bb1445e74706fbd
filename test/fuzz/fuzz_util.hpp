#pragma once
// Shared by the fuzz targets (test/fuzz/README.md). The contract every target checks: an input is
// either accepted or refused with the exception type the daemon expects for it; any other
// exception, a crash, a sanitizer report, a leak or a hang is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/log.hpp"
#include "runtime/runtime.hpp"

namespace coopnav::fuzz {

/// Stops the run on a broken invariant; libFuzzer saves the input as a crash.
[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "coopnav fuzz invariant broken: %s\n", what);
  std::abort();
}

/// An LCM payload as a daemon receives it on one of its channels: the first byte picks the
/// subscription (modulo their count), the rest is the payload handed to decodeOrReject.
struct ChannelInput {
  unsigned channel{0};
  const std::uint8_t* payload{nullptr};
  std::size_t size{0};
};

inline bool splitChannel(const std::uint8_t* data, std::size_t size, unsigned num_channels,
                         ChannelInput* out) {
  if (size < 1) return false;
  out->channel = data[0] % num_channels;
  out->payload = data + 1;
  out->size = size - 1;
  return true;
}

/// Decodes like Runtime::subscribe; false when the daemon would reject the bytes (counted drop).
template <class Msg>
bool decodeLikeDaemon(const ChannelInput& in, Msg* msg) {
  try {
    decodeOrReject(in.payload, in.size, *msg);
    return true;
  } catch (const RejectedMessage&) {
    return false;
  }
}

/// Encodes msg with LCM's encoder (the bytes a publisher would send).
template <class Msg>
std::vector<std::uint8_t> encode(const Msg& msg) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  if (msg.encode(buf.data(), 0, static_cast<int>(buf.size())) != static_cast<int>(buf.size()))
    fail("encode of a converted message failed");
  return buf;
}

/// What a daemon publishes after converting an accepted input must decode again: the encoders
/// trust the counts toLcm sets, so a mismatch here would be a malformed message on the bus.
template <class Msg>
Msg reencode(const Msg& msg) {
  const std::vector<std::uint8_t> buf = encode(msg);
  Msg back;
  ChannelInput in{0, buf.data(), buf.size()};
  if (!decodeLikeDaemon(in, &back)) fail("a converted message does not decode again");
  return back;
}

/// A per-process scratch directory for loaders that take paths (removed at exit). Inputs are
/// written under fixed names, so a crash reproduces from the saved input alone.
class ScratchDir {
 public:
  ScratchDir() {
    path_ = base() / ("coopnav_fuzz_" + std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  /// Writes bytes to <dir>/<name> and returns the full path.
  std::string write(const std::string& name, const std::uint8_t* data, std::size_t size) const {
    const std::filesystem::path p = path_ / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) fail("cannot write a scratch file");
    return p.string();
  }
  std::string path() const { return path_.string(); }

 private:
  /// $TMPDIR when set, else /dev/shm when there is one, else the system's temp folder. Each input
  /// rewrites a file in place; on ext4 (/tmp here) a file truncated and rewritten is flushed to the
  /// disk when it is closed, so every execution waited for the disk: fuzz_map_pgm ran 30x slower
  /// from /tmp than from the tmpfs. The loaders read the same bytes from either.
  static std::filesystem::path base() {
    if (const char* tmpdir = std::getenv("TMPDIR"); tmpdir != nullptr && *tmpdir != '\0')
      return std::filesystem::temp_directory_path();
    const std::filesystem::path shm = "/dev/shm";
    std::error_code ec;
    if (std::filesystem::is_directory(shm, ec) && ::access(shm.c_str(), W_OK) == 0) return shm;
    return std::filesystem::temp_directory_path();
  }

  std::filesystem::path path_;
};

/// One scratch directory per fuzzer process, built on first use.
inline const ScratchDir& scratch() {
  static const ScratchDir dir;
  return dir;
}

/// Splits an input into parts at a separator line ("\n--8<--\n"), for targets whose loader reads
/// several files (a map YAML and its PGM image). Missing parts are empty.
inline std::vector<std::string> splitParts(const std::uint8_t* data, std::size_t size,
                                           std::size_t num_parts) {
  static const std::string kSeparator = "\n--8<--\n";
  const std::string all(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (parts.size() + 1 < num_parts) {
    const std::size_t at = all.find(kSeparator, start);
    if (at == std::string::npos) break;
    parts.push_back(all.substr(start, at - start));
    start = at + kSeparator.size();
  }
  parts.push_back(all.substr(start));
  parts.resize(num_parts);
  return parts;
}

/// Keeps the daemons' logging from dominating the run time and the fuzzer's output.
inline void quietLogs() { setLogLevel("off"); }

/// The map targets' cell limit (the daemons' max_map_cells, 2^22 by default). A mutated walls
/// YAML or .bt easily asks for 10^5-10^6 cells: 0.3-1.5 s per execution in this build, 2-3 % of
/// the inputs and most of the run's time, spent on the same code as a small map. Over this limit
/// the loader's refusal is what is fuzzed. Every committed seed is below it (scenarios at 0.1 m).
inline constexpr std::int64_t kMaxMapCells = std::int64_t{1} << 15;

}  // namespace coopnav::fuzz
