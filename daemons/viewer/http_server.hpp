#pragma once
/// @file The viewer's HTTP side (cpp-httplib, its own threads): the page and its assets, the
/// scene as Server-Sent Events and as JSON, the map, the replay controls, and the page's
/// acknowledgements of what it drew (frame latency, what was drawn). The LCM thread hands it
/// finished JSON frames (publishFrame: a pointer swap under a mutex) and takes the controls the
/// page posted (takeControls); it never waits for a browser. A browser that is slow gets the
/// latest frame when it can take one (the frames in between are skipped); one that disconnects
/// frees its slot; one that stops reading is dropped after stalled_client_timeout; beyond
/// max_clients streams the server answers 503.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace httplib {
class Server;
}

namespace coopnav::viewer {

struct HttpOptions {
  std::string bind_address{"127.0.0.1"};
  int port{8088};  ///< 0 = any free port (port() tells which)
  int max_clients{8};
  bool replay{false};  ///< the replay controls are accepted
  /// A page whose stream takes no data for this long is dropped (its thread freed; the browser's
  /// EventSource connects again). The viewer's exit waits this long at most for such a page.
  std::chrono::milliseconds stalled_client_timeout{1000};
};

/// A replay control posted by the page: play, pause, speed (value = factor), seek (value = t [s]).
struct Control {
  std::string command;
  double value{0.0};
};

/// The latest frame and its version; stream handlers wait on it for a newer one.
class FrameHub {
 public:
  void publish(std::shared_ptr<const std::string> frame);
  std::shared_ptr<const std::string> latest() const;
  /// Waits up to `timeout` for a frame newer than `version`; on one, sets both and returns true.
  bool waitNewer(std::uint64_t& version, std::shared_ptr<const std::string>& frame,
                 std::chrono::milliseconds timeout);
  void stop();
  bool stopped() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::shared_ptr<const std::string> frame_;
  std::uint64_t version_{0};
  bool stopped_{false};
};

/// Bus message -> drawn frame: the monotonic time each scene utime was received, and the time
/// the page said it drew it.
class LatencyLog {
 public:
  using Clock = std::chrono::steady_clock;
  void received(std::int64_t utime, Clock::time_point t);
  void drawn(std::int64_t utime, Clock::time_point t);
  nlohmann::json stats() const;
  void clear();

 private:
  static constexpr std::size_t kKeep = 4096;
  mutable std::mutex mutex_;
  std::map<std::int64_t, Clock::time_point> received_;
  std::deque<double> latencies_ms_;
  std::int64_t unmatched_{0};
};

class ViewerHttp {
 public:
  /// Binds and starts serving; throws std::runtime_error when the address cannot be bound.
  ViewerHttp(const HttpOptions& options, std::string map_json);
  ~ViewerHttp();
  ViewerHttp(const ViewerHttp&) = delete;
  ViewerHttp& operator=(const ViewerHttp&) = delete;

  int port() const { return port_; }
  /// LCM thread: the scene's JSON text, sent to every stream.
  void publishFrame(std::string json);
  /// LCM thread: the controls posted since the last call, in order.
  std::vector<Control> takeControls();
  LatencyLog& latency() { return latency_; }
  int clients() const { return clients_.load(); }
  std::int64_t refused() const { return refused_.load(); }
  /// What the page reported drawn: its latest summary and every key drawn so far.
  nlohmann::json drawn() const;

 private:
  bool acquireClient();
  void setUpRoutes();

  HttpOptions options_;
  std::string map_json_;
  std::atomic<bool> stopping_{false};
  std::unique_ptr<httplib::Server> server_;  ///< the routes (never listens)
  std::unique_ptr<httplib::Server> front_;   ///< listens; the request gate before the routes
  std::thread thread_;
  std::atomic<bool> listen_done_{false};  ///< the accept loop has returned
  int port_{0};
  FrameHub hub_;
  LatencyLog latency_;
  std::atomic<int> clients_{0};
  std::atomic<std::int64_t> refused_{0};
  std::atomic<std::int64_t> frames_{0};
  mutable std::mutex mutex_;  ///< controls_, drawn_*
  std::vector<Control> controls_;
  nlohmann::json drawn_last_;
  std::set<std::string> drawn_ever_;
  std::int64_t acks_{0};
};

}  // namespace coopnav::viewer
