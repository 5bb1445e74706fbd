#include "viewer_node.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <type_traits>
#include <utility>

#include "coopnav/channels.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"

namespace coopnav {
namespace {

using nlohmann::json;

/// The map as the page draws it: the grid row by row from the bottom (j = 0, smallest y),
/// run-length encoded as [state, count, state, count, ...] with state 0 free, 1 occupied,
/// -1 unknown.
json mapJson(const OccupancyGrid2& grid, const std::string& source) {
  json rle = json::array();
  const auto& cells = grid.cells();
  for (std::size_t i = 0; i < cells.size();) {
    std::size_t j = i;
    while (j < cells.size() && cells[j] == cells[i]) ++j;
    rle.push_back(static_cast<int>(cells[i]));
    rle.push_back(j - i);
    i = j;
  }
  return {{"source", source},
          {"width", grid.width()},
          {"height", grid.height()},
          {"resolution", grid.resolution_m()},
          {"origin", {grid.origin_m().x(), grid.origin_m().y()}},
          {"rle", std::move(rle)}};
}

/// The scenario a recorded run used (run_one of tools/exp writes scenario.path beside the log).
std::string scenarioBesideLog(const std::string& log_file) {
  namespace fs = std::filesystem;
  const fs::path p = fs::path(log_file).parent_path() / "scenario.path";
  std::ifstream in(p);
  std::string line;
  if (!in || !std::getline(in, line)) return "";
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  std::error_code ec;
  return fs::is_regular_file(line, ec) ? line : "";
}

}  // namespace

void ViewerConfig::resolvePaths(const std::string& base_dir) {
  map_file = resolvePath(base_dir, map_file);
}

ViewerNode::ViewerNode(const Config& config, Runtime& runtime)
    : config_(config), runtime_(runtime), scene_([&] {
        viewer::SceneOptions o;
        o.max_utterances = config.max_utterances;
        o.cm_history_points = config.cm_history_points;
        o.ca_sample_period_s = config.ca_sample_period_s;
        o.bubble_hold_s = config.bubble_hold_s;
        o.status_stale_s = config.status_stale_s;
        o.limits = config.limits;
        return o;
      }()) {
  // The map, for the page and for the d_OH / d_OR segments.
  std::string map_file = config_.map_file;
  if (map_file.empty() && !config_.log_file.empty()) map_file = scenarioBesideLog(config_.log_file);
  json map = nullptr;
  if (!map_file.empty()) {
    MapLoadOptions opts;
    opts.build_tree = false;
    opts.max_cells = config_.max_map_cells;
    LoadedMap loaded;
    try {
      loaded = loadMap(map_file, opts);
    } catch (const MapLoadError& e) {
      throw StartupError(e.what());
    }
    map = mapJson(loaded.grid, map_file);
    scene_.setDistanceMap(std::make_shared<GridDistanceField>(
        std::move(loaded.grid),
        config_.unknown_is_obstacle ? UnknownPolicy::kObstacle : UnknownPolicy::kFree));
  }

  if (!config_.log_file.empty()) {
    try {
      replay_ = std::make_unique<viewer::Replay>(config_.log_file, scene_);
    } catch (const std::runtime_error& e) {
      throw StartupError(e.what());
    }
    replay_->setSpeed(config_.replay_speed);
    if (config_.replay_autoplay) replay_->play();
  }

  viewer::HttpOptions http;
  http.bind_address = config_.bind_address;
  http.port = config_.http_port;
  http.max_clients = config_.max_clients;
  http.stalled_client_timeout = std::chrono::milliseconds(
      static_cast<std::int64_t>(std::llround(config_.stalled_client_timeout_s * 1000.0)));
  http.replay = replay_ != nullptr;
  http_ = std::make_unique<viewer::ViewerHttp>(http, map.dump());

  if (!replay_) {
    subscribe<agent_states_t>(channels::kAgentStates);
    subscribe<bands_t>(channels::kBands);
    subscribe<reference_paths_t>(channels::kReferencePaths);
    subscribe<situation_t>(channels::kSituation);
    subscribe<path_assessment_t>(channels::kPathAssessment);
    subscribe<path_assessor_control_t>(channels::kPathAssessorControl);
    subscribe<utterance_t>(channels::kUtterance);
    subscribe<robot_action_t>(channels::kRobotAction);
    subscribe<velocity_command_t>(channels::kRobotCmd);
    subscribe<goals_t>(channels::kGoals);
    subscribe<daemon_status_t>(channels::kStatus);
    subscribe<sim_status_t>(channels::kSimStatus);
  }
  last_tick_ = last_push_ = std::chrono::steady_clock::now();
  const auto period =
      std::chrono::milliseconds(std::max(1, static_cast<int>(1000.0 / config_.push_rate_hz)));
  runtime_.addTimer(period, [this] { onTick(); });
  const std::string host =
      config_.bind_address == "0.0.0.0" ? std::string("127.0.0.1") : config_.bind_address;
  log().info("viewer: open http://{}:{}/ ({}{})", host, http_->port(),
             replay_ ? "replay of " + config_.log_file : std::string("live on the bus"),
             map_file.empty() ? ", no map" : ", map " + map_file);
  runtime_.setRunning(replay_ ? "replay" : "live");
  pushFrame();
}

ViewerNode::~ViewerNode() = default;

template <class Msg>
void ViewerNode::subscribe(const char* channel) {
  const std::string name = channel;
  // Not journaled: the scene is for looking at; a restarted viewer draws what comes next.
  runtime_.subscribe<Msg>(
      channel,
      [this, name](const Msg& m, std::int64_t recv_utime) {
        try {
          if constexpr (std::is_same_v<Msg, daemon_status_t>)
            scene_.apply(m, recv_utime);  // liveness on the viewer's receive clock
          else
            scene_.apply(m);
        } catch (const RejectedMessage&) {
          scene_.countRejected(name);
          throw;  // counted and logged by the runtime too
        }
        dirty_ = true;
        noteSceneTime();
      },
      0, false);
}

const viewer::SceneModel& ViewerNode::scene() const { return replay_ ? replay_->scene() : scene_; }

void ViewerNode::noteSceneTime() {
  const auto u = scene().utime();
  if (u && u != noted_utime_) {
    noted_utime_ = u;
    http_->latency().received(*u, std::chrono::steady_clock::now());
  }
}

json ViewerNode::frameJson() const {
  json j = scene().toJson();
  const RuntimeCounters& c = runtime_.counters();
  json& v = j["viewer"];
  v["received"] = c.received;
  v["rejected"] = c.rejected;
  v["dropped"] = c.dropped;
  v["clients"] = http_->clients();
  v["refused"] = http_->refused();
  v["mode"] = replay_ ? "replay" : "live";
  j["replay"] = replay_ ? replay_->timelineJson() : json(nullptr);
  return j;
}

void ViewerNode::pushFrame() {
  // The scene holds valid UTF-8 only (SceneModel::validUtf8); replacing any that is not (the
  // replay's file name, a counter's text) keeps a frame from ever failing to serialise.
  http_->publishFrame(frameJson().dump(-1, ' ', false, json::error_handler_t::replace));
  last_push_ = std::chrono::steady_clock::now();
  dirty_ = false;
}

void ViewerNode::applyControls() {
  for (const viewer::Control& c : http_->takeControls()) {
    if (!replay_) continue;
    if (c.command == "play") {
      replay_->play();
    } else if (c.command == "pause") {
      replay_->pause();
    } else if (c.command == "speed") {
      replay_->setSpeed(std::clamp(c.value, 0.05, 100.0));
    } else if (c.command == "seek") {
      replay_->seek(c.value);
      // A seek is a new start for the latency log: every utime is "received" again.
      noted_utime_.reset();
    }
    dirty_ = true;
  }
}

void ViewerNode::onTick() {
  const auto now = std::chrono::steady_clock::now();
  const double dt = std::chrono::duration<double>(now - last_tick_).count();
  last_tick_ = now;
  applyControls();
  if (replay_ && replay_->playing()) {
    // Playback pacing is the one use of the wall clock: it is how fast the page moves.
    replay_->advance(dt);
    dirty_ = true;
  }
  if (replay_) noteSceneTime();
  // Something new, or a second without (the page's clients count and status ages move too).
  if (dirty_ || now - last_push_ >= std::chrono::seconds(1)) pushFrame();
}

}  // namespace coopnav
