// The config loader: defaults only in the struct, errors that name key, value and range.
#include "config/config.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_util.hpp"

namespace coopnav {
namespace {

struct Inner {
  double gain{2.0};
  template <class V>
  void visit(V& v) {
    v("gain", gain, Range{0.0, 10.0});
  }
};

struct SampleConfig {
  double speed_m_s{0.7};
  int rate_hz{10};
  std::string mode{"lockstep"};
  bool speak{false};
  std::vector<std::string> participants{"a", "b"};
  Inner inner;
  template <class V>
  void visit(V& v) {
    v("speed_m_s", speed_m_s, Range{0.0, 2.0});
    v("rate_hz", rate_hz, Range{1, 100});
    v("mode", mode, OneOf{{"lockstep", "realtime"}});
    v("speak", speak);
    v("participants", participants);
    v("inner", inner);
  }
};

std::string writeTemp(const std::string& text) {
  static int n = 0;
  const auto p = test::scratchDir() / ("cfg_" + std::to_string(n++) + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}

TEST(ConfigTest, EmptyPathGivesTheStructDefaults) {
  const auto c = loadConfig<SampleConfig>("");
  EXPECT_EQ(c.speed_m_s, 0.7);
  EXPECT_EQ(c.rate_hz, 10);
  EXPECT_EQ(c.participants.size(), 2u);
}

TEST(ConfigTest, FileOverridesOnlyWhatItNames) {
  const auto c = loadConfig<SampleConfig>(
      writeTemp("speed_m_s: 1.1\ninner: {gain: 3}\nparticipants: [x]\nmode: realtime\n"));
  EXPECT_EQ(c.speed_m_s, 1.1);
  EXPECT_EQ(c.rate_hz, 10);
  EXPECT_EQ(c.inner.gain, 3.0);
  EXPECT_EQ(c.mode, "realtime");
  ASSERT_EQ(c.participants.size(), 1u);
}

TEST(ConfigTest, ErrorsNameTheKeyTheValueAndTheRange) {
  const auto path =
      writeTemp("speed_m_s: 5\nrate_hz: abc\nmode: fast\nbogus: 1\ninner: {gain: -1}\n");
  try {
    loadConfig<SampleConfig>(path);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos);
    EXPECT_NE(msg.find("'speed_m_s' = 5 is outside the allowed range [0, 2]"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("'rate_hz' = 'abc' has the wrong type"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'mode' = 'fast' is not one of {lockstep, realtime}"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("'bogus' is not a known key"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'inner.gain' = -1"), std::string::npos) << msg;
  }
}

TEST(ConfigTest, MissingFileAndSyntaxErrorsAreClear) {
  EXPECT_THROW(loadConfig<SampleConfig>("/nonexistent/x.yaml"), ConfigError);
  try {
    loadConfig<SampleConfig>(writeTemp("speed_m_s: [1,\n"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("syntax error at line"), std::string::npos);
  }
}

// Found by fuzz_config: a non-scalar key made rejectUnknownKeys throw YAML::TypedBadConversion,
// which no daemon catches (abort instead of exit 2).
TEST(ConfigTest, KeysThatAreNotNamesAreConfigErrors) {
  for (const char* text : {"[a, b]: 1\n", "? {x: 1}\n: 2\n", "inner: {[g]: 1}\n"}) {
    try {
      loadConfig<SampleConfig>(writeTemp(text));
      FAIL() << "expected ConfigError for " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("has a key that is not a name (line "),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(ConfigTest, NonFiniteNumbersAreRejected) {
  EXPECT_THROW(loadConfig<SampleConfig>(writeTemp("speed_m_s: .nan\n")), ConfigError);
}

TEST(ConfigTest, PrintedConfigLoadsBackToTheSameValues) {
  SampleConfig c;
  c.speed_m_s = 1.25;
  c.inner.gain = 4.0;
  const auto back = loadConfig<SampleConfig>(writeTemp(configToYaml(c)));
  EXPECT_EQ(back.speed_m_s, 1.25);
  EXPECT_EQ(back.inner.gain, 4.0);
}

struct TextConfig {
  std::string words{"left"};
  template <class V>
  void visit(V& v) {
    v("words", words);
  }
};

TEST(ConfigTest, TextThatWouldNotPrintBackIsRejectedNamingTheKey) {
  // Found by fuzz_config: a dialogue template ending in "\r" printed as it was, and "\r\n" then
  // read back as one line break, so --print-config loaded to a different config.
  const std::vector<std::string> bad = {
      "\"I will pass\r\"",  // carriage return
      "\"tab\there\"",      // any C0 control
      "\"a\\x85b\"",        // C1 NEL, a line break to YAML 1.1
      "\"a\\u2028b\"",      // line separator
  };
  for (const auto& v : bad) {
    try {
      loadConfig<TextConfig>(writeTemp("words: " + v + "\n"));
      ADD_FAILURE() << "accepted " << v;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("key 'words'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("control character"), std::string::npos) << e.what();
    }
  }
  EXPECT_NE(notConfigText(std::string("r\x9c\x98ht")), "");  // not UTF-8
  EXPECT_NE(notConfigText(std::string("\xC0\xAF")), "");     // overlong
  EXPECT_NE(notConfigText(std::string("\xE2\x82")), "");     // truncated
  EXPECT_EQ(notConfigText("Je passe à votre gauche, 右"), "");
  // Printable text, with YAML's special characters, prints and loads back as it was.
  SampleConfig c;
  c.participants = {"a: b", "#x", " lead", "trail ", "\"q\"", "à gauche"};
  EXPECT_EQ(loadConfig<SampleConfig>(writeTemp(configToYaml(c))).participants, c.participants);
}

}  // namespace
}  // namespace coopnav
