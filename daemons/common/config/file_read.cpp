#include "config/file_read.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace coopnav {
namespace {

/// What a file that is not a regular one is, for the message.
const char* kindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw FileReadError(path + ": " + why);
}

std::string notRegular(mode_t mode, const std::string& what) {
  return std::string("is ") + kindOf(mode) + "; the " + what + " must be a regular file";
}

std::string tooLarge(std::size_t size, std::size_t max_bytes, const std::string& what) {
  return "is " + std::to_string(size) + " bytes, more than the " + what + " may have (" +
         byteSizeText(max_bytes) + ")";
}

/// Closes the descriptor however the read ends.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::string byteSizeText(std::size_t bytes) {
  constexpr std::size_t kKiB = 1024, kMiB = kKiB * 1024;
  if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MiB";
  if (bytes >= kKiB && bytes % kKiB == 0) return std::to_string(bytes / kKiB) + " KiB";
  return std::to_string(bytes) + " bytes";
}

std::string readFileCapped(const std::string& path, std::size_t max_bytes,
                           const std::string& what) {
  // A look before opening: a device or a FIFO is refused without being opened at all (opening a
  // device may act on it). The check that counts is on the opened descriptor below: the name may
  // be swapped in between.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    refuse(path, "cannot open the " + what + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) refuse(path, notRegular(st.st_mode, what));
  const Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC));
  if (fd.get() < 0) refuse(path, "cannot open the " + what + ": " + std::strerror(errno));
  if (::fstat(fd.get(), &st) != 0)
    refuse(path, "cannot read the " + what + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) refuse(path, notRegular(st.st_mode, what));
  if (st.st_size < 0 || static_cast<unsigned long long>(st.st_size) > max_bytes)
    refuse(path, tooLarge(static_cast<std::size_t>(st.st_size), max_bytes, what));
  // Read to the end, not to st_size: the file may grow or shrink meanwhile. One byte past the cap
  // tells a file that grew over it.
  std::string data;
  data.resize(static_cast<std::size_t>(st.st_size) + 1);
  std::size_t have = 0;
  for (;;) {
    if (have == data.size()) {
      if (data.size() > max_bytes) refuse(path, tooLarge(have, max_bytes, what));
      data.resize(std::min(max_bytes + 1, 2 * data.size()));
    }
    const ssize_t n = ::read(fd.get(), &data[have], data.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      refuse(path, "cannot read the " + what + ": " + std::strerror(errno));
    }
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  if (have > max_bytes) refuse(path, tooLarge(have, max_bytes, what));
  data.resize(have);
  return data;
}

}  // namespace coopnav
