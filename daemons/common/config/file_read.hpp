#pragma once
/// @file The one way the daemons read a file at start (configs, scenarios, maps, images, .bt):
/// readFileCapped() opens it once, refuses anything that is not a regular file after following
/// symlinks (a directory, a FIFO, /dev/zero or a symlink to it) and anything over a size cap,
/// and reads it whole. A file read any other way could make a daemon block forever on a FIFO or
/// read /dev/zero until it ran out of memory (17-20 s and ~2 GB before std::bad_alloc, exit 1
/// instead of the exit code of a bad file).

#include <cstddef>
#include <stdexcept>
#include <string>

namespace coopnav {

/// A file that cannot be read as asked; what() names the file, what it is meant to be and why
/// (not found, not a regular file, over its cap: the cap is named).
class FileReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Largest YAML file a daemon reads: a config, a scenario or a map YAML (ROS map, walls map).
/// yaml-cpp holds a document in ~100-250 bytes per node: parsing a MiB of "0," takes ~1.6 s and
/// ~250 MB, 4 MiB ~8 s and ~1 GB. Our largest config is ~12 kB, a scenario of 64 humans ~30 kB,
/// and a MiB is a walls map of ~14k walls, more than a 2^22-cell map (max_map_cells) has room
/// for.
inline constexpr std::size_t kMaxYamlFileBytes = std::size_t{1} << 20;

/// Reads the file at `path` whole: `what` names it in messages ("config file", "PGM image").
/// Opened without blocking (O_NONBLOCK: a FIFO with no writer must not hang the start), then
/// checked on the opened descriptor: a regular file of at most max_bytes bytes. Throws
/// FileReadError "<path>: ..." naming `what` and, for a file too large, its size and the cap.
std::string readFileCapped(const std::string& path, std::size_t max_bytes, const std::string& what);

/// "1 MiB", "64 MiB", "512 KiB", or "N bytes": a cap as messages print it.
std::string byteSizeText(std::size_t bytes);

}  // namespace coopnav
