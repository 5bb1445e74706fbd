// coopnav_record: records LCM traffic into an LCM log file (the format lcm-logger writes and
// lcm-logplayer and coopnav_ctl read), without dropping a message when it is starved of CPU.
//
//   coopnav_record [--lcm-url URL] [-c REGEX] [-f] FILE
//
// Why not lcm-logger: Debian's lcm-logger 1.3.1 subscribes with LCM's default queue of 30
// messages and never raises it. On a loaded machine (ctest running end-to-end tests in
// parallel) its dispatch thread waits for a core while a lockstep run goes on, and every message
// beyond the 30th is dropped silently: a recorded run then lacks, say, the path assessor's last
// CM, and its transcript differs from the run's (measured: 3757 of ~3960 events recorded with
// the logger at nice 19 against four busy loops). Here the subscription queue is unlimited; the
// kernel socket buffer (recv_buf_size in the URL) holds what arrives meanwhile.
//
// Each batch of messages is flushed to the file once the queue is drained. The line "recording
// ..." on stderr says it is subscribed (a launcher starts the run after it). SIGINT / SIGTERM
// drain what is queued, close the file and print how many events were written: a launcher stops
// it as soon as the run is over (tools/exp: run_one), without waiting for the log to go quiet.
// What "queued" means is exact, not a quiet period: at the stop the recorder publishes a marker
// to itself (channel kFlushPrefix + its pid, never recorded); its one receive socket delivers in
// order, so once the marker is handled everything that had reached the socket before is too.
#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "stop_signals.hpp"

namespace {

// The stop's markers (this recorder's and any other's on the bus) are not traffic: never recorded.
constexpr const char* kFlushPrefix = "coopnav_record/flush/";

struct Recorder {
  lcm::LogFile* log{nullptr};
  std::int64_t events{0};
  std::int64_t bytes{0};
  bool write_failed{false};

  static void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                        Recorder* self) {
    // LCM's own self-test datagrams are not traffic of the system being recorded.
    if (channel.rfind("LCM_SELF_TEST", 0) == 0 || channel.rfind(kFlushPrefix, 0) == 0) return;
    lcm::LogEvent e{};
    e.timestamp = rbuf->recv_utime;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(rbuf->data_size);
    e.data = rbuf->data;
    if (self->log->writeEvent(&e) != 0) {
      self->write_failed = true;
      return;
    }
    ++self->events;
    self->bytes += rbuf->data_size;
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Records LCM messages into an LCM log file, with no subscription queue limit",
               "coopnav_record"};
  std::string url, regex = ".*", path;
  bool force = false;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL)");
  app.add_option("-c,--channel", regex, "channel regular expression (LCM's anchored syntax)");
  app.add_flag("-f,--force", force, "overwrite FILE if it exists");
  app.add_option("file", path, "log file to write")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  std::error_code ec;
  if (!force && std::filesystem::exists(path, ec)) {
    std::cerr << "coopnav_record: " << path << " exists (give -f to overwrite)\n";
    return 2;
  }

  coopnav::tools::installStopSignals();

  lcm::LCM lcm(url);
  if (!lcm.good() || lcm.getFileno() < 0) {
    std::cerr << "coopnav_record: LCM URL '" << (url.empty() ? "$LCM_DEFAULT_URL" : url)
              << "' is not usable\n";
    return 1;
  }
  lcm::LogFile log(path, "w");
  if (!log.good()) {
    std::cerr << "coopnav_record: cannot open " << path << " for writing\n";
    return 1;
  }
  Recorder rec;
  rec.log = &log;
  lcm::Subscription* sub = lcm.subscribeFunction(regex, &Recorder::onMessage, &rec);
  if (!sub) {
    std::cerr << "coopnav_record: cannot subscribe to '" << regex << "'\n";
    return 1;
  }
  sub->setQueueCapacity(0);
  std::cerr << "coopnav_record: recording '" << regex << "' into " << path << std::endl;

  pollfd fd{lcm.getFileno(), POLLIN, 0};
  auto drain = [&] {
    int handled = 0;
    while (lcm.handleTimeout(0) > 0) ++handled;
    if (handled > 0) std::fflush(log.getFilePtr());
  };
  while (!coopnav::tools::stopRequested() && !rec.write_failed) {
    if (::poll(&fd, 1, 200) > 0) drain();
  }
  // What reached the socket before the stop is recorded too, though LCM's receive thread may not
  // have read it yet (a process woken by SIGCONT and SIGTERM at once): drain until the marker
  // published now comes back after it (at most 5 s: a bus that does not loop back gives up then).
  const std::string marker = kFlushPrefix + std::to_string(::getpid());
  bool marker_back = false;
  lcm.subscribeFunction(
      marker, +[](const lcm::ReceiveBuffer*, const std::string&, bool* back) { *back = true; },
      &marker_back);
  const std::uint8_t nothing = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  if (lcm.publish(marker, &nothing, 1) == 0) {
    while (!marker_back && !rec.write_failed && std::chrono::steady_clock::now() < give_up)
      if (::poll(&fd, 1, 100) > 0) drain();
  }
  drain();
  std::fflush(log.getFilePtr());
  if (rec.write_failed) {
    std::cerr << "coopnav_record: writing " << path << " failed after " << rec.events
              << " events\n";
    return 1;
  }
  std::cerr << "coopnav_record: " << rec.events << " events (" << rec.bytes
            << " bytes of payload) in " << path << "\n";
  return 0;
}
