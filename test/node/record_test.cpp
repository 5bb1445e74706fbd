// coopnav_record (tools/record) as a process on this executable's own udpm port: what it writes
// is every message published while it was running, even when it got no CPU for a while (the
// reason it exists: lcm-logger 1.3.1 drops all but 30 queued messages then).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "logfile/log_reader.hpp"
#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

std::string recorderPath() { return ::coopnav::test::binaryDir() + "/tools/coopnav_record"; }

class RecordTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("coopnav_record_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    log_ = (dir_ / "run.lcm").string();
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // Publishes probes until the recorder has written one: it is subscribed from then on.
  bool waitRecording(lcm::LCM& lcm) {
    const std::uint8_t probe = 0;
    return test::waitFor(
        [&] {
          std::error_code ec;
          return fs::exists(log_, ec) && fs::file_size(log_, ec) > 0;
        },
        milliseconds(10000), [&] { lcm.publish("REC_PROBE", &probe, 1); });
  }

  std::vector<ctl::RawEvent> readAll() {
    ctl::LogEventReader reader(log_);
    std::vector<ctl::RawEvent> out;
    ctl::RawEvent e;
    while (reader.next(e)) out.push_back(e);
    EXPECT_FALSE(reader.counts().truncated);
    EXPECT_EQ(reader.counts().bad_headers, 0);
    return out;
  }

  fs::path dir_;
  std::string log_;
};

TEST_F(RecordTest, KeepsEveryMessageSentWhileItWasStopped) {
  lcm::LCM lcm(test::testLcmUrl());
  ASSERT_TRUE(lcm.good());
  test::ChildProcess rec(recorderPath(),
                         {"-f", "-c", "REC_.*", "--lcm-url", test::testLcmUrl(), log_});
  ASSERT_TRUE(waitRecording(lcm));

  // Stopped, as a process the scheduler leaves waiting on a loaded machine: the messages wait
  // in the socket buffer and then in LCM's queue, far more than its default 30.
  rec.signal(SIGSTOP);
  constexpr std::uint32_t kMessages = 300;
  for (std::uint32_t i = 0; i < kMessages; ++i) {
    std::uint8_t payload[64] = {};
    std::memcpy(payload, &i, sizeof i);
    lcm.publish("REC_DATA", payload, sizeof payload);
    lcm.publish("OTHER_CHANNEL", payload, 4);  // not matched by the recorder's expression
  }
  rec.signal(SIGCONT);
  rec.signal(SIGTERM);
  ASSERT_EQ(rec.waitExit(milliseconds(10000)), 0);

  std::vector<std::uint32_t> seen;
  std::int64_t last_event = -1;
  for (const auto& e : readAll()) {
    EXPECT_GT(e.event_number, last_event);
    last_event = e.event_number;
    EXPECT_GT(e.timestamp_us, 0);
    if (e.channel == "REC_PROBE") continue;
    ASSERT_EQ(e.channel, "REC_DATA");
    ASSERT_EQ(e.data.size(), 64u);
    std::uint32_t i = 0;
    std::memcpy(&i, e.data.data(), sizeof i);
    seen.push_back(i);
  }
  ASSERT_EQ(seen.size(), kMessages);
  for (std::uint32_t i = 0; i < kMessages; ++i) EXPECT_EQ(seen[i], i) << "out of order at " << i;
}

// Stopped at once after the last message: it is recorded (the stop drains up to the marker the
// recorder sends itself), and the marker is not, even by a recorder of every channel.
TEST_F(RecordTest, AStopRightAfterTheLastMessageKeepsItAndRecordsNoMarker) {
  lcm::LCM lcm(test::testLcmUrl());
  ASSERT_TRUE(lcm.good());
  test::ChildProcess other(recorderPath(), {"-f", "-c", ".*", "--lcm-url", test::testLcmUrl(),
                                            (dir_ / "other.lcm").string()});
  test::ChildProcess rec(recorderPath(), {"-f", "-c", ".*", "--lcm-url", test::testLcmUrl(), log_});
  ASSERT_TRUE(waitRecording(lcm));
  constexpr std::uint32_t kMessages = 200;
  for (std::uint32_t i = 0; i < kMessages; ++i) lcm.publish("REC_DATA", &i, sizeof i);
  rec.signal(SIGTERM);
  ASSERT_EQ(rec.waitExit(milliseconds(10000)), 0);
  other.signal(SIGTERM);
  ASSERT_EQ(other.waitExit(milliseconds(10000)), 0);
  std::uint32_t data = 0;
  for (const auto& e : readAll()) {
    EXPECT_NE(e.channel.rfind("coopnav_record/", 0), 0u) << e.channel;
    if (e.channel == "REC_DATA") ++data;
  }
  EXPECT_EQ(data, kMessages);
  ctl::LogEventReader reader((dir_ / "other.lcm").string());
  ctl::RawEvent e;
  while (reader.next(e)) EXPECT_NE(e.channel.rfind("coopnav_record/", 0), 0u) << e.channel;
}

TEST_F(RecordTest, RefusesToOverwriteWithoutForceAndABadUrl) {
  {
    std::FILE* f = std::fopen(log_.c_str(), "w");
    std::fclose(f);
  }
  test::ChildProcess no_force(recorderPath(), {"--lcm-url", test::testLcmUrl(), log_});
  EXPECT_EQ(no_force.waitExit(milliseconds(10000)), 2);
  EXPECT_EQ(fs::file_size(log_), 0u);

  test::ChildProcess bad_url(recorderPath(), {"-f", "--lcm-url", "nosuch://x", log_});
  EXPECT_EQ(bad_url.waitExit(milliseconds(10000)), 1);

  test::ChildProcess no_dir(recorderPath(), {"-f", "--lcm-url", test::testLcmUrl(),
                                             (dir_ / "missing" / "run.lcm").string()});
  EXPECT_EQ(no_dir.waitExit(milliseconds(10000)), 1);
}

}  // namespace
}  // namespace coopnav
