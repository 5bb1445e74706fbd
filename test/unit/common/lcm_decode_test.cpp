// The subscriptions' decoding (decodeOrReject, runtime.hpp) against malformed string lengths.
// Found by the fuzzers (test/fuzz): LCM 1.3.1's generated decoder computed `len - 1` for a string
// of length INT_MIN, which overflowed and made the decoder copy ~2 GB from the datagram (SIGSEGV in
// every daemon). lcmtypes/lcm_gen_fix_string_decode.cmake makes it fail the decode instead.
#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <vector>

#include "coopnav/distance_request_t.hpp"
#include "coopnav/robot_action_t.hpp"
#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

template <class Msg>
std::vector<std::uint8_t> encoded(const Msg& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

void putInt32Be(std::vector<std::uint8_t>& buf, std::size_t at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int k = 0; k < 4; ++k) buf[at + k] = static_cast<std::uint8_t>(u >> (24 - 8 * k));
}

// Byte offset of robot_action_t.reason's length: fingerprint 8, utime 8, step 8, action 1,
// human_id 4.
constexpr std::size_t kReasonLengthAt = 8 + 8 + 8 + 1 + 4;

TEST(LcmDecodeTest, StringLengthsBelowOneAreRejectedNotCrashing) {
  robot_action_t m{};
  m.action = robot_action_t::ACTION_DOCK;
  m.reason = "dock";
  const std::vector<std::uint8_t> good = encoded(m);
  robot_action_t out;
  ASSERT_NO_THROW(decodeOrReject(good.data(), good.size(), out));
  EXPECT_EQ(out.reason, "dock");

  for (const std::int32_t len : {INT_MIN, INT_MIN + 1, -1, 0}) {
    std::vector<std::uint8_t> bad = good;
    putInt32Be(bad, kReasonLengthAt, len);
    robot_action_t msg;
    EXPECT_THROW(decodeOrReject(bad.data(), bad.size(), msg), RejectedMessage) << "length " << len;
  }
}

TEST(LcmDecodeTest, StringLengthPastTheEndIsRejected) {
  robot_action_t m{};
  m.reason = "dock";
  std::vector<std::uint8_t> bad = encoded(m);
  putInt32Be(bad, kReasonLengthAt, INT_MAX);
  robot_action_t msg;
  EXPECT_THROW(decodeOrReject(bad.data(), bad.size(), msg), RejectedMessage);
}

TEST(LcmDecodeTest, ReplyChannelOfADistanceRequestIsGuardedToo) {
  distance_request_t m{};
  m.reply_channel = "COOPNAV_DIST_REP_x";
  m.num_queries = 0;
  std::vector<std::uint8_t> bad = encoded(m);
  putInt32Be(bad, 8 + 8 + 8, INT_MIN);  // after fingerprint, utime, request_id
  distance_request_t msg;
  EXPECT_THROW(decodeOrReject(bad.data(), bad.size(), msg), RejectedMessage);
}

}  // namespace
}  // namespace coopnav
