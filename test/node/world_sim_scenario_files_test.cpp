// Hostile scenario files of world_sim (daemons/world_sim/scenario.{hpp,cpp}, in the world_sim_node
// library, hence a node-tier test although it opens no LCM): a file that is not a regular one or
// is over its cap, a key given twice, more humans than a message carries. Each is a
// ScenarioError naming the file (the daemon's exit 3).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <string>

#include "config/file_read.hpp"
#include "coopnav/agent_states_t.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "maps/map_loader.hpp"
#include "scenario.hpp"
#include "test_paths.hpp"

namespace coopnav::world_sim {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const char* kHead = R"(name: crowd
seed: 7
time_limit_s: 40.0
map:
  walls:
    - {x0_m: -1, y0_m: 0, x1_m: 30, y1_m: 0, thickness_m: 0.2}
    - {x0_m: -1, y0_m: 20, x1_m: 30, y1_m: 20}
robot:
  start: {x_m: 1, y_m: 3, theta_rad: 0}
  goal: {x_m: 25, y_m: 3}
)";

/// A scenario of n humans in rows across the corridor.
std::string withHumans(int n) {
  std::string text = std::string(kHead) + "humans:\n";
  for (int i = 0; i < n; ++i) {
    const std::string x = std::to_string(5 + (i % 16)), y = std::to_string(2 + i / 16);
    text += "  - {id: " + std::to_string(i + 1) + ", start: {x_m: " + x + ", y_m: " + y +
            "}, goal: {x_m: 1, y_m: " + y + "}, behaviour: minimal}\n";
  }
  return text;
}

std::string parseError(const std::string& text) {
  try {
    parseScenario(text, "bad.yaml", ".");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

/// loadScenario's message, within 5 s (a FIFO opened for reading without O_NONBLOCK waits for a
/// writer forever: it is then opened for writing to release the thread).
std::string loadError(const std::string& path) {
  auto result = std::async(std::launch::async, [path]() -> std::string {
    try {
      loadScenario(path);
    } catch (const ScenarioError& e) {
      return e.what();
    }
    return "";
  });
  if (result.wait_for(5s) != std::future_status::ready) {
    ADD_FAILURE() << path << " blocked for 5 s";
    std::ofstream(path) << "";
  }
  return result.get();
}

bool has(const std::string& all, const std::string& s) { return all.find(s) != std::string::npos; }

class ScenarioFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("coopnav_scenario_files_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// Measured before: a scenario file that is /dev/zero was read forever.
TEST_F(ScenarioFiles, AFileThatIsNotRegularOrTooLargeIsRefusedAtOnce) {
  fs::create_symlink("/dev/zero", path("zero.yaml"));
  ASSERT_EQ(::mkfifo(path("fifo.yaml").c_str(), 0600), 0);
  fs::create_directories(path("dir.yaml"));
  std::ofstream(path("huge.yaml")) << "";
  fs::resize_file(path("huge.yaml"), kMaxYamlFileBytes + 1);  // sparse
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(has(loadError("/dev/zero"),
                  "/dev/zero: is a character device; the scenario file must be a regular file"));
  EXPECT_TRUE(has(loadError(path("zero.yaml")),
                  "zero.yaml: is a character device; the scenario file must be a regular file"));
  EXPECT_TRUE(has(loadError(path("fifo.yaml")),
                  "fifo.yaml: is a FIFO; the scenario file must be a regular file"));
  EXPECT_TRUE(has(loadError(path("dir.yaml")),
                  "dir.yaml: is a directory; the scenario file must be a regular file"));
  EXPECT_TRUE(has(loadError(path("huge.yaml")),
                  "huge.yaml: is 1048577 bytes, more than the scenario file may have (1 MiB)"));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  // Its map file: checked here, read by the map loader through the same helper.
  const std::string map_zero =
      "name: z\nseed: 1\ntime_limit_s: 10\nmap: {file: zero.yaml}\n"
      "robot: {start: {x_m: 1, y_m: 1}, goal: {x_m: 2, y_m: 1}}\n";
  std::ofstream(path("map_zero.yaml")) << map_zero;
  EXPECT_TRUE(has(loadError(path("map_zero.yaml")),
                  "key 'map.file' = '" + path("zero.yaml") + "' is not a regular file"));
}

// yaml-cpp keeps both pairs of a duplicated key and node[key] gives the first: the second value
// was ignored. Every mapping of a scenario refuses it, naming the key and both lines.
TEST_F(ScenarioFiles, AKeyGivenTwiceAnywhereIsRefusedNamingTheKeyAndBothLines) {
  const std::string base = withHumans(1);
  ASSERT_EQ(parseError(base), "");
  // Top level: a second seed at the end.
  EXPECT_TRUE(has(parseError(base + "seed: 8\n"),
                  "bad.yaml: key 'seed' is given more than once (lines 2 and 13)"))
      << parseError(base + "seed: 8\n");
  // Nested: the robot's goal given twice.
  const std::string nested = std::string(base).replace(base.find("  goal: {x_m: 25, y_m: 3}\n"), 0,
                                                       "  goal: {x_m: 20, y_m: 3}\n");
  EXPECT_TRUE(has(parseError(nested), "key 'robot.goal' is given more than once (lines 10 and 11)"))
      << parseError(nested);
  // Nested deeper: a coordinate of the robot's start.
  const std::string deep =
      std::string(base).replace(base.find("theta_rad: 0}"), 13, "theta_rad: 0, x_m: 9}");
  EXPECT_TRUE(
      has(parseError(deep), "key 'robot.start.x_m' is given more than once (lines 9 and 9)"))
      << parseError(deep);
  // A list item: a human's behaviour.
  const std::string item = std::string(base).replace(base.find("behaviour: minimal}"), 19,
                                                     "behaviour: minimal, behaviour: oblivious}");
  EXPECT_TRUE(
      has(parseError(item), "key 'humans[0].behaviour' is given more than once (lines 12 and 12)"))
      << parseError(item);
  // And a wall of the map section.
  const std::string wall =
      std::string(base).replace(base.find("thickness_m: 0.2}"), 17, "thickness_m: 0.2, y1_m: 5}");
  EXPECT_TRUE(
      has(parseError(wall), "key 'map.walls[0].y1_m' is given more than once (lines 6 and 6)"))
      << parseError(wall);
}

// Measured before: a scenario of 65 or 200 humans loaded, and then every agent-states message
// was rejected downstream (agent_states_t::MAX_HUMANS = 64).
TEST_F(ScenarioFiles, MoreHumansThanAMessageCarriesAreRefusedNamingTheBound) {
  ASSERT_EQ(kMaxScenarioHumans, static_cast<std::size_t>(agent_states_t::MAX_HUMANS));
  EXPECT_EQ(parseScenario(withHumans(64), "ok.yaml", ".").humans.size(), 64u);
  for (const int n : {65, 200}) {
    const std::string msg = parseError(withHumans(n));
    EXPECT_TRUE(has(msg, "bad.yaml: key 'humans' has " + std::to_string(n) +
                             " humans, more than the 64 a message carries "
                             "(agent_states_t::MAX_HUMANS)"))
        << msg;
  }
  std::ofstream(path("crowd.yaml")) << withHumans(65);
  EXPECT_TRUE(has(loadError(path("crowd.yaml")), "crowd.yaml: key 'humans' has 65 humans"));
}

// The example of docs/scenario-format.md, as a new user copies it: world_sim loads it and its
// starts and goals fit its map, the daemons' map loader (the band source's and the distance
// server's map_file) reads the same file, and it lock-steps with the daemons the paper scenarios
// do (a participant left out would step ahead of the others unnoticed).
TEST_F(ScenarioFiles, TheFormatDocumentsExampleLoads) {
  std::ifstream doc(::coopnav::test::sourceDir() + "/docs/scenario-format.md");
  ASSERT_TRUE(doc.good());
  std::string line, yaml;
  bool in_example = false, in_block = false;
  while (std::getline(doc, line)) {
    if (line == "## Example") in_example = true;
    if (!in_example) continue;
    if (line == "```yaml") {
      in_block = true;
    } else if (in_block && line == "```") {
      break;
    } else if (in_block) {
      yaml += line + "\n";
    }
  }
  ASSERT_FALSE(yaml.empty()) << "no ```yaml block under '## Example'";
  std::ofstream(path("example.yaml")) << yaml;
  const Scenario sc = loadScenario(path("example.yaml"));
  const LoadedMap loaded = loadScenarioMap(sc);
  const GridDistanceField map(loaded.grid);
  EXPECT_NO_THROW(checkScenarioAgainstMap(sc, map));
  EXPECT_EQ(loadMap(path("example.yaml")).grid, loaded.grid);
  const Scenario paper =
      loadScenario(::coopnav::test::sourceDir() + "/config/scenarios/open_facilitating.yaml");
  EXPECT_EQ(sc.lockstep.participants, paper.lockstep.participants);
  EXPECT_TRUE(sc.lockstep.enabled);
}

}  // namespace
}  // namespace coopnav::world_sim
