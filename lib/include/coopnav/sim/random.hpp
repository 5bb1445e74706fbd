#pragma once
/// @file The simulator's one source of randomness: a seeded xoshiro256** generator with its own
/// uniform and normal draws. std::mt19937 is portable but std::normal_distribution is not (its
/// algorithm is implementation-defined), so the draws are written here to make runs bit-identical
/// across standard libraries and machines.

#include <cstdint>

namespace coopnav::sim {

/// splitmix64 step (Steele, Lea, Flood 2014): expands one 64-bit seed into well-mixed words.
/// Also used to derive independent per-agent streams from (scenario seed, agent id).
std::uint64_t splitmix64(std::uint64_t& state);

/// xoshiro256** (Blackman & Vigna 2018) seeded through splitmix64. Deterministic for a seed.
class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0);

  /// A generator for an independent stream, e.g. one per human: derived from (seed, stream id).
  static Rng forStream(std::uint64_t seed, std::uint64_t stream_id);

  /// Next raw 64-bit word.
  std::uint64_t next();
  /// Uniform in [0, 1) with 53 random bits.
  double uniform01();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi);
  /// Normal draw (Marsaglia polar method, only +, *, /, log and sqrt, which IEEE 754 rounds
  /// correctly for sqrt; log is glibc's correctly rounded one on the supported platforms).
  double normal(double mean, double stddev);

 private:
  std::uint64_t s_[4];
  bool has_spare_{false};
  double spare_{0.0};
};

}  // namespace coopnav::sim
