// coopnav_ctl metrics on a synthetic log: the tracks, goal, outcome and CM it reads, and the
// JSON / CSV it writes (the metrics themselves: test/unit/metrics).
#include "run_metrics_export.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "coopnav/channels.hpp"
#include "coopnav/goals_t.hpp"

namespace coopnav::ctl {
namespace {

namespace fs = std::filesystem;

class MetricsLog {
 public:
  explicit MetricsLog(const std::string& path) : log_(path, "w") {}
  template <class Msg>
  void put(const std::string& channel, const Msg& msg) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    lcm::LogEvent e{0, stamp_, channel, static_cast<std::int32_t>(buf.size()), buf.data()};
    stamp_ += 1000;
    log_.writeEvent(&e);
  }

 private:
  lcm::LogFile log_;
  std::int64_t stamp_{1'700'000'000'000'000};
};

agent_state_t agentAt(std::int32_t id, double x, double y, double vx) {
  agent_state_t a{};
  a.id = id;
  a.kind = id == 0 ? agent_state_t::KIND_ROBOT : agent_state_t::KIND_HUMAN;
  a.x_m = x;
  a.y_m = y;
  a.vx_m_s = vx;
  a.theta_rad = vx >= 0 ? 0.0 : M_PI;
  a.radius_m = 0.3;
  return a;
}

/// The robot drives 1 m/s along +x from 0 to its goal at x 5 (t 5 s); a person walks -x from
/// x 10 at 1 m/s, 1 m to the side: at t 5 s they are abreast, 0.4 m apart surface to surface.
std::string writeRun(const fs::path& dir) {
  std::string path = (dir / "run.lcm").string();
  MetricsLog log(path);
  goals_t goals{};
  goal_t g{};
  g.agent_id = 0;
  g.kind = agent_state_t::KIND_ROBOT;
  g.x_m = 5.0;
  g.theta_rad = std::nan("");
  goals.goals.push_back(g);
  goals.num_goals = 1;
  log.put(channels::kGoals, goals);
  for (int k = 0; k <= 50; ++k) {
    agent_states_t s{};
    s.utime = k * 100000;
    s.step = k;
    s.robot = agentAt(0, 0.1 * k, 0.0, 1.0);
    s.humans.push_back(agentAt(1, 10.0 - 0.1 * k, 1.0, -1.0));
    s.num_humans = 1;
    log.put(channels::kAgentStates, s);
  }
  path_assessment_t p{};
  p.utime = 4'000'000;
  p.human_id = 1;
  p.cm_m = 0.25;
  p.cm_interaction_m = 0.5;
  p.is_contributing_interaction = situation_t::PRED_TRUE;
  p.p_contributing = 0.75;
  p.profile = "paper";
  log.put(channels::kPathAssessment, p);
  sim_status_t st{};
  st.utime = 5'000'000;
  st.step = 50;
  st.state = sim_status_t::STATE_GOAL_REACHED;
  st.scenario = "synthetic";
  st.robot_time_to_goal_s = 5.0;
  st.min_clearance_t_s = 5.0;
  st.contact_human_id = -1;
  st.contact_t_s = std::nan("");
  st.contact_robot_speed_m_s = std::nan("");
  log.put(channels::kSimStatus, st);
  return path;
}

TEST(RunMetricsExport, ScoresARecordedRun) {
  const fs::path dir =
      fs::temp_directory_path() / ("coopnav_metrics_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = writeRun(dir);

  const RunLog run = readRunLog(path);
  const RunAnalysis analysis = analyseRun(run);
  const auto goal = robotGoalFromLog(path);
  ASSERT_TRUE(goal.has_value());
  EXPECT_DOUBLE_EQ(goal->x(), 5.0);
  const metrics::RunInput in = metricsInput(run, analysis, goal, nullptr);
  ASSERT_EQ(in.frames.size(), 51u);
  EXPECT_EQ(in.outcome, metrics::Outcome::kGoalReached);
  EXPECT_DOUBLE_EQ(in.goal_time_s, 5.0);
  EXPECT_TRUE(in.wall_clearance_m.empty());

  const Json e = metricsEntry(run, analysis, metrics::computeRunMetrics(in), "run.lcm", false);
  EXPECT_EQ(e["scenario"], "synthetic");
  EXPECT_EQ(e["outcome"], "GOAL_REACHED");
  EXPECT_EQ(e["success"], true);
  EXPECT_NEAR(e["path_length_m"].get<double>(), 5.0, 1e-9);
  EXPECT_NEAR(e["spl"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(e["time_to_goal_s"].get<double>(), 5.0, 1e-9);
  EXPECT_NEAR(e["min_distance_to_person_m"].get<double>(), 0.4, 1e-9);
  EXPECT_TRUE(e["wall_collisions"].is_null());  // no map given
  ASSERT_EQ(e["persons"].size(), 1u);
  const Json& p = e["persons"][0];
  EXPECT_EQ(p["id"], 1);
  EXPECT_EQ(p["cm_interaction_m"], 0.5);
  EXPECT_EQ(p["is_contributing_interaction"], true);
  EXPECT_TRUE(p["robot_responsibility"].is_null());  // both kept their course
  EXPECT_GT(p["max_conflict_intensity"].get<double>(), 0.0);

  const std::string csv = metricsCsv({e, e});
  const auto header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.rfind("scenario,log,outcome,map,success,", 0), 0u) << header;
  EXPECT_NE(header.find(",person1_robot_responsibility,"), std::string::npos);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);  // header and two runs
  const std::string doc = dumpJson(metricsDocument({e}));
  EXPECT_EQ(parseJson(doc)["format"], kMetricsFormat);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace coopnav::ctl
