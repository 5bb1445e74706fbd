#pragma once
/// @file The browser viewer: subscribes to the coopnav channels (or replays a recorded log),
/// keeps the scene (scene_model.hpp) on the LCM thread, and every 1 / push_rate_hz hands its
/// JSON to the HTTP side (http_server.hpp), which serves one page drawing it. The LCM thread never
/// waits for a browser; the HTTP threads never touch the scene.

#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "config/config.hpp"
#include "http_server.hpp"
#include "maps/map_loader.hpp"
#include "replay.hpp"
#include "runtime/limits.hpp"
#include "runtime/runtime.hpp"
#include "scene_model.hpp"

namespace coopnav {

struct ViewerConfig {
  /// TCP port of the page; 0 = any free port (tests; the log line names it).
  int http_port{8088};
  /// Address the page is served on: 127.0.0.1 (this machine only) or 0.0.0.0 (every interface:
  /// a phone on the robot's network). The page has no authentication.
  std::string bind_address{"127.0.0.1"};
  /// Most pages streaming at once; one more is answered 503.
  int max_clients{8};
  /// [Hz] frames sent to each page at most this often (only when something changed).
  double push_rate_hz{10.0};
  /// [s] a page whose stream takes no data for this long is dropped (its browser connects again);
  /// the viewer's exit waits this long at most for such a page.
  double stalled_client_timeout_s{1.0};
  /// Map drawn under the scene: the daemons' map file (ROS YAML + PGM, .bt, walls YAML or a
  /// scenario). "" = the scenario of the replayed run (scenario.path beside the log, which
  /// scripts/run.sh writes), else no map.
  std::string map_file{""};
  /// Unknown map cells are drawn and measured as obstacles (as the distance server does).
  bool unknown_is_obstacle{true};
  /// Most cells of the map (exit 3 beyond).
  std::int64_t max_map_cells{kMaxMapCells};
  /// LCM log to replay instead of listening to the bus (`--log FILE` sets it).
  std::string log_file{""};
  /// Replay: playback speed at start (simulated seconds per wall second).
  double replay_speed{1.0};
  /// Replay: start playing at once (false: paused at the start).
  bool replay_autoplay{true};
  /// [s] spacing of the CA samples in a path assessment (the path assessor's sample_period_s).
  double ca_sample_period_s{0.1};
  /// [s] a speech bubble stays this long after the robot finished saying it.
  double bubble_hold_s{3.0};
  /// [s] a daemon whose status is this much older than the newest status is shown silent.
  double status_stale_s{3.0};
  /// Utterances and robot actions kept for the bubbles and the plots' round markers.
  int max_utterances{64};
  /// CM points kept per human for its plot.
  int cm_history_points{600};
  /// Caps on what a bus peer can make this daemon hold or do (runtime/limits.hpp).
  InputLimits limits;

  template <class V>
  void visit(V& v) {
    v("http_port", http_port, Range{0, 65535});
    v("bind_address", bind_address);
    v("max_clients", max_clients, Range{1, 64});
    v("push_rate_hz", push_rate_hz, Range{0.5, 60.0});
    v("stalled_client_timeout_s", stalled_client_timeout_s, Range{0.1, 60.0});
    v("map_file", map_file);
    v("unknown_is_obstacle", unknown_is_obstacle);
    v("max_map_cells", max_map_cells, Range{1.0, static_cast<double>(kMaxMapCellsCeiling)});
    v("log_file", log_file);
    v("replay_speed", replay_speed, Range{0.05, 100.0});
    v("replay_autoplay", replay_autoplay);
    v("ca_sample_period_s", ca_sample_period_s, Range{0.001, 10.0});
    v("bubble_hold_s", bubble_hold_s, Range{0.0, 60.0});
    v("status_stale_s", status_stale_s, Range{0.1, 3600.0});
    v("max_utterances", max_utterances, Range{1, 10000});
    v("cm_history_points", cm_history_points, Range{10, 100000});
    v("limits", limits);
    v.require(!bind_address.empty(), "bind_address", "must name an address, e.g. 127.0.0.1");
  }
  /// map_file relative to the config file (log_file: main() makes --log absolute).
  void resolvePaths(const std::string& base_dir);
};

class ViewerNode {
 public:
  using Config = ViewerConfig;
  /// Loads the map (StartupError: exit 3), reads the log in replay mode (StartupError), binds
  /// the HTTP port (std::runtime_error: exit 1) and subscribes (live mode).
  ViewerNode(const Config& config, Runtime& runtime);
  ~ViewerNode();

  /// The port the page is served on.
  int httpPort() const { return http_->port(); }
  /// The current scene (the LCM thread's; tests).
  const viewer::SceneModel& scene() const;
  /// The frame the page gets now: the scene's JSON plus the viewer's own counters and, in
  /// replay, the timeline.
  nlohmann::json frameJson() const;
  /// Builds and sends a frame now (the timer does it every 1 / push_rate_hz; tests).
  void pushFrame();
  viewer::ViewerHttp& http() { return *http_; }
  bool replaying() const { return replay_ != nullptr; }
  viewer::Replay* replay() { return replay_.get(); }

 private:
  template <class Msg>
  void subscribe(const char* channel);
  void onTick();
  void applyControls();
  /// Notes a new scene utime for the latency log (bus message -> drawn frame).
  void noteSceneTime();

  Config config_;
  Runtime& runtime_;
  viewer::SceneModel scene_;
  std::unique_ptr<viewer::Replay> replay_;
  std::unique_ptr<viewer::ViewerHttp> http_;
  bool dirty_{true};
  std::optional<std::int64_t> noted_utime_;
  std::chrono::steady_clock::time_point last_tick_;
  std::chrono::steady_clock::time_point last_push_;
};

}  // namespace coopnav
