// One declaration per config key: each daemon's Config struct lists its keys once, in
// visit(), with their defaults (the in-class initialisers) and ranges. This test enumerates them
// through the visitor (nested keys dotted: "speech.rate_wpm") and checks the two copies people
// read against it:
//   - config/<daemon>.yaml sets exactly the known keys (a key may be left out only when its README
//     row says "optional" in its Default column), and the "(min..max)" ranges its comments give
//     are the key's Range;
//   - the daemon's README table `| Key | Default | Range | Meaning |` lists exactly the known keys
//     (a row `prefix.*` stands for every key under prefix; a row may list several keys), with the
//     struct's default (numbers, booleans, strings) and Range ("[min, max]"; a OneOf key's values).
// Numbers compare as numbers: 0.1 = 0.10, 1e-6 = 0.000001, 2^22 = 4194304.

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "band_source/band_source_node.hpp"
#include "config/config.hpp"
#include "dialogue_manager/dialogue_manager_node.hpp"
#include "obstacle_distance_server/obstacle_distance_server_node.hpp"
#include "path_assessor/path_assessor_node.hpp"
#include "situation_assessor/situation_assessor_node.hpp"
#include "test_paths.hpp"
#include "viewer/viewer_node.hpp"
#include "world_sim/world_sim_node.hpp"

namespace coopnav {
namespace {

const std::string kRoot = ::coopnav::test::sourceDir();

/// One leaf key of a config, as its visit() declares it.
struct KeyInfo {
  enum class Kind { kNumber, kBool, kString, kOther };
  std::string key;  ///< dotted
  Kind kind{Kind::kOther};
  double number{0.0};  ///< default of a number
  bool boolean{false};
  std::string text;  ///< default of a string
  std::optional<Range> range;
  std::optional<std::vector<std::string>> one_of;
};

/// The visitor that lists the keys of a config (with their defaults, as visited on a
/// default-constructed struct).
class KeyLister {
 public:
  KeyLister(std::vector<KeyInfo>& out, std::string prefix)
      : out_(out), prefix_(std::move(prefix)) {}

  template <class T, class... Options>
  void operator()(const char* key, T& field, const Options&... options) {
    if constexpr (detail::HasVisit<T>::value) {
      KeyLister sub(out_, prefix_ + key + ".");
      field.visit(sub);
    } else {
      KeyInfo k;
      k.key = prefix_ + key;
      if constexpr (std::is_same_v<T, bool>) {
        k.kind = KeyInfo::Kind::kBool;
        k.boolean = field;
      } else if constexpr (std::is_arithmetic_v<T>) {
        k.kind = KeyInfo::Kind::kNumber;
        k.number = static_cast<double>(field);
      } else if constexpr (std::is_same_v<T, std::string>) {
        k.kind = KeyInfo::Kind::kString;
        k.text = field;
      }
      (note(options, k), ...);
      out_.push_back(k);
    }
  }
  void require(bool, const std::string&, const std::string&) {}
  void skip(const char*) {}

 private:
  static void note(const Range& r, KeyInfo& k) { k.range = r; }
  static void note(const OneOf& o, KeyInfo& k) { k.one_of = o.values; }
  static void note(const Required&, KeyInfo&) {}

  std::vector<KeyInfo>& out_;
  std::string prefix_;
};

template <class Config>
std::vector<KeyInfo> keysOf() {
  Config config;
  std::vector<KeyInfo> keys;
  KeyLister lister(keys, "");
  config.visit(lister);
  return keys;
}

// ---- text helpers

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// A number as the docs write it: "0.10", "1e-6", "2^22", "-inf"; nullopt if it is none.
std::optional<double> parseNumber(std::string s) {
  s = trim(s);
  if (s.empty()) return std::nullopt;
  const auto caret = s.find('^');
  if (caret != std::string::npos) {
    const auto base = parseNumber(s.substr(0, caret));
    const auto exp = parseNumber(s.substr(caret + 1));
    if (!base || !exp) return std::nullopt;
    return std::pow(*base, *exp);
  }
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') return std::nullopt;
  return x;
}

/// The number a cell starts with ("4194304 (2^22)" -> 4194304).
std::optional<double> leadingNumber(const std::string& cell) {
  std::string s = trim(cell);
  if (!s.empty() && s.front() == '`' && s.back() == '`') s = s.substr(1, s.size() - 2);
  const auto space = s.find(' ');
  return parseNumber(space == std::string::npos ? s : s.substr(0, space));
}

bool sameNumber(double a, double b) {
  if (a == b) return true;
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

std::string rangeText(const Range& r) { return "[" + fmt(r.min) + ", " + fmt(r.max) + "]"; }

/// The first "[a, b]" of a cell whose ends are numbers.
std::optional<Range> intervalIn(const std::string& cell) {
  static const std::regex re(R"(\[([^\[\],]+),([^\[\],]+)\])");
  for (std::sregex_iterator it(cell.begin(), cell.end(), re), end; it != end; ++it) {
    const auto lo = parseNumber((*it)[1].str());
    const auto hi = parseNumber((*it)[2].str());
    if (lo && hi) return Range{*lo, *hi};
  }
  return std::nullopt;
}

// ---- README table

struct ReadmeRow {
  int line{0};
  std::vector<std::string> keys;  ///< as written; "prefix.*" for a group
  std::string default_cell, range_cell;
};

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool code = false;  // a '|' inside `...` is text
  for (std::size_t i = 1; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '`') code = !code;
    if (c == '|' && !code && line[i - 1] != '\\') {
      cells.push_back(trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  return cells;
}

/// The rows of the README's config table; `problems` gets what is wrong with the table itself.
std::vector<ReadmeRow> readmeTable(const std::string& path, std::vector<std::string>& problems) {
  std::ifstream in(path);
  if (!in) {
    problems.push_back(path + ": cannot open");
    return {};
  }
  static const std::regex header(R"(^\|\s*key\s*\|\s*default\s*\|\s*range\s*\|\s*meaning\s*\|\s*$)",
                                 std::regex::icase);
  std::vector<ReadmeRow> rows;
  std::string line;
  int n = 0;
  bool in_table = false, found = false;
  while (std::getline(in, line)) {
    ++n;
    if (!in_table) {
      if (!found && std::regex_match(line, header)) in_table = found = true;
      continue;
    }
    if (line.rfind("|", 0) != 0) break;
    if (line.find("---") != std::string::npos &&
        line.find_first_not_of("|-: ") == std::string::npos)
      continue;  // the separator
    const auto cells = splitCells(line);
    if (cells.size() < 4) {
      problems.push_back(path + ":" + std::to_string(n) + ": a row of fewer than 4 cells");
      continue;
    }
    ReadmeRow row;
    row.line = n;
    static const std::regex code("`([^`]+)`");
    for (std::sregex_iterator it(cells[0].begin(), cells[0].end(), code), end; it != end; ++it)
      row.keys.push_back((*it)[1].str());
    if (row.keys.empty())
      problems.push_back(path + ":" + std::to_string(n) + ": no `key` in the first column");
    row.default_cell = cells[1];
    row.range_cell = cells[2];
    rows.push_back(row);
  }
  if (!found)
    problems.push_back(path + ": no table with the header | Key | Default | Range | Meaning |");
  return rows;
}

bool isGroup(const std::string& k) { return k.size() > 2 && k.compare(k.size() - 2, 2, ".*") == 0; }
bool inGroup(const std::string& key, const std::string& group) {
  const std::string prefix = group.substr(0, group.size() - 1);  // "a.*" -> "a."
  return key.rfind(prefix, 0) == 0;
}

/// The Default cell's part for the i-th of n keys of a row ("0.05, 2.0" for two keys).
std::string defaultFor(const ReadmeRow& row, std::size_t i) {
  if (row.keys.size() < 2) return row.default_cell;
  std::vector<std::string> parts;
  std::stringstream s(row.default_cell);
  for (std::string p; std::getline(s, p, ',');) parts.push_back(trim(p));
  return parts.size() == row.keys.size() ? parts[i] : row.default_cell;
}

std::string unquote(std::string s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '`' && s.back() == '`') s = s.substr(1, s.size() - 2);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

void checkReadmeRow(const std::string& where, const KeyInfo& k, const std::string& def,
                    const std::string& range_cell, std::vector<std::string>& problems) {
  auto bad = [&](const std::string& what) {
    problems.push_back(where + ": key '" + k.key + "': " + what);
  };
  switch (k.kind) {
    case KeyInfo::Kind::kNumber: {
      const auto d = leadingNumber(def);
      if (!d) {
        bad("Default '" + def + "' is not a number; the struct's default is " + fmt(k.number));
      } else if (!sameNumber(*d, k.number)) {
        bad("Default " + def + " differs from the struct's default " + fmt(k.number));
      }
      const auto r = intervalIn(range_cell);
      if (k.range && !r) {
        bad("Range '" + range_cell + "' gives no [min, max]; the struct's is " +
            rangeText(*k.range));
      } else if (!k.range && r) {
        bad("Range '" + range_cell + "' but the struct declares no Range for it");
      } else if (k.range && r &&
                 !(sameNumber(r->min, k.range->min) && sameNumber(r->max, k.range->max))) {
        bad("Range " + rangeText(*r) + " differs from the struct's " + rangeText(*k.range));
      }
      break;
    }
    case KeyInfo::Kind::kBool: {
      const std::string d = lower(unquote(def));
      if (d != (k.boolean ? "true" : "false"))
        bad("Default '" + def + "' differs from the struct's default " +
            (k.boolean ? "true" : "false"));
      break;
    }
    case KeyInfo::Kind::kString: {
      const std::string d = unquote(def);
      // "(required)" and the like: a key whose in-struct value is no default.
      if (!(d.size() > 1 && d.front() == '(') && d != k.text)
        bad("Default '" + def + "' differs from the struct's default \"" + k.text + "\"");
      if (k.one_of) {
        for (const auto& v : *k.one_of)
          if (range_cell.find(v) == std::string::npos)
            bad("Range '" + range_cell + "' does not list the allowed value '" + v + "'");
      }
      break;
    }
    case KeyInfo::Kind::kOther:
      break;
  }
}

// ---- YAML file

/// Dotted leaf keys of a YAML mapping (a mapping value is descended into; `{}` has no leaves).
void leaves(const YAML::Node& node, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& kv : node) {
    const std::string key = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      leaves(kv.second, key + ".", out);
    } else {
      out.push_back(key);
    }
  }
}

/// Per dotted key of a YAML file: the "(a..b)" ranges of the comment block above it (a key right
/// below another, with no comment of its own, shares that key's block).
std::map<std::string, std::vector<Range>> commentRanges(const std::string& path) {
  std::ifstream in(path);
  static const std::regex key_line(R"(^(\s*)([A-Za-z_][A-Za-z0-9_]*):(.*)$)");
  static const std::regex range(
      R"((-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?)\.\.(-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?))");
  std::map<std::string, std::vector<Range>> out;
  std::vector<std::pair<std::size_t, std::string>> stack;  // (indent, key)
  std::string block;               // comment text since the last key or blank line
  std::vector<Range> last_ranges;  // of the previous key line
  bool previous_was_key = false;
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (t.empty()) {
      block.clear();
      previous_was_key = false;
      continue;
    }
    if (t[0] == '#') {
      block += t + "\n";
      previous_was_key = false;
      continue;
    }
    std::smatch m;
    if (!std::regex_match(line, m, key_line)) {
      previous_was_key = false;
      continue;
    }
    const std::size_t indent = m[1].length();
    while (!stack.empty() && stack.back().first >= indent) stack.pop_back();
    std::string dotted;
    for (const auto& s : stack) dotted += s.second + ".";
    dotted += m[2].str();
    std::vector<Range> ranges;
    if (block.empty() && previous_was_key) {
      ranges = last_ranges;
    } else {
      for (std::sregex_iterator it(block.begin(), block.end(), range), end; it != end; ++it)
        ranges.push_back(Range{std::stod((*it)[1].str()), std::stod((*it)[2].str())});
    }
    out[dotted] = ranges;
    last_ranges = ranges;
    block.clear();
    previous_was_key = true;
    if (trim(m[3].str()).empty()) stack.emplace_back(indent, m[2].str());  // a mapping follows
  }
  return out;
}

// ---- the check of one daemon

/// Every mismatch of daemon's README table and YAML file (under `root`) with Config's keys.
template <class Config>
std::vector<std::string> problemsOf(const std::string& daemon, const std::string& root = kRoot) {
  const std::vector<KeyInfo> keys = keysOf<Config>();
  std::map<std::string, const KeyInfo*> by_key;
  for (const auto& k : keys) by_key[k.key] = &k;
  std::vector<std::string> problems;

  // README table
  const std::string readme = "daemons/" + daemon + "/README.md";
  const auto rows = readmeTable(root + "/" + readme, problems);
  std::map<std::string, int> listed;    // key -> rows listing it
  std::set<std::string> optional_keys;  // keys whose row says "optional"
  for (const auto& row : rows) {
    const std::string where = readme + ":" + std::to_string(row.line);
    const bool optional = lower(row.default_cell).find("optional") != std::string::npos;
    for (std::size_t i = 0; i < row.keys.size(); ++i) {
      const std::string& rk = row.keys[i];
      if (isGroup(rk)) {
        bool any = false;
        for (const auto& k : keys) {
          if (!inGroup(k.key, rk)) continue;
          any = true;
          ++listed[k.key];
          if (optional) optional_keys.insert(k.key);
        }
        if (!any) problems.push_back(where + ": row '" + rk + "' matches no key of the struct");
        continue;
      }
      const auto it = by_key.find(rk);
      if (it == by_key.end()) {
        problems.push_back(where + ": key '" + rk + "' is not a key of the struct");
        continue;
      }
      ++listed[rk];
      if (optional) optional_keys.insert(rk);
      checkReadmeRow(where, *it->second, defaultFor(row, i), row.range_cell, problems);
    }
  }
  for (const auto& k : keys) {
    const int n = listed.count(k.key) ? listed.at(k.key) : 0;
    if (n == 0) problems.push_back(readme + ": key '" + k.key + "' is missing from the table");
    if (n > 1)
      problems.push_back(readme + ": key '" + k.key + "' is listed " + std::to_string(n) +
                         " times");
  }

  // config/<daemon>.yaml
  const std::string yaml = "config/" + daemon + ".yaml";
  YAML::Node file;
  try {
    file = YAML::LoadFile(root + "/" + yaml);
  } catch (const YAML::Exception& e) {
    problems.push_back(yaml + ": " + e.what());
    return problems;
  }
  std::vector<std::string> in_file;
  if (file.IsMap()) leaves(file, "", in_file);
  const std::set<std::string> in_file_set(in_file.begin(), in_file.end());
  for (const auto& k : in_file)
    if (!by_key.count(k)) problems.push_back(yaml + ": key '" + k + "' is not a key of the struct");
  for (const auto& k : keys)
    if (!in_file_set.count(k.key) && !optional_keys.count(k.key))
      problems.push_back(yaml + ": key '" + k.key + "' is not set (and " + readme +
                         " does not say it is optional)");
  for (const auto& [key, ranges] : commentRanges(root + "/" + yaml)) {
    const auto it = by_key.find(key);
    if (it == by_key.end() || ranges.empty()) continue;
    const KeyInfo& k = *it->second;
    if (!k.range) continue;  // ranges checked elsewhere (e.g. BandPlannerConfig::validate())
    bool match = false;
    std::string given;
    for (const auto& r : ranges) {
      match = match || (sameNumber(r.min, k.range->min) && sameNumber(r.max, k.range->max));
      given += (given.empty() ? "" : ", ") + fmt(r.min) + ".." + fmt(r.max);
    }
    if (!match)
      problems.push_back(yaml + ": key '" + key + "': the comment gives (" + given +
                         "), the struct's Range is " + rangeText(*k.range));
  }
  try {
    loadConfig<Config>(root + "/" + yaml);
  } catch (const ConfigError& e) {
    problems.push_back(yaml + " does not load: " + e.what());
  }
  return problems;
}

std::string report(const std::string& daemon, const std::vector<std::string>& problems) {
  std::string s = daemon + ": " + std::to_string(problems.size()) + " mismatch(es)\n";
  for (const auto& p : problems) s += "  " + p + "\n";
  return s;
}

#define COOPNAV_CHECK_DAEMON(Node, name)            \
  TEST(ConfigKeysTest, name) {                      \
    const auto p = problemsOf<Node::Config>(#name); \
    EXPECT_TRUE(p.empty()) << report(#name, p);     \
  }

COOPNAV_CHECK_DAEMON(PathAssessorNode, path_assessor)
COOPNAV_CHECK_DAEMON(SituationAssessorNode, situation_assessor)
COOPNAV_CHECK_DAEMON(DialogueManagerNode, dialogue_manager)
COOPNAV_CHECK_DAEMON(ObstacleDistanceServerNode, obstacle_distance_server)
COOPNAV_CHECK_DAEMON(WorldSimNode, world_sim)
COOPNAV_CHECK_DAEMON(BandSourceNode, band_source)
COOPNAV_CHECK_DAEMON(ViewerNode, viewer)

// The check itself: a sample daemon whose README and YAML disagree with its struct in every way
// the check knows, and the same files put right.
struct SampleInner {
  int depth{3};
  std::string words{"hello"};
  template <class V>
  void visit(V& v) {
    v("depth", depth, Range{1, 10});
    v("words", words);
  }
};
struct SampleConfig {
  double rate_hz{0.1};
  double tolerance{1e-6};
  bool fast{true};
  std::string mode{"a"};
  SampleInner inner;
  template <class V>
  void visit(V& v) {
    v("rate_hz", rate_hz, Range{0.01, 100.0});
    v("tolerance", tolerance, Range{0.0, 1.0});
    v("fast", fast);
    v("mode", mode, OneOf{{"a", "b"}});
    v("inner", inner);
  }
};

std::string writeSample(const std::string& readme_rows, const std::string& yaml) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("coopnav_keys_" + std::to_string(::getpid()));
  fs::create_directories(root / "daemons" / "sample");
  fs::create_directories(root / "config");
  std::ofstream(root / "daemons" / "sample" / "README.md")
      << "# sample\n\n| Key | Default | Range | Meaning |\n|---|---|---|---|\n"
      << readme_rows << "\n## Next\n";
  std::ofstream(root / "config" / "sample.yaml") << yaml;
  return root.string();
}

bool mentions(const std::vector<std::string>& problems, const std::string& a,
              const std::string& b) {
  for (const auto& p : problems)
    if (p.find(a) != std::string::npos && p.find(b) != std::string::npos) return true;
  return false;
}

TEST(ConfigKeysTest, TheCheckFindsEveryKindOfMismatch) {
  const std::string good_rows =
      "| `rate_hz` | 0.10 | [0.01, 100] | x |\n"
      "| `tolerance` | 0.000001 | [0, 1] | x |\n"
      "| `fast` | true | bool | x |\n"
      "| `mode` | `a` | `a`, `b` | x |\n"
      "| `inner.depth`, `inner.words` | 3, hello | [1, 10] | x |\n";
  const std::string good_yaml =
      "# Rate [Hz] (0.01..100).\nrate_hz: 0.1\n# Tolerance (0..1).\ntolerance: 1e-6\nfast: "
      "true\nmode: a\n"
      "inner:\n  # Depth (1..10).\n  depth: 3\n  words: hello\n";
  {
    const auto p = problemsOf<SampleConfig>("sample", writeSample(good_rows, good_yaml));
    EXPECT_TRUE(p.empty()) << report("sample", p);
  }
  {
    const auto p = problemsOf<SampleConfig>(
        "sample", writeSample("| `rate_hz` | 0.2 | [0.01, 10] | x |\n"
                              "| `fast` | false | bool | x |\n"
                              "| `mode` | `a` | `a` only | x |\n"
                              "| `inner.*` | see file | | x |\n"
                              "| `gone` | 1 | [0, 1] | x |\n",
                              "# Rate (0..100).\nrate_hz: 0.1\nfast: true\nmode: a\nextra: 1\n"
                              "inner: {depth: 3}\n"));
    const std::string why = report("sample", p);
    EXPECT_TRUE(mentions(p, "'rate_hz'", "Default 0.2 differs")) << why;
    EXPECT_TRUE(mentions(p, "'rate_hz'", "Range [0.01, 10] differs")) << why;
    EXPECT_TRUE(mentions(p, "'fast'", "differs from the struct's default true")) << why;
    EXPECT_TRUE(mentions(p, "'mode'", "allowed value 'b'")) << why;
    EXPECT_TRUE(mentions(p, "README.md", "'tolerance' is missing from the table")) << why;
    EXPECT_TRUE(mentions(p, "README.md", "'gone' is not a key")) << why;
    EXPECT_TRUE(mentions(p, "sample.yaml", "'tolerance' is not set")) << why;
    EXPECT_TRUE(mentions(p, "sample.yaml", "'inner.words' is not set")) << why;
    EXPECT_TRUE(mentions(p, "sample.yaml", "'extra' is not a key")) << why;
    EXPECT_TRUE(mentions(p, "'rate_hz'", "the comment gives (0..100)")) << why;
    EXPECT_TRUE(mentions(p, "sample.yaml", "does not load")) << why;
  }
  {
    // A row whose Default says optional lets the YAML leave its keys out.
    const auto p = problemsOf<SampleConfig>(
        "sample", writeSample(good_rows + "", "rate_hz: 0.1\ntolerance: 0\nfast: true\nmode: a\n"));
    EXPECT_TRUE(mentions(p, "sample.yaml", "'inner.depth' is not set")) << report("sample", p);
    std::string rows = good_rows;
    rows.replace(rows.find("| 3, hello |"), 11, "| 3, hello (optional) |");
    const auto q = problemsOf<SampleConfig>(
        "sample", writeSample(rows, "rate_hz: 0.1\ntolerance: 0\nfast: true\nmode: a\n"));
    EXPECT_FALSE(mentions(q, "sample.yaml", "is not set")) << report("sample", q);
  }
  std::filesystem::remove_all(writeSample("", ""));
}

// The visitor sees every key, nested ones dotted, with its default and range.
TEST(ConfigKeysTest, TheVisitorListsNestedKeysWithDefaultsAndRanges) {
  const auto keys = keysOf<DialogueManagerNode::Config>();
  const KeyInfo* rate = nullptr;
  for (const auto& k : keys)
    if (k.key == "speech.rate_wpm") rate = &k;
  ASSERT_NE(rate, nullptr);
  EXPECT_EQ(rate->kind, KeyInfo::Kind::kNumber);
  EXPECT_EQ(rate->number, 175.0);
  ASSERT_TRUE(rate->range.has_value());
  EXPECT_EQ(rate->range->min, 80.0);
  EXPECT_EQ(rate->range->max, 450.0);
  EXPECT_EQ(*parseNumber("2^26"), 67108864.0);
  EXPECT_TRUE(sameNumber(*parseNumber("1e-6"), *parseNumber("0.000001")));
  EXPECT_TRUE(sameNumber(*leadingNumber("0.10"), 0.1));
}

}  // namespace
}  // namespace coopnav
