// coopnav_robot_side: the robot's ROS 2 nodes, for test/py/test_ros2_bridge.py and by hand. A
// DDS participant written directly on Cyclone DDS with ROS 2's names, types (the bridge's IDL)
// and QoS, fed by world_sim's world on its own LCM bus:
//   world COOPNAV_AGENT_STATES -> /odom (nav_msgs/Odometry, odom frame, twist in the base frame)
//                                 and /tracked_agents (cohan_msgs/TrackedAgents, map frame), or
//                                 with --people /people (people_msgs/People, map frame)
//   world COOPNAV_GOALS (the robot's) -> /goal_pose (geometry_msgs/PoseStamped)
//   world COOPNAV_SCAN            -> /scan (sensor_msgs/LaserScan, base frame)
//   /cmd_vel (geometry_msgs/Twist) -> world COOPNAV_ROBOT_CMD (the simulated base's command)
//   /coopnav/utterance, /coopnav/markers: printed ("UTTERANCE <text>", "MARKERS <n>").
// --sim-cues-from URL (simulation only): COOPNAV_BANDS and COOPNAV_UTTERANCE of the pipeline's
// bus are passed to the world as they are. world_sim's people predict the robot from its band and
// hear what it says; on a robot they see it and hear its speech stack (/coopnav/utterance), which
// no ROS topic can stand for here.
// Every /cmd_vel is printed "CMD <monotonic s> <vx> <vy> <omega>" so that a script can time the
// watchdog; every /scan written "SCAN <utime> <rays> <finite rays> <sum of finite ranges>".
// --echo-pipeline (with --sim-cues-from): what the bridge made of them on the pipeline's bus,
// "PIPE_SCAN ..." (as SCAN, of COOPNAV_SCAN) and "PIPE_HUMANS <utime> <ids>" (of
// COOPNAV_AGENT_STATES), for a script to compare. Stops on SIGINT/SIGTERM.
#include <dds/dds.h>
#include <poll.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/laser_scan_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "ros2_conversions.hpp"

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

using namespace coopnav;

void printScan(const char* tag, const laser_scan_t& m);

struct RobotSide {
  dds_entity_t pp{0};
  dds_entity_t odom{0}, agents{0}, goal{0}, scan{0}, cmd{0}, markers{0}, utterance{0};
  lcm::LCM* lcm{nullptr};
  ros2::Transform2 map_to_odom;  // the inverse of the bridge's odom -> map
  std::int64_t last_utime{0};
  std::optional<goal_t> robot_goal;
  int states_seen{0};
  long markers_seen{0};
  bool people{false};  ///< humans on /people (people_msgs) instead of /tracked_agents

  dds_entity_t make(const std::string& name, const dds_topic_descriptor_t* desc, bool reader,
                    bool sensor) {
    const dds_entity_t topic = dds_create_topic(pp, desc, name.c_str(), nullptr, nullptr);
    if (topic < 0) throw std::runtime_error("topic " + name + ": " + dds_strretcode(topic));
    dds_qos_t* q = dds_create_qos();
    if (sensor) {
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 5);
    } else {
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
    }
    dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
    const dds_entity_t e = reader ? dds_create_reader(pp, topic, q, nullptr)
                                  : dds_create_writer(pp, topic, q, nullptr);
    dds_delete_qos(q);
    if (e < 0) throw std::runtime_error("endpoint " + name + ": " + dds_strretcode(e));
    return e;
  }

  void onStates(const agent_states_t& m) {
    last_utime = m.utime;
    char odom_frame[] = "odom";
    char map_frame[] = "map";
    char base[] = "base_link";
    const ros2::Time stamp = ros2::utimeToStamp(m.utime);
    const ros2::Pose2 p = map_to_odom.apply({m.robot.x_m, m.robot.y_m, m.robot.theta_rad});
    ros2::Odometry o{};
    o.header.stamp = stamp;
    o.header.frame_id = odom_frame;
    o.child_frame_id = base;
    o.pose.pose.position = {p.x_m, p.y_m, 0.0};
    o.pose.pose.orientation = ros2::quaternionOfYaw(p.yaw_rad);
    // The twist in the base frame (REP 105): the world velocity rotated by -heading.
    const ros2::Transform2 to_base{0.0, 0.0, -m.robot.theta_rad};
    to_base.rotate(m.robot.vx_m_s, m.robot.vy_m_s, o.twist.twist.linear.x, o.twist.twist.linear.y);
    o.twist.twist.angular.z = m.robot.omega_rad_s;
    dds_write(odom, &o);

    if (people) {
      writePeople(m, stamp);
    } else {
      writeTrackedAgents(m, stamp);
    }

    // The goal again every second of message time: a volatile topic, and rviz2 users click once.
    if (robot_goal && states_seen++ % 10 == 0) {
      ros2::PoseStamped g{};
      g.header.stamp = stamp;
      g.header.frame_id = map_frame;
      g.pose.position = {robot_goal->x_m, robot_goal->y_m, 0.0};
      g.pose.orientation =
          ros2::quaternionOfYaw(std::isfinite(robot_goal->theta_rad) ? robot_goal->theta_rad : 0.0);
      dds_write(goal, &g);
    }
  }

  /// people_msgs/People: name "person_<id>" (the bridge takes the id from its digits), position
  /// and velocity in the map frame; no radius (the bridge's human_radius_m).
  void writePeople(const agent_states_t& m, const ros2::Time& stamp) {
    char map_frame[] = "map";
    std::vector<std::string> names(m.humans.size());
    std::vector<people_msgs_msg_dds__Person_> list(m.humans.size());
    for (std::size_t i = 0; i < m.humans.size(); ++i) {
      const auto& h = m.humans[i];
      names[i] = "person_" + std::to_string(h.id);
      list[i] = {};
      list[i].name = names[i].data();
      list[i].position = {h.x_m, h.y_m, 0.0};
      list[i].velocity = {h.vx_m_s, h.vy_m_s, 0.0};
      list[i].reliability = 1.0;
    }
    ros2::People p{};
    p.header.stamp = stamp;
    p.header.frame_id = map_frame;
    p.people = {static_cast<std::uint32_t>(list.size()), static_cast<std::uint32_t>(list.size()),
                list.empty() ? nullptr : list.data(), false};
    dds_write(agents, &p);
  }

  void writeTrackedAgents(const agent_states_t& m, const ros2::Time& stamp) {
    char map_frame[] = "map";
    char empty[] = "";
    std::vector<cohan_msgs_msg_dds__TrackedSegment_> segs(m.humans.size());
    std::vector<cohan_msgs_msg_dds__TrackedAgent_> list(m.humans.size());
    for (std::size_t i = 0; i < m.humans.size(); ++i) {
      const auto& h = m.humans[i];
      segs[i] = {};
      segs[i].type = 1;  // TORSO
      segs[i].pose.pose.position = {h.x_m, h.y_m, 0.0};
      segs[i].pose.pose.orientation = ros2::quaternionOfYaw(h.theta_rad);
      segs[i].twist.twist.linear = {h.vx_m_s, h.vy_m_s, 0.0};
      segs[i].twist.twist.angular.z = h.omega_rad_s;
      list[i] = {};
      list[i].track_id = static_cast<std::uint64_t>(h.id);
      list[i].state = 1;  // MOVING
      list[i].type = 1;   // HUMAN
      list[i].name = empty;
      list[i].radius = h.radius_m;
      list[i].segments = {1, 1, &segs[i], false};
    }
    ros2::TrackedAgents a{};
    a.header.stamp = stamp;
    a.header.frame_id = map_frame;
    a.agents = {static_cast<std::uint32_t>(list.size()), static_cast<std::uint32_t>(list.size()),
                list.empty() ? nullptr : list.data(), false};
    dds_write(agents, &a);
  }

  void onGoals(const goals_t& m) {
    for (const auto& g : m.goals)
      if (g.kind == agent_state_t::KIND_ROBOT) robot_goal = g;
  }

  void onScan(const laser_scan_t& m) {
    char base[] = "base_link";
    std::vector<float> ranges = m.ranges_m;
    ros2::LaserScan s{};
    s.header.stamp = ros2::utimeToStamp(m.utime);
    s.header.frame_id = base;
    s.angle_min = m.angle_min_rad;
    s.angle_increment = m.angle_increment_rad;
    s.angle_max = m.angle_min_rad + m.angle_increment_rad * static_cast<float>(ranges.size() - 1);
    s.range_min = m.range_min_m;
    s.range_max = m.range_max_m;
    s.ranges = {static_cast<std::uint32_t>(ranges.size()),
                static_cast<std::uint32_t>(ranges.size()), ranges.empty() ? nullptr : ranges.data(),
                false};
    dds_write(scan, &s);
    printScan("SCAN", m);
  }

  template <class Msg, class Fn>
  void take(dds_entity_t reader, Fn&& fn) {
    for (;;) {
      void* samples[8] = {};
      dds_sample_info_t infos[8];
      const dds_return_t n = dds_take(reader, samples, infos, 8, 8);
      if (n <= 0) return;
      for (dds_return_t i = 0; i < n; ++i)
        if (infos[i].valid_data) fn(*static_cast<const Msg*>(samples[i]));
      dds_return_loan(reader, samples, n);
    }
  }

  void pollDds() {
    take<ros2::Twist>(cmd, [&](const ros2::Twist& t) {
      std::printf("CMD %.6f %.4f %.4f %.4f\n", nowS(), t.linear.x, t.linear.y, t.angular.z);
      velocity_command_t c{};
      c.utime = last_utime;
      c.step = -1;
      c.vx_m_s = t.linear.x;
      c.vy_m_s = t.linear.y;
      c.omega_rad_s = t.angular.z;
      c.mode = velocity_command_t::MODE_NAVIGATING;
      lcm->publish(channels::kRobotCmd, &c);
    });
    take<std_msgs_msg_dds__String_>(utterance, [&](const std_msgs_msg_dds__String_& s) {
      std::printf("UTTERANCE %s\n", s.data);
    });
    take<visualization_msgs_msg_dds__MarkerArray_>(
        markers, [&](const visualization_msgs_msg_dds__MarkerArray_& m) {
          ++markers_seen;
          for (std::uint32_t i = 0; i < m.markers._length; ++i)
            if (std::string(m.markers._buffer[i].ns) == "cp_h" && markers_seen % 20 == 1)
              std::printf("MARKER cp_h %d\n", m.markers._buffer[i].id);
        });
    std::fflush(stdout);
  }
};

/// "<tag> <utime> <rays> <finite rays> <sum of the finite ranges>": equal lines, equal scans.
void printScan(const char* tag, const laser_scan_t& m) {
  double sum = 0.0;
  int finite = 0;
  for (const float r : m.ranges_m) {
    if (!std::isfinite(r)) continue;
    sum += r;
    ++finite;
  }
  std::printf("%s %lld %zu %d %.6f\n", tag, static_cast<long long>(m.utime), m.ranges_m.size(),
              finite, sum);
}

void printPipelineHumans(const agent_states_t& m) {
  std::printf("PIPE_HUMANS %lld", static_cast<long long>(m.utime));
  for (const auto& h : m.humans) std::printf(" %d", h.id);
  std::printf("\n");
}

/// A pipeline message passed to the world's bus as it is (--sim-cues-from).
void forwardToWorld(const lcm::ReceiveBuffer* rb, const std::string& channel, lcm::LCM* world) {
  world->publish(channel, rb->data, rb->data_size);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The robot's ROS 2 nodes on Cyclone DDS, simulated from world_sim's LCM world."};
  std::string lcm_url;
  int domain = 0;
  std::vector<double> odom_origin{0.0, 0.0, 0.0};
  std::string cues_url;
  app.add_option("--lcm-url", lcm_url, "world_sim's LCM bus")->required();
  app.add_option("--domain", domain, "DDS domain (ROS_DOMAIN_ID)")->required();
  app.add_option("--odom-origin", odom_origin, "odom frame origin in the map: x y yaw")
      ->expected(3);
  app.add_option("--sim-cues-from", cues_url,
                 "pipeline bus whose bands and utterances the simulated people perceive");
  bool people = false;
  bool echo_pipeline = false;
  app.add_flag("--people", people, "humans on /people (people_msgs/People), not /tracked_agents");
  app.add_flag("--echo-pipeline", echo_pipeline,
               "print the pipeline bus's COOPNAV_SCAN and humans (needs --sim-cues-from)");
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  lcm::LCM lcm(lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr, "robot_side: LCM %s unusable\n", lcm_url.c_str());
    return 1;
  }
  RobotSide r;
  r.lcm = &lcm;
  r.map_to_odom = ros2::Transform2{odom_origin[0], odom_origin[1], odom_origin[2]}.inverse();
  r.pp = dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr);
  if (r.pp < 0) {
    std::fprintf(stderr, "robot_side: DDS participant: %s\n", dds_strretcode(r.pp));
    return 1;
  }
  try {
    r.odom = r.make("rt/odom", &nav_msgs_msg_dds__Odometry__desc, false, false);
    r.people = people;
    r.agents = people ? r.make("rt/people", &people_msgs_msg_dds__People__desc, false, false)
                      : r.make("rt/tracked_agents", &cohan_msgs_msg_dds__TrackedAgents__desc, false,
                               false);
    r.goal = r.make("rt/goal_pose", &geometry_msgs_msg_dds__PoseStamped__desc, false, false);
    r.scan = r.make("rt/scan", &sensor_msgs_msg_dds__LaserScan__desc, false, true);
    r.cmd = r.make("rt/cmd_vel", &geometry_msgs_msg_dds__Twist__desc, true, false);
    r.markers =
        r.make("rt/coopnav/markers", &visualization_msgs_msg_dds__MarkerArray__desc, true, false);
    r.utterance = r.make("rt/coopnav/utterance", &std_msgs_msg_dds__String__desc, true, false);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robot_side: %s\n", e.what());
    dds_delete(r.pp);
    return 1;
  }
  lcm.subscribeFunction<agent_states_t, RobotSide*>(
      channels::kAgentStates,
      [](const lcm::ReceiveBuffer*, const std::string&, const agent_states_t* m, RobotSide* self) {
        self->onStates(*m);
      },
      &r);
  lcm.subscribeFunction<goals_t, RobotSide*>(
      channels::kGoals,
      [](const lcm::ReceiveBuffer*, const std::string&, const goals_t* m, RobotSide* self) {
        self->onGoals(*m);
      },
      &r);
  lcm.subscribeFunction<laser_scan_t, RobotSide*>(
      channels::kScan,
      [](const lcm::ReceiveBuffer*, const std::string&, const laser_scan_t* m, RobotSide* self) {
        self->onScan(*m);
      },
      &r);
  std::unique_ptr<lcm::LCM> cues;
  if (!cues_url.empty()) {
    cues = std::make_unique<lcm::LCM>(cues_url);
    if (!cues->good()) {
      std::fprintf(stderr, "robot_side: LCM %s unusable\n", cues_url.c_str());
      dds_delete(r.pp);
      return 1;
    }
    for (const char* channel : {channels::kBands, channels::kUtterance})
      cues->subscribeFunction(channel, &forwardToWorld, &lcm);
    if (echo_pipeline) {
      cues->subscribeFunction<laser_scan_t, void*>(
          channels::kScan,
          [](const lcm::ReceiveBuffer*, const std::string&, const laser_scan_t* m, void*) {
            printScan("PIPE_SCAN", *m);
          },
          nullptr);
      cues->subscribeFunction<agent_states_t, void*>(
          channels::kAgentStates,
          [](const lcm::ReceiveBuffer*, const std::string&, const agent_states_t* m, void*) {
            printPipelineHumans(*m);
          },
          nullptr);
    }
  }
  std::printf("READY\n");
  std::fflush(stdout);
  while (!g_stop) {
    lcm.handleTimeout(cues ? 1 : 2);
    if (cues) cues->handleTimeout(1);
    r.pollDds();
  }
  std::printf("MARKERS %ld\n", r.markers_seen);
  dds_delete(r.pp);
  return 0;
}
