// Scenario files of world_sim (daemons/world_sim/scenario.{hpp,cpp}, in the world_sim_node
// library, hence a node-tier test although it opens no LCM): a complete file loads into the
// struct; each kind of mistake gives one clear message naming the file, the key, the value and
// what is allowed.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "coopnav/distance/grid_distance_field.hpp"
#include "scenario.hpp"
#include "test_paths.hpp"

namespace coopnav::world_sim {
namespace {

namespace fs = std::filesystem;

const char* kValid = R"(
name: corridor_facilitating
seed: 7
time_limit_s: 40.0
map:
  walls:
    - {x0_m: -1, y0_m: 0, x1_m: 30, y1_m: 0, thickness_m: 0.2}
    - {x0_m: -1, y0_m: 6, x1_m: 30, y1_m: 6}
rates: {physics_hz: 40, publish_hz: 10}
lockstep: {enabled: true, participants: [band_source, dialogue_manager], step_timeout_s: 5}
robot:
  start: {x_m: 1, y_m: 3, theta_rad: 0}
  goal: {x_m: 25, y_m: 3}
  radius_m: 0.4
  kinematics: holonomic
  limits: {max_forward_m_s: 0.7, max_acc_forward_m_s2: 0.5}
humans:
  - id: 1
    start: {x_m: 25, y_m: 3, theta_rad: 3.14159}
    goal: {x_m: 1, y_m: 3}
    via: [{x_m: 13, y_m: 3}]
    behaviour: facilitating
    speed_m_s: 1.1
    params: {trigger_ttc_s: 4.5, yield: {offset_m: 0.8}}
  - id: 2
    start: {x_m: 28, y_m: 2}
    goal: {x_m: 2, y_m: 2}
    behaviour: social_force
    params: {robot_weight: 3.0}
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

/// The error message of parsing `text`, or "" when it parses.
std::string errorOf(const std::string& text) {
  try {
    parseScenario(text, "bad.yaml", ".");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(Scenario, ValidFileLoadsWithDefaultsForOmittedKeys) {
  const Scenario sc = parseScenario(kValid, "ok.yaml", ".");
  EXPECT_EQ(sc.name, "corridor_facilitating");
  EXPECT_EQ(sc.seed, 7u);
  EXPECT_EQ(sc.map.walls.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.map.walls[1].thickness_m, WallSegment{}.thickness_m);
  EXPECT_EQ(sc.lockstep.participants,
            (std::vector<std::string>{"band_source", "dialogue_manager"}));
  EXPECT_EQ(sc.robot.kinematics, sim::Kinematics::kHolonomic);
  EXPECT_DOUBLE_EQ(sc.robot.limits.max_forward_m_s, 0.7);
  EXPECT_DOUBLE_EQ(sc.robot.limits.max_omega_rad_s, sim::RobotLimits{}.max_omega_rad_s);
  ASSERT_EQ(sc.humans.size(), 2u);
  EXPECT_EQ(sc.humans[0].behaviour.type, sim::BehaviourType::kFacilitating);
  EXPECT_DOUBLE_EQ(sc.humans[0].behaviour.facilitating.trigger_ttc_s, 4.5);
  EXPECT_DOUBLE_EQ(sc.humans[0].behaviour.facilitating.yield.offset_m, 0.8);
  EXPECT_DOUBLE_EQ(sc.humans[0].behaviour.facilitating.yield.wall_margin_m,
                   sim::YieldParams{}.wall_margin_m);
  EXPECT_EQ(sc.humans[0].via.size(), 1u);
  EXPECT_DOUBLE_EQ(sc.humans[1].speed_m_s, sim::HumanSpec{}.speed_m_s);
  EXPECT_DOUBLE_EQ(sc.humans[1].behaviour.social_force.robot_weight, 3.0);

  const sim::WorldSpec w = toWorldSpec(sc);
  EXPECT_DOUBLE_EQ(w.settings.physics_dt_s, 0.025);
  EXPECT_EQ(w.settings.substeps_per_step, 4);
  // The walls of the file, rasterised as the daemon does (free for y in (0.1, 5.9)).
  const GridDistanceField map(loadScenarioMap(sc).grid);
  EXPECT_NO_THROW(checkScenarioAgainstMap(sc, map));
  sim::Simulation simulation(w, &map);  // a loaded scenario is a valid world
  EXPECT_EQ(simulation.agents().size(), 3u);
}

struct BadCase {
  const char* what;
  std::string from, to;
  std::vector<std::string> expect;  ///< substrings of the message
};

TEST(Scenario, EachMistakeGivesAClearError) {
  const std::vector<BadCase> cases = {
      {"missing key", "  goal: {x_m: 25, y_m: 3}\n", "", {"bad.yaml", "'robot.goal'", "missing"}},
      {"missing human key",
       "    behaviour: social_force\n",
       "",
       {"'humans[1].behaviour'", "missing"}},
      {"wrong type", "seed: 7", "seed: seven", {"'seed'", "seven", "wrong type"}},
      {"unknown key", "  radius_m: 0.4", "  radius: 0.4", {"'robot.radius'", "not a known key"}},
      {"unknown behaviour",
       "behaviour: facilitating",
       "behaviour: teleport",
       {"'humans[0].behaviour'", "teleport", "minimal", "responsive"}},
      {"negative speed",
       "speed_m_s: 1.1",
       "speed_m_s: -1.0",
       {"'humans[0].speed_m_s'", "-1.0", "[0, 3]"}},
      {"duplicate id", "  - id: 2", "  - id: 1", {"'humans[1].id'", "duplicates humans[0].id"}},
      {"unknown param",
       "trigger_ttc_s: 4.5",
       "trigger_ttc: 4.5",
       {"'humans[0].params.trigger_ttc'", "not a known key"}},
      {"param out of range",
       "offset_m: 0.8",
       "offset_m: 9",
       {"'humans[0].params.yield.offset_m'", "[0, 3]"}},
      {"two maps", "map:\n", "map:\n  file: open.yaml\n", {"'map.'", "exactly one"}},
      {"bad rate ratio", "publish_hz: 10", "publish_hz: 15", {"'rates.physics_hz'", "multiple"}},
      {"slow physics", "physics_hz: 40", "physics_hz: 10", {"'rates.physics_hz'", "[20, 2000]"}},
      {"bad kinematics",
       "kinematics: holonomic",
       "kinematics: tracked",
       {"'robot.kinematics'", "differential, holonomic"}},
      {"bad planner",
       "trigger_ttc_s: 4.5",
       "planner: cohan",
       {"'humans[0].params.planner'", "analytic, band"}},
      {"humans not a list", "humans:\n", "humans: 3\nx_humans:\n", {"'humans'", "list"}},
      // A key that is no name threw out of the reader's destructor (found by fuzz_scenario).
      {"key not a name", "seed: 7", "seed: 7\n[a, b]: 1", {"bad.yaml", "not a name (line"}},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string msg = errorOf(replaced(kValid, c.from, c.to));
    ASSERT_FALSE(msg.empty());
    for (const auto& s : c.expect) EXPECT_NE(msg.find(s), std::string::npos) << msg;
  }
}

TEST(Scenario, StandstillAndBodyCheckKeysLoadAndAreChecked) {
  // Left out: lib/sim's defaults.
  const Scenario plain = parseScenario(kValid, "ok.yaml", ".");
  EXPECT_DOUBLE_EQ(plain.standstill_time_s, sim::SimSettings{}.standstill_time_s);
  EXPECT_DOUBLE_EQ(plain.standstill_distance_m, sim::SimSettings{}.standstill_distance_m);
  EXPECT_DOUBLE_EQ(plain.humans[0].behaviour.body_check.squeeze_margin_m,
                   sim::BodyCheckParams{}.squeeze_margin_m);
  // Given: into the world spec and the human's behaviour config.
  std::string text = replaced(kValid, "time_limit_s: 40.0\n",
                              "time_limit_s: 40.0\nstandstill_time_s: 8\n"
                              "standstill_distance_m: 0.2\n");
  text = replaced(text, "    speed_m_s: 1.1\n",
                  "    speed_m_s: 1.1\n    body_check: {squeeze_margin_m: 0.1, wait_gap_m: 0.5}\n");
  const Scenario sc = parseScenario(text, "ok.yaml", ".");
  const sim::WorldSpec w = toWorldSpec(sc);
  EXPECT_DOUBLE_EQ(w.settings.standstill_time_s, 8.0);
  EXPECT_DOUBLE_EQ(w.settings.standstill_distance_m, 0.2);
  EXPECT_DOUBLE_EQ(w.humans[0].behaviour.body_check.squeeze_margin_m, 0.1);
  EXPECT_DOUBLE_EQ(w.humans[0].behaviour.body_check.wait_gap_m, 0.5);
  EXPECT_DOUBLE_EQ(w.humans[0].behaviour.body_check.engage_distance_m,
                   sim::BodyCheckParams{}.engage_distance_m);
  // Out of range, unknown: named.
  std::string msg = errorOf(replaced(text, "standstill_time_s: 8", "standstill_time_s: -1"));
  EXPECT_NE(msg.find("'standstill_time_s'"), std::string::npos) << msg;
  msg = errorOf(replaced(text, "wait_gap_m: 0.5", "wait_gap: 0.5"));
  EXPECT_NE(msg.find("'humans[0].body_check.wait_gap'"), std::string::npos) << msg;
  msg = errorOf(replaced(text, "squeeze_margin_m: 0.1", "squeeze_margin_m: 2"));
  EXPECT_NE(msg.find("'humans[0].body_check.squeeze_margin_m'"), std::string::npos) << msg;
}

TEST(Scenario, SyntaxErrorNamesTheLine) {
  const std::string msg = errorOf("name: x\nseed: [1,\n");
  EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line"), std::string::npos) << msg;
}

TEST(Scenario, StartInsideAWallIsRejectedAgainstTheMap) {
  Scenario sc = parseScenario(kValid, "walls.yaml", ".");
  sc.humans[1].start.y_m = 0.05;  // inside the lower wall
  sc.robot.goal.y_m = 5.7;        // free but closer to the wall than the robot's radius
  const GridDistanceField map(loadScenarioMap(sc).grid);
  try {
    checkScenarioAgainstMap(sc, map);
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'humans[1].start'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not in free space"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'robot.goal'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("radius"), std::string::npos) << msg;
  }
}

TEST(Scenario, LoadsFromFileAndResolvesTheMapPath) {
  const fs::path dir =
      fs::temp_directory_path() / ("coopnav_scenario_" + std::to_string(::getpid()));
  fs::create_directories(dir / "maps");
  std::ofstream(dir / "maps" / "m.yaml") << "image: m.pgm\n";
  const std::string text =
      replaced(kValid,
               "map:\n  walls:\n    - {x0_m: -1, y0_m: 0, x1_m: 30, y1_m: 0, thickness_m: 0.2}\n"
               "    - {x0_m: -1, y0_m: 6, x1_m: 30, y1_m: 6}\n",
               "map:\n  file: maps/m.yaml\n");
  std::ofstream(dir / "s.yaml") << text;
  const Scenario sc = loadScenario((dir / "s.yaml").string());
  EXPECT_EQ(fs::path(sc.map.file), (dir / "maps" / "m.yaml").lexically_normal());

  // A directory where the scenario file should be (it opens, and fails at the first read).
  try {
    loadScenario((dir / "maps").string());
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }

  // A map file name the system refuses (ENAMETOOLONG): does not exist, no filesystem_error.
  try {
    parseScenario(replaced(text, "maps/m.yaml", "maps/" + std::string(300, 'A') + ".yaml"),
                  "long.yaml", dir.string());
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }

  std::ofstream(dir / "bad.yaml") << replaced(text, "maps/m.yaml", "maps/none.yaml");
  try {
    loadScenario((dir / "bad.yaml").string());
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'map.file'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  }
  EXPECT_THROW(loadScenario((dir / "absent.yaml").string()), ScenarioError);
  fs::remove_all(dir);
}

TEST(Scenario, TrackerAndGoalKeysLoadAndAreChecked) {
  // Left out: the tracker is off and the goals are published.
  const Scenario plain = parseScenario(kValid, "ok.yaml", ".");
  EXPECT_FALSE(plain.tracker.active());
  EXPECT_TRUE(plain.publish_human_goals);
  const std::string text = replaced(
      kValid, "time_limit_s: 40.0\n",
      "time_limit_s: 40.0\npublish_human_goals: false\n"
      "tracker: {position_sigma_m: 0.05, miss_probability: 0.05, id_switches: 1, range_m: 12,\n"
      "          velocity_window_steps: 4, drop_after_s: 0.5, id_switch_window_s: 20}\n");
  const Scenario sc = parseScenario(text, "ok.yaml", ".");
  EXPECT_FALSE(sc.publish_human_goals);
  EXPECT_TRUE(sc.tracker.active());
  EXPECT_DOUBLE_EQ(sc.tracker.position_sigma_m, 0.05);
  EXPECT_DOUBLE_EQ(sc.tracker.miss_probability, 0.05);
  EXPECT_EQ(sc.tracker.id_switches, 1);
  EXPECT_EQ(sc.tracker.velocity_window_steps, 4);
  EXPECT_DOUBLE_EQ(sc.tracker.range_m, 12.0);
  EXPECT_DOUBLE_EQ(sc.tracker.drop_after_s, 0.5);
  EXPECT_DOUBLE_EQ(sc.tracker.id_switch_window_s, 20.0);
  std::string msg = errorOf(replaced(text, "miss_probability: 0.05", "miss_probability: 1.5"));
  EXPECT_NE(msg.find("'tracker.miss_probability' = 1.5"), std::string::npos) << msg;
  msg = errorOf(replaced(text, "id_switches: 1", "id_switches: 1.5"));
  EXPECT_NE(msg.find("'tracker.id_switches'"), std::string::npos) << msg;
  msg = errorOf(replaced(text, "range_m: 12", "range: 12"));
  EXPECT_NE(msg.find("'tracker.range'"), std::string::npos) << msg;
  msg = errorOf(replaced(text, "publish_human_goals: false", "publish_human_goals: maybe"));
  EXPECT_NE(msg.find("'publish_human_goals'"), std::string::npos) << msg;
}

TEST(Scenario, AvoidanceTimingLoadsIntoTheWorldAndIsChecked) {
  // Left out: each behaviour's own trigger.
  EXPECT_EQ(toWorldSpec(parseScenario(kValid, "ok.yaml", ".")).avoidance_timing,
            sim::AvoidanceTiming::kTrigger);
  const std::string text =
      replaced(kValid, "time_limit_s: 40.0\n", "time_limit_s: 40.0\navoidance_timing: realistic\n");
  EXPECT_EQ(toWorldSpec(parseScenario(text, "ok.yaml", ".")).avoidance_timing,
            sim::AvoidanceTiming::kRealistic);
  const std::string msg =
      errorOf(replaced(text, "avoidance_timing: realistic", "avoidance_timing: early"));
  EXPECT_NE(msg.find("'avoidance_timing'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("realistic"), std::string::npos) << msg;
}

TEST(Scenario, RecordedHumansTakeTheirStartAndGoalFromTheirTracks) {
  const std::string path = ::coopnav::test::testDataDir() + "/scenarios/recorded_zara01.yaml";
  const Scenario sc = loadScenario(path);
  ASSERT_EQ(sc.humans.size(), 2u);
  for (const auto& h : sc.humans) EXPECT_EQ(h.behaviour.type, sim::BehaviourType::kRecorded);
  // Walker a (CSV, 33 samples) and walker b (JSON, 32 samples), rotated by 90 degrees and moved
  // by (22, 3): a's first point (-1.505478, 17.34706) -> (4.65294, 1.494522).
  EXPECT_EQ(sc.humans[0].behaviour.recorded.track.size(), 33u);
  EXPECT_EQ(sc.humans[1].behaviour.recorded.track.size(), 32u);
  EXPECT_NEAR(sc.humans[0].start.x_m, 22.0 - 17.34706, 1e-9);
  EXPECT_NEAR(sc.humans[0].start.y_m, 3.0 - 1.505478, 1e-9);
  EXPECT_NEAR(sc.humans[0].goal.x_m, 22.0 - 5.563478, 1e-9);
  EXPECT_NEAR(sc.humans[1].goal.x_m, 22.0 - 20.42463, 1e-9);
  EXPECT_DOUBLE_EQ(sc.humans[1].behaviour.recorded.time_offset_s, 4.8);
  EXPECT_NE(sc.recorded_sources[1].file.find("zara01_pair0.json"), std::string::npos);
  EXPECT_EQ(sc.recorded_sources[1].walker, "b");
  // The track of the JSON is the pedestrians file's own.
  const auto full =
      loadTrack({::coopnav::test::testDataDir() + "/pedestrians/headon_pairs.json", 0, "b"});
  ASSERT_EQ(full.size(), 32u);
  EXPECT_DOUBLE_EQ(full[5].x_m, sc.humans[1].behaviour.recorded.track[5].x_m);
  // A loaded recorded scenario is a valid world on its map.
  const GridDistanceField map(loadScenarioMap(sc).grid);
  EXPECT_NO_THROW(checkScenarioAgainstMap(sc, map));
  sim::Simulation simulation(toWorldSpec(sc), &map);
  EXPECT_EQ(simulation.agents().size(), 3u);
}

TEST(Scenario, RecordedHumanMistakesAreNamed) {
  const fs::path dir =
      fs::temp_directory_path() / ("coopnav_recorded_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "walk.csv") << "t x y\n0 1 1\n0.5 2 1\n0.5 3 1\n";
  std::ofstream(dir / "ok.csv") << "0 1 1\n1 2 1\n";
  const std::string tracks = ::coopnav::test::testDataDir() + "/tracks/zara01_pair0.json";
  auto scenario = [&](const std::string& human) {
    return "name: r\nseed: 1\ntime_limit_s: 10\nmap: {walls: [{x0_m: -5, y0_m: -5, x1_m: 5, "
           "y1_m: -5}]}\nrobot: {start: {x_m: 0, y_m: 3}, goal: {x_m: 0, y_m: 3}}\nhumans:\n  - " +
           human + "\n";
  };
  auto error = [&](const std::string& human) {
    try {
      parseScenario(scenario(human), "rec.yaml", dir.string());
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("{id: 1, behaviour: recorded, params: {file: ok.csv}}"), "");
  // A CSV row out of order: the file and its line.
  std::string msg = error("{id: 1, behaviour: recorded, params: {file: walk.csv}}");
  EXPECT_NE(msg.find("'humans[0].params.file'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("walk.csv:4:"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded, params: {file: none.csv}}");
  EXPECT_NE(msg.find("none.csv"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded}");
  EXPECT_NE(msg.find("'humans[0].params' is missing"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded, params: {file: " + tracks + ", walker: c, pair: 0}}");
  EXPECT_NE(msg.find("'humans[0].params.walker' = 'c'"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded, params: {file: " + tracks + ", walker: a}}");
  EXPECT_NE(msg.find("'humans[0].params.pair' is missing"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded, params: {file: " + tracks + ", walker: a, pair: 3}}");
  EXPECT_NE(msg.find("pair 3 is not in"), std::string::npos) << msg;
  msg = error("{id: 1, behaviour: recorded, params: {file: ok.csv, pair: 0}}");
  EXPECT_NE(msg.find("'humans[0].params.pair' is for a .json track only"), std::string::npos)
      << msg;
  // Its start and goal are the track's: no keys of a recorded human.
  msg = error("{id: 1, behaviour: recorded, start: {x_m: 0, y_m: 0}, params: {file: ok.csv}}");
  EXPECT_NE(msg.find("'humans[0].start' is not a known key"), std::string::npos) << msg;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace coopnav::world_sim
