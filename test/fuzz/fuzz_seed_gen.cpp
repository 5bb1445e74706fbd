// Writes the generated seeds of test/fuzz/corpus/ (README.md): valid encoded messages for each
// daemon's channels (first byte = the target's channel selector), a small log of them, small
// PGM / walls / scenario maps and a .bt tree. Hand-written and copied seeds (configs, scenarios)
// are added by scripts/fuzz.sh --seed. Usage: fuzz_seed_gen <corpus dir>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <string>
#include <vector>

#include "coopnav/agent_states_t.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/distance_reply_t.hpp"
#include "coopnav/distance_request_t.hpp"
#include "coopnav/goals_t.hpp"
#include "coopnav/path_assessment_t.hpp"
#include "coopnav/path_assessor_control_t.hpp"
#include "coopnav/reference_paths_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "coopnav/sim_status_t.hpp"
#include "coopnav/situation_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "coopnav/utterance_t.hpp"
#include "coopnav/velocity_command_t.hpp"
#include "maps/map_loader.hpp"

namespace {

using namespace coopnav;
namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

fs::path g_root;

template <class Msg>
std::vector<std::uint8_t> encoded(const Msg& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

void writeFile(const std::string& target, const std::string& name,
               const std::vector<std::uint8_t>& bytes) {
  const fs::path dir = g_root / target;
  fs::create_directories(dir);
  std::ofstream out(dir / name, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

void writeText(const std::string& target, const std::string& name, const std::string& text) {
  writeFile(target, name, std::vector<std::uint8_t>(text.begin(), text.end()));
}

/// A seed of a channel-selecting target: selector byte, then the encoded message.
template <class Msg>
void seed(const std::string& target, const std::string& name, std::uint8_t channel, const Msg& m) {
  std::vector<std::uint8_t> bytes{channel};
  const auto payload = encoded(m);
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  writeFile(target, name, bytes);
}

agent_state_t agent(std::int32_t id, std::int8_t kind, double x_m, double y_m, double theta_rad) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x_m;
  a.y_m = y_m;
  a.theta_rad = theta_rad;
  a.vx_m_s = kind == agent_state_t::KIND_ROBOT ? 0.6 : -1.1;
  a.vy_m_s = 0.0;
  a.omega_rad_s = 0.0;
  a.radius_m = kind == agent_state_t::KIND_ROBOT ? 0.35 : 0.3;
  return a;
}

agent_states_t agentStates(int num_humans) {
  agent_states_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.robot = agent(0, agent_state_t::KIND_ROBOT, 1.0, 1.5, 0.0);
  for (int i = 0; i < num_humans; ++i)
    m.humans.push_back(agent(i + 1, agent_state_t::KIND_HUMAN, 9.0 - i, 1.5 + 0.5 * i, M_PI));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  return m;
}

goals_t goals() {
  goals_t m{};
  m.utime = 0;
  goal_t r{};
  r.agent_id = 0;
  r.kind = agent_state_t::KIND_ROBOT;
  r.x_m = 12.0;
  r.y_m = 1.5;
  r.theta_rad = 0.0;
  goal_t h = r;
  h.agent_id = 1;
  h.kind = agent_state_t::KIND_HUMAN;
  h.x_m = -2.0;
  h.theta_rad = kNaN;  // any heading
  m.goals = {r, h};
  m.num_goals = 2;
  return m;
}

band_t band(std::int32_t id, std::int8_t kind, double x0_m, double vx_m_s, int num_poses) {
  band_t b{};
  b.agent_id = id;
  b.kind = kind;
  for (int k = 0; k < num_poses; ++k) {
    timed_pose_t p{};
    p.t_s = 0.4 * k;
    p.x_m = x0_m + vx_m_s * p.t_s;
    p.y_m = 1.5 + 0.05 * k;
    p.theta_rad = vx_m_s > 0 ? 0.0 : M_PI;
    b.poses.push_back(p);
  }
  b.num_poses = static_cast<std::int16_t>(b.poses.size());
  return b;
}

bands_t bands(int num_humans, int num_poses) {
  bands_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.status = bands_t::STATUS_OK;
  m.robot_mode = 1;
  m.iterations = 40;
  m.final_cost = 3.5;
  m.solve_time_ms = 12.0;
  m.robot = band(0, agent_state_t::KIND_ROBOT, 1.0, 0.6, num_poses);
  for (int i = 0; i < num_humans; ++i)
    m.humans.push_back(band(i + 1, agent_state_t::KIND_HUMAN, 9.0 - i, -1.1, num_poses));
  m.num_humans = static_cast<std::int16_t>(m.humans.size());
  m.room_plans.assign(m.humans.size(), bands_t::ROOM_DOCK_HERE);
  return m;
}

reference_paths_t referencePaths(int num_paths, int num_points) {
  reference_paths_t m{};
  m.utime = 1200000;
  m.step = 12;
  for (int i = 0; i < num_paths; ++i) {
    path_t p{};
    p.agent_id = i + 1;
    for (int k = 0; k < num_points; ++k) {
      p.x_m.push_back(9.0 - 0.5 * k);
      p.y_m.push_back(1.5 + 0.1 * i);
    }
    p.num_points = static_cast<std::int16_t>(p.x_m.size());
    m.paths.push_back(p);
    m.revision.push_back(i + 1);
  }
  m.num_paths = static_cast<std::int16_t>(m.paths.size());
  return m;
}

robot_action_t robotAction(std::int8_t action) {
  robot_action_t m{};
  m.utime = 3400000;
  m.step = 34;
  m.action = action;
  m.human_id = 1;
  m.reason = "round 2: both constrained -> dock";
  return m;
}

path_assessor_control_t control(std::int8_t command) {
  path_assessor_control_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.human_id = 1;
  m.command = command;
  m.reason = "round 1";
  const bool start = command == path_assessor_control_t::COMMAND_START;
  m.d_oh_m = start ? 0.8 : kNaN;
  m.d_h_m = start ? 0.35 : kNaN;
  return m;
}

step_ack_t stepAck() {
  step_ack_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.participant = "band_source";
  return m;
}

situation_t situation(std::int8_t crossing_status) {
  situation_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.human_id = 1;
  m.crossing_status = crossing_status;
  m.i_star = 17;
  m.t_cross_s = 6.8;
  m.cp_h_x_m = 5.0;
  m.cp_h_y_m = 1.2;
  m.cp_r_x_m = 5.0;
  m.cp_r_y_m = 1.8;
  m.dir = situation_t::DIR_RIGHT;
  m.d_h_m = 0.35;
  m.d_oh_m = 0.8;
  m.d_or_m = 1.1;
  m.d_hr_m = kNaN;
  m.human_needs_to_contribute = situation_t::PRED_TRUE;
  m.human_is_constrained = situation_t::PRED_FALSE;
  m.robot_is_constrained = situation_t::PRED_UNKNOWN;
  m.tau_h_m = 0.3;
  m.tau_oh_m = 0.5;
  m.tau_or_m = 0.5;
  m.tau_hr_m = 0.6;
  m.reason = "d_h 0.35 > tau_h 0.30";
  return m;
}

path_assessment_t pathAssessment(int num_samples) {
  path_assessment_t m{};
  m.utime = 2400000;
  m.step = 24;
  m.human_id = 1;
  m.recording = num_samples > 0 ? path_assessment_t::REC_RECORDING : path_assessment_t::REC_IDLE;
  for (int k = 0; k < num_samples; ++k) m.ca_m.push_back(0.05 * k);
  m.num_samples = static_cast<std::int16_t>(m.ca_m.size());
  m.window_samples = num_samples;
  m.cm_m = num_samples > 0 ? 0.2 : kNaN;
  m.is_contributing = num_samples > 0 ? situation_t::PRED_FALSE : situation_t::PRED_UNKNOWN;
  m.interaction_samples = num_samples;
  m.cm_interaction_m = num_samples > 0 ? 0.2 : kNaN;
  m.is_contributing_interaction = m.is_contributing;
  m.gamma = 0.98;
  m.profile = "paper";
  m.tau_m = 0.4;
  m.tau_mode = path_assessment_t::TAU_FIXED;
  m.tau_fixed_m = 0.4;
  m.room_m = 1.15;
  m.tau_room_m = 0.4;
  return m;
}

utterance_t utterance(std::int8_t act, std::int8_t direction, int round) {
  utterance_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.human_id = 1;
  m.speech_act = act;
  m.direction = direction;
  m.round = static_cast<std::int8_t>(round);
  m.t_cross_s = round == 3 ? kNaN : 6.8;
  m.text = "I will pass on your right.";
  return m;
}

velocity_command_t command() {
  velocity_command_t m{};
  m.utime = 1200000;
  m.step = 12;
  m.vx_m_s = 0.6;
  m.vy_m_s = -0.1;
  m.omega_rad_s = 0.05;
  m.mode = velocity_command_t::MODE_NAVIGATING;
  return m;
}

daemon_status_t daemonStatus() {
  daemon_status_t m{};
  m.utime = 1700000000000000;
  m.name = "band_source";
  m.pid = 4242;
  m.state = daemon_status_t::STATE_RUNNING;
  m.received = 120;
  m.dropped = 1;
  m.rejected = 0;
  m.published = 360;
  m.last_logic_utime = 1200000;
  m.cycle_p50_ms = 11.0;
  m.cycle_max_ms = 30.0;
  m.detail = "map open.yaml 300x60 @ 0.05 m";
  return m;
}

sim_status_t simStatus(std::int8_t state) {
  sim_status_t m{};
  m.utime = 20000000;
  m.step = 200;
  m.state = state;
  m.scenario = "narrow_minimal";
  m.min_clearance_m = 0.42;
  m.robot_time_to_goal_s = 19.5;
  m.detail = "";
  return m;
}

distance_request_t distanceRequest() {
  distance_request_t m{};
  m.utime = 1200000;
  m.request_id = (std::int64_t{4242} << 32) + 1;
  m.reply_channel = std::string(channels::kDistanceReplyPrefix) + "situation_assessor_4242";
  const double kinds[3][5] = {
      {5.0, 1.5, 0.0, 0.0, 10.0}, {5.0, 1.5, 0.0, 1.0, 10.0}, {5.0, 1.5, 0.0, -1.0, 10.0}};
  for (int k = 0; k < 3; ++k) {
    distance_query_t q{};
    q.kind = static_cast<std::int8_t>(k);
    q.px_m = kinds[k][0];
    q.py_m = kinds[k][1];
    q.nx = kinds[k][2];
    q.ny = kinds[k][3];
    q.max_range_m = kinds[k][4];
    m.queries.push_back(q);
  }
  m.num_queries = static_cast<std::int16_t>(m.queries.size());
  return m;
}

distance_reply_t distanceReply() {
  distance_reply_t m{};
  m.utime = 1200000;
  m.request_id = (std::int64_t{4242} << 32) + 1;
  m.status = distance_reply_t::STATUS_OK;
  m.error = "";
  const std::int8_t statuses[] = {distance_result_t::STATUS_OK, distance_result_t::STATUS_NOT_FOUND,
                                  distance_result_t::STATUS_INVALID_QUERY};
  for (const std::int8_t s : statuses) {
    distance_result_t r{};
    r.status = s;
    r.distance_m = s == distance_result_t::STATUS_INVALID_QUERY ? kNaN : 0.8;
    r.obstacle_x_m = s == distance_result_t::STATUS_OK ? 5.0 : kNaN;
    r.obstacle_y_m = s == distance_result_t::STATUS_OK ? 2.3 : kNaN;
    m.results.push_back(r);
  }
  m.num_results = static_cast<std::int16_t>(m.results.size());
  return m;
}

void lcmSeeds() {
  // band_source: 0 agent states, 1 goals, 2 robot action
  seed("fuzz_lcm_band_source", "agent_states_1", 0, agentStates(1));
  seed("fuzz_lcm_band_source", "agent_states_3", 0, agentStates(3));
  seed("fuzz_lcm_band_source", "agent_states_0", 0, agentStates(0));
  seed("fuzz_lcm_band_source", "goals", 1, goals());
  seed("fuzz_lcm_band_source", "robot_action_dock", 2, robotAction(robot_action_t::ACTION_DOCK));
  seed("fuzz_lcm_band_source", "robot_action_resume", 2,
       robotAction(robot_action_t::ACTION_RESUME));
  // situation_assessor: 0 reference paths, 1 bands, 2 distance reply
  seed("fuzz_lcm_situation_assessor", "reference_paths_1x8", 0, referencePaths(1, 8));
  seed("fuzz_lcm_situation_assessor", "reference_paths_2x3", 0, referencePaths(2, 3));
  seed("fuzz_lcm_situation_assessor", "bands_1x10", 1, bands(1, 10));
  seed("fuzz_lcm_situation_assessor", "bands_2x4", 1, bands(2, 4));
  seed("fuzz_lcm_situation_assessor", "distance_reply", 2, distanceReply());
  // path_assessor: 0 reference paths, 1 control, 2 agent states, 3 step ack
  seed("fuzz_lcm_path_assessor", "reference_paths_1x8", 0, referencePaths(1, 8));
  seed("fuzz_lcm_path_assessor", "control_start", 1,
       control(path_assessor_control_t::COMMAND_START));
  seed("fuzz_lcm_path_assessor", "control_reset", 1,
       control(path_assessor_control_t::COMMAND_RESET));
  seed("fuzz_lcm_path_assessor", "agent_states_1", 2, agentStates(1));
  seed("fuzz_lcm_path_assessor", "step_ack", 3, stepAck());
  // dialogue_manager: 0 situation, 1 path assessment, 2 agent states, 3 step ack
  seed("fuzz_lcm_dialogue_manager", "situation_ok", 0, situation(situation_t::CROSSING_OK));
  seed("fuzz_lcm_dialogue_manager", "situation_beyond", 0,
       situation(situation_t::CROSSING_BEYOND_HORIZON));
  seed("fuzz_lcm_dialogue_manager", "path_assessment_5", 1, pathAssessment(5));
  seed("fuzz_lcm_dialogue_manager", "path_assessment_0", 1, pathAssessment(0));
  seed("fuzz_lcm_dialogue_manager", "agent_states_2", 2, agentStates(2));
  seed("fuzz_lcm_dialogue_manager", "step_ack", 3, stepAck());
  // world_sim: 0 daemon status, 1 velocity command, 2 utterance, 3 bands
  seed("fuzz_lcm_world_sim", "daemon_status", 0, daemonStatus());
  seed("fuzz_lcm_world_sim", "command", 1, command());
  seed("fuzz_lcm_world_sim", "utterance_inform", 2,
       utterance(utterance_t::ACT_INFORM_DIRECTION, situation_t::DIR_RIGHT, 1));
  seed("fuzz_lcm_world_sim", "utterance_thank", 2,
       utterance(utterance_t::ACT_THANK, situation_t::DIR_UNDEFINED, 3));
  seed("fuzz_lcm_world_sim", "bands_1x10", 3, bands(1, 10));
  // obstacle_distance_server: the request alone
  writeFile("fuzz_lcm_obstacle_distance_server", "request_3", encoded(distanceRequest()));
}

/// fuzz_lcm_sequence's input: records [selector][length, 2 bytes little endian][payload]; the
/// selector picks the channel as fuzz_lcm_sequence.cpp numbers them.
class Sequence {
 public:
  enum Selector : std::uint8_t {
    kAgentStates = 0,
    kBands = 1,
    kReferencePaths = 2,
    kSituation = 3,
    kPathAssessment = 4,
    kRobotAction = 5,
    kStepAck = 6,
    kGoals = 7,
  };
  template <class Msg>
  Sequence& add(Selector selector, const Msg& m) {
    const auto payload = encoded(m);
    bytes_.push_back(selector);
    bytes_.push_back(static_cast<std::uint8_t>(payload.size() & 0xFFu));
    bytes_.push_back(static_cast<std::uint8_t>((payload.size() >> 8) & 0xFFu));
    bytes_.insert(bytes_.end(), payload.begin(), payload.end());
    return *this;
  }
  /// fuzz_viewer_scene numbers its first 8 channels the same: the seeds are its own too.
  void write(const std::string& name) const {
    writeFile("fuzz_lcm_sequence", name, bytes_);
    writeFile("fuzz_viewer_scene", name, bytes_);
  }

 private:
  std::vector<std::uint8_t> bytes_;
};

/// `m` stamped `utime` at lockstep step `step` (-1: free-running).
template <class Msg>
Msg stamped(Msg m, std::int64_t utime, std::int64_t step) {
  m.utime = utime;
  m.step = step;
  return m;
}

/// Agent states of step k of a head-on walk (robot east from x = 1 m, humans west from 9 m).
agent_states_t walkAt(int num_humans, int k, std::int64_t step) {
  agent_states_t m = stamped(agentStates(num_humans), 1'000'000 + k * 100'000, step);
  m.robot.x_m += 0.06 * k;
  for (auto& h : m.humans) h.x_m -= 0.11 * k;
  return m;
}

void sequenceSeeds() {
  using S = Sequence;
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  {  // a lockstep run: the pipeline's own outputs go round (bands, situations, acks)
    S s;
    s.add(S::kGoals, goals());
    for (int k = 0; k < 6; ++k) s.add(S::kAgentStates, walkAt(1, k, k));
    s.write("lockstep_run");
  }
  {  // free-running, one message of every channel
    S s;
    s.add(S::kGoals, goals()).add(S::kAgentStates, walkAt(2, 0, -1));
    s.add(S::kReferencePaths, stamped(referencePaths(2, 8), 1'000'000, -1));
    s.add(S::kBands, stamped(bands(2, 10), 1'050'000, -1));
    s.add(S::kSituation, stamped(situation(situation_t::CROSSING_OK), 1'050'000, -1));
    s.add(S::kPathAssessment, stamped(pathAssessment(5), 1'050'000, -1));
    s.add(S::kRobotAction, stamped(robotAction(robot_action_t::ACTION_DOCK), 1'050'000, -1));
    step_ack_t ack = stepAck();
    ack.participant = "dialogue_manager";
    s.add(S::kStepAck, stamped(ack, 1'000'000, 0));
    s.add(S::kAgentStates, walkAt(2, 1, -1));
    s.write("free_running_every_channel");
  }
  {  // bands whose two poses are 10^7 s apart: the common time grid must not span them
    S s;
    bands_t b = stamped(bands(1, 2), 1'100'000, -1);
    b.robot.poses[1].t_s = 1e7;
    b.humans[0].poses[1].t_s = 1e7;
    s.add(S::kReferencePaths, stamped(referencePaths(1, 2), 1'000'000, -1)).add(S::kBands, b);
    s.write("bands_spanning_1e7_s");
  }
  {  // stamps at INT64_MAX, then normal traffic
    S s;
    s.add(S::kGoals, goals()).add(S::kAgentStates, stamped(walkAt(1, 0, -1), kMax, -1));
    for (int k = 1; k < 5; ++k) s.add(S::kAgentStates, walkAt(1, k, -1));
    s.add(S::kReferencePaths, stamped(referencePaths(1, 4), kMax - 1, -1));
    s.add(S::kSituation, stamped(situation(situation_t::CROSSING_OK), kMax - 1, -1));
    for (int k = 1; k < 4; ++k)
      s.add(S::kSituation,
            stamped(situation(situation_t::CROSSING_OK), 1'000'000 + k * 100'000, -1));
    s.write("int64_max_stamps");
  }
  {  // more human ids than the per-id caps (the target sets limits.max_ids to 64)
    S s;
    for (int k = 0; k < 2; ++k) {
      agent_states_t a = walkAt(40, k, -1);
      for (auto& h : a.humans) h.id += 40 * k;
      s.add(S::kAgentStates, a);
      reference_paths_t r = stamped(referencePaths(12, 3), 1'000'000 + k * 100'000, -1);
      for (auto& p : r.paths) p.agent_id += 12 * k + 100;
      s.add(S::kReferencePaths, r);
    }
    for (int k = 0; k < 6; ++k) {
      situation_t sit = stamped(situation(situation_t::CROSSING_OK), 1'000'000 + k * 100'000, -1);
      sit.human_id = 200 + k;
      s.add(S::kSituation, sit);
    }
    s.write("new_ids_beyond_max_ids");
  }
  {  // the band source's planner meets new humans every cycle (its memory is capped by max_ids)
    S s;
    s.add(S::kGoals, goals());
    for (int k = 0; k < 6; ++k) {  // 12 humans and the robot: over the band source's max_ids of 8
      agent_states_t a = walkAt(2, k % 10, -1);
      a.utime = 1'000'000 + k * 100'000;
      for (auto& h : a.humans) h.id += 2 * k + 300;
      s.add(S::kAgentStates, a);
    }
    s.write("band_planner_new_ids");
  }
  {  // lockstep steps far ahead of anything acknowledged
    S s;
    for (int k = 0; k < 12; ++k)
      s.add(S::kReferencePaths, stamped(referencePaths(1, 2), 1'000'000, 1'000'000 + 7 * k));
    s.add(S::kStepAck, stamped(stepAck(), 1'000'000, 1'000'000'000));
    s.add(S::kAgentStates, walkAt(1, 0, 1'000'000'000'000));
    s.write("far_future_steps");
  }
  {  // texts that would forge log lines, and long ones
    S s;
    robot_action_t a = stamped(robotAction(robot_action_t::ACTION_DOCK), 1'000'000, -1);
    a.human_id = 4242;
    a.reason = "hostile\n[0000-00-00 00:00:00.000] [coopnav:1] [critical] FORGED\x1b[2J\r";
    s.add(S::kGoals, goals()).add(S::kRobotAction, a).add(S::kAgentStates, walkAt(1, 0, -1));
    situation_t sit = stamped(situation(situation_t::CROSSING_OK), 1'000'000, -1);
    sit.reason = std::string(1500, 'r');
    s.add(S::kSituation, sit);
    s.write("hostile_texts");
  }
}

void logSeed() {
  const fs::path dir = g_root / "fuzz_run_log";
  fs::create_directories(dir);
  const std::string path = (dir / "small.lcm").string();
  lcm::LogFile log(path, "w");
  std::int64_t t_us = 1700000000000000;
  std::int64_t n = 0;
  const auto add = [&](const char* channel, const std::vector<std::uint8_t>& bytes) {
    lcm::LogEvent e;
    e.eventnum = n++;
    e.timestamp = t_us += 100000;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(bytes.size());
    e.data = const_cast<std::uint8_t*>(bytes.data());
    log.writeEvent(&e);
  };
  add(channels::kStatus, encoded(daemonStatus()));
  add(channels::kAgentStates, encoded(agentStates(1)));
  add(channels::kReferencePaths, encoded(referencePaths(1, 8)));
  add(channels::kSituation, encoded(situation(situation_t::CROSSING_OK)));
  add(channels::kUtterance,
      encoded(utterance(utterance_t::ACT_INFORM_DIRECTION, situation_t::DIR_RIGHT, 1)));
  add(channels::kPathAssessorControl, encoded(control(path_assessor_control_t::COMMAND_START)));
  add(channels::kPathAssessment, encoded(pathAssessment(5)));
  add(channels::kRobotAction, encoded(robotAction(robot_action_t::ACTION_DOCK)));
  add(channels::kBands, encoded(bands(1, 4)));
  add(channels::kSimStatus, encoded(simStatus(sim_status_t::STATE_GOAL_REACHED)));
}

const char* const kSeparator = "\n--8<--\n";

void mapSeeds() {
  // P2 and P5 images of a 6 x 4 corridor: black walls top and bottom, white free, grey unknown.
  const std::string p2 =
      "P2\n# corridor\n6 4\n255\n0 0 0 0 0 0\n254 254 205 254 254 254\n"
      "254 254 254 254 254 254\n0 0 0 0 0 0\n";
  std::string p5 = "P5\n6 4\n255\n";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 6; ++c)
      p5.push_back(static_cast<char>(r == 0 || r == 3 ? 0 : (c == 2 && r == 1 ? 205 : 254)));
  std::string p5_16 = "P5\n2 2\n65535\n";
  for (const int v : {0, 65535, 32768, 65534}) {
    p5_16.push_back(static_cast<char>(v >> 8));
    p5_16.push_back(static_cast<char>(v & 0xff));
  }
  writeText("fuzz_map_pgm", "corridor_p2.pgm", p2);
  writeText("fuzz_map_pgm", "corridor_p5.pgm", p5);
  writeText("fuzz_map_pgm", "p5_16bit.pgm", p5_16);

  const std::string ros_yaml =
      "image: map.pgm\nresolution: 0.5\norigin: [-1.0, -1.0, 0.0]\nnegate: 0\n"
      "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n";
  writeText("fuzz_map_yaml", "ros_p2", ros_yaml + kSeparator + p2);
  writeText("fuzz_map_yaml", "ros_p5", ros_yaml + kSeparator + p5);
  const std::string walls =
      "resolution_m: 0.1\nmargin_m: 0.2\nwalls:\n"
      "  - {x0_m: 0.0, y0_m: 0.0, x1_m: 6.0, y1_m: 0.0, thickness_m: 0.1}\n"
      "  - {x0_m: 0.0, y0_m: 2.0, x1_m: 6.0, y1_m: 2.6, thickness_m: 0.1}\n"
      "boxes:\n  - {min_x_m: 2.0, min_y_m: 0.0, max_x_m: 2.5, max_y_m: 0.6}\n";
  writeText("fuzz_map_yaml", "walls", walls);
  writeText("fuzz_map_yaml", "scenario_inline",
            "name: s\nmap:\n  resolution_m: 0.1\n  walls:\n"
            "    - {x0_m: 0.0, y0_m: 0.0, x1_m: 4.0, y1_m: 0.0, thickness_m: 0.1}\n");
  writeText("fuzz_map_yaml", "scenario_self", "name: s\nmap: {file: map.yaml}\n");

  // A .bt tree of the walls map, written by the loader's own writer.
  const fs::path tmp = fs::temp_directory_path() / "coopnav_seed_walls.yaml";
  {
    std::ofstream out(tmp);
    out << walls;
  }
  const LoadedMap map = loadMap(tmp.string());
  fs::remove(tmp);
  fs::create_directories(g_root / "fuzz_map_bt");
  writeBt(*map.tree, (g_root / "fuzz_map_bt" / "walls.bt").string());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_seed_gen <corpus dir>\n";
    return 2;
  }
  g_root = argv[1];
  lcmSeeds();
  sequenceSeeds();
  logSeed();
  mapSeeds();
  return 0;
}
