// Files the daemons read at start (config/file_read.hpp): one helper reads them all, refusing
// what is not a regular file (/dev/zero, a symlink to it, a FIFO, a directory) without blocking,
// and a file over its cap without reading it; a config file goes through it (exit 2). And a key
// given twice in any mapping the ConfigReader reads is an error naming the key and both lines.
#include "config/file_read.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace coopnav {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("coopnav_file_read_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string write(const std::string& name, const std::string& content) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
  /// A sparse file of `bytes` bytes (no disk space used).
  std::string sparse(const std::string& name, std::uintmax_t bytes) const {
    const std::string p = write(name, "");
    fs::resize_file(p, bytes);
    return p;
  }
  std::string symlinkToDevZero(const std::string& name) const {
    const fs::path p = path_ / name;
    fs::create_symlink("/dev/zero", p);
    return p.string();
  }
  std::string fifo(const std::string& name) const {
    const fs::path p = path_ / name;
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
    return p.string();
  }
  std::string subdir(const std::string& name) const {
    const fs::path p = path_ / name;
    fs::create_directories(p);
    return p.string();
  }
  std::string dir() const { return path_.string(); }

 private:
  fs::path path_;
};

/// Runs f on a thread and returns its FileReadError / ConfigError message; fails the test if f
/// blocks for 5 s (a FIFO opened for reading without O_NONBLOCK waits for a writer forever: the
/// thread is then left behind, and the FIFO is opened for writing to release it).
template <class Error, class F>
std::string errorWithin5s(F f, const std::string& fifo_to_release = "") {
  auto result = std::async(std::launch::async, [f]() -> std::string {
    try {
      f();
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  });
  if (result.wait_for(5s) != std::future_status::ready) {
    ADD_FAILURE() << "blocked for 5 s";
    if (!fifo_to_release.empty()) std::ofstream(fifo_to_release) << "";
  }
  return result.get();
}

std::string readErr(const std::string& path, std::size_t cap) {
  return errorWithin5s<FileReadError>([=] { readFileCapped(path, cap, "test file"); }, path);
}

bool has(const std::string& all, const std::string& s) { return all.find(s) != std::string::npos; }

TEST(FileReadTest, ARegularFileIsReadWholeUpToItsCap) {
  TempDir tmp;
  const std::string text = "key: value\n" + std::string(1000, 'x');
  EXPECT_EQ(readFileCapped(tmp.write("a.yaml", text), text.size(), "test file"), text);
  EXPECT_EQ(readFileCapped(tmp.write("empty.yaml", ""), 10, "test file"), "");
  // A symlink to a regular file is that file.
  fs::create_symlink(tmp.dir() + "/a.yaml", tmp.dir() + "/link.yaml");
  EXPECT_EQ(readFileCapped(tmp.dir() + "/link.yaml", text.size(), "test file"), text);
  // One byte over the cap: refused, naming the file, what it is, its size and the cap.
  const std::string msg = readErr(tmp.dir() + "/a.yaml", text.size() - 1);
  EXPECT_TRUE(has(msg, "a.yaml") && has(msg, "test file") &&
              has(msg, std::to_string(text.size()) + " bytes") &&
              has(msg, "(" + std::to_string(text.size() - 1) + " bytes)"))
      << msg;
}

TEST(FileReadTest, WhatIsNotARegularFileIsRefusedWithoutBlocking) {
  TempDir tmp;
  const std::string link = tmp.symlinkToDevZero("zero.yaml");
  const std::string fifo = tmp.fifo("fifo.yaml");
  const std::string dir = tmp.subdir("dir.yaml");
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(has(readErr("/dev/zero", 1 << 20),
                  "/dev/zero: is a character device; the test file must be a regular file"));
  EXPECT_TRUE(has(readErr(link, 1 << 20), "zero.yaml: is a character device"));
  EXPECT_TRUE(
      has(readErr(fifo, 1 << 20), "fifo.yaml: is a FIFO; the test file must be a regular file"));
  EXPECT_TRUE(
      has(readErr(dir, 1 << 20), "dir.yaml: is a directory; the test file must be a regular file"));
  EXPECT_TRUE(has(readErr(tmp.dir() + "/absent.yaml", 1 << 20),
                  "absent.yaml: cannot open the test file: No such file or directory"));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
}

TEST(FileReadTest, AFileOverItsCapIsRefusedBeforeItIsRead) {
  TempDir tmp;
  // 1 TiB, sparse: read, it would take minutes and all the memory there is.
  const std::string huge = tmp.sparse("huge.yaml", std::uintmax_t{1} << 40);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = readErr(huge, kMaxYamlFileBytes);
  EXPECT_TRUE(
      has(msg, "huge.yaml: is 1099511627776 bytes, more than the test file may have (1 MiB)"))
      << msg;
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  EXPECT_EQ(byteSizeText(64u << 20), "64 MiB");
  EXPECT_EQ(byteSizeText(512u << 10), "512 KiB");
  EXPECT_EQ(byteSizeText(1000), "1000 bytes");
}

struct Item {
  double x_m{0.0};
  template <class V>
  void visit(V& v) {
    v("x_m", x_m, Range{-10.0, 10.0});
  }
};

struct Inner {
  double gain{2.0};
  template <class V>
  void visit(V& v) {
    v("gain", gain, Range{0.0, 10.0});
  }
};

struct FileConfig {
  double speed_m_s{0.7};
  Inner inner;
  std::vector<Item> items;
  template <class V>
  void visit(V& v) {
    v("speed_m_s", speed_m_s, Range{0.0, 2.0});
    v("inner", inner);
    v("items", items);
  }
};

std::string configErr(const std::string& path) {
  return errorWithin5s<ConfigError>([=] { loadConfig<FileConfig>(path); }, path);
}

// Measured before: a config that is /dev/zero read until std::bad_alloc (exit 1, not 2).
TEST(FileReadTest, ConfigFilesThatAreNotRegularOrTooLargeAreConfigErrors) {
  TempDir tmp;
  const std::string link = tmp.symlinkToDevZero("zero.yaml");
  const std::string fifo = tmp.fifo("fifo.yaml");
  const std::string dir = tmp.subdir("dir.yaml");
  const std::string huge = tmp.sparse("huge.yaml", kMaxYamlFileBytes + 1);
  EXPECT_TRUE(has(configErr("/dev/zero"),
                  "/dev/zero: is a character device; the config file must be a regular file"));
  EXPECT_TRUE(has(configErr(link),
                  "zero.yaml: is a character device; the config file must be a regular file"));
  EXPECT_TRUE(has(configErr(fifo), "fifo.yaml: is a FIFO; the config file must be a regular file"));
  EXPECT_TRUE(
      has(configErr(dir), "dir.yaml: is a directory; the config file must be a regular file"));
  EXPECT_TRUE(has(configErr(huge),
                  "huge.yaml: is 1048577 bytes, more than the config file may "
                  "have (1 MiB)"));
  EXPECT_TRUE(has(configErr(tmp.dir() + "/absent.yaml"), "cannot open the config file"));
  // At the cap it is read (and here refused for what it holds, not for its size).
  const std::string at_cap = tmp.write(
      "at_cap.yaml", "speed_m_s: 1.0\n#" + std::string(kMaxYamlFileBytes - 17, 'x') + "\n");
  ASSERT_EQ(fs::file_size(at_cap), kMaxYamlFileBytes);
  EXPECT_EQ(loadConfig<FileConfig>(at_cap).speed_m_s, 1.0);
}

// Measured before: "gamma: 0.5" appended to a config that already set gamma was ignored (the
// first value kept, exit 0).
TEST(FileReadTest, AKeyGivenTwiceInAnyMappingIsAConfigErrorNamingBothLines) {
  TempDir tmp;
  const std::string top =
      configErr(tmp.write("top.yaml", "speed_m_s: 1.0\ninner: {}\nspeed_m_s: 9\n"));
  EXPECT_TRUE(has(top, "top.yaml: key 'speed_m_s' is given more than once (lines 1 and 3)")) << top;
  const std::string nested = configErr(tmp.write("nested.yaml", "inner:\n  gain: 1\n  gain: 3\n"));
  EXPECT_TRUE(has(nested, "nested.yaml: key 'inner.gain' is given more than once (lines 2 and 3)"))
      << nested;
  const std::string item =
      configErr(tmp.write("item.yaml", "items:\n  - {x_m: 1}\n  - x_m: 2\n    x_m: 3\n"));
  EXPECT_TRUE(has(item, "item.yaml: key 'items[1].x_m' is given more than once (lines 3 and 4)"))
      << item;
  // Three times: one message, with the first two lines.
  const std::string thrice =
      configErr(tmp.write("thrice.yaml", "speed_m_s: 1\nspeed_m_s: 1\nspeed_m_s: 1\n"));
  EXPECT_TRUE(has(thrice, "(lines 1 and 2)")) << thrice;
  EXPECT_FALSE(has(thrice, "line 3")) << thrice;
  // The same value twice is refused too: which one was meant is not the loader's guess.
  EXPECT_FALSE(configErr(tmp.write("same.yaml", "inner: {gain: 1, gain: 1}\n")).empty());
  // A --set override of a key the file gives once stays one key.
  EXPECT_EQ(loadConfig<FileConfig>(tmp.write("once.yaml", "speed_m_s: 1.0\n"), {"speed_m_s=1.5"})
                .speed_m_s,
            1.5);
}

}  // namespace
}  // namespace coopnav
