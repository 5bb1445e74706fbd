#include "http_server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "web_assets.hpp"

namespace coopnav::viewer {
namespace {

using nlohmann::json;

/// Threads beyond the streams: page, assets, JSON, controls and acks while max_clients stream.
constexpr int kSpareThreads = 6;
/// A stream with nothing new sends an SSE comment this often (proxies, and to notice a gone peer).
constexpr std::chrono::milliseconds kKeepAlive{1000};
/// [s] Longest gap within a request: a browser sends one in a single write. A connection thread
/// waiting for the rest of a half-sent request (not yet a stream, so not shut down at the stop)
/// holds the exit this long at most.
constexpr time_t kRequestReadTimeoutS = 1;
/// Largest body a POST may have (a control or an ack with its drawn summary).
constexpr std::size_t kMaxBodyBytes = 64 * 1024;
/// Most distinct drawn keys remembered (what the page has drawn at least once).
constexpr std::size_t kMaxDrawnKeys = 4096;

}  // namespace

// ---- FrameHub

void FrameHub::publish(std::shared_ptr<const std::string> frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    frame_ = std::move(frame);
    ++version_;
  }
  cv_.notify_all();
}

std::shared_ptr<const std::string> FrameHub::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frame_;
}

bool FrameHub::waitNewer(std::uint64_t& version, std::shared_ptr<const std::string>& frame,
                         std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  const bool newer = cv_.wait_for(
      lock, timeout, [&] { return stopped_ || (version_ != version && frame_ != nullptr); });
  if (!newer || stopped_) return false;
  version = version_;
  frame = frame_;
  return true;
}

void FrameHub::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
  }
  cv_.notify_all();
}

bool FrameHub::stopped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stopped_;
}

// ---- LatencyLog

void LatencyLog::received(std::int64_t utime, Clock::time_point t) {
  std::lock_guard<std::mutex> lock(mutex_);
  received_.emplace(utime, t);  // the first reception of a utime counts
  while (received_.size() > kKeep) received_.erase(received_.begin());
}

void LatencyLog::drawn(std::int64_t utime, Clock::time_point t) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = received_.find(utime);
  if (it == received_.end()) {
    ++unmatched_;
    return;
  }
  latencies_ms_.push_back(std::chrono::duration<double, std::milli>(t - it->second).count());
  received_.erase(it);  // a frame drawn again (another page, a repaint) is not a new latency
  while (latencies_ms_.size() > kKeep) latencies_ms_.pop_front();
}

json LatencyLog::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<double> v(latencies_ms_.begin(), latencies_ms_.end());
  std::sort(v.begin(), v.end());
  const auto q = [&](double p) -> json {
    if (v.empty()) return nullptr;
    const auto i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
    return v[std::min(i, v.size() - 1)];
  };
  return {{"n", v.size()},
          {"p50_ms", q(0.5)},
          {"p99_ms", q(0.99)},
          {"max_ms", v.empty() ? json(nullptr) : json(v.back())},
          {"unmatched", unmatched_}};
}

void LatencyLog::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  latencies_ms_.clear();
  unmatched_ = 0;
}

// ---- ViewerHttp

ViewerHttp::ViewerHttp(const HttpOptions& options, std::string map_json)
    : options_(options),
      map_json_(std::move(map_json)),
      server_(std::make_unique<httplib::Server>()) {
  const int threads = options_.max_clients + kSpareThreads;
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  // SO_REUSEADDR (a restarted viewer binds at once) but not httplib's default SO_REUSEPORT, with
  // which a second viewer on the same port would bind too and share the connections silently.
  server_->set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  server_->set_payload_max_length(kMaxBodyBytes);
  server_->set_keep_alive_timeout(2);
  server_->set_read_timeout(kRequestReadTimeoutS);
  // A page that takes nothing for this long is dropped (its stream thread is freed): httplib 0.11
  // hands out no socket to shut down, so this is also how long the exit may wait for it.
  const auto stall_us =
      std::chrono::duration_cast<std::chrono::microseconds>(options_.stalled_client_timeout)
          .count();
  server_->set_write_timeout(static_cast<time_t>(stall_us / 1000000),
                             static_cast<time_t>(stall_us % 1000000));
  setUpRoutes();
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.bind_address);
    if (port_ <= 0) throw std::runtime_error("cannot bind any port on " + options_.bind_address);
  } else {
    if (!server_->bind_to_port(options_.bind_address, options_.port))
      throw std::runtime_error("cannot bind " + options_.bind_address + ":" +
                               std::to_string(options_.port) + " (in use, or not an address here)");
    port_ = options_.port;
  }
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listen_done_ = true;
  });
  // stop() is a no-op on a server not yet in its accept loop, which would then never end: the
  // viewer is constructed only once the loop runs (or has given up).
  while (!server_->is_running() && !listen_done_)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

ViewerHttp::~ViewerHttp() {
  // Streams waiting for a frame return at once; one blocked writing to a page that does not read
  // returns within stalled_client_timeout, a half-sent request within kRequestReadTimeoutS.
  hub_.stop();
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

void ViewerHttp::publishFrame(std::string json) {
  ++frames_;
  hub_.publish(std::make_shared<const std::string>(std::move(json)));
}

std::vector<Control> ViewerHttp::takeControls() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Control> out;
  out.swap(controls_);
  return out;
}

json ViewerHttp::drawn() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"acks", acks_},
          {"last", drawn_last_},
          {"ever", json(std::vector<std::string>(drawn_ever_.begin(), drawn_ever_.end()))}};
}

bool ViewerHttp::acquireClient() {
  int n = clients_.load();
  while (n < options_.max_clients) {
    if (clients_.compare_exchange_weak(n, n + 1)) return true;
  }
  ++refused_;
  return false;
}

void ViewerHttp::setUpRoutes() {
  using httplib::Request;
  using httplib::Response;
  for (const WebAsset& a : webAssets()) {
    const std::string path = a.path;
    const auto serve = [a](const Request&, Response& res) {
      res.set_header("Cache-Control", "no-cache");
      res.set_content(std::string(a.body), a.content_type);
    };
    server_->Get(path, serve);
    if (path == "/index.html") server_->Get("/", serve);
  }

  server_->Get("/events", [this](const Request&, Response& res) {
    if (!acquireClient()) {
      res.status = 503;
      res.set_content(
          "too many viewers (max_clients " + std::to_string(options_.max_clients) + ")\n",
          "text/plain");
      return;
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    auto version = std::make_shared<std::uint64_t>(0);
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, version](std::size_t, httplib::DataSink& sink) {
          std::shared_ptr<const std::string> frame;
          if (!hub_.waitNewer(*version, frame, kKeepAlive)) {
            if (hub_.stopped()) return false;
            static constexpr char kComment[] = ": keep-alive\n\n";
            return sink.write(kComment, sizeof kComment - 1);
          }
          std::string event;
          event.reserve(frame->size() + 8);
          event.append("data: ").append(*frame).append("\n\n");
          return sink.write(event.data(), event.size());  // false: the browser went away
        },
        [this](bool) { --clients_; });
  });

  server_->Get("/scene.json", [this](const Request&, Response& res) {
    const auto frame = hub_.latest();
    res.set_header("Cache-Control", "no-cache");
    res.set_content(frame ? *frame : std::string("{}"), "application/json");
  });
  server_->Get("/map.json", [this](const Request&, Response& res) {
    res.set_content(map_json_, "application/json");
  });
  server_->Get("/drawn.json", [this](const Request&, Response& res) {
    res.set_header("Cache-Control", "no-cache");
    res.set_content(drawn().dump(), "application/json");
  });
  server_->Get("/stats.json", [this](const Request&, Response& res) {
    const json j = {{"clients", clients_.load()},
                    {"max_clients", options_.max_clients},
                    {"refused", refused_.load()},
                    {"frames", frames_.load()},
                    {"latency", latency_.stats()}};
    res.set_header("Cache-Control", "no-cache");
    res.set_content(j.dump(), "application/json");
  });

  server_->Post("/stats/reset", [this](const Request&, Response& res) {
    latency_.clear();
    res.status = 204;
  });

  server_->Post("/control", [this](const Request& req, Response& res) {
    if (!options_.replay) {
      res.status = 409;
      res.set_content("live view: no replay controls\n", "text/plain");
      return;
    }
    const json body = json::parse(req.body, nullptr, false);
    static const std::set<std::string> kCommands{"play", "pause", "speed", "seek"};
    if (!body.is_object() || !body.contains("command") || !body["command"].is_string() ||
        !kCommands.count(body["command"].get<std::string>())) {
      res.status = 400;
      res.set_content("expected {\"command\": play|pause|speed|seek, \"value\": number}\n",
                      "text/plain");
      return;
    }
    Control c;
    c.command = body["command"].get<std::string>();
    if (body.contains("value") && body["value"].is_number()) c.value = body["value"].get<double>();
    if (!std::isfinite(c.value)) {
      res.status = 400;
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (controls_.size() < 256) controls_.push_back(std::move(c));
    }
    res.status = 204;
  });

  server_->Post("/ack", [this](const Request& req, Response& res) {
    const auto now = LatencyLog::Clock::now();
    const json body = json::parse(req.body, nullptr, false);
    if (!body.is_object()) {
      res.status = 400;
      return;
    }
    if (body.contains("utime") && body["utime"].is_number_integer())
      latency_.drawn(body["utime"].get<std::int64_t>(), now);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++acks_;
      if (body.contains("drawn") && body["drawn"].is_object()) drawn_last_ = body["drawn"];
      if (body.contains("keys") && body["keys"].is_array()) {
        for (const auto& k : body["keys"]) {
          if (!k.is_string() || drawn_ever_.size() >= kMaxDrawnKeys) continue;
          const auto& s = k.get_ref<const std::string&>();
          if (s.size() <= 128) drawn_ever_.insert(s);
        }
      }
    }
    res.status = 204;
  });
}

}  // namespace coopnav::viewer
