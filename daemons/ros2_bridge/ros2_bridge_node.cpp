#include "ros2_bridge_node.hpp"

#include <dds/dds.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include "coopnav/channels.hpp"
#include "runtime/daemon_main.hpp"
#include "runtime/log.hpp"
#include "wire/conversions.hpp"

namespace coopnav {

namespace {

/// ROS 2's default QoS (rmw_qos_profile_default): reliable, volatile, keep last 10.
dds_qos_t* defaultQos() {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
  return q;
}

/// ROS 2's sensor-data QoS (rmw_qos_profile_sensor_data): best effort, volatile, keep last 5.
dds_qos_t* sensorQos() {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 5);
  return q;
}

/// A sample arrived (Cyclone DDS's thread): one byte on the wake pipe. Non-blocking: a full
/// pipe already wakes the loop, and nothing else is done on DDS's thread.
void onDataAvailable(dds_entity_t, void* arg) {
  const int fd = *static_cast<const int*>(arg);
  const char c = 'd';
  [[maybe_unused]] const auto n = ::write(fd, &c, 1);
}

}  // namespace

/// The DDS entities, and the wake-up of the runtime's loop: every reader has a listener whose
/// data-available callback writes the self-pipe `wake` that the loop polls (Runtime::addReadable),
/// so a sample is taken as soon as it arrives, on the loop's thread, and nothing polls DDS.
struct Ros2BridgeNode::Dds {
  dds_entity_t participant{0};
  dds_entity_t odom{0}, pose{0}, tracked{0}, people{0}, goal{0}, scan{0};
  dds_entity_t cmd_vel{0}, markers{0}, utterance{0};
  int wake[2]{-1, -1};
  dds_listener_t* listener{nullptr};

  Dds() {
    if (::pipe(wake) != 0) throw StartupError(std::string("wake pipe: ") + std::strerror(errno));
    for (const int fd : wake) {
      ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
      ::fcntl(fd, F_SETFD, FD_CLOEXEC);
    }
    listener = dds_create_listener(&wake[1]);
    dds_lset_data_available(listener, onDataAvailable);
  }
  ~Dds() {
    // The participant (and its readers, whose listeners write the pipe) goes first.
    if (participant > 0) dds_delete(participant);
    if (listener != nullptr) dds_delete_listener(listener);
    for (const int fd : wake)
      if (fd >= 0) ::close(fd);
  }
  Dds(const Dds&) = delete;
  Dds& operator=(const Dds&) = delete;

  /// Empties the wake pipe (before the takes: a sample after them writes it again).
  void drainWake() const {
    char buf[256];
    while (::read(wake[0], buf, sizeof buf) > 0) {
    }
  }

  dds_entity_t endpoint(const std::string& name, const dds_topic_descriptor_t* desc, bool reader,
                        bool sensor) {
    if (name.empty()) return 0;
    const dds_entity_t topic = dds_create_topic(participant, desc, name.c_str(), nullptr, nullptr);
    if (topic < 0) throw StartupError("DDS topic " + name + ": " + dds_strretcode(topic));
    dds_qos_t* q = sensor ? sensorQos() : defaultQos();
    const dds_entity_t e = reader ? dds_create_reader(participant, topic, q, listener)
                                  : dds_create_writer(participant, topic, q, nullptr);
    dds_delete_qos(q);
    if (e < 0)
      throw StartupError(std::string("DDS ") + (reader ? "reader" : "writer") + " " + name + ": " +
                         dds_strretcode(e));
    return e;
  }
};

namespace {

/// Takes every pending sample of `reader` (loaned) and hands the valid ones to `fn`; a
/// RejectedMessage is counted and logged, never stops the loop.
template <class Msg, class Fn>
void takeAll(dds_entity_t reader, Runtime& runtime, const char* what, Fn&& fn) {
  if (reader <= 0) return;
  constexpr std::size_t kBatch = 16;
  for (;;) {
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      try {
        fn(*static_cast<const Msg*>(samples[i]));
      } catch (const RejectedMessage& e) {
        runtime.countRejected();
        log().warn("ros2_bridge: {} rejected: {}", what, e.what());
      } catch (const DroppedMessage& e) {
        runtime.countDropped();
        log().debug("ros2_bridge: {} dropped: {}", what, e.what());
      }
    }
    dds_return_loan(reader, samples, n);
    if (n < static_cast<dds_return_t>(kBatch)) return;
  }
}

int domainOf(int configured) {
  if (configured >= 0) return configured;
  const char* env = std::getenv("ROS_DOMAIN_ID");
  if (env == nullptr || *env == '\0') return 0;
  char* end = nullptr;
  const long d = std::strtol(env, &end, 10);
  if (*end != '\0' || d < 0 || d > 232)
    throw StartupError(std::string("ROS_DOMAIN_ID '") + env + "' is not 0..232");
  return static_cast<int>(d);
}

}  // namespace

Ros2BridgeNode::Ros2BridgeNode(const Config& config, Runtime& runtime)
    : config_(config), runtime_(runtime), start_(std::chrono::steady_clock::now()) {
  frames_.map_frame = config.map_frame;
  frames_.odom_frame = config.odom_frame;
  frames_.odom_to_map = {config.odom_to_map_x_m, config.odom_to_map_y_m,
                         config.odom_to_map_yaw_rad};
  human_options_.default_radius_m = config.human_radius_m;
  human_options_.body_segment_type = static_cast<std::int8_t>(config.body_segment_type);

  auto dds = std::make_unique<Dds>();
  const int domain = domainOf(config.domain_id);
  dds->participant = dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr);
  if (dds->participant < 0)
    throw StartupError(std::string("DDS participant on domain ") + std::to_string(domain) + ": " +
                       dds_strretcode(dds->participant));
  const auto name = [&](const std::string& t) {
    return ros2::ddsTopicName(config.ros_namespace, t);
  };
  const auto& t = config.topics;
  dds->odom = dds->endpoint(name(t.odom), &nav_msgs_msg_dds__Odometry__desc, true, false);
  dds->pose = dds->endpoint(name(t.pose), &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                            true, false);
  if (config.humans_from == "tracked_agents")
    dds->tracked = dds->endpoint(name(t.tracked_agents), &cohan_msgs_msg_dds__TrackedAgents__desc,
                                 true, false);
  else
    dds->people = dds->endpoint(name(t.people), &people_msgs_msg_dds__People__desc, true, false);
  dds->goal = dds->endpoint(name(t.goal), &geometry_msgs_msg_dds__PoseStamped__desc, true, false);
  dds->scan = dds->endpoint(name(t.scan), &sensor_msgs_msg_dds__LaserScan__desc, true, true);
  dds->cmd_vel = dds->endpoint(name(t.cmd_vel), &geometry_msgs_msg_dds__Twist__desc, false, false);
  dds->markers =
      dds->endpoint(name(t.markers), &visualization_msgs_msg_dds__MarkerArray__desc, false, false);
  dds->utterance = dds->endpoint(name(t.utterance), &std_msgs_msg_dds__String__desc, false, false);
  dds_ = dds.release();

  runtime.subscribe<velocity_command_t>(
      channels::kRobotCmd, [this](const velocity_command_t& m, std::int64_t) { onCommand(m); }, 4,
      false);
  runtime.subscribe<bands_t>(
      channels::kBands, [this](const bands_t& m, std::int64_t) { onBands(m); }, 2, false);
  runtime.subscribe<situation_t>(
      channels::kSituation, [this](const situation_t& m, std::int64_t) { onSituation(m); }, 0,
      false);
  runtime.subscribe<utterance_t>(
      channels::kUtterance, [this](const utterance_t& m, std::int64_t) { onUtterance(m); }, 0,
      false);
  runtime.addReadable(dds_->wake[0], [this] { pollDds(); });
  pollDds();  // what arrived before the loop polls the pipe
  runtime.addTimer(
      std::chrono::milliseconds(static_cast<int>(std::lround(1000.0 / config.watchdog_hz))),
      [this] { watchdogTick(); });
  running_detail_ = "DDS domain " + std::to_string(domain);
  runtime.setRunning(running_detail_);
  log().info("ros2_bridge: DDS domain {}, namespace '{}', humans from {}", domain,
             config.ros_namespace, config.humans_from);
}

Ros2BridgeNode::~Ros2BridgeNode() { delete dds_; }

double Ros2BridgeNode::monotonicNowS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Ros2BridgeNode::pollDds() {
  dds_->drainWake();
  takeAll<ros2::Odometry>(dds_->odom, runtime_, "odometry",
                          [this](const ros2::Odometry& m) { onOdometry(m); });
  takeAll<ros2::PoseWithCovarianceStamped>(
      dds_->pose, runtime_, "pose",
      [this](const ros2::PoseWithCovarianceStamped& m) { onPose(m); });
  takeAll<ros2::TrackedAgents>(dds_->tracked, runtime_, "tracked agents",
                               [this](const ros2::TrackedAgents& m) { onTrackedAgents(m); });
  takeAll<ros2::People>(dds_->people, runtime_, "people",
                        [this](const ros2::People& m) { onPeople(m); });
  takeAll<ros2::PoseStamped>(dds_->goal, runtime_, "goal",
                             [this](const ros2::PoseStamped& m) { onGoal(m); });
  takeAll<ros2::LaserScan>(dds_->scan, runtime_, "scan",
                           [this](const ros2::LaserScan& m) { onScan(m); });
}

void Ros2BridgeNode::onOdometry(const ros2::Odometry& msg) {
  const std::int64_t utime = ros2::stampToUtime(msg.header.stamp);
  // With a pose topic the odometry pose is in the odom frame and the map pose goes through the
  // AMCL-derived transform; without, through the configured one (frameToMap).
  const agent_state_t robot = ros2::robotFromOdometry(msg, frames_, config_.robot_radius_m);
  robot_in_odom_ = ros2::pose2Of(msg.pose.pose);
  robot_in_map_ = ros2::Pose2{robot.x_m, robot.y_m, robot.theta_rad};
  agent_states_t out{};
  out.utime = utime;
  out.step = -1;
  out.robot = robot;
  if (humans_utime_ >= 0 &&
      std::abs(utimeDiffSeconds(utime, humans_utime_)) <= config_.humans_max_age_s)
    out.humans = humans_;
  out.num_humans = static_cast<std::int16_t>(out.humans.size());
  runtime_.noteLogicTime(utime);
  runtime_.publish(channels::kAgentStates, out);
}

void Ros2BridgeNode::onPose(const ros2::PoseWithCovarianceStamped& msg) {
  const std::string frame = msg.header.frame_id == nullptr ? "" : msg.header.frame_id;
  if (!frame.empty() && frame != frames_.map_frame)
    throw RejectedMessage("pose in frame '" + frame + "', not the map frame");
  if (!robot_in_odom_) throw DroppedMessage("pose before any odometry");
  // AMCL's pose and the latest odometry pose stand for the same instant (AMCL stamps its pose
  // with the scan it used; the odometry runs at tens of Hz, so the two differ by one period).
  frames_.odom_to_map = ros2::odomToMapFromPoses(ros2::pose2Of(msg.pose.pose), *robot_in_odom_);
}

void Ros2BridgeNode::onTrackedAgents(const ros2::TrackedAgents& msg) {
  const std::int64_t utime = ros2::stampToUtime(msg.header.stamp);
  humans_ = ros2::humansFromTrackedAgents(msg, frames_, human_options_);
  humans_utime_ = utime;
}

void Ros2BridgeNode::onPeople(const ros2::People& msg) {
  const std::int64_t utime = ros2::stampToUtime(msg.header.stamp);
  humans_ = ros2::humansFromPeople(msg, frames_, human_options_);
  humans_utime_ = utime;
}

void Ros2BridgeNode::onGoal(const ros2::PoseStamped& msg) {
  runtime_.publish(channels::kGoals, ros2::goalsFromPoseStamped(msg, frames_, 0));
}

void Ros2BridgeNode::onScan(const ros2::LaserScan& msg) {
  if (!robot_in_map_) throw DroppedMessage("scan before any odometry (no sensor pose)");
  const ros2::Pose2 laser{config_.laser_x_m, config_.laser_y_m, config_.laser_yaw_rad};
  runtime_.publish(channels::kScan, ros2::scanFromLaserScan(msg, *robot_in_map_, laser, -1));
}

void Ros2BridgeNode::writeTwist(const ros2::Twist& t) {
  if (dds_->cmd_vel > 0) dds_write(dds_->cmd_vel, &t);
}

void Ros2BridgeNode::onCommand(const velocity_command_t& msg) {
  const ros2::Twist t = ros2::twistOfCommand(msg);  // throws on NaN: nothing is sent
  last_command_s_ = monotonicNowS();
  writeTwist(t);
  if (holding_) {
    holding_ = false;
    log().info("ros2_bridge: velocity commands again");
    runtime_.setRunning(running_detail_);
  }
}

void Ros2BridgeNode::watchdogTick() {
  // Only once a command was heard: before, the base belongs to whoever else drives it (teleop).
  if (!last_command_s_) return;
  if (!ros2::commandStale(last_command_s_, monotonicNowS(), config_.cmd_timeout_s)) return;
  writeTwist(ros2::Twist{});
  ++watchdog_zeros_;
  if (!holding_) {
    holding_ = true;
    log().warn("ros2_bridge: no velocity command for {} s: zero on /cmd_vel",
               config_.cmd_timeout_s);
    runtime_.setDegraded("no velocity command: the watchdog holds the base");
  }
}

void Ros2BridgeNode::onBands(const bands_t& msg) {
  bands_ = msg;
  // A situation of a human no longer planned for is gone.
  for (auto it = situations_.begin(); it != situations_.end();) {
    bool planned = false;
    for (const auto& h : msg.humans) planned = planned || h.agent_id == it->first;
    it = planned ? std::next(it) : situations_.erase(it);
  }
  publishMarkers();
}

void Ros2BridgeNode::onSituation(const situation_t& msg) { situations_[msg.human_id] = msg; }

void Ros2BridgeNode::onUtterance(const utterance_t& msg) {
  if (msg.delivery != utterance_t::DELIVERY_SAID) return;
  utterance_ = msg;
  if (dds_->utterance > 0) {
    std_msgs_msg_dds__String_ s{};
    s.data = const_cast<char*>(msg.text.c_str());
    dds_write(dds_->utterance, &s);
  }
}

void Ros2BridgeNode::publishMarkers() {
  if (dds_->markers <= 0 || !bands_) return;
  std::vector<situation_t> situations;
  situations.reserve(situations_.size());
  for (const auto& [id, s] : situations_) situations.push_back(s);
  const utterance_t* say = nullptr;
  if (utterance_ &&
      utimeDiffSeconds(bands_->utime, utterance_->utime) <= config_.utterance_display_s)
    say = &*utterance_;
  const std::vector<ros2::MarkerSpec> specs = ros2::markersOf(*bands_, situations, say);
  // The DDS structs point into `specs` and `points` (alive until dds_write returns).
  std::vector<visualization_msgs_msg_dds__Marker_> markers(specs.size());
  std::vector<std::vector<geometry_msgs_msg_dds__Point_>> points(specs.size());
  static char kEmpty[] = "";
  const ros2::Time stamp = ros2::utimeToStamp(bands_->utime);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const auto& s = specs[i];
    auto& m = markers[i];
    m = visualization_msgs_msg_dds__Marker_{};
    m.header.stamp = stamp;
    m.header.frame_id = const_cast<char*>(config_.map_frame.c_str());
    m.ns = const_cast<char*>(s.ns.c_str());
    m.id = s.id;
    m.type = s.type;
    m.action = s.action;
    m.pose.position = {s.pose.x_m, s.pose.y_m, s.z_m};
    m.pose.orientation = ros2::quaternionOfYaw(s.pose.yaw_rad);
    m.scale = {s.scale_x, s.scale_y, s.scale_z};
    m.color = {s.r, s.g, s.b, s.a};
    for (const auto& p : s.points) points[i].push_back({p.x_m, p.y_m, s.z_m});
    m.points._length = m.points._maximum = static_cast<std::uint32_t>(points[i].size());
    m.points._buffer = points[i].empty() ? nullptr : points[i].data();
    m.texture_resource = kEmpty;
    m.texture.header.frame_id = kEmpty;
    m.texture.format = kEmpty;
    m.text = const_cast<char*>(s.text.c_str());
    m.mesh_resource = kEmpty;
    m.mesh_file.filename = kEmpty;
  }
  visualization_msgs_msg_dds__MarkerArray_ array{};
  array.markers._length = array.markers._maximum = static_cast<std::uint32_t>(markers.size());
  array.markers._buffer = markers.data();
  dds_write(dds_->markers, &array);
}

}  // namespace coopnav
