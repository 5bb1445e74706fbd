// Map loaders: ROS map_server YAML + PGM (open.pgm corridor widths), .bt round trip, walls maps,
// and every bad input giving a MapLoadError that names what is wrong.
#include "maps/map_loader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/distance/octree_conversion.hpp"
#include "maps/map_source.hpp"
#include "runtime/daemon_main.hpp"
#include "test_paths.hpp"

namespace coopnav {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kOpenYaml = ::coopnav::test::testDataDir() + "/maps/open.yaml";

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("coopnav_map_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string write(const std::string& name, const std::string& content) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
  std::string dir() const { return path_.string(); }

 private:
  fs::path path_;
};

const char* kRosYaml =
    "image: m.pgm\nresolution: 0.5\norigin: [1.0, -2.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n";

// Message of the MapLoadError thrown by f, or "" when none is thrown.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const MapLoadError& e) {
    return e.what();
  }
  return "";
}

// Free length through a corridor at x: rays up and down from a point inside it.
double corridorWidth(const GridDistanceField& field, double x_m, double y_inside_m) {
  const DistanceResult up = field.ray({x_m, y_inside_m}, {0.0, 1.0}, 20.0);
  const DistanceResult down = field.ray({x_m, y_inside_m}, {0.0, -1.0}, 20.0);
  EXPECT_EQ(up.status, DistanceStatus::kOk);
  EXPECT_EQ(down.status, DistanceStatus::kOk);
  return up.distance_m + down.distance_m;
}

TEST(MapLoaderTest, OpenPgmCorridorWidths) {
  // Given the CoHAN open map
  const LoadedMap map = loadMap(kOpenYaml);
  ASSERT_EQ(map.grid.width(), 928);
  ASSERT_EQ(map.grid.height(), 576);
  EXPECT_DOUBLE_EQ(map.grid.resolution_m(), 0.05);
  EXPECT_EQ(map.grid.origin_m(), Eigen::Vector2d(-5.0, -10.0));
  const GridDistanceField field(map.grid);
  // Then the wide corridor (y 3.50 - 9.50) and the narrow one (y 0.45 - 2.70) measure 6.00 m and
  // 2.25 m at x = 15 and x = 30.15, both along the divider (x 9.65 - 35.30)
  for (const double x_m : {15.0, 30.15}) {
    EXPECT_NEAR(corridorWidth(field, x_m, 6.5), 6.00, 1e-9) << "x = " << x_m;
    EXPECT_NEAR(corridorWidth(field, x_m, 1.5), 2.25, 1e-9) << "x = " << x_m;
    const DistanceResult up = field.ray({x_m, 1.5}, {0.0, 1.0}, 20.0);
    EXPECT_NEAR(up.obstacle.y(), 2.70, 1e-9);
  }
  // And the hand-drawn top wall wobbles by one pixel: at x = 30.00 it starts at y = 9.45
  EXPECT_NEAR(corridorWidth(field, 30.0, 6.5), 5.95, 1e-9);
  // And NEAREST mid-corridor is the half width less half a cell (snapped to the cell centre)
  EXPECT_NEAR(field.nearest({30.01, 1.56}).distance_m, 2.70 - 1.575, 1e-9);
  // And the pillar interior (drawn as a hollow outline) is unknown, outside the map is outside
  EXPECT_EQ(field.nearest({-4.9, -9.9}).status, DistanceStatus::kUnknownSpace);
  EXPECT_EQ(field.nearest({50.0, 0.0}).status, DistanceStatus::kOutsideMap);
  // And the OcTree of record holds the known cells
  ASSERT_NE(map.tree, nullptr);
  EXPECT_DOUBLE_EQ(map.tree->getResolution(), 0.05);
  const auto* node = map.tree->search(15.0 - (-5.0), 6.5 - (-10.0), 0.025);
  ASSERT_NE(node, nullptr);
  EXPECT_FALSE(map.tree->isNodeOccupied(node));
}

TEST(MapLoaderTest, P2AndP5GiveTheSameGridWithRosSemantics) {
  TempDir tmp;
  // Given the same 3x2 image (row 0 = top) as ASCII with comments and as binary
  tmp.write("m.pgm", "P2\n# a comment\n3 2 # trailing\n255\n0 205 254\n# mid\n100 91 255\n");
  const std::string p2 = tmp.write("p2.yaml", kRosYaml);
  const LoadedMap a = loadMap(p2);
  const std::string pixels{'\x00', '\xcd', '\xfe', '\x64', '\x5b', '\xff'};
  tmp.write("m5.pgm", "P5\n# c\n3 2\n255\n" + pixels);
  std::string yaml5 = kRosYaml;
  yaml5.replace(yaml5.find("m.pgm"), 5, "m5.pgm");
  const LoadedMap b = loadMap(tmp.write("p5.yaml", yaml5));
  // Then both grids are equal
  EXPECT_EQ(a.grid, b.grid);
  // And follow map_server: p = (255 - v) / 255, occupied > 0.65, free < 0.196, top row at j = 1
  EXPECT_EQ(a.grid.at(0, 1), CellState::kOccupied);  // 0
  EXPECT_EQ(a.grid.at(1, 1), CellState::kUnknown);   // 205: p = 0.19608 > 0.196
  EXPECT_EQ(a.grid.at(2, 1), CellState::kFree);      // 254
  EXPECT_EQ(a.grid.at(0, 0), CellState::kUnknown);   // 100: p = 0.608
  EXPECT_EQ(a.grid.at(1, 0), CellState::kUnknown);   // 91: p = 0.643
  EXPECT_EQ(a.grid.at(2, 0), CellState::kFree);      // 255
  EXPECT_EQ(a.grid.origin_m(), Eigen::Vector2d(1.0, -2.0));
  // And negate flips the reading; an absolute image path works too
  std::string neg = kRosYaml;
  neg.replace(neg.find("negate: 0"), 9, "negate: 1");
  neg.replace(neg.find("m.pgm"), 5, tmp.dir() + "/m.pgm");
  const LoadedMap c = loadMap(tmp.write("sub_neg.yaml", neg));
  EXPECT_EQ(c.grid.at(0, 1), CellState::kFree);
  EXPECT_EQ(c.grid.at(2, 1), CellState::kOccupied);
}

TEST(MapLoaderTest, SixteenBitP5) {
  TempDir tmp;
  const std::string pixels{'\x00', '\x00', '\x03', '\xe8'};  // 0 and 1000 of maxval 1000
  tmp.write("m.pgm", "P5 2 1 1000\n" + pixels);
  const LoadedMap m = loadMap(tmp.write("m.yaml", kRosYaml));
  EXPECT_EQ(m.grid.at(0, 0), CellState::kOccupied);
  EXPECT_EQ(m.grid.at(1, 0), CellState::kFree);
}

TEST(MapLoaderTest, BtRoundTripOfOpenMap) {
  TempDir tmp;
  // Given the open map written as .bt
  const LoadedMap map = loadMap(kOpenYaml);
  const std::string bt = tmp.dir() + "/open.bt";
  writeBt(*map.tree, bt);
  // When read back with the grid origin as the tree frame's world position
  MapLoadOptions options;
  options.bt_origin_m = map.tree_origin_m;
  const LoadedMap back = loadMap(bt, options);
  // Then it is the same grid, cropped to the known cells' bounding box
  EXPECT_DOUBLE_EQ(back.grid.resolution_m(), map.grid.resolution_m());
  EXPECT_EQ(back.grid.count(CellState::kOccupied), map.grid.count(CellState::kOccupied));
  EXPECT_EQ(back.grid.count(CellState::kFree), map.grid.count(CellState::kFree));
  int mismatches = 0;
  for (int j = 0; j < map.grid.height(); ++j) {
    for (int i = 0; i < map.grid.width(); ++i) {
      const auto c = back.grid.cellOf(map.grid.cellCenter_m(i, j));
      const CellState s = c ? back.grid.at(c->x(), c->y()) : CellState::kUnknown;
      mismatches += s != map.grid.at(i, j);
    }
  }
  EXPECT_EQ(mismatches, 0);
  // And corridor widths are unchanged
  const GridDistanceField field(back.grid);
  EXPECT_NEAR(corridorWidth(field, 15.0, 6.5), 6.00, 1e-6);
}

TEST(MapLoaderTest, BtRoundTripIsExactWhenCornersAreKnown) {
  TempDir tmp;
  OccupancyGrid2 grid(37, 21, 0.1, Eigen::Vector2d(-3.0, 4.0), CellState::kFree);
  for (int k = 0; k < 21; ++k) grid.set(k + 5, k, CellState::kOccupied);
  grid.set(3, 3, CellState::kUnknown);
  for (const int layers : {1, 2, 4}) {
    const auto tree = gridToOctree(grid, layers);
    writeBt(*tree, tmp.dir() + "/g.bt");
    MapLoadOptions options;
    options.bt_origin_m = grid.origin_m();
    EXPECT_EQ(loadMap(tmp.dir() + "/g.bt", options).grid, grid) << layers << " layers";
  }
}

TEST(MapLoaderTest, BtHeightBandSelectsTheSlab) {
  TempDir tmp;
  // Given a 3-D tree (0.1 m): free floor layer at z 0.05, a table top at z 0.75 over x [0.5, 0.7)
  octomap::OcTree tree(0.1);
  for (int i = 0; i < 10; ++i) {
    tree.updateNode(octomap::point3d(i * 0.1f + 0.05f, 0.05f, 0.05f), false);
    if (i == 5 || i == 6) tree.updateNode(octomap::point3d(i * 0.1f + 0.05f, 0.05f, 0.75f), true);
  }
  writeBt(tree, tmp.dir() + "/t.bt");
  MapLoadOptions options;
  options.bt_origin_m = Eigen::Vector2d(10.0, 20.0);
  // When projected at floor height, everything is free
  const LoadedMap floor = loadMap(tmp.dir() + "/t.bt", options);
  EXPECT_EQ(floor.grid.width(), 10);
  EXPECT_EQ(floor.grid.count(CellState::kFree), 10u);
  EXPECT_NEAR(floor.grid.origin_m().x(), 10.0, 1e-12);
  // When the band includes the table top, its two cells are occupied
  options.bt_z_max_m = 1.0;
  const LoadedMap table = loadMap(tmp.dir() + "/t.bt", options);
  EXPECT_EQ(table.grid.count(CellState::kOccupied), 2u);
  EXPECT_EQ(table.grid.at(5, 0), CellState::kOccupied);
  EXPECT_EQ(table.grid.at(4, 0), CellState::kFree);
  // When the band holds no voxel, or is empty, the error says so
  options.bt_z_min_m = 2.0;
  options.bt_z_max_m = 3.0;
  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/t.bt", options); }),
              AllOf(HasSubstr("t.bt"), HasSubstr("no known voxel in the height band [2, 3]")));
  options.bt_z_max_m = 1.0;
  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/t.bt", options); }), HasSubstr("is empty"));
}

TEST(MapLoaderTest, AWallWithoutThicknessHasTheDocumentedDefault) {
  const auto load = [](const std::string& wall) {
    return loadMapFromNode(YAML::Load("{resolution_m: 0.05, walls: [" + wall + "]}"),
                           "/nonexistent", {}, "scenario.yaml: map")
        .grid;
  };
  EXPECT_EQ(load("{x0_m: 0, y0_m: 0, x1_m: 4, y1_m: 0}"),
            load("{x0_m: 0, y0_m: 0, x1_m: 4, y1_m: 0, thickness_m: " +
                 std::to_string(kDefaultWallThickness_m) + "}"));
  EXPECT_NE(load("{x0_m: 0, y0_m: 0, x1_m: 4, y1_m: 0}"),
            load("{x0_m: 0, y0_m: 0, x1_m: 4, y1_m: 0, thickness_m: 0.6}"));
}

// docs/scenario-format.md: resolution_m is optional; the daemons loading a scenario file as their
// map must agree with world_sim's default.
TEST(MapLoaderTest, AWallsMapWithoutResolutionHasTheDocumentedDefault) {
  const auto load = [](const std::string& res) {
    return loadMapFromNode(YAML::Load("{" + res + "walls: [{x0_m: 0, y0_m: 0, x1_m: 4, y1_m: 0}]}"),
                           "/nonexistent", {}, "scenario.yaml: map")
        .grid;
  };
  const auto grid = load("");
  EXPECT_DOUBLE_EQ(grid.resolution_m(), kDefaultWallsMapResolution_m);
  EXPECT_EQ(grid, load("resolution_m: " + std::to_string(kDefaultWallsMapResolution_m) + ", "));
  EXPECT_DOUBLE_EQ(load("resolution_m: 0.1, ").resolution_m(), 0.1);
}

TEST(MapLoaderTest, WallsMapIsFourConnectedAndBoxesFill) {
  const YAML::Node node = YAML::Load(R"(
resolution_m: 0.1
margin_m: 0.5
walls:
  - {x0_m: 0.0, y0_m: 0.0, x1_m: 7.0, y1_m: 3.0, thickness_m: 0.01}
  - {x0_m: 0.0, y0_m: 4.0, x1_m: 7.0, y1_m: 4.0, thickness_m: 0.3}
boxes:
  - {min_x_m: 2.0, min_y_m: 5.0, max_x_m: 3.0, max_y_m: 5.5}
)");
  const LoadedMap map = loadMapFromNode(node, "/nonexistent", {}, "scenario.yaml: map");
  const OccupancyGrid2& g = map.grid;
  // (extent: walls grown by half their thickness, boxes, then the margin; whole cells)
  EXPECT_NEAR(g.origin_m().x(), -0.15 - 0.5, 1e-12);
  EXPECT_NEAR(g.origin_m().y(), -0.005 - 0.5, 1e-12);
  EXPECT_EQ(g.height(), 66);  // ceil((5.5 + 0.5 - (-0.505)) / 0.1)
  const GridDistanceField field(g);
  // Then a ray crossing the thin diagonal wall anywhere is stopped by it
  const Eigen::Vector2d along = Eigen::Vector2d(7.0, 3.0).normalized();
  const Eigen::Vector2d normal(-along.y(), along.x());
  for (int k = 1; k < 200; ++k) {
    const Eigen::Vector2d on = along * (k * 7.6 / 200.0);
    const DistanceResult r = field.ray(on - 0.4 * normal, normal, 1.0);
    ASSERT_EQ(r.status, DistanceStatus::kOk) << on.transpose();
    EXPECT_LT(r.distance_m, 0.4 + 0.1 * M_SQRT2) << on.transpose();
  }
  // And the thick wall and the box are solid, the rest is free
  EXPECT_EQ(field.nearest({1.0, 4.1}).status, DistanceStatus::kInObstacle);
  EXPECT_EQ(field.nearest({1.0, 3.9}).status, DistanceStatus::kInObstacle);
  EXPECT_EQ(field.nearest({2.5, 5.25}).status, DistanceStatus::kInObstacle);
  EXPECT_EQ(field.nearest({2.05, 5.05}).status, DistanceStatus::kInObstacle);
  EXPECT_EQ(field.nearest({2.5, 5.65}).status, DistanceStatus::kOk);
  EXPECT_EQ(g.count(CellState::kUnknown), 0u);
  // And the same map loads from a file, directly or through `file:`
  TempDir tmp;
  std::ofstream(tmp.dir() + "/walls.yaml") << YAML::Dump(node);
  EXPECT_EQ(loadMap(tmp.dir() + "/walls.yaml").grid, g);
  EXPECT_EQ(loadMapFromNode(YAML::Load("{file: walls.yaml}"), tmp.dir()).grid, g);
  // A scenario file is a map source too: its `map:` walls, or its `map: {file: ...}`.
  YAML::Node scenario;
  scenario["name"] = "s";
  scenario["map"] = node;
  std::ofstream(tmp.dir() + "/scenario.yaml") << YAML::Dump(scenario);
  EXPECT_EQ(loadMap(tmp.dir() + "/scenario.yaml").grid, g);
  std::ofstream(tmp.dir() + "/scenario_file.yaml") << "name: s\nmap: {file: walls.yaml}\n";
  EXPECT_EQ(loadMap(tmp.dir() + "/scenario_file.yaml").grid, g);
}

TEST(MapLoaderTest, BadInputsGiveClearErrors) {
  TempDir tmp;
  const std::string good_pgm = "P2\n2 2\n255\n0 255 255 0\n";
  tmp.write("m.pgm", good_pgm);
  const auto ros = [&](const std::string& name, const std::string& yaml) {
    return errorOf([&] { loadMap(tmp.write(name, yaml)); });
  };
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    return s.replace(s.find(from), from.size(), to);
  };

  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/nope.yaml"); }),
              AllOf(HasSubstr("nope.yaml"), HasSubstr("cannot open")));
  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/nope.bt"); }),
              AllOf(HasSubstr("nope.bt"), HasSubstr("cannot open")));
  EXPECT_THAT(ros("a.yaml", replace(kRosYaml, "resolution: 0.5\n", "")),
              AllOf(HasSubstr("a.yaml"), HasSubstr("missing key 'resolution'")));
  EXPECT_THAT(ros("b.yaml", replace(kRosYaml, "0.5", "fine")),
              AllOf(HasSubstr("b.yaml"), HasSubstr("'resolution'"), HasSubstr("line 2"),
                    HasSubstr("'fine'")));
  EXPECT_THAT(ros("c.yaml", replace(kRosYaml, "-2.0, 0.0]", "-2.0, 0.3]")),
              AllOf(HasSubstr("c.yaml"), HasSubstr("yaw 0.3"), HasSubstr("not supported")));
  EXPECT_THAT(ros("d.yaml", replace(kRosYaml, "[1.0, -2.0, 0.0]", "1.0")),
              AllOf(HasSubstr("'origin'"), HasSubstr("[x, y, yaw]")));
  EXPECT_THAT(ros("e.yaml", replace(kRosYaml, "m.pgm", "missing.pgm")),
              AllOf(HasSubstr("e.yaml"), HasSubstr("missing.pgm"), HasSubstr("not found")));
  EXPECT_THAT(ros("f.yaml", std::string(kRosYaml) + "mode: scale\n"),
              AllOf(HasSubstr("'mode'"), HasSubstr("scale"), HasSubstr("trinary")));
  EXPECT_THAT(ros("g.yaml", replace(kRosYaml, "negate: 0", "negate: 2")),
              AllOf(HasSubstr("'negate'"), HasSubstr("'2'")));
  EXPECT_THAT(ros("h.yaml", replace(kRosYaml, "free_thresh: 0.196", "free_thresh: 0.9")),
              HasSubstr("free_thresh"));
  EXPECT_THAT(ros("i.yaml", "image: [unclosed\n"), AllOf(HasSubstr("i.yaml"), HasSubstr("line")));
  EXPECT_THAT(ros("j.yaml", "foo: 1\n"), AllOf(HasSubstr("j.yaml"), HasSubstr("'image'")));

  const auto pgm = [&](const std::string& content) {
    tmp.write("bad.pgm", content);
    return ros("bad.yaml", replace(kRosYaml, "m.pgm", "bad.pgm"));
  };
  EXPECT_THAT(pgm("P6\n2 2\n255\n"), AllOf(HasSubstr("bad.pgm"), HasSubstr("bad PGM magic 'P6'")));
  EXPECT_THAT(pgm("P5\n2 2\n255\n\x01\x02"),
              AllOf(HasSubstr("bad.pgm"), HasSubstr("truncated"), HasSubstr("expected 4 bytes"),
                    HasSubstr("got 2")));
  EXPECT_THAT(pgm("P2\n2 2\n255\n1 2 3\n"),
              AllOf(HasSubstr("truncated"), HasSubstr("expected 4 values, got 3")));
  EXPECT_THAT(pgm("P2\n2 2\n255\n1 2 3 x\n"),
              AllOf(HasSubstr("bad PGM pixel 'x"), HasSubstr("byte")));
  EXPECT_THAT(pgm("P2\n2 2\n100\n1 2 3 200\n"), HasSubstr("exceeds maxval 100"));
  EXPECT_THAT(pgm("P2\n2 -2\n255\n"), HasSubstr("bad PGM height"));
  EXPECT_THAT(pgm("P5\n2 2\n"), HasSubstr("truncated PGM header"));

  EXPECT_THAT(errorOf([&] { loadMap(tmp.write("garbage.bt", "not an octree\n")); }),
              AllOf(HasSubstr("garbage.bt"), HasSubstr("OctoMap")));
  EXPECT_THAT(ros("w1.yaml", "resolution_m: 0.1\nwalls: 3\n"),
              AllOf(HasSubstr("w1.yaml"), HasSubstr("'walls'"), HasSubstr("sequence")));
  EXPECT_THAT(ros("w2.yaml", "resolution_m: 0.1\nwalls:\n  - {x0_m: 0, y0_m: 0, x1_m: 1}\n"),
              AllOf(HasSubstr("walls[0]"), HasSubstr("missing key 'y1_m'")));
  EXPECT_THAT(ros("w3.yaml",
                  "resolution_m: 0.1\nboxes:\n  - {min_x_m: 0, min_y_m: a, max_x_m: 1, "
                  "max_y_m: 1}\n"),
              AllOf(HasSubstr("boxes[0].min_y_m"), HasSubstr("'a'"), HasSubstr("line 3")));
  EXPECT_THAT(ros("w4.yaml", "walls: []\nresolution_m: 0.1\n"), HasSubstr("without any wall"));
  EXPECT_THAT(errorOf([&] { loadMapFromNode(YAML::Load("{file: [1]}"), tmp.dir()); }),
              HasSubstr("'file'"));
}

// Found by fuzz_map_pgm: sides near the tokeniser's 2^40 clamp made the size check's product
// overflow (UB; under UBSan an abort) instead of giving "bad PGM size".
TEST(MapLoaderTest, HugePgmSidesAreRejectedWithoutOverflow) {
  TempDir tmp;
  EXPECT_THAT(errorOf([&] { readPgm(tmp.write("a.pgm", "P2\n1099511627776 64294967296\n255\n")); }),
              HasSubstr("bad PGM size"));
  EXPECT_THAT(errorOf([&] { readPgm(tmp.write("b.pgm", "P5\n99999999999999 3\n255\n")); }),
              HasSubstr("bad PGM size"));
}

// Found by fuzz_map_yaml: a scenario whose map section names the scenario itself recursed until
// the stack overflowed (a crash of every map-loading daemon at start, instead of exit 3).
TEST(MapLoaderTest, GoalRegionsComeFromTheMapFileThenTheSectionNamingIt) {
  TempDir tmp;
  tmp.write("m.pgm", "P2\n2 2\n255\n0 255 255 0\n");
  tmp.write("m.yaml",
            std::string(kRosYaml) + "goal_regions:\n  - {x0_m: 1, y0_m: 2, x1_m: 3, y1_m: 4}\n");
  const LoadedMap plain = loadMap(tmp.dir() + "/m.yaml");
  ASSERT_EQ(plain.goal_regions.size(), 1u);
  EXPECT_EQ(plain.goal_regions[0].a, Eigen::Vector2d(1.0, 2.0));
  EXPECT_EQ(plain.goal_regions[0].b, Eigen::Vector2d(3.0, 4.0));
  const LoadedMap scenario = loadMap(tmp.write(
      "s.yaml",
      "map:\n  file: m.yaml\n  goal_regions:\n    - {x0_m: 5, y0_m: 6, x1_m: 5, y1_m: 6}\n"));
  ASSERT_EQ(scenario.goal_regions.size(), 2u);
  EXPECT_EQ(scenario.goal_regions[1].a, Eigen::Vector2d(5.0, 6.0));
  EXPECT_EQ(scenario.goal_regions[1].b, Eigen::Vector2d(5.0, 6.0));
  const LoadedMap walls =
      loadMap(tmp.write("w.yaml",
                        "resolution_m: 0.1\nwalls: [{x0_m: 0, y0_m: 0, x1_m: 2, y1_m: 0}]\n"
                        "goal_regions: [{x0_m: 1, y0_m: 1, x1_m: 1, y1_m: 2}]\n"));
  EXPECT_EQ(walls.goal_regions.size(), 1u);
  // Bad ones name the item and the key.
  EXPECT_THAT(
      errorOf([&] { loadMap(tmp.write("b1.yaml", std::string(kRosYaml) + "goal_regions: 3\n")); }),
      AllOf(HasSubstr("b1.yaml"), HasSubstr("'goal_regions'"), HasSubstr("sequence")));
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("b2.yaml", std::string(kRosYaml) +
                                                 "goal_regions: [{x0_m: 1, y0_m: 2, x1_m: 3}]\n"));
              }),
              AllOf(HasSubstr("goal_regions[0]"), HasSubstr("missing key 'y1_m'")));
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("b3.yaml",
                                  std::string(kRosYaml) +
                                      "goal_regions: [{x0_m: 1, y0_m: 2, x1_m: 3, y1_m: .nan}]\n"));
              }),
              AllOf(HasSubstr("goal_regions[0].y1_m"), HasSubstr("finite")));
}

TEST(MapLoaderTest, MapFilesNamingThemselvesAreRejected) {
  TempDir tmp;
  EXPECT_THAT(
      errorOf([&] { loadMap(tmp.write("self.yaml", "name: s\nmap: {file: self.yaml}\n")); }),
      HasSubstr("nest more than"));
  tmp.write("a.yaml", "map: {file: b.yaml}\n");
  EXPECT_THAT(errorOf([&] { loadMap(tmp.write("b.yaml", "map: {file: a.yaml}\n")); }),
              HasSubstr("nest more than"));
}

// Found by fuzz_map_pgm: a header claiming 2^30 pixels made readPgm allocate and clear the raster
// (2 GB for 16 bit) before it found the data missing. Now the data is checked first; the ASCII
// message says so ("room for at most").
TEST(MapLoaderTest, PgmHeaderClaimingAHugeImageFailsBeforeAllocating) {
  TempDir tmp;
  EXPECT_THAT(
      errorOf([&] { readPgm(tmp.write("a.pgm", "P5\n32768 32768\n65535\n\x01\x02")); }),
      AllOf(HasSubstr("truncated"), HasSubstr("expected 2147483648 bytes"), HasSubstr("got 2")));
  EXPECT_THAT(errorOf([&] { readPgm(tmp.write("b.pgm", "P2\n32768 32768\n255\n1 2 3\n")); }),
              AllOf(HasSubstr("truncated"), HasSubstr("expected 1073741824 values"),
                    HasSubstr("room for at most 4")));
}

// Found by fuzz_map_bt: a 759-byte .bt whose leaves spanned ~2^26 cells took 43 s and 1.1 GB to
// load, and leaves farther apart made OccupancyGrid2 throw std::invalid_argument past the
// loader (exit 1, not 3). Both are now a MapLoadError naming the cell count.
TEST(MapLoaderTest, BtWhoseLeavesSpanTooManyCellsIsABadMap) {
  TempDir tmp;
  for (const double corner_m : {150.0, 3000.0}) {
    octomap::OcTree tree(0.1);
    tree.updateNode(octomap::point3d(-corner_m, -corner_m, 0.05f), true);
    tree.updateNode(octomap::point3d(corner_m, corner_m, 0.05f), true);
    const std::string path = tmp.dir() + "/far.bt";
    ASSERT_TRUE(tree.writeBinary(path));
    EXPECT_THAT(errorOf([&] { loadMap(path); }),
                AllOf(HasSubstr("far.bt"), HasSubstr("cells, more than 4194304")))
        << corner_m;
  }
}

// The rasteriser tests only the cells of each row near the wall (a long diagonal wall used to
// cost its bounding box's area). Every cell whose centre is within half the thickness of a wall
// must still be occupied, whatever the slope, thickness, resolution and grid origin; the other
// occupied cells are the ones the centre line crosses (their centre within a half diagonal).
TEST(MapLoaderTest, EveryCellWithinAWallsHalfThicknessIsOccupiedAtAnySlope) {
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> coord(-3.0, 9.0), unit(0.0, 1.0);
  struct W {
    double x0, y0, x1, y1, half;
  };
  // Distance from (px, py) to the segment, written apart from the loader's Eigen code.
  const auto dist = [](const W& w, double px, double py) {
    const double dx = w.x1 - w.x0, dy = w.y1 - w.y0, len2 = dx * dx + dy * dy;
    double t = len2 > 0.0 ? ((px - w.x0) * dx + (py - w.y0) * dy) / len2 : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    return std::hypot(px - (w.x0 + t * dx), py - (w.y0 + t * dy));
  };
  for (int trial = 0; trial < 60; ++trial) {
    const double res = 0.02 + 0.2 * unit(rng);
    std::vector<W> walls;
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "resolution_m: " << res << "\nmargin_m: " << 0.3 * unit(rng) << "\nwalls:\n";
    const int n = 1 + trial % 5;
    for (int k = 0; k < n; ++k) {
      W w{coord(rng), coord(rng), coord(rng), coord(rng), 0.0};
      if (k == 1) w.y1 = w.y0;               // horizontal,
      if (k == 2) w.x1 = w.x0;               // vertical,
      if (k == 3) w.x1 = w.x0, w.y1 = w.y0;  // a point
      w.half = 0.5 * (0.005 + (trial % 2 ? 0.6 : 0.1) * unit(rng));
      walls.push_back(w);
      yaml << "  - {x0_m: " << w.x0 << ", y0_m: " << w.y0 << ", x1_m: " << w.x1
           << ", y1_m: " << w.y1 << ", thickness_m: " << 2.0 * w.half << "}\n";
    }
    const OccupancyGrid2 g = rasteriseWallsMap(YAML::Load(yaml.str()), "walls.yaml");
    int within = 0;
    for (int j = 0; j < g.height(); ++j) {
      for (int i = 0; i < g.width(); ++i) {
        const Eigen::Vector2d c = g.cellCenter_m(i, j);
        double nearest = std::numeric_limits<double>::infinity();
        bool inside = false;
        for (const W& w : walls) {
          const double d = dist(w, c.x(), c.y());
          nearest = std::min(nearest, d);
          // (a margin of 1e-12 m: the loader's rounding may differ in the last bits)
          if (d <= w.half - 1e-12) inside = true;
        }
        within += inside;
        if (inside) {
          ASSERT_EQ(g.at(i, j), CellState::kOccupied)
              << "trial " << trial << " cell " << i << "," << j << "\n"
              << yaml.str();
        } else if (g.at(i, j) == CellState::kOccupied) {
          ASSERT_LE(nearest, res * M_SQRT1_2 + 1e-9)
              << "trial " << trial << " cell " << i << "," << j << "\n"
              << yaml.str();
        }
      }
    }
    if (trial % 2) {
      EXPECT_GT(within, 0) << yaml.str();  // the thick walls cover cell centres
    }
  }
}

// The band source and world_sim load maps without the OcTree (build_tree false): the same grid,
// no tree, and the same refusals, the tree's own limits included, as the distance server.
TEST(MapLoaderTest, WithoutTheTreeTheGridAndTheRefusalsAreTheSame) {
  MapLoadOptions no_tree;
  no_tree.build_tree = false;
  const LoadedMap with = loadMap(kOpenYaml);
  const LoadedMap without = loadMap(kOpenYaml, no_tree);
  ASSERT_NE(with.tree, nullptr);
  EXPECT_EQ(without.tree, nullptr);
  EXPECT_EQ(without.grid, with.grid);
  MapSource source;
  source.map_file = kOpenYaml;
  const LoadedField field = loadDistanceField(source, /*build_tree=*/false);
  EXPECT_EQ(field.map.tree, nullptr);
  EXPECT_EQ(field.field->nearest({12.0, 1.5}).distance_m,
            loadDistanceField(source).field->nearest({12.0, 1.5}).distance_m);
  TempDir tmp;
  // 40 001 x 1 cells: under max_map_cells, over OctoMap's 2^15 keys each way of the origin.
  const std::string long_corridor =
      tmp.write("long.yaml",
                "resolution_m: 0.1\nmargin_m: 0.0\nwalls:\n"
                "  - {x0_m: 0, y0_m: 0, x1_m: 4000, y1_m: 0, thickness_m: 0.01}\n");
  const std::string huge_res =
      tmp.write("huge.yaml",
                "resolution_m: 8.9e53\nboxes:\n  - {min_x_m: 0, min_y_m: 0, max_x_m: 1, "
                "max_y_m: 1}\n");
  for (const MapLoadOptions& options : {MapLoadOptions{}, no_tree}) {
    EXPECT_THAT(errorOf([&] { loadMap(long_corridor, options); }),
                AllOf(HasSubstr("long.yaml"), HasSubstr("40001 x 1 cells exceeds the OcTree key")));
    EXPECT_THAT(errorOf([&] { loadMap(huge_res, options); }),
                HasSubstr("8.9e53 m per cell is outside [0.001, 10]"));
  }
}

// Found by fuzz_map_yaml's kind of input: a few lines of walls YAML at a tiny resolution asked for
// up to 2^30 cells.
TEST(MapLoaderTest, WallsMapOverTheCellLimitIsABadMap) {
  TempDir tmp;
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("fine.yaml",
                                  "resolution_m: 0.001\nboxes:\n"
                                  "  - {min_x_m: 0, min_y_m: 0, max_x_m: 10, max_y_m: 10}\n"));
              }),
              AllOf(HasSubstr("fine.yaml"), HasSubstr("larger than 4194304 cells")));
}

// OctoMap's coordinates are floats: a resolution whose voxel centres overflow a float (found by
// fuzz_map_yaml: undefined behaviour inside OctoMap) or underflow to 0 is a bad map, not a crash
// or a tree with every voxel at one key. The loader's resolution range refuses both ends first;
// the tree's own check stays behind it for a grid built in code.
TEST(MapLoaderTest, AResolutionAnOcTreeCannotHoldIsABadMap) {
  TempDir tmp;
  const std::string huge = tmp.write(
      "huge.yaml",
      "resolution_m: 8.9e53\nboxes:\n  - {min_x_m: 0, min_y_m: 0, max_x_m: 1, max_y_m: 1}\n");
  const std::string tiny = tmp.write("tiny.yaml",
                                     "resolution_m: 1e-50\nboxes:\n  - {min_x_m: 0, min_y_m: 0, "
                                     "max_x_m: 2e-50, max_y_m: 2e-50}\n");
  for (const std::string& path : {huge, tiny}) {
    EXPECT_THAT(errorOf([&] { loadMap(path); }),
                AllOf(HasSubstr(path), HasSubstr("m per cell is outside [0.001, 10]")));
  }
  EXPECT_THROW(gridToOctree(OccupancyGrid2(2, 2, 1e39, Eigen::Vector2d::Zero(), CellState::kFree)),
               std::invalid_argument);
  EXPECT_THROW(gridToOctree(OccupancyGrid2(2, 2, 1e-50, Eigen::Vector2d::Zero(), CellState::kFree)),
               std::invalid_argument);
}

// Found by fuzz_map_yaml (after 9.7M executions): an extent far longer one way than the cell
// count allows and far shorter than one cell the other way rounded to 0 rows, so w x h passed the
// size check as 0 and the width overflowed its int cast (undefined behaviour). Now every map has
// at least one row and one column, and such a map is too large, with its size named.
TEST(MapLoaderTest, AnExtentBelowOneCellOneWayStillCountsItsCellsTheOther) {
  TempDir tmp;
  const std::string thin =
      tmp.write("thin.yaml",
                "resolution_m: 10\nboxes:\n  - {min_x_m: 2.0, min_y_m: 0.0, max_x_m: 7.7e65, "
                "max_y_m: 0.7}\n");
  EXPECT_THAT(errorOf([&] { loadMap(thin); }),
              AllOf(HasSubstr(thin), HasSubstr("cells (max_map_cells)")));
}

// A directory opens like a file and fails at the first read, where libstdc++ throws past the
// loader (fuzz_map_yaml: `map: {file: ..}` in a scenario). Named anywhere, it is a bad map.
TEST(MapLoaderTest, ADirectoryIsABadMapFileWhereverItIsNamed) {
  TempDir tmp;
  fs::create_directories(tmp.dir() + "/dir.bt");
  fs::create_directories(tmp.dir() + "/dir.yaml");
  const std::string scenario = tmp.write("scenario.yaml", "map:\n  file: ..\n");
  const std::string ros = tmp.write("ros.yaml",
                                    "image: .\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                                    "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  for (const std::string& path :
       {tmp.dir(), tmp.dir() + "/dir.bt", tmp.dir() + "/dir.yaml", scenario, ros}) {
    EXPECT_THAT(errorOf([&] { loadMap(path); }), HasSubstr("is a directory")) << path;
  }
  // A name the system refuses (a 300-byte component, ENAMETOOLONG) is a file not found, not a
  // filesystem_error past the loader (fuzz_map_yaml).
  const std::string long_name(300, 'A');
  const std::string long_image =
      tmp.write("long.yaml", "image: " + long_name +
                                 ".pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                                 "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_THAT(errorOf([&] { loadMap(long_image); }), HasSubstr("not found"));
  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/" + long_name + ".yaml"); }),
              HasSubstr("cannot open"));
  EXPECT_THAT(errorOf([&] { loadMap(tmp.dir() + "/" + long_name + ".bt"); }),
              HasSubstr("cannot open"));
  MapSource source;
  source.map_file = scenario;
  EXPECT_THROW(loadDistanceField(source), StartupError);
}

// A 100 x 100-cell walls map: within the default limit, over a lowered one, whichever the source.
TEST(MapLoaderTest, MaxCellsLowersTheLimitOfEverySourceAndTheMessageNamesTheKey) {
  TempDir tmp;
  const std::string walls = tmp.write(
      "walls.yaml",
      "resolution_m: 0.1\nboxes:\n  - {min_x_m: 0, min_y_m: 0, max_x_m: 10, max_y_m: 10}\n");
  EXPECT_EQ(loadMap(walls).grid.width(), 100);
  MapLoadOptions options;
  options.max_cells = 10000;
  EXPECT_EQ(loadMap(walls, options).grid.height(), 100);  // the limit itself is allowed
  options.max_cells = 9999;
  EXPECT_THAT(errorOf([&] { loadMap(walls, options); }),
              AllOf(HasSubstr("walls.yaml"), HasSubstr("larger than 9999 cells (max_map_cells)")));

  // The same map as a .bt (its leaves span 100 x 100 cells) and as a ROS map (a 100 x 100 image).
  OccupancyGrid2 grid(100, 100, 0.1, Eigen::Vector2d::Zero(), CellState::kFree);
  grid.set(0, 0, CellState::kOccupied);
  grid.set(99, 99, CellState::kOccupied);
  const std::string bt = tmp.dir() + "/map.bt";
  writeBt(*gridToOctree(grid, 2), bt);
  options.bt_z_min_m = 0.0;
  options.bt_z_max_m = 0.1;
  EXPECT_THAT(errorOf([&] { loadMap(bt, options); }), HasSubstr("map.bt"));
  options.max_cells = kMaxMapCells;
  EXPECT_EQ(loadMap(bt, options).grid.width(), 100);

  std::string pgm = "P5 100 100 255\n" + std::string(100 * 100, static_cast<char>(254));
  tmp.write("map.pgm", pgm);
  const std::string ros =
      tmp.write("ros.yaml",
                "image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_EQ(loadMap(ros).grid.width(), 100);
  options.max_cells = 9999;
  EXPECT_THAT(errorOf([&] { loadMap(ros, options); }),
              AllOf(HasSubstr("ros.yaml"), HasSubstr("larger than 9999 cells (max_map_cells)")));

  // A daemon's max_map_cells reaches the loader: exit 3 at start.
  MapSource source;
  source.map_file = walls;
  source.max_map_cells = 9999;
  EXPECT_THROW(loadDistanceField(source), StartupError);
  source.max_map_cells = 10000;
  EXPECT_NE(loadDistanceField(source).field, nullptr);
}

// Every map file is read through readFileCapped (config/file_read.hpp). Measured before: a map
// YAML, a ROS map's image or a .bt that is /dev/zero (or a symlink to it) took 17-20 s and ~2 GB
// and ended in std::bad_alloc (exit 1, not 3). Now each is refused at once, without reading it
// and without blocking on a FIFO, naming the file and what it should be.
TEST(MapLoaderTest, MapFilesThatAreNotRegularOrTooLargeAreBadMapsWhereverTheyAreNamed) {
  TempDir tmp;
  const std::string dir = tmp.dir();
  fs::create_symlink("/dev/zero", dir + "/zero.yaml");
  fs::create_symlink("/dev/zero", dir + "/zero.bt");
  fs::create_symlink("/dev/zero", dir + "/zero.pgm");
  ASSERT_EQ(::mkfifo((dir + "/fifo.yaml").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir + "/fifo.bt").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir + "/fifo.pgm").c_str(), 0600), 0);
  // Sparse files one byte over each cap (no disk used).
  const auto sparse = [&](const std::string& name, std::uintmax_t bytes) {
    const std::string p = tmp.write(name, "");
    fs::resize_file(p, bytes);
    return p;
  };
  const std::string huge_yaml = sparse("huge.yaml", kMaxYamlFileBytes + 1);
  const std::string huge_bt = sparse("huge.bt", maxBtBytes(kMaxMapCells) + 1);
  sparse("huge.pgm", maxPgmBytes(kMaxMapCells) + 1);
  const auto ros = [&](const std::string& name, const std::string& image) {
    return tmp.write(name, "image: " + image +
                               "\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                               "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  };
  struct Case {
    std::string path;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"/dev/zero", "/dev/zero: is a character device; the map file must be a regular file"},
      {dir + "/zero.yaml", "zero.yaml: is a character device; the map file must be a regular file"},
      {dir + "/fifo.yaml", "fifo.yaml: is a FIFO; the map file must be a regular file"},
      {huge_yaml, "huge.yaml: is 1048577 bytes, more than the map file may have (1 MiB)"},
      {dir + "/zero.bt", "zero.bt: is a character device; the OctoMap file must be a regular file"},
      {dir + "/fifo.bt", "fifo.bt: is a FIFO; the OctoMap file must be a regular file"},
      {huge_bt, "huge.bt: is 68157441 bytes, more than the OctoMap file may have (65 MiB)"},
      {ros("img_zero.yaml", "/dev/zero"),
       "/dev/zero: is a character device; the PGM image must be a regular file"},
      {ros("img_link.yaml", "zero.pgm"),
       "zero.pgm: is a character device; the PGM image must be a regular file"},
      {ros("img_fifo.yaml", "fifo.pgm"),
       "fifo.pgm: is a FIFO; the PGM image must be a regular file"},
      {ros("img_huge.yaml", "huge.pgm"),
       "huge.pgm: is 34603009 bytes, more than the PGM image may have (33 MiB)"},
      {tmp.write("scenario.yaml", "map: {file: zero.yaml}\n"), "zero.yaml: is a character device"},
  };
  for (const Case& c : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_THAT(errorOf([&] { loadMap(c.path); }), HasSubstr(c.says)) << c.path;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1)) << c.path;
    // As a daemon's map_file: StartupError (exit 3).
    MapSource source;
    source.map_file = c.path;
    EXPECT_THROW(loadDistanceField(source), StartupError) << c.path;
  }
  // The image and .bt caps follow max_map_cells: a raised limit reads a larger file.
  EXPECT_EQ(maxPgmBytes(kMaxMapCells), kMapFileHeaderBytes + 8 * (std::size_t{1} << 22));
  EXPECT_LT(maxBtBytes(kMaxMapCells), maxBtBytes(kMaxMapCellsCeiling));
  MapLoadOptions raised;
  raised.max_cells = kMaxMapCells * 2;
  EXPECT_THAT(errorOf([&] { loadMap(huge_bt, raised); }), HasSubstr("not a readable OctoMap"));
}

// yaml-cpp keeps both pairs of a duplicated key and node[key] gives the first: the second value
// was ignored without a word. Every mapping the map loader reads refuses it, naming both lines.
TEST(MapLoaderTest, AKeyGivenTwiceIsABadMapNamingTheKeyAndBothLines) {
  TempDir tmp;
  tmp.write("m.pgm", "P2\n2 2\n255\n0 255 255 0\n");
  EXPECT_THAT(
      errorOf(
          [&] { loadMap(tmp.write("ros.yaml", std::string(kRosYaml) + "resolution: 1e-9\n")); }),
      AllOf(HasSubstr("ros.yaml: key 'resolution' is given more than once (lines 2 and 7)")));
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("walls.yaml",
                                  "resolution_m: 0.1\nwalls:\n"
                                  "  - {x0_m: 0, y0_m: 0, x1_m: 1, y1_m: 0, x1_m: 9}\n"));
              }),
              HasSubstr("walls.yaml: key 'walls[0].x1_m' is given more than once (lines 3 and 3)"));
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("boxes.yaml",
                                  "resolution_m: 0.1\nboxes:\n  - min_x_m: 0\n    min_y_m: 0\n"
                                  "    max_x_m: 1\n    max_y_m: 1\n    min_y_m: -5\n"));
              }),
              HasSubstr("key 'boxes[0].min_y_m' is given more than once (lines 4 and 7)"));
  // A scenario's map section, a file or inline, and the scenario file itself.
  tmp.write("ok.yaml", kRosYaml);
  EXPECT_THAT(
      errorOf([&] { loadMap(tmp.write("s1.yaml", "map:\n  file: ok.yaml\n  file: ros.yaml\n")); }),
      HasSubstr("s1.yaml: map: key 'file' is given more than once (lines 2 and 3)"));
  EXPECT_THAT(errorOf([&] {
                loadMap(tmp.write("s2.yaml", "map: {file: ok.yaml}\nmap: {file: ros.yaml}\n"));
              }),
              HasSubstr("s2.yaml: key 'map' is given more than once (lines 1 and 2)"));
  EXPECT_EQ(loadMap(tmp.write("s3.yaml", "map: {file: ok.yaml}\n")).grid.width(), 2);
}

// Measured before: a ROS map at resolution 1e-9 loaded, and every query fell outside it. Every
// source (ROS map, walls map, .bt) refuses a resolution outside [1 mm, 10 m], naming the file and
// the value; both ends load.
TEST(MapLoaderTest, AResolutionOutsideOneMillimetreToTenMetresIsABadMapOfEverySource) {
  TempDir tmp;
  tmp.write("m.pgm", "P2\n2 2\n255\n0 255 255 0\n");
  const auto ros = [&](const std::string& res) {
    return tmp.write("ros_" + res + ".yaml",
                     "image: m.pgm\nresolution: " + res +
                         "\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\n"
                         "free_thresh: 0.196\n");
  };
  const auto walls = [&](const std::string& res) {
    return tmp.write("walls_" + res + ".yaml",
                     "resolution_m: " + res +
                         "\nboxes:\n  - {min_x_m: 0, min_y_m: 0, max_x_m: 0.002, max_y_m: "
                         "0.002}\n");
  };
  for (const std::string res : {"1e-9", "1e3", "-0.05", "0"}) {
    const std::string r = ros(res), w = walls(res);
    EXPECT_THAT(errorOf([&] { loadMap(r); }), HasSubstr(r + ": key 'resolution' (line 2) = " + res +
                                                        " m per cell is outside [0.001, 10]"));
    EXPECT_THAT(errorOf([&] { loadMap(w); }),
                HasSubstr(w + ": key 'resolution_m' (line 1) = " + res +
                          " m per cell is outside [0.001, 10]"));
  }
  for (const std::string res : {"0.001", "10"}) {
    EXPECT_EQ(loadMap(ros(res)).grid.width(), 2);
    EXPECT_EQ(loadMap(walls(res)).grid.width(), res == "10" ? 1 : 2);
  }
  for (const double res : {1e-9, 1e3}) {
    octomap::OcTree tree(res);
    tree.updateNode(octomap::point3d(0.0f, 0.0f, 0.0f), true);
    const std::string bt = tmp.dir() + "/r.bt";
    ASSERT_TRUE(tree.writeBinary(bt));
    EXPECT_THAT(
        errorOf([&] { loadMap(bt); }),
        AllOf(HasSubstr(bt + ": resolution = "), HasSubstr("m per cell is outside [0.001, 10]")))
        << res;
  }
}

}  // namespace
}  // namespace coopnav
