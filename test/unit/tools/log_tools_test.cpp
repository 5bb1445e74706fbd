// coopnav_ctl's log tools on a synthetic scripted run written with lcm::LogFile: transcript text,
// summary.json fields, cm_by_gamma against discountedMean, the trace the figures draw, broken
// logs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "coopnav/assessment/path_assessment.hpp"
#include "coopnav/bands_t.hpp"
#include "coopnav/channels.hpp"
#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "json.hpp"
#include "logfile/log_reader.hpp"
#include "maps/map_loader.hpp"
#include "run_analysis.hpp"
#include "summary.hpp"
#include "test_paths.hpp"
#include "trace.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

namespace fs = std::filesystem;

// A temporary directory removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("coopnav_tools_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    if (!std::getenv("COOPNAV_KEEP_TEST_FILES")) fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

class LogWriter {
 public:
  explicit LogWriter(const std::string& path, std::int64_t timestamp0 = 1'700'000'000'000'000)
      : log_(path, "w"), timestamp_(timestamp0) {
    if (!log_.good()) throw std::runtime_error("cannot write " + path);
  }
  template <class Msg>
  void put(const std::string& channel, const Msg& msg) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    raw(channel, buf);
  }
  void raw(const std::string& channel, std::vector<std::uint8_t> bytes) {
    lcm::LogEvent e{0, timestamp_, channel, static_cast<std::int32_t>(bytes.size()), bytes.data()};
    timestamp_ += 1234;  // logger receive time: must not show anywhere
    log_.writeEvent(&e);
  }
  // Bytes outside any event (corruption between events).
  void garbage(const std::vector<std::uint8_t>& bytes) {
    std::fwrite(bytes.data(), 1, bytes.size(), log_.getFilePtr());
  }

 private:
  lcm::LogFile log_;
  std::int64_t timestamp_;
};

// The scripted run: robot along +x from x 0, human 1 along -x from x 16 (closing 2 m/s, t_CROSS
// = 8 - 0.1 k s at step k), the human stepping aside from step 20. Round 1 at step 10 (START,
// inform left), round 2 at step 40 (dock, reset), crossing at step 80 (stop, resume), thanks at
// step 85. The path assessor samples one CA per step from step 10.
constexpr int kSteps = 90;
constexpr int kStartStep = 10;
constexpr int kResetStep = 40;

std::int64_t utimeOf(int k) { return std::int64_t{k} * 100'000; }
double humanY(int k) { return 1.5 + (k >= 20 ? std::min(0.05 * (k - 20), 0.9) : 0.0); }
double caOfSample(int j) { return std::min(0.03 * j, 0.9); }

std::vector<double> interactionCa(int k) {
  std::vector<double> ca;
  for (int j = 0; j <= k - kStartStep; ++j) ca.push_back(caOfSample(j));
  return ca;
}

agent_state_t agent(std::int32_t id, std::int8_t kind, double x, double y, double theta) {
  agent_state_t a{};
  a.id = id;
  a.kind = kind;
  a.x_m = x;
  a.y_m = y;
  a.theta_rad = theta;
  a.radius_m = 0.3;
  return a;
}

agent_states_t statesAt(int k) {
  agent_states_t s{};
  s.utime = utimeOf(k);
  s.step = k;
  s.robot = agent(0, agent_state_t::KIND_ROBOT, 0.1 * k, 1.5, 0.0);
  s.num_humans = 1;
  s.humans = {agent(1, agent_state_t::KIND_HUMAN, 16.0 - 0.1 * k, humanY(k), M_PI)};
  return s;
}

situation_t situationAt(int k) {
  const double nan = std::nan("");
  situation_t s{};
  s.utime = utimeOf(k);
  s.step = k;
  s.human_id = 1;
  s.tau_h_m = 0.3;
  s.tau_oh_m = 1.0;
  s.tau_or_m = 0.3;
  s.tau_hr_m = 1.2;
  if (k < 5 || k >= 80) {
    s.crossing_status = k < 5 ? situation_t::CROSSING_BEYOND_HORIZON : situation_t::CROSSING_OK;
    s.i_star = -1;
    s.t_cross_s = s.cp_h_x_m = s.cp_h_y_m = s.cp_r_x_m = s.cp_r_y_m = nan;
    s.d_h_m = s.d_oh_m = s.d_or_m = s.d_hr_m = nan;
    s.dir = situation_t::DIR_UNDEFINED;
    s.human_needs_to_contribute = s.human_is_constrained = s.robot_is_constrained =
        situation_t::PRED_UNKNOWN;
    s.reason = k < 5 ? "crossing beyond the band horizon" : "agents have crossed";
    return s;
  }
  s.crossing_status = situation_t::CROSSING_OK;
  s.i_star = 80 - k;
  s.t_cross_s = (80 - k) / 10.0;
  s.cp_h_x_m = 8.0;
  s.cp_h_y_m = 2.4;
  s.cp_r_x_m = 8.0;
  s.cp_r_y_m = 1.2;
  s.dir = situation_t::DIR_LEFT;
  s.d_h_m = 0.9;
  s.d_oh_m = 2.0;
  s.d_or_m = 0.2;
  s.d_hr_m = 1.2;
  s.human_needs_to_contribute = situation_t::PRED_TRUE;
  s.human_is_constrained = situation_t::PRED_FALSE;
  s.robot_is_constrained = situation_t::PRED_TRUE;
  return s;
}

path_assessment_t assessmentAt(int k) {
  path_assessment_t p{};
  p.utime = utimeOf(k);
  p.step = k;
  p.human_id = 1;
  p.gamma = 0.98;
  p.profile = "paper";
  p.tau_m = 0.4;
  const auto inter = interactionCa(k);
  // Samples at or before the reset's step leave the window from the next step on.
  const std::size_t window_begin =
      k > kResetStep ? static_cast<std::size_t>(kResetStep - kStartStep + 1) : 0;
  p.ca_m.assign(inter.begin() + static_cast<std::ptrdiff_t>(window_begin), inter.end());
  p.recording = k >= 80 ? path_assessment_t::REC_STOPPED : path_assessment_t::REC_RECORDING;
  p.num_samples = static_cast<std::int16_t>(p.ca_m.size());
  p.window_samples = static_cast<std::int32_t>(p.ca_m.size());
  p.cm_m = *assessment::discountedMean(p.ca_m, p.gamma);
  p.is_contributing = p.cm_m > p.tau_m ? situation_t::PRED_TRUE : situation_t::PRED_FALSE;
  p.interaction_samples = static_cast<std::int32_t>(inter.size());
  p.cm_interaction_m = *assessment::discountedMean(inter, p.gamma);
  p.is_contributing_interaction =
      p.cm_interaction_m > p.tau_m ? situation_t::PRED_TRUE : situation_t::PRED_FALSE;
  // The forecast: unknown for the first 4 steps of the interaction, then 0.01 k.
  p.p_contributing = k >= kStartStep + 4 ? 0.01 * k : std::nan("");
  return p;
}

utterance_t say(int k, std::int8_t act, std::int8_t dir, std::int8_t round, double t_cross,
                const std::string& text) {
  utterance_t u{};
  u.utime = utimeOf(k);
  u.step = k;
  u.human_id = 1;
  u.speech_act = act;
  u.direction = dir;
  u.round = round;
  u.t_cross_s = t_cross;
  u.text = text;
  u.delivery = utterance_t::DELIVERY_SAID;
  u.speech_start_s = 0.0;
  u.speech_duration_s = 1.5;
  return u;
}

path_assessor_control_t control(int k, std::int8_t command, const std::string& reason) {
  path_assessor_control_t c{};
  c.utime = utimeOf(k);
  c.step = k;
  c.human_id = 1;
  c.command = command;
  c.reason = reason;
  return c;
}

robot_action_t action(int k, std::int8_t a, const std::string& reason) {
  robot_action_t r{};
  r.utime = utimeOf(k);
  r.step = k;
  r.action = a;
  r.human_id = 1;
  r.reason = reason;
  return r;
}

sim_status_t simStatus(int k, std::int8_t state, const std::string& detail) {
  sim_status_t s{};
  s.utime = utimeOf(k);
  s.step = k;
  s.state = state;
  s.scenario = "open_facilitating";
  s.min_clearance_m = 0.65;
  s.robot_time_to_goal_s = state == sim_status_t::STATE_GOAL_REACHED ? 8.9 : std::nan("");
  s.min_clearance_t_s = 8.0;
  s.contact = sim_status_t::CONTACT_NONE;
  s.contact_human_id = -1;
  s.contact_t_s = s.contact_robot_speed_m_s = std::nan("");
  s.detail = detail;
  return s;
}

reference_paths_t referencePaths() {
  reference_paths_t r{};
  r.num_paths = 1;
  path_t p{};
  p.agent_id = 1;
  p.num_points = 2;
  p.x_m = {16.0, 0.0};
  p.y_m = {1.5, 1.5};
  r.paths = {p};
  r.revision = {0};
  return r;
}

// The dialogue manager's messages of step k, in its publishing order.
void dialogueAt(LogWriter& w, int k) {
  using U = utterance_t;
  if (k == kStartStep) {
    w.put(channels::kPathAssessorControl,
          control(k, path_assessor_control_t::COMMAND_START, "round 1"));
    w.put(channels::kUtterance, say(k, U::ACT_INFORM_DIRECTION, situation_t::DIR_LEFT, 1, 7.0,
                                    "I will pass on your left."));
  } else if (k == kResetStep) {
    w.put(channels::kUtterance, say(k, U::ACT_INFORM_DOCKING, situation_t::DIR_UNDEFINED, 2, 4.0,
                                    "I will wait here for you to pass."));
    w.put(channels::kRobotAction,
          action(k, robot_action_t::ACTION_DOCK, "robot constrained, human not contributing"));
    w.put(channels::kPathAssessorControl,
          control(k, path_assessor_control_t::COMMAND_RESET, "round 2"));
  } else if (k == 80) {
    w.put(channels::kPathAssessorControl,
          control(k, path_assessor_control_t::COMMAND_STOP, "crossed"));
    w.put(channels::kRobotAction, action(k, robot_action_t::ACTION_RESUME, "human passed"));
  } else if (k == 85) {
    w.put(channels::kUtterance,
          say(k, U::ACT_THANK, situation_t::DIR_UNDEFINED, 3, std::nan(""), "Thank you."));
  }
}

struct WriteOptions {
  // Another arrival order of the daemons' messages within each step (the logger hears several
  // processes; only the dialogue manager's own order is fixed).
  bool shuffle{false};
  std::int64_t timestamp0{1'700'000'000'000'000};
};

void writeScriptedRun(const std::string& path, const WriteOptions& o = {}) {
  LogWriter w(path, o.timestamp0);
  daemon_status_t status{};
  status.name = "band_source";
  for (int k = 0; k < kSteps; ++k) {
    if (k % 10 == 0 && o.shuffle) w.put(channels::kSimStatus, simStatus(k, 0, ""));
    w.put(channels::kAgentStates, statesAt(k));
    if (k == 0) w.put(channels::kReferencePaths, referencePaths());
    if (!o.shuffle && k >= kStartStep) w.put(channels::kPathAssessment, assessmentAt(k));
    if (!o.shuffle) w.put(channels::kSituation, situationAt(k));
    dialogueAt(w, k);
    if (o.shuffle) w.put(channels::kSituation, situationAt(k));
    if (o.shuffle && k >= kStartStep) w.put(channels::kPathAssessment, assessmentAt(k));
    if (k % 10 == 0 && !o.shuffle) w.put(channels::kSimStatus, simStatus(k, 0, ""));
    if (k == 3) {
      status.utime = o.timestamp0;  // wall clock, as daemons stamp it
      w.put(channels::kStatus, status);
      w.raw("FOREIGN_CHANNEL", {1, 2, 3});
    }
  }
  w.put(channels::kSimStatus,
        simStatus(kSteps - 1, sim_status_t::STATE_GOAL_REACHED, "robot reached its goal"));
}

const char* const kExpectedTranscript =
    "# scenario open_facilitating\n"
    "t=0.00s  human 1  t_cross=-  UNKNOWN crossing BEYOND_HORIZON, needs UNKNOWN, "
    "human_constrained UNKNOWN, robot_constrained UNKNOWN: \"crossing beyond the band horizon\" "
    "(first of 5)\n"
    "t=1.00s  human 1  t_cross=7.00s  RECORDER START (why: round 1)\n"
    "t=1.00s  human 1  t_cross=7.00s  SAY INFORM_DIRECTION \"I will pass on your left.\" "
    "(round 1, direction left)\n"
    "t=4.00s  human 1  t_cross=4.00s  SAY INFORM_DOCKING \"I will wait here for you to pass.\" "
    "(round 2)\n"
    "t=4.00s  human 1  t_cross=4.00s  ACTION DOCK (why: robot constrained, human not "
    "contributing)\n"
    "t=4.00s  human 1  t_cross=4.00s  RECORDER RESET (why: round 2)\n"
    "t=8.00s  human 1  t_cross=-  UNKNOWN crossing OK, needs UNKNOWN, human_constrained UNKNOWN, "
    "robot_constrained UNKNOWN: \"agents have crossed\" (first of 10)\n"
    "t=8.00s  human 1  t_cross=-  RECORDER STOP (why: crossed)\n"
    "t=8.00s  human 1  t_cross=-  ACTION RESUME (why: human passed)\n"
    "t=8.50s  human 1  t_cross=-  SAY THANK \"Thank you.\" (round 3)\n"
    "t=8.90s  human 1  FINAL CM window=0.900 m (49 samples, IsContributing TRUE), "
    "interaction=0.813 m (80 samples, IsContributing TRUE), gamma 0.98, tau 0.40 m\n"
    "t=8.90s  SIM GOAL_REACHED  step 89  min_clearance=0.650m  robot_time_to_goal=8.90s  "
    "\"robot reached its goal\"\n";

std::string transcriptOf(const std::string& log, const TranscriptOptions& o = {}) {
  const RunLog run = readRunLog(log);
  const RunAnalysis a = analyseRun(run);
  return formatTranscript(a.scenario, buildTranscript(run, a, o));
}

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

TEST(LogTools, ReadsEveryEventAndCountsForeignOnes) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.agent_states.size(), static_cast<std::size_t>(kSteps));
  EXPECT_EQ(run.situations.size(), static_cast<std::size_t>(kSteps));
  EXPECT_EQ(run.assessments.size(), static_cast<std::size_t>(kSteps - kStartStep));
  EXPECT_EQ(run.utterances.size(), 3u);
  EXPECT_EQ(run.actions.size(), 2u);
  EXPECT_EQ(run.controls.size(), 3u);
  EXPECT_EQ(run.sim_status.size(), 10u);
  EXPECT_EQ(run.reference_paths.size(), 1u);
  EXPECT_EQ(run.daemon_status.size(), 1u);
  EXPECT_EQ(run.counts.unknown_channel, 1);
  EXPECT_EQ(run.counts.not_needed, 0);
  EXPECT_EQ(run.counts.undecodable, 0);
  EXPECT_FALSE(run.counts.anyCorruption());
  EXPECT_EQ(run.counts.events, run.counts.decoded + 1);
}

TEST(LogTools, TranscriptTextIsExact) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  EXPECT_EQ(transcriptOf(dir.file("run.lcm")), kExpectedTranscript);
}

TEST(LogTools, TranscriptIgnoresWallClockAndCrossDaemonInterleaving) {
  TempDir dir;
  writeScriptedRun(dir.file("a.lcm"));
  WriteOptions other;
  other.shuffle = true;
  other.timestamp0 = 42;
  writeScriptedRun(dir.file("b.lcm"), other);
  EXPECT_EQ(transcriptOf(dir.file("b.lcm")), transcriptOf(dir.file("a.lcm")));
}

TEST(LogTools, TranscriptOptionsLeaveOutLines) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  TranscriptOptions o;
  o.include_sim_status = false;
  o.include_unknown = false;
  o.include_final_cm = false;
  const std::string t = transcriptOf(dir.file("run.lcm"), o);
  EXPECT_EQ(countOf(t, "\n"), 9);  // header + 8 dialogue lines
  EXPECT_EQ(countOf(t, "SIM "), 0);
  EXPECT_EQ(countOf(t, "UNKNOWN"), 0);
  EXPECT_EQ(countOf(t, "FINAL"), 0);
}

TEST(LogTools, DegradedDaemonsOnlyOnRequestOncePerDetail) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    bands_t bands{};
    bands.robot.poses.clear();
    w.put(channels::kBands, bands);  // a channel the tools do not need
    daemon_status_t st{};
    st.name = "situation_assessor";
    st.state = daemon_status_t::STATE_DEGRADED;
    st.detail = "distance server silent";
    for (int k = 0; k < 6; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      if (k >= 4) w.put(channels::kStatus, st);
    }
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.counts.not_needed, 1);
  const RunAnalysis a = analyseRun(run);
  EXPECT_EQ(formatTranscript("x", buildTranscript(run, a)), "# scenario x\n");
  TranscriptOptions o;
  o.include_daemon_status = true;
  EXPECT_EQ(formatTranscript("x", buildTranscript(run, a, o)),
            "# scenario x\n"
            "t~0.40s  DAEMON situation_assessor DEGRADED \"distance server silent\" (wall-clock "
            "status; time of the last step logged)\n");
}

TEST(LogTools, InteractionCaIsRebuiltAcrossTheReset) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const RunAnalysis a = analyseRun(run);
  ASSERT_EQ(a.humans.size(), 1u);
  const HumanAnalysis& h = a.humans[0];
  EXPECT_TRUE(h.interaction_ca_complete);
  EXPECT_EQ(h.interaction_ca_m, interactionCa(kSteps - 1));
  EXPECT_EQ(h.window_starts, (std::vector<std::size_t>{0, kResetStep - kStartStep + 1}));
  ASSERT_TRUE(h.recorder_start_s.has_value());
  EXPECT_DOUBLE_EQ(*h.recorder_start_s, 1.0);
  EXPECT_TRUE(h.docked);
  ASSERT_TRUE(h.first_round_situation.has_value());
  EXPECT_EQ(run.situations[*h.first_round_situation].step, kStartStep);
  // The rebuilt interaction gives the published interaction CM.
  EXPECT_NEAR(*assessment::discountedMean(h.interaction_ca_m, 0.98),
              run.assessments.back().cm_interaction_m, 1e-12);
}

TEST(LogTools, SummaryReportsBothCmsOutcomeAndTranscript) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json doc =
      parseJson(dumpJson(summaryDocument({summarizeRun(run, analyseRun(run), "run.lcm")})));
  EXPECT_EQ(doc.at("format"), kSummaryFormat);
  const Json& s = doc.at("scenarios").at(0);
  EXPECT_EQ(s.at("scenario"), "open_facilitating");
  EXPECT_EQ(s.at("log"), "run.lcm");
  EXPECT_EQ(s.at("final_state"), "GOAL_REACHED");
  EXPECT_EQ(s.at("collision"), false);
  EXPECT_TRUE(s.at("collision").is_boolean());
  EXPECT_DOUBLE_EQ(s.at("min_clearance_m").get<double>(), 0.65);
  EXPECT_DOUBLE_EQ(s.at("robot_time_to_goal_s").get<double>(), 8.9);
  EXPECT_EQ(s.at("docked"), true);
  // Closest approach of the script: step 80, both at x 8, y 1.5 and 2.4, radii 0.3.
  EXPECT_NEAR(s.at("min_clearance_states_m").get<double>(), 0.3, 1e-9);
  EXPECT_EQ(s.at("outcome"), "GOAL_REACHED");
  EXPECT_DOUBLE_EQ(s.at("min_clearance_t_s").get<double>(), 8.0);
  EXPECT_TRUE(s.at("contact").is_null());
  // The script logs no robot command.
  EXPECT_EQ(s.at("docks"), 0);
  EXPECT_EQ(s.at("retreats"), 0);
  EXPECT_EQ(s.at("guard_steps"), 0);

  const Json& h = s.at("humans").at(0);
  const path_assessment_t& last = run.assessments.back();
  EXPECT_EQ(h.at("id"), 1);
  EXPECT_EQ(h.at("cm_window_m").get<double>(), last.cm_m);
  EXPECT_EQ(h.at("cm_interaction_m").get<double>(), last.cm_interaction_m);
  EXPECT_EQ(h.at("window_samples"), 49);
  EXPECT_EQ(h.at("interaction_samples"), 80);
  EXPECT_EQ(h.at("is_contributing"), true);
  EXPECT_EQ(h.at("is_contributing_interaction"), true);
  EXPECT_EQ(h.at("recording"), "STOPPED");
  EXPECT_EQ(h.at("docked"), true);
  EXPECT_EQ(h.at("thanked"), true);
  EXPECT_EQ(h.at("interaction_ca_complete"), true);
  EXPECT_TRUE(h.at("goal_inference").is_null());  // goals given: nothing inferred
  const Json& round1 = h.at("first_round");
  ASSERT_TRUE(round1.is_object());
  EXPECT_DOUBLE_EQ(round1.at("t_s").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(round1.at("cp_h_m").at(1).get<double>(), 2.4);
  EXPECT_EQ(round1.at("dir"), "left");

  const Json& entries = h.at("transcript");
  ASSERT_EQ(entries.size(), 8u);
  EXPECT_EQ(entries[0].at("kind"), "recorder");
  EXPECT_EQ(entries[0].at("command"), "START");
  EXPECT_EQ(entries[1].at("kind"), "say");
  EXPECT_EQ(entries[1].at("act"), "INFORM_DIRECTION");
  EXPECT_EQ(entries[1].at("text"), "I will pass on your left.");
  EXPECT_EQ(entries[1].at("round"), 1);
  EXPECT_EQ(entries[1].at("direction"), "left");
  EXPECT_DOUBLE_EQ(entries[1].at("t_s").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(entries[1].at("t_cross_s").get<double>(), 7.0);
  EXPECT_EQ(entries[1].at("delivery"), "said");
  EXPECT_EQ(entries[1].at("speech_start_s"), 0.0);
  EXPECT_EQ(entries[1].at("speech_duration_s"), 1.5);
  EXPECT_DOUBLE_EQ(entries[1].at("lead_s").get<double>(), 7.0 - 1.5);
  EXPECT_EQ(entries[3].at("kind"), "action");
  EXPECT_EQ(entries[3].at("action"), "DOCK");
  // THANK after crossing: t_CROSS unknown -> null, and so is its lead.
  EXPECT_TRUE(entries[7].at("t_cross_s").is_null());
  EXPECT_TRUE(entries[7].at("lead_s").is_null());
  EXPECT_FALSE(entries[0].contains("delivery"));  // only utterances have one

  // The forecast: the last, over time every 0.5 s from the first assessment (null while
  // unknown) and the last one, and at each round's words (the latest assessment before them).
  EXPECT_DOUBLE_EQ(h.at("p_contributing").get<double>(), 0.89);
  const Json& series = h.at("p_contributing_over_time");
  ASSERT_EQ(series.size(), 17u);  // 1.0, 1.5, .., 8.5 s and the last, 8.9 s
  EXPECT_DOUBLE_EQ(series[0].at(0).get<double>(), 1.0);
  EXPECT_TRUE(series[0].at(1).is_null());
  EXPECT_DOUBLE_EQ(series[1].at(0).get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(series[1].at(1).get<double>(), 0.15);
  EXPECT_DOUBLE_EQ(series[16].at(0).get<double>(), 8.9);
  EXPECT_DOUBLE_EQ(series[16].at(1).get<double>(), 0.89);
  EXPECT_TRUE(entries[1].at("p_contributing").is_null()) << "round 1: not known yet";
  EXPECT_EQ(entries[2].at("round"), 2);
  EXPECT_DOUBLE_EQ(entries[2].at("p_contributing").get<double>(), 0.40);
}

// Given a run whose dialogue manager decided three utterances, said the first after an earlier
// one was still being spoken, was too late for the second and muted for the thanks, when the
// transcript and the summary are built, then the said line is a plain SAY line, the others say
// why they were not said, and the summary gives every delivery and lead.
TEST(LogTools, UtterancesNotSaidAreTranscribedWithTheReason) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    using U = utterance_t;
    for (int k = 0; k < 90; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      w.put(channels::kSituation, situationAt(k));
      if (k == kStartStep) {
        U u = say(k, U::ACT_INFORM_DIRECTION, situation_t::DIR_LEFT, 1, 7.0,
                  "I will pass on your left.");
        u.speech_start_s = 0.4;
        w.put(channels::kUtterance, u);
      } else if (k == 77) {
        U u = say(k, U::ACT_REPEAT_DIRECTION, situation_t::DIR_LEFT, 2, 0.3,
                  "I am passing on your left.");
        u.delivery = U::DELIVERY_TOO_LATE;
        u.speech_start_s = 0.05;
        u.speech_duration_s = 3.11;
        w.put(channels::kUtterance, u);
      } else if (k == 85) {
        U u = say(k, U::ACT_THANK, situation_t::DIR_UNDEFINED, 3, std::nan(""), "Thank you.");
        u.delivery = U::DELIVERY_MUTED;
        w.put(channels::kUtterance, u);
      }
    }
  }
  TranscriptOptions o;
  o.include_unknown = false;
  EXPECT_EQ(transcriptOf(dir.file("run.lcm"), o),
            "# scenario (unnamed)\n"
            "t=1.00s  human 1  t_cross=7.00s  SAY INFORM_DIRECTION \"I will pass on your left.\" "
            "(round 1, direction left)\n"
            "t=7.70s  human 1  t_cross=0.30s  NOT SAID (too late: its 3.11 s of speech would end "
            "2.86 s after the crossing) REPEAT_DIRECTION \"I am passing on your left.\" (round 2, "
            "direction left)\n"
            "t=8.50s  human 1  t_cross=-  NOT SAID (muted) THANK \"Thank you.\" (round 3)\n");

  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json h =
      parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm"))).at("humans").at(0);
  EXPECT_EQ(h.at("thanked"), false) << "a muted thanks is not said";
  const Json& t = h.at("transcript");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].at("delivery"), "said");
  EXPECT_DOUBLE_EQ(t[0].at("lead_s").get<double>(), 7.0 - 0.4 - 1.5);
  EXPECT_EQ(t[1].at("delivery"), "too_late");
  EXPECT_DOUBLE_EQ(t[1].at("speech_start_s").get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(t[1].at("speech_duration_s").get<double>(), 3.11);
  EXPECT_DOUBLE_EQ(t[1].at("lead_s").get<double>(), 0.3 - 0.05 - 3.11);
  EXPECT_EQ(t[2].at("delivery"), "muted");
  EXPECT_TRUE(t[2].at("lead_s").is_null());
  EXPECT_EQ(deliveryName(0), "delivery_0");
  EXPECT_TRUE(wasSaid(0));
}

velocity_command_t command(int k, std::int8_t mode, std::int8_t guard) {
  velocity_command_t c{};
  c.utime = utimeOf(k);
  c.step = k;
  c.mode = mode;
  c.guard = guard;
  return c;
}

TEST(LogTools, SummaryScoresTheGoalInferredAtRoundOneAgainstWhereTheHumanWent) {
  // Goals withheld: two candidates ahead of and behind the human (who walks -x from x 16 to
  // 7.1); the band source names the one behind it until step 5, then the one ahead.
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    for (int k = 0; k < kSteps; ++k) {
      goal_estimates_t g{};
      g.utime = utimeOf(k);
      g.step = k;
      g.num_goals = 2;
      g.goal_x_m = {0.0, 20.0};
      g.goal_y_m = {1.5, 1.5};
      goal_estimate_t e{};
      e.agent_id = 1;
      e.most_likely = k < 5 ? 1 : 0;
      e.num_goals = 2;
      e.probability = k < 5 ? std::vector<float>{0.4f, 0.6f} : std::vector<float>{0.75f, 0.25f};
      g.num_humans = 1;
      g.humans = {e};
      w.put(channels::kGoalEstimates, g);
      w.put(channels::kAgentStates, statesAt(k));
      w.put(channels::kSituation, situationAt(k));
    }
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.goal_estimates.size(), static_cast<std::size_t>(kSteps));
  const Json h =
      parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm"))).at("humans").at(0);
  const Json& g = h.at("goal_inference");
  EXPECT_EQ(g.at("candidates"), 2);
  EXPECT_EQ(g.at("at_round1"), 0);
  EXPECT_NEAR(g.at("p_at_round1").get<double>(), 0.75, 1e-6);
  EXPECT_EQ(g.at("truth"), 0);  // last seen at x 7.1: nearer x 0 than x 20
  EXPECT_EQ(g.at("correct"), true);
  EXPECT_NEAR(g.at("last_seen_m").at(0).get<double>(), 16.0 - 0.1 * (kSteps - 1), 1e-9);
}

// A goal estimate whose most_likely index names no candidate (any peer can publish one and the
// recorder keeps it): no crash, no candidate named, not scored correct.
TEST(LogTools, SummaryIgnoresAGoalIndexOutOfRange) {
  for (const auto& [most_likely, probabilities] :
       std::vector<std::pair<std::int16_t, std::size_t>>{{300, 2}, {2, 2}, {1, 0}}) {
    TempDir dir;
    {
      LogWriter w(dir.file("run.lcm"));
      for (int k = 0; k < kSteps; ++k) {
        goal_estimates_t g{};
        g.utime = utimeOf(k);
        g.step = k;
        g.num_goals = 2;
        g.goal_x_m = {0.0, 20.0};
        g.goal_y_m = {1.5, 1.5};
        goal_estimate_t e{};
        e.agent_id = 1;
        e.most_likely = most_likely;
        e.num_goals = static_cast<std::int16_t>(probabilities);
        e.probability.assign(probabilities, 0.5f);
        g.num_humans = 1;
        g.humans = {e};
        w.put(channels::kGoalEstimates, g);
        w.put(channels::kAgentStates, statesAt(k));
        w.put(channels::kSituation, situationAt(k));
      }
    }
    const RunLog run = readRunLog(dir.file("run.lcm"));
    ASSERT_EQ(run.goal_estimates.size(), static_cast<std::size_t>(kSteps));
    const Json g = parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm")))
                       .at("humans")
                       .at(0)
                       .at("goal_inference");
    EXPECT_EQ(g.at("candidates"), 2) << most_likely;
    EXPECT_TRUE(g.at("at_round1").is_null()) << most_likely;
    EXPECT_TRUE(g.at("p_at_round1").is_null()) << most_likely;
    EXPECT_EQ(g.at("truth"), 0) << most_likely;
    EXPECT_EQ(g.at("correct"), false) << most_likely;
  }
}

// Strings from the bus printed by the transcript: a newline cannot forge a line, no control
// byte (ESC, CR, C1 CSI) reaches the terminal.
TEST(LogTools, TranscriptEscapesEveryStringFromTheBus) {
  const std::string forged = "x\nt=1.00s  human 1  t_cross=7.00s  SAY INFORM_DIRECTION \"hi\"";
  const std::string hostile = forged +
                              "\x1b[2J\r\x07\x7f\xc2\x9b"
                              "31m\xff";
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    for (int k = 0; k < 3; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      w.put(channels::kSituation, situationAt(k));
    }
    daemon_status_t status{};
    status.utime = utimeOf(1);
    status.name = hostile;
    status.state = daemon_status_t::STATE_DEGRADED;
    status.detail = hostile;
    w.put(channels::kStatus, status);
    w.put(channels::kRobotAction, action(1, robot_action_t::ACTION_DOCK, hostile));
    w.put(channels::kPathAssessorControl,
          control(1, path_assessor_control_t::COMMAND_START, hostile));
    w.put(channels::kUtterance,
          say(1, utterance_t::ACT_INFORM_DIRECTION, situation_t::DIR_LEFT, 1, 7.0, hostile));
    sim_status_t st = simStatus(2, sim_status_t::STATE_GOAL_REACHED, hostile);
    st.scenario = hostile;
    w.put(channels::kSimStatus, st);
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const RunAnalysis a = analyseRun(run);
  TranscriptOptions o;
  o.include_daemon_status = true;
  const std::string t = formatTranscript(a.scenario, buildTranscript(run, a, o));
  // Header, UNKNOWN, ACTION, RECORDER, SAY, DAEMON, SIM: seven lines, each ended by the tool's
  // own newline; the forged "t=1.00s ... SAY" starts none of them.
  EXPECT_EQ(countOf(t, "\n"), 7) << t;
  EXPECT_EQ(countOf(t, "\nt=1.00s"), 0) << t;
  EXPECT_EQ(countOf(t, "\nt=0.10s  human 1  t_cross=7.00s  SAY INFORM_DIRECTION \"x\\nt=1.00s"), 1)
      << t;
  EXPECT_EQ(t.rfind("# scenario x\\nt=1.00s", 0), 0u) << t;
  for (const char c : t) {
    const auto b = static_cast<unsigned char>(c);
    EXPECT_TRUE(c == '\n' || (b >= 0x20 && b != 0x7f)) << "control byte " << int{b} << " in\n" << t;
  }
  EXPECT_EQ(t.find("\xc2\x9b"), std::string::npos) << "C1 CSI reached the output";
  EXPECT_NE(t.find("\\u001b[2J\\r\\u0007\\u007f\\u009b31m\\ufffd"), std::string::npos) << t;
  EXPECT_EQ(printable("a\\b \"q\" \xc3\xa9"), "a\\\\b \"q\" \xc3\xa9");  // UTF-8 kept
  EXPECT_EQ(jsonQuote("\x1b\xc2\x85"), "\"\\u001b\\u0085\"");
}

TEST(LogTools, SummaryCountsWhatTheRobotDidAndSaysWhoTouchedWhom) {
  using C = velocity_command_t;
  // Modes step by step: navigating, docking (2 steps), holding, resuming, docking again,
  // retreating (3 steps), navigating, retreating again; the guard acting on 4 steps.
  const std::vector<std::pair<std::int8_t, std::int8_t>> script = {
      {C::MODE_NAVIGATING, C::GUARD_NONE},   {C::MODE_DOCKING, C::GUARD_NONE},
      {C::MODE_DOCKING, C::GUARD_SLOWED},    {C::MODE_HOLDING, C::GUARD_NONE},
      {C::MODE_RESUMING, C::GUARD_STOPPED},  {C::MODE_DOCKING, C::GUARD_NONE},
      {C::MODE_RETREATING, C::GUARD_NONE},   {C::MODE_RETREATING, C::GUARD_EVADING},
      {C::MODE_RETREATING, C::GUARD_NONE},   {C::MODE_NAVIGATING, C::GUARD_NONE},
      {C::MODE_RETREATING, C::GUARD_SLOWED},
  };
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    for (std::size_t k = 0; k < script.size(); ++k) {
      const int step = static_cast<int>(k);
      w.put(channels::kAgentStates, statesAt(step));
      w.put(channels::kRobotCmd, command(step, script[k].first, script[k].second));
    }
    sim_status_t fin = simStatus(static_cast<int>(script.size()), sim_status_t::STATE_COLLISION,
                                 "human 1 walked into the robot at rest at t 1.05 s");
    fin.min_clearance_m = -0.01;
    fin.min_clearance_t_s = 1.1;
    fin.contact = sim_status_t::CONTACT_HUMAN_AT_FAULT;
    fin.contact_human_id = 1;
    fin.contact_t_s = 1.05;
    fin.contact_robot_speed_m_s = -0.125;
    w.put(channels::kSimStatus, fin);
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.commands.size(), script.size());
  EXPECT_EQ(run.counts.undecodable, 0);
  const RobotBehaviourCounts n = countRobotBehaviour(run);
  EXPECT_EQ(n.commands, static_cast<std::int64_t>(script.size()));
  EXPECT_EQ(n.docks, 2);
  EXPECT_EQ(n.retreats, 2);
  EXPECT_EQ(n.guard_steps, 4);

  const Json s = parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm")));
  EXPECT_EQ(s.at("outcome"), "COLLISION");
  EXPECT_EQ(s.at("final_state"), "COLLISION");
  EXPECT_EQ(s.at("docks"), 2);
  EXPECT_EQ(s.at("retreats"), 2);
  EXPECT_EQ(s.at("guard_steps"), 4);
  EXPECT_DOUBLE_EQ(s.at("min_clearance_m").get<double>(), -0.01);
  EXPECT_DOUBLE_EQ(s.at("min_clearance_t_s").get<double>(), 1.1);
  const Json& c = s.at("contact");
  ASSERT_TRUE(c.is_object());
  EXPECT_EQ(c.at("human_id"), 1);
  EXPECT_DOUBLE_EQ(c.at("t_s").get<double>(), 1.05);
  EXPECT_EQ(c.at("robot_at_fault"), false);
  EXPECT_DOUBLE_EQ(c.at("robot_speed_m_s").get<double>(), -0.125);

  // The robot at fault.
  {
    LogWriter w(dir.file("fault.lcm"));
    sim_status_t fin = simStatus(3, sim_status_t::STATE_COLLISION, "");
    fin.contact = sim_status_t::CONTACT_ROBOT_AT_FAULT;
    fin.contact_human_id = 2;
    fin.contact_t_s = 0.3;
    fin.contact_robot_speed_m_s = 0.4;
    w.put(channels::kSimStatus, fin);
  }
  const RunLog fault = readRunLog(dir.file("fault.lcm"));
  const Json f = parseJson(dumpJson(summarizeRun(fault, analyseRun(fault), "fault.lcm")));
  EXPECT_EQ(f.at("contact").at("robot_at_fault"), true);
  EXPECT_EQ(f.at("contact").at("human_id"), 2);
  EXPECT_EQ(f.at("docks"), 0);
}

TEST(LogTools, ARobotCommandOfAnOlderShapeIsNotNeededNotCorrupt) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    // Another fingerprint (an older velocity_command_t): does not decode as this build's.
    std::vector<std::uint8_t> bytes(50, 0);
    bytes[0] = 0x12;
    w.raw(channels::kRobotCmd, bytes);
    w.put(channels::kRobotCmd, command(0, velocity_command_t::MODE_DOCKING, 0));
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.counts.not_needed, 1);
  EXPECT_EQ(run.counts.undecodable, 0);
  EXPECT_FALSE(run.counts.anyCorruption());
  EXPECT_EQ(countRobotBehaviour(run).docks, 1);
}

TEST(LogTools, CmByGammaIsDiscountedMeanOfTheLoggedCa) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json h =
      parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm"))).at("humans").at(0);
  const Json& window = h.at("cm_by_gamma");
  const Json& inter = h.at("cm_interaction_by_gamma");
  ASSERT_EQ(window.size(), std::size(kSummaryGammas));
  for (const double gamma : kSummaryGammas) {
    char key[16];
    std::snprintf(key, sizeof key, "%.2f", gamma);
    ASSERT_TRUE(window.contains(key)) << key;
    // Shortest round-trip text: the exact double comes back.
    EXPECT_EQ(window.at(key).get<double>(),
              *assessment::discountedMean(run.assessments.back().ca_m, gamma))
        << key;
    EXPECT_EQ(inter.at(key).get<double>(),
              *assessment::discountedMean(interactionCa(kSteps - 1), gamma))
        << key;
  }
  EXPECT_EQ(window.at("0.98").get<double>(), run.assessments.back().cm_m);
}

TEST(LogTools, MergeReplacesTheSameScenarioAndKeepsOrder) {
  const Json a = {{"scenario", "open_facilitating"}, {"x", 1.0}};
  const Json b = {{"scenario", "narrow_minimal"}, {"x", 2.0}};
  const Json a2 = {{"scenario", "open_facilitating"}, {"x", 3.0}};
  const Json merged = mergeSummaries(
      {parseJson(dumpJson(summaryDocument({a, b}))), parseJson(dumpJson(summaryDocument({a2})))});
  const Json& list = merged.at("scenarios");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].at("scenario"), "open_facilitating");
  EXPECT_EQ(list[0].at("x"), 3.0);
  EXPECT_EQ(list[1].at("scenario"), "narrow_minimal");
  EXPECT_THROW(mergeSummaries({Json::object()}), std::runtime_error);
}

TEST(LogTools, SummaryTextSurvivesParseAndDumpUnchanged) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const std::string text = dumpJson(summaryDocument({summarizeRun(run, analyseRun(run), "r.lcm")}));
  EXPECT_EQ(dumpJson(parseJson(text)), text);
  EXPECT_NE(text.find("\"cm_window_m\": "), std::string::npos);
}

TEST(LogTools, JsonNumbersStringsAndNull) {
  EXPECT_EQ(jsonNumber(0.1), "0.1");
  EXPECT_EQ(jsonNumber(0.98), "0.98");
  EXPECT_EQ(jsonNumber(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(jsonNumber(std::nan("")), "null");
  EXPECT_EQ(jsonNumber(-INFINITY), "null");
  EXPECT_EQ(jsonNumber(-0.0), "0");
  EXPECT_EQ(dumpJson(numberOrNull(std::nan(""))), "null\n");
  EXPECT_EQ(dumpJson(numberOrNull(std::optional<double>())), "null\n");
  const std::string tricky = "say \"hi\"\\ \n\t\x01 é";
  EXPECT_EQ(jsonQuote(tricky), "\"say \\\"hi\\\"\\\\ \\n\\t\\u0001 é\"");
  const Json o = {{"s", tricky}, {"n", nullptr}, {"b", true}};
  const Json back = parseJson(dumpJson(o));
  EXPECT_EQ(back.at("s"), tricky);
  EXPECT_TRUE(back.at("n").is_null());
  EXPECT_EQ(back.at("b"), true);
  EXPECT_THROW(parseJson("{\"a\": [1, 2"), std::runtime_error);
  // Not well-formed UTF-8 (a corrupt log's text): written as U+FFFD, so the file stays JSON.
  EXPECT_EQ(jsonQuote("a\xff\xc3"
                      "b\xed\xa0\x80"),
            "\"a\\ufffd\\ufffdb\\ufffd\\ufffd\\ufffd\"");
  EXPECT_EQ(parseJson(dumpJson(Json{{"s",
                                     "a\xff"
                                     "b"}}))
                .at("s"),
            "a\xef\xbf\xbd"
            "b");
}

TEST(LogTools, JsonNumbersReadBackToTheSameText) {
  const std::string text = "[0.1, 0.98, 1e-05, 1e+20, 0.3333333333333333, 12, -3, 0]\n";
  const Json back = parseJson(text);
  EXPECT_EQ(dumpJson(back), text);
  EXPECT_EQ(back.at(0).get<double>(), 0.1);
  EXPECT_EQ(back.at(5), 12);
}

// Given text that YAML (or a lenient reader) accepts but JSON does not, when it is read, then
// reading fails and says where and why.
TEST(LogTools, ReadingRejectsWhatIsNotJson) {
  const char* const kNotJson[] = {
      "{a: 1}",               // YAML flow map: unquoted key
      "{\"a\": 1,}",          // trailing comma in an object
      "[1, 2,]",              // trailing comma in an array
      "a: 1\n",               // YAML block map
      "- 1\n- 2\n",           // YAML block sequence
      "{'a': 1}",             // single quotes
      "{\"a\": 1} # note",    // comment
      "// note\n{\"a\": 1}",  // comment
      "{\"a\": ~}",           // YAML null
      "{\"a\": .inf}",        // YAML infinity
      "{\"a\": NaN}",         // not a JSON number
      "{\"a\": 0x10}",        // hexadecimal
      "{\"a\": 01}",          // leading zero
      "{\"a\": yes}",         // YAML 1.1 boolean
      "{\"a\": 1e999}",       // no double holds it
      "{\"a\": \"\xff\"}",    // not UTF-8
      "{} {}",                // two documents
      "",                     // nothing
  };
  for (const char* text : kNotJson) {
    try {
      (void)parseJson(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("invalid JSON: ", 0), 0u) << what;
      EXPECT_EQ(what.find("[json.exception"), std::string::npos) << what;
    }
  }
  try {
    (void)parseJson("{a: 1}");
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "invalid JSON: parse error at line 1, column 2: syntax error while parsing "
                 "object key - invalid literal; last read: '{a'; expected string literal");
  }

  // A summary file names itself in the error.
  TempDir dir;
  {
    std::ofstream out(dir.file("summary.json"));
    out << "{\"format\": \"coopnav-summary/1\", \"scenarios\": [],}\n";
  }
  try {
    (void)readSummaryFile(dir.file("summary.json"));
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(dir.file("summary.json") + ": invalid JSON: parse error at line 1", 0), 0u)
        << what;
  }
}

TEST(LogTools, CmTableSitsBesideTableI) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json other = {{"scenario", "narrow_minimal"}, {"humans", Json::array()}};
  const Json doc = summaryDocument({other, summarizeRun(run, analyseRun(run), "run.lcm")});
  const std::string table = formatCmTable(parseJson(dumpJson(doc)));
  std::istringstream lines(table);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 6u) << table;  // 3 notes, header, 2 rows
  // What ran, from the logged assessment (not the paper's values assumed).
  EXPECT_EQ(rows[2], "Ran with: gamma 0.98, tau 0.40 m (fixed), profile paper.") << table;
  // Table I order: open before narrow, whatever the file order.
  EXPECT_EQ(rows[4].rfind("open_facilitating", 0), 0u) << rows[4];
  EXPECT_NE(rows[4].find(" 0.81 "), std::string::npos) << rows[4];  // ours (interaction)
  EXPECT_NE(rows[4].find(" 0.94 "), std::string::npos) << rows[4];  // paper
  EXPECT_NE(rows[4].find(" 0.90 "), std::string::npos) << rows[4];  // window
  EXPECT_NE(rows[4].find("TRUE"), std::string::npos);
  EXPECT_NE(rows[4].find("GOAL_REACHED"), std::string::npos);
  EXPECT_EQ(rows[5].rfind("narrow_minimal", 0), 0u) << rows[5];
  EXPECT_NE(rows[5].find(" 0.05 "), std::string::npos) << rows[5];
  EXPECT_DOUBLE_EQ(paperTableCm("open_minimal"), 0.15);
  EXPECT_DOUBLE_EQ(paperTableCm("narrow_facilitating"), 0.49);
  EXPECT_TRUE(std::isnan(paperTableCm("walls_oblivious")));
}

// coopnav_ctl trace: what the figures are drawn from (tools/exp/coopnav_exp/figures.py).
TEST(LogTools, TraceHoldsStatesAssessmentsWordsAndWhenEachCaSampleWasTaken) {
  TempDir dir;
  writeScriptedRun(dir.file("run.lcm"));
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const RunAnalysis a = analyseRun(run);
  const Json doc = traceDocument(run, a, dir.file("run.lcm"), "");
  EXPECT_EQ(doc.at("format"), "coopnav-trace");
  EXPECT_EQ(doc.at("scenario"), "open_facilitating");
  EXPECT_EQ(doc.at("robot").at("t_s").size(), static_cast<std::size_t>(kSteps));
  EXPECT_EQ(doc.at("robot").at("x_m").size(), static_cast<std::size_t>(kSteps));
  ASSERT_EQ(doc.at("humans").size(), 1u);
  EXPECT_EQ(doc.at("humans").at(0).at("id"), 1);
  ASSERT_EQ(doc.at("utterances").size(), 3u);
  EXPECT_EQ(doc.at("utterances").at(0).at("act"), "INFORM_DIRECTION");
  EXPECT_DOUBLE_EQ(doc.at("utterances").at(0).at("t_s").get<double>(), 1.0);
  EXPECT_EQ(doc.at("utterances").at(1).at("text"), "I will wait here for you to pass.");
  ASSERT_EQ(doc.at("actions").size(), 2u);
  EXPECT_EQ(doc.at("actions").at(0).at("action"), "DOCK");
  EXPECT_DOUBLE_EQ(doc.at("actions").at(0).at("t_s").get<double>(), 4.0);
  EXPECT_TRUE(doc.at("map").is_null());
  EXPECT_EQ(doc.at("outcome").at("state"), "GOAL_REACHED");

  ASSERT_EQ(doc.at("assessments").size(), 1u);
  const Json& h = doc.at("assessments").at(0);
  EXPECT_EQ(h.at("profile"), "paper");
  EXPECT_EQ(h.at("t_s").size(), static_cast<std::size_t>(kSteps - kStartStep));
  const Json& ca = h.at("ca");
  EXPECT_TRUE(ca.at("whole_interaction").get<bool>());
  ASSERT_EQ(ca.at("ca_m").size(), a.humans.at(0).interaction_ca_m.size());
  ASSERT_EQ(ca.at("t_s").size(), ca.at("ca_m").size());
  // Sample k was taken when the interaction count reached k + 1: the assessments' own times.
  std::size_t checked = 0;
  for (const auto& p : run.assessments) {
    if (p.interaction_samples < 1 ||
        static_cast<std::size_t>(p.interaction_samples) > ca.at("t_s").size())
      continue;
    EXPECT_DOUBLE_EQ(ca.at("t_s").at(p.interaction_samples - 1).get<double>(), utimeToS(p.utime));
    ++checked;
  }
  EXPECT_GT(checked, 40u);
  EXPECT_EQ(ca.at("window_start_t_s").size(), a.humans.at(0).window_starts.size());
  // CM against γ by the path assessor's formula, at 0.98 among others.
  const Json& cg = h.at("cm_by_gamma");
  ASSERT_EQ(cg.at("gamma").size(), 51u);
  EXPECT_NEAR(cg.at("gamma").at(48).get<double>(), 0.98, 1e-12);
  EXPECT_DOUBLE_EQ(cg.at("cm_m").at(48).get<double>(),
                   *assessment::discountedMean(a.humans.at(0).interaction_ca_m,
                                               cg.at("gamma").at(48).get<double>()));
  EXPECT_FALSE(h.at("first_round").is_null());

  // Same messages, same bytes, whatever the wall clock and the interleaving across daemons.
  WriteOptions other;
  other.shuffle = true;
  other.timestamp0 = 42;
  writeScriptedRun(dir.file("b.lcm"), other);
  const RunLog run_b = readRunLog(dir.file("b.lcm"));
  Json doc_b = traceDocument(run_b, analyseRun(run_b), dir.file("b.lcm"), "");
  doc_b["log"] = doc.at("log");
  EXPECT_EQ(dumpJson(doc_b), dumpJson(doc));
}

TEST(LogTools, TraceModesAreTheBandSourcesChanges) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    const std::int8_t modes[] = {
        velocity_command_t::MODE_NAVIGATING, velocity_command_t::MODE_NAVIGATING,
        velocity_command_t::MODE_DOCKING,    velocity_command_t::MODE_HOLDING,
        velocity_command_t::MODE_HOLDING,    velocity_command_t::MODE_RESUMING};
    for (int k = 0; k < 6; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      w.put(channels::kRobotCmd, command(k, modes[k], velocity_command_t::GUARD_NONE));
    }
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json doc = traceDocument(run, analyseRun(run), dir.file("run.lcm"), "");
  const Json& m = doc.at("modes");
  ASSERT_EQ(m.size(), 4u) << dumpJson(m);
  EXPECT_EQ(m.at(0).at("mode"), "navigating");
  EXPECT_EQ(m.at(1).at("mode"), "docking");
  EXPECT_EQ(m.at(2).at("mode"), "holding");
  EXPECT_EQ(m.at(3).at("mode"), "resuming");
  EXPECT_DOUBLE_EQ(m.at(2).at("t_s").get<double>(), 0.3);
}

// The map as the scenario gives it: its walls, and the grid the daemons load, cell by cell.
TEST(LogTools, TraceMapIsTheScenarioMapWithItsWallsAndGrid) {
  TempDir dir;
  {
    std::ofstream out(dir.file("corridor.yaml"));
    out << "name: corridor\nmap:\n  resolution_m: 0.1\n  walls:\n"
           "    - {x0_m: 0, y0_m: 0, x1_m: 10, y1_m: 0}\n"
           "    - {x0_m: 0, y0_m: 2, x1_m: 10, y1_m: 2, thickness_m: 0.2}\n";
  }
  const Json m = traceMap(dir.file("corridor.yaml"));
  ASSERT_EQ(m.at("walls").size(), 2u);
  EXPECT_EQ(m.at("walls").at(1), Json::parse("[0, 2, 10, 2]"));
  EXPECT_TRUE(m.at("file").is_null());
  EXPECT_DOUBLE_EQ(m.at("resolution_m").get<double>(), 0.1);
  const LoadedMap loaded = loadMap(dir.file("corridor.yaml"));
  const OccupancyGrid2& g = loaded.grid;
  EXPECT_EQ(m.at("width"), g.width());
  EXPECT_EQ(m.at("height"), g.height());
  std::size_t cells = 0;
  for (const auto& run : m.at("obstacle_runs")) {
    const int j = run.at(0), i0 = run.at(1), i1 = run.at(2);
    for (int i = i0; i < i1; ++i) EXPECT_NE(g.at(i, j), CellState::kFree) << i << " " << j;
    cells += static_cast<std::size_t>(i1 - i0);
  }
  EXPECT_EQ(cells, g.size() - g.count(CellState::kFree));
  EXPECT_GT(cells, 0u);

  // A scenario naming a ROS map: the file it names, resolved against the scenario's folder.
  const Json ros = traceMap(::coopnav::test::sourceDir() + "/config/scenarios/narrow_minimal.yaml");
  EXPECT_EQ(fs::path(ros.at("file").get<std::string>()).filename().string(), "open.yaml");
  EXPECT_TRUE(fs::exists(ros.at("file").get<std::string>()));
  EXPECT_DOUBLE_EQ(ros.at("resolution_m").get<double>(), 0.05);
  EXPECT_EQ(ros.at("origin_m"), Json::parse("[-5, -10]"));
  EXPECT_TRUE(ros.at("walls").empty());
  EXPECT_THROW(traceMap(dir.file("absent.yaml")), std::exception);
}

TEST(LogTools, BrokenLogIsSkippedAndCountedNotFatal) {
  TempDir dir;
  const std::string path = dir.file("broken.lcm");
  {
    LogWriter w(path);
    w.put(channels::kAgentStates, statesAt(0));
    // Right channel, wrong bytes: does not decode.
    w.raw(channels::kUtterance, {0xde, 0xad, 0xbe, 0xef, 0, 1, 2, 3, 4});
    // A valid message of another type on the utterance channel: fingerprint mismatch.
    w.put(channels::kUtterance, statesAt(1));
    // Garbage between events, then a header claiming an impossible channel length.
    w.garbage({0x00, 0x11, 0x22, 0x33, 0x44});
    w.garbage({0xED, 0xA1, 0xDA, 0x01, 0, 0, 0,    0,    0,    0,    0, 9, 0, 0,
               0,    0,    0,    0,    0, 1, 0x7f, 0xff, 0xff, 0xff, 0, 0, 0, 4});
    dialogueAt(w, kStartStep);
    // A negative array count: the generated decoder throws, which must be caught.
    auto bad = statesAt(2);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(bad.getEncodedSize()));
    bad.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    // num_humans sits after the fingerprint (8), utime, step (16) and the robot (4+1+7*8).
    const std::size_t num_humans_at = 8 + 16 + 4 + 1 + 7 * 8;
    bytes[num_humans_at] = 0xff;
    bytes[num_humans_at + 1] = 0xff;
    w.raw(channels::kAgentStates, bytes);
    w.put(channels::kSituation, situationAt(kStartStep));
    // The last event cut short: a plausible header whose payload runs past the end.
    w.garbage({0xED, 0xA1, 0xDA, 0x01, 0, 0, 0, 0, 0, 0, 0, 9,    0, 0,   0,
               0,    0,    0,    0,    1, 0, 0, 0, 4, 0, 0, 0x10, 0, 'C', 'O'});
  }
  RunLog run;
  ASSERT_NO_THROW(run = readRunLog(path));
  EXPECT_EQ(run.agent_states.size(), 1u);
  EXPECT_EQ(run.controls.size(), 1u);
  EXPECT_EQ(run.utterances.size(), 1u);
  EXPECT_EQ(run.situations.size(), 1u);
  EXPECT_EQ(run.counts.undecodable, 3);
  EXPECT_EQ(run.counts.undecodable_by_channel.at(channels::kUtterance), 2);
  EXPECT_EQ(run.counts.undecodable_by_channel.at(channels::kAgentStates), 1);
  EXPECT_EQ(run.counts.bad_headers, 1);
  EXPECT_GE(run.counts.skipped_bytes, 5);
  EXPECT_TRUE(run.counts.truncated);
  EXPECT_TRUE(run.counts.anyCorruption());
  EXPECT_NE(run.counts.describe().find("undecodable 3"), std::string::npos);

  const RunAnalysis a = analyseRun(run);
  const std::string t = formatTranscript(a.scenario, buildTranscript(run, a));
  EXPECT_EQ(t,
            "# scenario (unnamed)\n"
            "t=1.00s  human 1  t_cross=7.00s  RECORDER START (why: round 1)\n"
            "t=1.00s  human 1  t_cross=7.00s  SAY INFORM_DIRECTION \"I will pass on your left.\" "
            "(round 1, direction left)\n");
  EXPECT_NO_THROW(summarizeRun(run, a, "broken.lcm").dump());
  EXPECT_NO_THROW(dumpJson(traceDocument(run, a, dir.file("broken.lcm"), "")));
}

TEST(LogTools, MissingOrEmptyLog) {
  TempDir dir;
  EXPECT_THROW(readRunLog(dir.file("absent.lcm")), std::runtime_error);
  { std::ofstream(dir.file("empty.lcm")); }
  const RunLog run = readRunLog(dir.file("empty.lcm"));
  EXPECT_EQ(run.counts.events, 0);
  EXPECT_FALSE(run.counts.anyCorruption());
  const RunAnalysis a = analyseRun(run);
  EXPECT_EQ(formatTranscript("x", buildTranscript(run, a)), "# scenario x\n");
  // A trace of nothing is still a trace: no states, no words.
  const Json doc = traceDocument(run, a, dir.file("empty.lcm"), "");
  EXPECT_TRUE(doc.at("robot").at("t_s").empty());
  EXPECT_TRUE(doc.at("utterances").empty());
}

// What a fault run is judged by (scripts/coopnav faults) is in summary.json, never read from the
// transcript's text: restarts, degraded daemons, crossings with unknown obstacle distances, and
// a precautionary dock marked degraded.
TEST(LogTools, SummaryNamesRestartsDegradedDaemonsAndUnknownDistances) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    daemon_status_t st{};
    st.name = "situation_assessor";
    st.state = daemon_status_t::STATE_DEGRADED;
    st.detail = "distance server: no answer";
    for (int k = 0; k < 12; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      situation_t sit = situationAt(k + 5);  // crossings found, distances known
      sit.utime = utimeOf(k);
      sit.step = k;
      if (k >= 8) {
        sit.d_oh_m = std::nan("");     // the distance server did not answer in time
        w.put(channels::kStatus, st);  // twice the same: named once
      }
      w.put(channels::kSituation, sit);
      if (k == 6) {
        step_ack_t ack{};
        ack.utime = utimeOf(k);
        ack.step = k;
        ack.participant = "band_source";
        ack.restart = step_ack_t::RESTART_RECOVERED;
        ack.restart_step = k;
        ack.restart_note = "journal of 6 steps replayed";
        w.put(channels::kStepAck, ack);
        w.put(channels::kStepAck, ack);  // the same restart's next ack: one restart
      }
      if (k == 10)
        w.put(channels::kRobotAction,
              action(k, robot_action_t::ACTION_DOCK,
                     "needs ? -> degraded: precautionary dock (d_OR unknown)"));
    }
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  const Json s = parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm")));
  const Json& f = s.at("faults");
  ASSERT_EQ(f.at("restarts").size(), 1u);
  EXPECT_EQ(f.at("restarts").at(0).at("participant"), "band_source");
  EXPECT_EQ(f.at("restarts").at(0).at("step"), 6);
  EXPECT_EQ(f.at("restarts").at(0).at("recovered"), true);
  EXPECT_EQ(f.at("restarts").at(0).at("note"), "journal of 6 steps replayed");
  ASSERT_EQ(f.at("degraded_daemons").size(), 1u);
  EXPECT_EQ(f.at("degraded_daemons").at(0).at("name"), "situation_assessor");
  EXPECT_EQ(f.at("crossing_situations"), 12);
  EXPECT_EQ(f.at("crossing_distance_unknown"), 4);
  const Json& entries = s.at("humans").at(0).at("transcript");
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries.at(0).at("action"), "DOCK");
  EXPECT_EQ(entries.at(0).at("degraded"), true);
}

// Who answered the lockstep how far (scripts/coopnav multihost: a cut-off participant), from the
// step acks: the highest step per participant, "I am here" acks (-1) not counted.
TEST(LogTools, SummaryNamesTheLastStepEachParticipantAcknowledged) {
  TempDir dir;
  {
    LogWriter w(dir.file("run.lcm"));
    auto ack = [&](const char* who, std::int64_t step) {
      step_ack_t a{};
      a.utime = step >= 0 ? utimeOf(static_cast<int>(step)) : 0;
      a.step = step;
      a.participant = who;
      w.put(channels::kStepAck, a);
    };
    ack("world_sim", -1);
    ack("path_assessor", -1);
    for (int k = 0; k < 10; ++k) {
      w.put(channels::kAgentStates, statesAt(k));
      ack("world_sim", k);
      if (k <= 6) ack("path_assessor", k);  // cut off after step 6
      ack("dialogue_manager", k);           // went on without it
    }
    ack("dialogue_manager", 3);  // a late repeat of an old step: not the last one
  }
  const RunLog run = readRunLog(dir.file("run.lcm"));
  EXPECT_EQ(run.counts.undecodable, 0);
  const Json s = parseJson(dumpJson(summarizeRun(run, analyseRun(run), "run.lcm")));
  const Json& last = s.at("faults").at("last_acked_step");
  ASSERT_EQ(last.size(), 3u);
  EXPECT_EQ(last.at("world_sim"), 9);
  EXPECT_EQ(last.at("path_assessor"), 6);
  EXPECT_EQ(last.at("dialogue_manager"), 9);
}

}  // namespace
}  // namespace coopnav::ctl
