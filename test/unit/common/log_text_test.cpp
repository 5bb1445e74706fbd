// What a log line may hold of text from a message (daemons/common/runtime/log.hpp): escaped,
// capped, and rate-limited per pattern.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "runtime/log.hpp"

namespace coopnav {
namespace {

TEST(LogTextTest, ControlCharactersAndAnsiEscapesAreWrittenAsHex) {
  EXPECT_EQ(escapeLogText("plain text", 100), "plain text");
  EXPECT_EQ(escapeLogText("a\nb\r\x1b[31mc", 100), "a\\x0Ab\\x0D\\x1B[31mc");
  EXPECT_EQ(escapeLogText(std::string("nul\0x", 5), 100), "nul\\x00x");
  EXPECT_EQ(escapeLogText("del\x7f", 100), "del\\x7F");
  EXPECT_EQ(escapeLogText("a\nb", 100, true), "a\nb");  // the project's own multi-line text
}

TEST(LogTextTest, Utf8StaysAndWhatIsNotUtf8OrAC1ControlIsEscaped) {
  EXPECT_EQ(escapeLogText("d\xc3\xa9j\xc3\xa0 \xe2\x86\x92 \xf0\x9f\x98\x80", 100),
            "d\xc3\xa9j\xc3\xa0 \xe2\x86\x92 \xf0\x9f\x98\x80");
  EXPECT_EQ(escapeLogText("\xc2\x9b"
                          "31m",
                          100),
            "\\xC2\\x9B31m");                               // U+009B: CSI on some terminals
  EXPECT_EQ(escapeLogText("\xff\xc3", 100), "\\xFF\\xC3");  // not UTF-8, cut-off sequence
  EXPECT_EQ(escapeLogText("\xed\xa0\x80", 100), "\\xED\\xA0\\x80");  // a surrogate
  EXPECT_EQ(escapeLogText("\xe0\x80\xaf", 100), "\\xE0\\x80\\xAF");  // overlong
}

TEST(LogTextTest, LongTextIsCutAtACharacterBoundaryWithAMark) {
  const std::string long_text(60000, 'x');
  const std::string cut = escapeLogText(long_text, 1024);
  EXPECT_EQ(cut.size(), 1024u + 3u);
  EXPECT_EQ(cut.substr(cut.size() - 3), "...");
  // Never in the middle of an escape or a UTF-8 sequence.
  EXPECT_EQ(escapeLogText("ab\n", 4), "ab...");
  EXPECT_EQ(escapeLogText("a\xc3\xa9", 2), "a...");
}

/// Runs `body` with stderr going to a file and returns what was written.
template <class Body>
std::string captureStderr(Body body) {
  char path[] = "/tmp/coopnav_log_test_XXXXXX";
  const int fd = ::mkstemp(path);
  const int saved = ::dup(STDERR_FILENO);
  ::dup2(fd, STDERR_FILENO);
  body();
  log().flush();
  ::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ::close(fd);
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  ::unlink(path);
  return ss.str();
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST(LogTextTest, ALineRepeatedFasterThanTheRateIsSuppressedAndCounted) {
  setLogCaps(1024, 20);
  const std::string out = captureStderr([] {
    flushLogSuppressions();  // a fresh second
    for (int i = 0; i < 3000; ++i) log().warn("rejected message {} on X: bad", i);
    log().warn("another line");
    flushLogSuppressions();
  });
  EXPECT_EQ(count(out, "rejected message"), 20 + 1) << out.substr(0, 2000);  // + the summary
  EXPECT_EQ(count(out, "suppressed 2980 lines"), 1) << out.substr(0, 4000);
  EXPECT_EQ(count(out, "another line"), 1);
}

TEST(LogTextTest, AForgedLineInAMessageStaysOnItsOwnLine) {
  setLogCaps(1024, 20);
  const std::string out = captureStderr([] {
    log().warn("reason: {}", "ok\n[0000-00-00 00:00:00.000] [coopnav:1] [critical] forged\x1b[2J");
  });
  EXPECT_EQ(count(out, "\n"), 1) << out;
  EXPECT_EQ(out.find('\x1b'), std::string::npos) << out;
  EXPECT_NE(out.find("\\x0A[0000"), std::string::npos) << out;
}

}  // namespace
}  // namespace coopnav
