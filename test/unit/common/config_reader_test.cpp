// ConfigReader as the scenario files use it (world_sim's scenario loader reads through
// it too): required keys, keys given no value, lists of mappings, values that are reported and
// not stored, keys read by nobody on purpose, and where each message points.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "config/config.hpp"

namespace coopnav {
namespace {

struct Item {
  double x_m{0.0};
  double weight{1.0};
  template <class V>
  void visit(V& v) {
    v("x_m", x_m, Range{-10.0, 10.0}, Required{});
    v("weight", weight, Range{0.0, 5.0});
  }
};

struct Sample {
  std::string name;
  double low{1.0};
  double high{2.0};
  std::string kind{"a"};
  std::vector<Item> items;
  std::vector<std::string> tags;
  Item inner;
  template <class V>
  void visit(V& v) {
    v("name", name, Required{});
    v("low", low, Range{0.0, 10.0});
    v("high", high, Range{0.0, 10.0});
    v.require(high > low, "high", "must be greater than low");
    v("kind", kind, OneOf{{"a", "b"}}, Required{});
    v("items", items);
    v("tags", tags);
    v("inner", inner);
    v.skip("notes");
  }
};

/// Reads `text` into `out`; the errors, joined by newlines.
std::string read(const std::string& text, Sample& out) {
  ConfigReader r(YAML::Load(text), "f.yaml");
  out.visit(r);
  r.rejectUnknownKeys();
  std::string all;
  for (const auto& e : r.errors()) all += e + "\n";
  return all;
}

bool has(const std::string& all, const std::string& s) { return all.find(s) != std::string::npos; }

TEST(ConfigReaderTest, RequiredKeysMustBeGivenAValue) {
  Sample s;
  const std::string e = read("name:\nlow: 1.5\n", s);
  EXPECT_TRUE(has(e, "f.yaml: key 'name' is missing (required)")) << e;
  EXPECT_TRUE(has(e, "f.yaml: key 'kind' is missing (required)")) << e;
  Sample t;
  EXPECT_EQ(read("name: n\nkind: b\n", t), "");
  EXPECT_EQ(t.name, "n");
  EXPECT_EQ(t.kind, "b");
}

TEST(ConfigReaderTest, AKeyGivenNoValueKeepsTheStructsValue) {
  Sample s;
  EXPECT_EQ(read("name: n\nkind: a\nlow: ~\nhigh:\ninner:\nitems:\n", s), "");
  EXPECT_EQ(s.low, 1.0);
  EXPECT_EQ(s.high, 2.0);
}

TEST(ConfigReaderTest, ListsOfMappingsReadEachItemWithItsOwnKeyPath) {
  Sample s;
  EXPECT_EQ(read("name: n\nkind: a\nitems: [{x_m: 1}, {x_m: -2, weight: 3}]\ntags: [p, q]\n", s),
            "");
  ASSERT_EQ(s.items.size(), 2u);
  EXPECT_EQ(s.items[0].weight, 1.0);
  EXPECT_EQ(s.items[1].x_m, -2.0);
  EXPECT_EQ(s.tags, (std::vector<std::string>{"p", "q"}));

  const std::string e = read(
      "name: n\nkind: a\nitems:\n  - {weight: 9, y: 1}\n  - 3\n  -\n  - {x_m: 0}\ntags: p\n", s);
  EXPECT_TRUE(has(e, "key 'items[0].x_m' is missing (required)")) << e;
  EXPECT_TRUE(has(e, "key 'items[0].weight' = 9 is outside the allowed range [0, 5]")) << e;
  EXPECT_TRUE(has(e, "key 'items[0].y' is not a known key")) << e;
  EXPECT_TRUE(has(e, "key 'items[1].' must be a mapping")) << e;
  EXPECT_TRUE(has(e, "key 'items[2].' must be a mapping")) << e;  // "- " with no value
  EXPECT_FALSE(has(e, "items[3]")) << e;
  EXPECT_TRUE(has(e, "key 'tags' must be a list")) << e;
}

TEST(ConfigReaderTest, AValueOutOfItsRangeIsReportedAsWrittenAndNotStored) {
  Sample s;
  // high = -1.0 is not stored: the cross-field check sees high = 2 > low = 1.5 and stays quiet.
  const std::string e = read("name: n\nkind: c\nlow: 1.5\nhigh: -1.0\n", s);
  EXPECT_TRUE(has(e, "key 'high' = -1.0 is outside the allowed range [0, 10]")) << e;
  EXPECT_FALSE(has(e, "greater than low")) << e;
  EXPECT_EQ(s.high, 2.0);
  EXPECT_TRUE(has(e, "key 'kind' = 'c' is not one of {a, b}")) << e;
  EXPECT_EQ(s.kind, "a");
}

TEST(ConfigReaderTest, MessagesNameTheTypeTheLineAndTheNestedKey) {
  Sample s;
  const std::string e =
      read("name: n\nkind: a\nlow: seven\nhigh: [1]\ninner: 5\nnotes: {x: 1}\n", s);
  EXPECT_TRUE(has(e, "key 'low' = 'seven' has the wrong type: expected a number (line 3)")) << e;
  EXPECT_TRUE(has(e, "key 'high' must be a number")) << e;
  // Nothing of a nested key that is no mapping is read, so nothing more is said of it.
  EXPECT_TRUE(has(e, "key 'inner.' must be a mapping")) << e;
  EXPECT_FALSE(has(e, "inner.x_m")) << e;
  EXPECT_FALSE(has(e, "notes")) << e;  // skip(): known, not read
}

TEST(ConfigReaderTest, ValidateConfigChecksTheStructsOwnValues) {
  Sample s;
  s.low = 20.0;
  const auto errors = validateConfig(s, "built");
  ASSERT_FALSE(errors.empty());
  EXPECT_TRUE(has(errors[0], "built: key 'low' = 20 is outside the allowed range [0, 10]"))
      << errors[0];
  for (const auto& e : errors) EXPECT_FALSE(has(e, "missing")) << e;  // no file: nothing missing
}

}  // namespace
}  // namespace coopnav
