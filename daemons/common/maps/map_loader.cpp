#include "map_loader.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <istream>
#include <limits>
#include <sstream>
#include <streambuf>

#include "config/config.hpp"
#include "config/file_read.hpp"
#include "coopnav/distance/octree_conversion.hpp"

namespace coopnav {
namespace {

namespace fs = std::filesystem;

// An origin yaw below this is taken as 0 (YAML files print "0.000000").
constexpr double kYawTolerance_rad = 1e-9;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw MapLoadError(where + ": " + what);
}

std::string lineOf(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  if (m.line < 0) return "";
  return " (line " + std::to_string(m.line + 1) + ")";
}

std::string scalarOf(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a sequence";
  if (n.IsMap()) return "a mapping";
  return "null";
}

YAML::Node requireKey(const YAML::Node& node, const std::string& key, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) fail(where, "missing key '" + key + "'" + lineOf(node));
  return v;
}

double asDouble(const YAML::Node& v, const std::string& key, const std::string& where) {
  if (v.IsScalar()) {
    try {
      const double d = v.as<double>();
      if (std::isfinite(d)) return d;
    } catch (const YAML::BadConversion&) {
    }
  }
  fail(where, "key '" + key + "'" + lineOf(v) + " must be a finite number, got " + scalarOf(v));
}

double requireDouble(const YAML::Node& node, const std::string& key, const std::string& where) {
  return asDouble(requireKey(node, key, where), key, where);
}

std::string requireString(const YAML::Node& node, const std::string& key,
                          const std::string& where) {
  const YAML::Node v = requireKey(node, key, where);
  if (!v.IsScalar() || v.Scalar().empty()) {
    fail(where,
         "key '" + key + "'" + lineOf(v) + " must be a non-empty string, got " + scalarOf(v));
  }
  return v.Scalar();
}

void requireInRange(double value, double lo, double hi, const YAML::Node& node,
                    const std::string& key, const std::string& where) {
  if (value < lo || value > hi) {
    std::ostringstream os;
    os << "key '" << key << "'" << lineOf(node[key]) << " = " << value << " is outside [" << lo
       << ", " << hi << "]";
    fail(where, os.str());
  }
}

// Every map file is read here. A directory, /dev/zero, a FIFO or a file over its cap is a bad map
// (exit 3), refused before it is read (a directory once threw std::ios_base::failure past the
// loader, found by fuzz_map_yaml; /dev/zero was read until std::bad_alloc).
std::string readFile(const std::string& path, std::size_t max_bytes, const std::string& what) {
  try {
    return readFileCapped(path, max_bytes, what);
  } catch (const FileReadError& e) {
    throw MapLoadError(e.what());
  }
}

// A key given twice in a mapping the loader reads: node[key] would take the first and ignore the
// second without a word.
void rejectDuplicateKeys(const YAML::Node& node, const std::string& where,
                         const std::string& prefix = "") {
  reportDuplicateKeys(node, [&](const std::string& key, const std::string& msg) {
    fail(where, "key '" + prefix + key + "' " + msg);
  });
}

// Every map source's resolution: `written` is the value as the file gives it.
void requireResolution(double resolution_m, const std::string& written, const std::string& what,
                       const std::string& where) {
  if (resolution_m >= kMinMapResolution_m && resolution_m <= kMaxMapResolution_m) return;
  std::ostringstream os;
  os << what << " = " << written << " m per cell is outside [" << kMinMapResolution_m << ", "
     << kMaxMapResolution_m << "] (a slip of units, not a map)";
  fail(where, os.str());
}

// The bytes of a string as a stream without a copy (OctoMap reads from an istream).
class StringViewBuf : public std::streambuf {
 public:
  explicit StringViewBuf(std::string& data) {
    setg(data.data(), data.data(), data.data() + data.size());
  }
};

YAML::Node loadYamlFile(const std::string& path) {
  const std::string text = readFile(path, kMaxYamlFileBytes, "map file");
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    fail(path, "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

bool hasSuffix(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) ==
           std::tolower(static_cast<unsigned char>(b));
  });
}

// PGM header tokeniser: whitespace and '#' comments to the end of the line separate tokens.
class PgmCursor {
 public:
  PgmCursor(const std::string& data, const std::string& path) : data_(data), path_(path) {}

  void skipSpaceAndComments() {
    while (pos_ < data_.size()) {
      const char ch = data_[pos_];
      if (ch == '#') {
        while (pos_ < data_.size() && data_[pos_] != '\n' && data_[pos_] != '\r') ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(ch))) {
        ++pos_;
      } else {
        break;
      }
    }
  }

  // Returns false at end of data; throws on a non-digit token.
  bool nextUnsigned(long long* value, const std::string& what) {
    skipSpaceAndComments();
    if (pos_ >= data_.size()) return false;
    const std::size_t start = pos_;
    long long v = 0;
    while (pos_ < data_.size() && std::isdigit(static_cast<unsigned char>(data_[pos_]))) {
      v = std::min<long long>(v * 10 + (data_[pos_] - '0'), 1LL << 40);
      ++pos_;
    }
    if (pos_ == start ||
        (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_])) &&
         data_[pos_] != '#')) {
      const std::size_t end = std::min(data_.size(), start + 16);
      throw MapLoadError(path_ + ": bad PGM " + what + " '" + data_.substr(start, end - start) +
                         "' at byte " + std::to_string(start));
    }
    *value = v;
    return true;
  }

  std::size_t pos() const { return pos_; }
  void advance(std::size_t n) { pos_ += n; }

 private:
  const std::string& data_;
  const std::string& path_;
  std::size_t pos_{2};  // after the magic number
};

// Marks cells whose centre is within half_width_m of segment a-b, and the 4-connected cells the
// segment itself crosses (Amanatides & Woo 1987 traversal), so thin walls stay closed.
void rasteriseSegment(OccupancyGrid2* grid, const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m,
                      double half_width_m) {
  const double res = grid->resolution_m();
  const Eigen::Vector2d lo = a_m.cwiseMin(b_m) - Eigen::Vector2d::Constant(half_width_m);
  const Eigen::Vector2d hi = a_m.cwiseMax(b_m) + Eigen::Vector2d::Constant(half_width_m);
  const int i0 = std::max(0, static_cast<int>(std::floor((lo.x() - grid->origin_m().x()) / res)));
  const int j0 = std::max(0, static_cast<int>(std::floor((lo.y() - grid->origin_m().y()) / res)));
  const int i1 = std::min(grid->width() - 1,
                          static_cast<int>(std::floor((hi.x() - grid->origin_m().x()) / res)));
  const int j1 = std::min(grid->height() - 1,
                          static_cast<int>(std::floor((hi.y() - grid->origin_m().y()) / res)));
  const Eigen::Vector2d ab = b_m - a_m;
  const double len2 = ab.squaredNorm();
  // Per row, only the cells near the part of the segment within reach of that row are tested:
  // scanning the whole bounding box made a long diagonal wall cost its box's area, not its
  // length (a walls map of ~100 diagonal walls took 200 ms under fuzz_map_yaml, 65 % of it
  // here). The closest point of the segment to a cell centre that is within half_width_m lies
  // within half_width_m of the row in y and of the centre in x; one cell more each way keeps
  // the exact test below the judge, so the cells are those of the full scan.
  const double reach_m = half_width_m + res;
  for (int j = j0; j <= j1; ++j) {
    const double y_m = grid->cellCenter_m(i0, j).y();
    double t_lo = 0.0, t_hi = 1.0;
    if (ab.y() != 0.0) {
      t_lo = (y_m - reach_m - a_m.y()) / ab.y();
      t_hi = (y_m + reach_m - a_m.y()) / ab.y();
      if (t_lo > t_hi) std::swap(t_lo, t_hi);
      t_lo = std::max(t_lo, 0.0);
      t_hi = std::min(t_hi, 1.0);
      if (t_lo > t_hi) continue;
    } else if (std::abs(y_m - a_m.y()) > reach_m) {
      continue;
    }
    const double xa_m = a_m.x() + t_lo * ab.x(), xb_m = a_m.x() + t_hi * ab.x();
    // Clamped as a double: no out-of-range int cast. (Not finite cannot happen on a grid that
    // passed the cell limit; the whole row is then the safe answer.)
    const bool finite = std::isfinite(xa_m) && std::isfinite(xb_m);
    const auto column = [&](double x_m) {
      const double c = std::floor((x_m - grid->origin_m().x()) / res);
      return c < i0 ? i0 : (c > i1 ? i1 : static_cast<int>(c));
    };
    const int row_i0 = finite ? column(std::min(xa_m, xb_m) - reach_m) : i0;
    const int row_i1 = finite ? column(std::max(xa_m, xb_m) + reach_m) : i1;
    for (int i = row_i0; i <= row_i1; ++i) {
      const Eigen::Vector2d p = grid->cellCenter_m(i, j);
      const double t = len2 > 0.0 ? std::clamp((p - a_m).dot(ab) / len2, 0.0, 1.0) : 0.0;
      if ((p - (a_m + t * ab)).norm() <= half_width_m) grid->set(i, j, CellState::kOccupied);
    }
  }
  const Eigen::Vector2d g = (a_m - grid->origin_m()) / res;
  const Eigen::Vector2d g_end = (b_m - grid->origin_m()) / res;
  int i = static_cast<int>(std::floor(g.x()));
  int j = static_cast<int>(std::floor(g.y()));
  const int i_end = static_cast<int>(std::floor(g_end.x()));
  const int j_end = static_cast<int>(std::floor(g_end.y()));
  const Eigen::Vector2d d = g_end - g;
  const int si = d.x() > 0 ? 1 : (d.x() < 0 ? -1 : 0);
  const int sj = d.y() > 0 ? 1 : (d.y() < 0 ? -1 : 0);
  const auto crossing = [](int cell, int step, double g0, double d0) {
    if (step == 0) return std::numeric_limits<double>::infinity();
    return (static_cast<double>(step > 0 ? cell + 1 : cell) - g0) / d0;
  };
  const int max_steps = std::abs(i_end - i) + std::abs(j_end - j);
  for (int k = 0; k <= max_steps; ++k) {
    if (grid->contains(i, j)) grid->set(i, j, CellState::kOccupied);
    if (i == i_end && j == j_end) break;
    if (crossing(i, si, g.x(), d.x()) < crossing(j, sj, g.y(), d.y())) {
      i += si;
    } else {
      j += sj;
    }
  }
}

LoadedMap fromGrid(OccupancyGrid2 grid, const MapLoadOptions& options, const std::string& source) {
  LoadedMap map;
  try {
    if (options.build_tree) {
      map.tree = gridToOctree(grid, options.slab_layers);
    } else {
      checkOctreeCanHold(grid, options.slab_layers);
    }
  } catch (const std::invalid_argument& e) {
    fail(source, e.what());
  }
  map.tree_origin_m = grid.origin_m();
  map.grid = std::move(grid);
  map.source = source;
  return map;
}

LoadedMap loadBt(const std::string& path, const MapLoadOptions& options) {
  std::string data = readFile(path, maxBtBytes(options.max_cells), "OctoMap file");
  if (!(options.bt_z_min_m < options.bt_z_max_m)) {
    std::ostringstream os;
    os << "height band [" << options.bt_z_min_m << ", " << options.bt_z_max_m
       << "] m is empty (z_min must be < z_max)";
    fail(path, os.str());
  }
  LoadedMap map;
  map.tree = std::make_unique<octomap::OcTree>(0.1);  // readBinary takes the file's resolution
  StringViewBuf buf(data);
  std::istream in(&buf);
  if (!map.tree->readBinary(in)) fail(path, "not a readable OctoMap binary (.bt) file");
  {
    std::ostringstream res;
    res << map.tree->getResolution();
    requireResolution(map.tree->getResolution(), res.str(), "resolution", path);
  }
  map.tree_origin_m = options.bt_origin_m;
  try {
    map.grid = octreeToGrid(*map.tree, options.bt_z_min_m, options.bt_z_max_m, options.bt_origin_m,
                            options.max_cells);
  } catch (const std::invalid_argument& e) {
    // Too large, or a resolution that is not a number > 0: a bad file (exit 3), not a crash of
    // the loader's caller with an exception it does not expect.
    fail(path, e.what());
  }
  if (map.grid.empty()) {
    std::ostringstream os;
    os << "no known voxel in the height band [" << options.bt_z_min_m << ", " << options.bt_z_max_m
       << "] m";
    fail(path, os.str());
  }
  map.source = path;
  return map;
}

// A scenario's map may name a file that is itself a scenario, and so on; a file that names itself
// (or a cycle) recursed until the stack overflowed (found by fuzz_map_yaml). Real chains are one
// or two files long.
constexpr int kMaxMapFileNesting = 8;

LoadedMap loadMapNested(const std::string& path, const MapLoadOptions& options, int nesting);
LoadedMap loadMapFromNodeNested(const YAML::Node& map_node, const std::string& base_dir,
                                const MapLoadOptions& options, const std::string& where,
                                int nesting);

/// Appends node's `goal_regions` (optional) to map.
void appendGoalRegions(const YAML::Node& node, const std::string& where, LoadedMap* map) {
  const YAML::Node list = node["goal_regions"];
  if (!list) return;
  if (!list.IsSequence()) {
    fail(where, "key 'goal_regions'" + lineOf(list) + " must be a sequence, got " + scalarOf(list));
  }
  if (map->goal_regions.size() + list.size() > kMaxMapGoalRegions) {
    fail(where, "key 'goal_regions'" + lineOf(list) + ": more than " +
                    std::to_string(kMaxMapGoalRegions) + " goal regions");
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    const YAML::Node e = list[k];
    const std::string item = "goal_regions[" + std::to_string(k) + "]";
    if (!e.IsMap()) fail(where, item + lineOf(e) + " must be a mapping, got " + scalarOf(e));
    rejectDuplicateKeys(e, where, item + ".");
    const auto get = [&](const char* field) {
      return asDouble(requireKey(e, field, where + ": " + item), item + "." + field, where);
    };
    map->goal_regions.push_back({{get("x0_m"), get("y0_m")}, {get("x1_m"), get("y1_m")}});
  }
}

LoadedMap loadYamlMap(const YAML::Node& node, const std::string& base_dir,
                      const MapLoadOptions& options, const std::string& where, int nesting) {
  if (!node.IsMap()) fail(where, "expected a YAML mapping, got " + scalarOf(node));
  rejectDuplicateKeys(node, where);
  if (node["image"] || node["walls"] || node["boxes"]) {
    LoadedMap m = fromGrid(node["image"] ? loadRosMap(node, base_dir, where, options.max_cells)
                                         : rasteriseWallsMap(node, where, options.max_cells),
                           options, where);
    appendGoalRegions(node, where, &m);
    return m;
  }
  // A scenario file: its `map:` (a file or walls) is the map, so every daemon of a run can be
  // pointed at the scenario itself and is sure to load what the simulator loads.
  if (node["map"] && node["map"].IsMap())
    return loadMapFromNodeNested(node["map"], base_dir, options, where + ": map", nesting);
  fail(where,
       "neither a ROS map (key 'image'), a walls map (keys 'walls', 'boxes') nor a scenario "
       "(key 'map')" +
           lineOf(node));
}

}  // namespace

std::size_t maxPgmBytes(std::int64_t max_cells) {
  return kMapFileHeaderBytes +
         kMaxPgmBytesPerCell * static_cast<std::size_t>(std::max<std::int64_t>(max_cells, 0));
}

std::size_t maxBtBytes(std::int64_t max_cells) {
  return kMapFileHeaderBytes +
         kMaxBtBytesPerCell * static_cast<std::size_t>(std::max<std::int64_t>(max_cells, 0));
}

PgmImage readPgm(const std::string& path, std::int64_t max_cells) {
  const std::string data = readFile(path, maxPgmBytes(max_cells), "PGM image");
  if (data.size() < 2 || data[0] != 'P' || (data[1] != '2' && data[1] != '5')) {
    fail(path, "bad PGM magic '" + data.substr(0, std::min<std::size_t>(2, data.size())) +
                   "' (expected P2 or P5)");
  }
  const bool binary = data[1] == '5';
  PgmCursor cur(data, path);
  long long w = 0, h = 0, maxval = 0;
  if (!cur.nextUnsigned(&w, "width") || !cur.nextUnsigned(&h, "height") ||
      !cur.nextUnsigned(&maxval, "maxval")) {
    fail(path, "truncated PGM header");
  }
  // Each side is bounded before the product: the tokeniser clamps a number to 2^40, and the
  // product of two such numbers overflows long long (found by fuzz_map_pgm).
  if (w <= 0 || h <= 0 || w > (1LL << 30) || h > (1LL << 30) || w * h > (1LL << 30)) {
    fail(path, "bad PGM size " + std::to_string(w) + " x " + std::to_string(h));
  }
  if (maxval <= 0 || maxval > 65535) {
    fail(path, "bad PGM maxval " + std::to_string(maxval) + " (expected 1..65535)");
  }
  PgmImage img;
  img.width = static_cast<int>(w);
  img.height = static_cast<int>(h);
  img.maxval = static_cast<int>(maxval);
  const std::size_t n = static_cast<std::size_t>(w * h);
  // The raster is only allocated once the data is known to hold it: a header alone may claim 2^30
  // pixels, and a 20-byte file made the loader allocate and clear 2 GB (found by fuzz_map_pgm).
  if (binary) {
    // Exactly one whitespace byte separates maxval from the raster (which may begin with bytes
    // that look like whitespace or '#').
    cur.advance(1);
    const std::size_t bytes_per_px = maxval < 256 ? 1 : 2;
    const std::size_t need = n * bytes_per_px;
    const std::size_t have = data.size() > cur.pos() ? data.size() - cur.pos() : 0;
    if (have < need) {
      fail(path, "truncated PGM pixel data: expected " + std::to_string(need) + " bytes for " +
                     std::to_string(w) + " x " + std::to_string(h) + ", got " +
                     std::to_string(have));
    }
    img.pixels.resize(n);
    const auto* raw = reinterpret_cast<const unsigned char*>(data.data() + cur.pos());
    for (std::size_t k = 0; k < n; ++k) {
      img.pixels[k] = bytes_per_px == 1
                          ? raw[k]
                          : static_cast<std::uint16_t>((raw[2 * k] << 8) | raw[2 * k + 1]);
    }
  } else {
    // n values need a digit each and a separator between two.
    const std::size_t have = data.size() > cur.pos() ? data.size() - cur.pos() : 0;
    if (n > (have + 1) / 2) {
      fail(path, "truncated PGM pixel data: expected " + std::to_string(n) +
                     " values, the file has room for at most " + std::to_string((have + 1) / 2));
    }
    img.pixels.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      long long v = 0;
      if (!cur.nextUnsigned(&v, "pixel")) {
        fail(path, "truncated PGM pixel data: expected " + std::to_string(n) + " values, got " +
                       std::to_string(k));
      }
      img.pixels[k] = static_cast<std::uint16_t>(std::min<long long>(v, 65535));
      if (v > maxval) {
        fail(path, "PGM pixel " + std::to_string(k) + " value " + std::to_string(v) +
                       " exceeds maxval " + std::to_string(maxval));
      }
    }
  }
  if (binary) {
    for (std::size_t k = 0; k < n; ++k) {
      if (img.pixels[k] > maxval) {
        fail(path, "PGM pixel " + std::to_string(k) + " value " + std::to_string(img.pixels[k]) +
                       " exceeds maxval " + std::to_string(maxval));
      }
    }
  }
  return img;
}

OccupancyGrid2 loadRosMap(const YAML::Node& node, const std::string& base_dir,
                          const std::string& where, std::int64_t max_cells) {
  rejectDuplicateKeys(node, where);
  const std::string image = requireString(node, "image", where);
  const double resolution_m = requireDouble(node, "resolution", where);
  requireResolution(resolution_m, node["resolution"].Scalar(),
                    "key 'resolution'" + lineOf(node["resolution"]), where);
  const YAML::Node origin = requireKey(node, "origin", where);
  if (!origin.IsSequence() || origin.size() != 3) {
    fail(where, "key 'origin'" + lineOf(origin) + " must be a sequence [x, y, yaw], got " +
                    scalarOf(origin));
  }
  const double ox = asDouble(origin[0], "origin[0]", where);
  const double oy = asDouble(origin[1], "origin[1]", where);
  const double yaw = asDouble(origin[2], "origin[2]", where);
  if (std::abs(yaw) > kYawTolerance_rad) {
    fail(where, "key 'origin'" + lineOf(origin) + ": yaw " + origin[2].Scalar() +
                    " rad is not supported (only axis-aligned maps, yaw = 0)");
  }
  const YAML::Node negate_node = requireKey(node, "negate", where);
  int negate = -1;
  if (negate_node.IsScalar()) {
    if (negate_node.Scalar() == "0" || negate_node.Scalar() == "false") negate = 0;
    if (negate_node.Scalar() == "1" || negate_node.Scalar() == "true") negate = 1;
  }
  if (negate < 0) {
    fail(where,
         "key 'negate'" + lineOf(negate_node) + " must be 0 or 1, got " + scalarOf(negate_node));
  }
  const double occupied_thresh = requireDouble(node, "occupied_thresh", where);
  const double free_thresh = requireDouble(node, "free_thresh", where);
  requireInRange(occupied_thresh, 0.0, 1.0, node, "occupied_thresh", where);
  requireInRange(free_thresh, 0.0, 1.0, node, "free_thresh", where);
  if (!(free_thresh < occupied_thresh)) {
    fail(where, "free_thresh (" + node["free_thresh"].Scalar() +
                    ") must be below occupied_thresh (" + node["occupied_thresh"].Scalar() + ")");
  }
  if (const YAML::Node mode = node["mode"]) {
    const std::string m = mode.IsScalar() ? mode.Scalar() : "";
    if (m == "scale" || m == "raw") {
      fail(where, "key 'mode'" + lineOf(mode) + " = '" + m +
                      "' is not supported (only 'trinary': free / occupied / unknown)");
    }
    if (m != "trinary") {
      fail(where, "key 'mode'" + lineOf(mode) + " must be 'trinary', 'scale' or 'raw', got " +
                      scalarOf(mode));
    }
  }

  const fs::path image_path =
      fs::path(image).is_absolute() ? fs::path(image) : fs::path(base_dir) / image;
  // The error_code overload: the throwing one throws filesystem_error past the loader for a
  // name the system refuses (a 300-byte component: ENAMETOOLONG; found by fuzz_map_yaml).
  std::error_code ec;
  if (!fs::exists(image_path, ec)) {
    fail(where, "image file '" + image_path.string() + "' (key 'image'" + lineOf(node["image"]) +
                    ") not found" + (ec ? " (" + ec.message() + ")" : std::string()));
  }
  const PgmImage img = readPgm(image_path.string(), max_cells);
  if (std::int64_t{img.width} * img.height > max_cells) {
    fail(where, "image '" + image_path.string() + "' of " + std::to_string(img.width) + " x " +
                    std::to_string(img.height) + " pixels is larger than " +
                    std::to_string(max_cells) + " cells (max_map_cells)");
  }

  // ROS map_server trinary semantics: p = (maxval - v) / maxval (v / maxval when negated);
  // occupied if p > occupied_thresh, free if p < free_thresh, else unknown. Image row 0 is the
  // top, grid row 0 the bottom.
  OccupancyGrid2 grid(img.width, img.height, resolution_m, Eigen::Vector2d(ox, oy),
                      CellState::kUnknown);
  const double maxval = img.maxval;
  for (int r = 0; r < img.height; ++r) {
    for (int c = 0; c < img.width; ++c) {
      const double v = img.pixels[static_cast<std::size_t>(r) * img.width + c];
      const double p = negate ? v / maxval : (maxval - v) / maxval;
      const int j = img.height - 1 - r;
      if (p > occupied_thresh) {
        grid.set(c, j, CellState::kOccupied);
      } else if (p < free_thresh) {
        grid.set(c, j, CellState::kFree);
      }
    }
  }
  return grid;
}

OccupancyGrid2 rasteriseWallsMap(const YAML::Node& node, const std::string& where,
                                 std::int64_t max_cells) {
  rejectDuplicateKeys(node, where);
  double res = kDefaultWallsMapResolution_m;
  if (node["resolution_m"]) {
    res = requireDouble(node, "resolution_m", where);
    requireResolution(res, node["resolution_m"].Scalar(),
                      "key 'resolution_m'" + lineOf(node["resolution_m"]), where);
  }
  double margin_m = 0.0;
  if (node["margin_m"]) {
    margin_m = asDouble(node["margin_m"], "margin_m", where);
    if (margin_m < 0.0) fail(where, "key 'margin_m'" + lineOf(node["margin_m"]) + " must be >= 0");
  }
  struct Wall {
    Eigen::Vector2d a, b;
    double half_m;
  };
  std::vector<Wall> walls;
  std::vector<Eigen::AlignedBox2d> boxes;
  Eigen::AlignedBox2d extent;  // empty
  for (const char* key : {"walls", "boxes"}) {
    const YAML::Node list = node[key];
    if (!list) continue;
    if (!list.IsSequence()) {
      fail(where, std::string("key '") + key + "'" + lineOf(list) + " must be a sequence, got " +
                      scalarOf(list));
    }
    for (std::size_t k = 0; k < list.size(); ++k) {
      const YAML::Node e = list[k];
      const std::string item = std::string(key) + "[" + std::to_string(k) + "]";
      if (!e.IsMap()) fail(where, item + lineOf(e) + " must be a mapping, got " + scalarOf(e));
      rejectDuplicateKeys(e, where, item + ".");
      const auto get = [&](const char* field) {
        return asDouble(requireKey(e, field, where + ": " + item), item + "." + field, where);
      };
      if (std::string(key) == "walls") {
        const double thickness_m = e["thickness_m"] ? get("thickness_m") : kDefaultWallThickness_m;
        Wall w{{get("x0_m"), get("y0_m")}, {get("x1_m"), get("y1_m")}, 0.5 * thickness_m};
        if (!(w.half_m > 0.0)) {
          fail(where, item + ".thickness_m" + lineOf(e["thickness_m"]) + " must be > 0");
        }
        extent.extend(w.a.cwiseMin(w.b) - Eigen::Vector2d::Constant(w.half_m));
        extent.extend(w.a.cwiseMax(w.b) + Eigen::Vector2d::Constant(w.half_m));
        walls.push_back(w);
      } else {
        const Eigen::AlignedBox2d b(Eigen::Vector2d(get("min_x_m"), get("min_y_m")),
                                    Eigen::Vector2d(get("max_x_m"), get("max_y_m")));
        if (!(b.min().array() < b.max().array()).all()) {
          fail(where, item + lineOf(e) + " must have min_x_m < max_x_m and min_y_m < max_y_m");
        }
        extent.extend(b);
        boxes.push_back(b);
      }
    }
  }
  if (walls.empty() && boxes.empty())
    fail(where, "walls map without any wall or box" + lineOf(node));
  const Eigen::Vector2d origin = extent.min() - Eigen::Vector2d::Constant(margin_m);
  const Eigen::Vector2d size = extent.sizes() + Eigen::Vector2d::Constant(2.0 * margin_m);
  // The 1e-9 keeps an extent that is an exact multiple of res from gaining a column. At least one
  // cell each way: an extent far below res would otherwise give 0 x huge cells, which passed the
  // size check and overflowed the int cast (found by fuzz_map_yaml).
  const double w = std::max(1.0, std::ceil(size.x() / res - 1e-9));
  const double h = std::max(1.0, std::ceil(size.y() / res - 1e-9));
  if (w * h > static_cast<double>(max_cells)) {
    std::ostringstream os;
    os << "walls map of " << w << " x " << h << " cells at resolution_m " << res
       << " is larger than " << max_cells << " cells (max_map_cells)";
    fail(where, os.str());
  }
  OccupancyGrid2 grid(static_cast<int>(w), static_cast<int>(h), res, origin, CellState::kFree);
  for (const Wall& wall : walls) rasteriseSegment(&grid, wall.a, wall.b, wall.half_m);
  for (const Eigen::AlignedBox2d& b : boxes) {
    const int i0 = std::max(0, static_cast<int>(std::floor((b.min().x() - origin.x()) / res)));
    const int j0 = std::max(0, static_cast<int>(std::floor((b.min().y() - origin.y()) / res)));
    const int i1 =
        std::min(grid.width(), static_cast<int>(std::ceil((b.max().x() - origin.x()) / res)));
    const int j1 =
        std::min(grid.height(), static_cast<int>(std::ceil((b.max().y() - origin.y()) / res)));
    for (int j = j0; j < j1; ++j) {
      for (int i = i0; i < i1; ++i) grid.set(i, j, CellState::kOccupied);
    }
  }
  return grid;
}

namespace {

LoadedMap loadMapNested(const std::string& path, const MapLoadOptions& options, int nesting) {
  if (hasSuffix(path, ".bt")) return loadBt(path, options);
  if (hasSuffix(path, ".ot")) fail(path, "'.ot' trees are not supported (convert to .bt)");
  const YAML::Node node = loadYamlFile(path);
  return loadYamlMap(node, fs::path(path).parent_path().string(), options, path, nesting);
}

LoadedMap loadMapFromNodeNested(const YAML::Node& map_node, const std::string& base_dir,
                                const MapLoadOptions& options, const std::string& where,
                                int nesting) {
  if (!map_node || !map_node.IsMap()) {
    fail(where, "expected a mapping with 'file' or walls/boxes, got " + scalarOf(map_node));
  }
  rejectDuplicateKeys(map_node, where);
  if (const YAML::Node file = map_node["file"]) {
    const std::string f = requireString(map_node, "file", where);
    if (nesting >= kMaxMapFileNesting) {
      fail(where, "key 'file'" + lineOf(file) + " = '" + f + "': map files nest more than " +
                      std::to_string(kMaxMapFileNesting) +
                      " deep (a scenario whose map names itself, or a cycle)");
    }
    const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : fs::path(base_dir) / f;
    LoadedMap m = loadMapNested(p.string(), options, nesting + 1);
    appendGoalRegions(map_node, where, &m);
    return m;
  }
  return loadYamlMap(map_node, base_dir, options, where, nesting);
}

}  // namespace

LoadedMap loadMap(const std::string& path, const MapLoadOptions& options) {
  return loadMapNested(path, options, 0);
}

LoadedMap loadMapFromNode(const YAML::Node& map_node, const std::string& base_dir,
                          const MapLoadOptions& options, const std::string& where) {
  return loadMapFromNodeNested(map_node, base_dir, options, where, 0);
}

void writeBt(const octomap::OcTree& tree, const std::string& path) {
  if (!tree.writeBinaryConst(path)) throw MapLoadError(path + ": cannot write OctoMap file");
}

}  // namespace coopnav
