// The daemons' loop sleeps in poll() until its next timer is due: the timeout must round up, or
// the last fraction of a millisecond before every timer is spent polling with timeout 0 (a loop
// that spun ~1 ms in every 5-10 ms timer period, and all the time with a 1 ms timer).
#include <gtest/gtest.h>

#include <chrono>

#include "runtime/runtime.hpp"

namespace coopnav {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

TEST(RuntimePollTimeout, AFractionOfAMillisecondWaitsAWholeOne) {
  EXPECT_EQ(Runtime::pollTimeoutMs(microseconds(1)), 1);
  EXPECT_EQ(Runtime::pollTimeoutMs(microseconds(400)), 1);
  EXPECT_EQ(Runtime::pollTimeoutMs(microseconds(999)), 1);
  EXPECT_EQ(Runtime::pollTimeoutMs(microseconds(5200)), 6);
}

TEST(RuntimePollTimeout, WholeMillisecondsAreKept) {
  EXPECT_EQ(Runtime::pollTimeoutMs(milliseconds(5)), 5);
  EXPECT_EQ(Runtime::pollTimeoutMs(milliseconds(50)), 50);
}

TEST(RuntimePollTimeout, DueOrOverdueDoesNotWait) {
  EXPECT_EQ(Runtime::pollTimeoutMs(microseconds(0)), 0);
  EXPECT_EQ(Runtime::pollTimeoutMs(milliseconds(-3)), 0);
}

TEST(RuntimePollTimeout, AtMostOneSecond) {
  EXPECT_EQ(Runtime::pollTimeoutMs(std::chrono::seconds(10)), 1000);
}

}  // namespace
}  // namespace coopnav
