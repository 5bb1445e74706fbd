#include "loss_decision.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace coopnav::relay {
namespace {

using Copy = std::tuple<std::size_t, std::size_t, std::uint64_t>;

/// Decisions of one run in which the copies arrive in the given order, listed in a fixed order.
std::vector<bool> decisions(std::vector<Copy> arrival, std::uint64_t seed, double loss) {
  LossDecider d(seed, loss);
  std::vector<std::pair<Copy, bool>> out;
  for (const auto& c : arrival)
    out.push_back({c, d.drop(std::get<0>(c), std::get<1>(c), std::get<2>(c))});
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<bool> r;
  for (const auto& [c, drop] : out) r.push_back(drop);
  return r;
}

std::vector<Copy> someCopies() {
  std::vector<Copy> c;
  for (std::uint64_t m = 0; m < 400; ++m) {
    for (std::size_t from = 0; from < 3; ++from) c.push_back({from, (from + 1) % 3, m * 7919});
  }
  c.push_back({0, 1, 0});  // the same message again: decided afresh
  return c;
}

TEST(LossDecisionTest, TheSameSeedDropsTheSameCopiesWhateverTheirArrivalOrder) {
  // Given the copies of one run, arriving in two orders that keep each endpoint pair's own order
  // (as the relay sees them: one process's messages in its publishing order, interleaved
  // differently with the others').
  const std::vector<Copy> a = someCopies();
  std::vector<Copy> b = a;
  std::stable_sort(b.begin(), b.end(),
                   [](const Copy& x, const Copy& y) { return std::get<0>(x) > std::get<0>(y); });
  ASSERT_NE(a, b);
  // Then the same copies are dropped; another seed drops others.
  EXPECT_EQ(decisions(a, 42, 0.1), decisions(b, 42, 0.1));
  EXPECT_NE(decisions(a, 42, 0.1), decisions(a, 43, 0.1));
}

TEST(LossDecisionTest, DropsTheGivenFractionAndARepeatIsDecidedAfresh) {
  std::size_t dropped = 0;
  const std::size_t n = 200000;
  for (std::uint64_t m = 0; m < n; ++m) dropped += dropCopy(7, 0.1, 0, 1, m, 0) ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(dropped) / n, 0.1, 0.005);
  EXPECT_FALSE(dropCopy(7, 0.0, 0, 1, 123, 0));
  EXPECT_TRUE(dropCopy(7, 1.0, 0, 1, 123, 0));
  // A message dropped once is not dropped for ever: its later occurrences are other draws.
  LossDecider d(7, 0.5);
  int kept = 0;
  for (int k = 0; k < 64; ++k) kept += d.drop(0, 1, 99) ? 0 : 1;
  EXPECT_GT(kept, 10);
  EXPECT_LT(kept, 54);
}

}  // namespace
}  // namespace coopnav::relay
