// The one log reader of every tool (daemons/common/logfile: the viewer's replay, coopnav_ctl):
// only a regular file is read (a device, a FIFO with no writer, a directory are refused at
// once with a message saying so: /dev/zero was read for ever), and never past its size at open
// (a log still being written is read as it was).
#include "logfile/log_reader.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace coopnav::logfile {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

fs::path scratchDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void writeEvents(const std::string& path, int n, const char* mode) {
  lcm::LogFile log(path, mode);
  ASSERT_TRUE(log.good());
  std::vector<std::uint8_t> data(16, 0xAB);
  for (int i = 0; i < n; ++i) {
    lcm::LogEvent ev{};
    ev.eventnum = i;
    ev.timestamp = 1000 + i;
    ev.channel = "SOME_CHANNEL";
    ev.datalen = static_cast<std::int32_t>(data.size());
    ev.data = data.data();
    log.writeEvent(&ev);
  }
}

TEST(LogReaderTest, ADeviceAFifoOrADirectoryIsRefusedAtOnce) {
  const fs::path dir = scratchDir("log_reader_refuse");
  const std::string fifo = (dir / "fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/zero"), fifo, dir.string()}) {
    const auto start = std::chrono::steady_clock::now();
    try {
      LogEventReader reader(path);
      ADD_FAILURE() << path << " was opened as a log";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, 2s) << path;
    EXPECT_THROW(readRunLog(path), std::runtime_error) << path;
  }
  EXPECT_THROW(LogEventReader((dir / "missing").string()), std::runtime_error);
  fs::remove_all(dir);
}

TEST(LogReaderTest, NothingPastTheSizeAtOpenIsRead) {
  const fs::path dir = scratchDir("log_reader_size");
  const std::string path = (dir / "run.lcm").string();
  writeEvents(path, 3, "w");
  LogEventReader reader(path);
  writeEvents(path, 5, "a");  // the logger goes on writing
  RawEvent e;
  int n = 0;
  while (reader.next(e)) ++n;
  EXPECT_EQ(n, 3);
  EXPECT_FALSE(reader.counts().anyCorruption()) << reader.counts().describe();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace coopnav::logfile
