#include "http_server.hpp"

#include <httplib.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <list>
#include <stdexcept>
#include <string_view>
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
/// The gate in front of httplib (RequestGate): a request's line and headers must arrive whole
/// within kRequestDeadline, in at most kMaxHeaderBytes and kMaxHeaderLines; at most
/// kMaxPendingRequests connections wait for theirs, a newer one evicting the one that has waited
/// longest (an idle or slowloris connection: a browser sends a request in one write).
constexpr std::chrono::milliseconds kRequestDeadline{1000};
constexpr std::size_t kMaxHeaderBytes = 16 * 1024;
constexpr std::size_t kMaxHeaderLines = 100;
constexpr int kMaxPendingRequests = 32;

// httplib 0.11's Server hands each accepted connection to its private virtual
// process_and_close_socket, which reads the request with a per-read timeout only and no bound
// on the header count: a request trickled a byte at a time holds a thread for ever, a million
// headers are all kept. The gate overrides that function to check the request first (peeking,
// so the bytes stay for httplib) and then hands the connection to a second Server holding the
// routes, whose base implementation it calls through a pointer to the private member, taken
// by the explicit instantiation below (the one standard way to name a private member).
using ProcessSocket = bool (httplib::Server::*)(socket_t);
ProcessSocket processSocketMember();
template <ProcessSocket Member>
struct ProcessSocketAccess {
  friend ProcessSocket processSocketMember() { return Member; }
};
template struct ProcessSocketAccess<&httplib::Server::process_and_close_socket>;

/// The Server with the routes. It never listens: the gate calls it per connection, for one
/// request (keep-alive off: a second request on the connection would not pass the gate).
class RoutesServer : public httplib::Server {
 public:
  RoutesServer() {
    // httplib serves a connection only while its listening socket is valid; this one has none.
    svr_sock_ = 0;
    set_keep_alive_max_count(1);
  }
  ~RoutesServer() override { svr_sock_ = INVALID_SOCKET; }
  RoutesServer(const RoutesServer&) = delete;
  RoutesServer& operator=(const RoutesServer&) = delete;
  bool serve(socket_t sock) { return (this->*processSocketMember())(sock); }
};

/// Why a connection did not pass the gate (the status it gets, 0 = closed without one).
enum class GateVerdict { kPass, kClosed, kTimeout, kTooLarge };

/// The listening Server: every connection passes the gate before the routes see it.
class GatedServer : public httplib::Server {
 public:
  GatedServer(RoutesServer& routes, std::atomic<bool>& stopping)
      : routes_(routes), stopping_(stopping) {}

  std::int64_t turnedAway() const { return turned_away_.load(); }

 private:
  bool process_and_close_socket(socket_t sock) override {
    const GateVerdict v = admit(sock);
    if (v == GateVerdict::kPass) return routes_.serve(sock);
    ++turned_away_;
    const char* answer = v == GateVerdict::kTimeout ? "HTTP/1.1 408 Request Timeout\r\n"
                         : v == GateVerdict::kTooLarge
                             ? "HTTP/1.1 431 Request Header Fields Too Large\r\n"
                             : nullptr;
    if (answer) {
      const std::string text =
          std::string(answer) + "Connection: close\r\nContent-Length: 0\r\n\r\n";
      [[maybe_unused]] const auto sent =
          ::send(sock, text.data(), text.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return false;
  }

  /// Waits (peeking) until the request's line, headers and body are all in, within the bounds.
  GateVerdict admit(socket_t sock) {
    const auto start = std::chrono::steady_clock::now();
    std::list<socket_t>::iterator mine;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      // The longest waiting goes (its poll wakes on the shutdown and it is turned away).
      while (static_cast<int>(pending_.size()) >= kMaxPendingRequests) {
        ::shutdown(pending_.front(), SHUT_RD);
        pending_.pop_front();
      }
      mine = pending_.insert(pending_.end(), sock);
    }
    const GateVerdict v = wait(sock, start);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = std::find(pending_.begin(), pending_.end(), sock);
      if (it != pending_.end()) pending_.erase(it);
    }
    return v;
  }

  GateVerdict wait(socket_t sock, std::chrono::steady_clock::time_point start) const {
    std::string buf(kMaxHeaderBytes + kMaxBodyBytes, '\0');
    ssize_t last = -1;
    while (!stopping_.load()) {
      const auto left = kRequestDeadline - std::chrono::duration_cast<std::chrono::milliseconds>(
                                               std::chrono::steady_clock::now() - start);
      if (left.count() <= 0) return GateVerdict::kTimeout;
      pollfd p{sock, POLLIN, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(std::min<std::int64_t>(left.count(), 50)));
      if (ready < 0 && errno != EINTR) return GateVerdict::kClosed;
      if (ready <= 0) continue;
      const ssize_t n = ::recv(sock, buf.data(), buf.size(), MSG_PEEK | MSG_DONTWAIT);
      if (n == 0) return GateVerdict::kClosed;
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
        return GateVerdict::kClosed;
      }
      const std::string_view in(buf.data(), static_cast<std::size_t>(n));
      const std::size_t end = in.find("\r\n\r\n");
      if (end == std::string_view::npos) {
        if (in.size() >= kMaxHeaderBytes) return GateVerdict::kTooLarge;
      } else {
        if (end + 4 > kMaxHeaderBytes) return GateVerdict::kTooLarge;
        const std::string_view head = in.substr(0, end + 2);
        if (static_cast<std::size_t>(std::count(head.begin(), head.end(), '\n')) >
            kMaxHeaderLines + 1)
          return GateVerdict::kTooLarge;
        // A body (a POST) must be in too: its length is bounded below kMaxBodyBytes by httplib.
        const std::size_t body = contentLength(head);
        if (body > kMaxBodyBytes) return GateVerdict::kPass;  // httplib answers 413
        if (in.size() >= end + 4 + body) return GateVerdict::kPass;
      }
      // Nothing new yet: the peeked bytes stay readable, so poll would return at once.
      if (n == last) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      last = n;
    }
    return GateVerdict::kClosed;
  }

  static std::size_t contentLength(std::string_view head) {
    static constexpr std::string_view kName = "\ncontent-length:";
    std::string lower(head);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::size_t at = lower.find(kName);
    if (at == std::string::npos) return 0;
    std::size_t i = at + kName.size();
    while (i < lower.size() && lower[i] == ' ') ++i;
    std::size_t n = 0;
    for (; i < lower.size() && std::isdigit(static_cast<unsigned char>(lower[i])) != 0; ++i) {
      n = n * 10 + static_cast<std::size_t>(lower[i] - '0');
      if (n > kMaxBodyBytes) return kMaxBodyBytes + 1;
    }
    return n;
  }

  RoutesServer& routes_;
  std::atomic<bool>& stopping_;
  std::mutex mutex_;
  std::list<socket_t> pending_;
  std::atomic<std::int64_t> turned_away_{0};
};

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
    : options_(options), map_json_(std::move(map_json)) {
  auto routes = std::make_unique<RoutesServer>();
  auto front = std::make_unique<GatedServer>(*routes, stopping_);
  server_ = std::move(routes);
  // Threads: the streams, the spare ones, and the connections waiting at the gate.
  const int threads = options_.max_clients + kSpareThreads + kMaxPendingRequests;
  front->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  // SO_REUSEADDR (a restarted viewer binds at once) but not httplib's default SO_REUSEPORT, with
  // which a second viewer on the same port would bind too and share the connections silently.
  socket_t listening = INVALID_SOCKET;
  front->set_socket_options([&listening](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listening = sock;
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
  front_ = std::move(front);
  if (options_.port == 0) {
    port_ = front_->bind_to_any_port(options_.bind_address);
    if (port_ <= 0) throw std::runtime_error("cannot bind any port on " + options_.bind_address);
  } else {
    if (!front_->bind_to_port(options_.bind_address, options_.port))
      throw std::runtime_error("cannot bind " + options_.bind_address + ":" +
                               std::to_string(options_.port) + " (in use, or not an address here)");
    port_ = options_.port;
  }
  // httplib listens with a backlog of 5: a burst of connections (300 idle ones) overflows it and
  // every later connect waits for the kernel's SYN retries (1 s, 3 s, ...). A second listen()
  // sets the backlog; the gate then sorts them.
  if (listening != INVALID_SOCKET) ::listen(listening, SOMAXCONN);
  thread_ = std::thread([this] {
    front_->listen_after_bind();
    listen_done_ = true;
  });
  // stop() is a no-op on a server not yet in its accept loop, which would then never end: the
  // viewer is constructed only once the loop runs (or has given up).
  while (!front_->is_running() && !listen_done_)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

ViewerHttp::~ViewerHttp() {
  // Streams waiting for a frame return at once; one blocked writing to a page that does not read
  // returns within stalled_client_timeout, a connection at the gate within 50 ms.
  stopping_ = true;
  hub_.stop();
  front_->stop();
  if (thread_.joinable()) thread_.join();
  front_.reset();  // joins the connection threads before the routes they use go
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
