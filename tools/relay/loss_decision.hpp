#pragma once
// Which forwarded copies coopnav_lossy_relay drops. The decision is a function of the seed, the
// two endpoints, the message (channel + payload hash) and how many times that same message went
// from that endpoint to that one before, never of the order in which the processes' messages
// reached the relay: in lockstep every process publishes the same messages in every run, so the
// same seed drops the same copies however the scheduler interleaved them (with one random stream
// drawn in arrival order, it did not). A re-sent identical message counts as the next occurrence
// and is decided afresh, so a drop never repeats for ever.
#include <cstddef>
#include <cstdint>
#include <map>
#include <tuple>

namespace coopnav::relay {

/// SplitMix64's finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014): a well-mixed 64-bit value of its input.
inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// True: drop this copy. `loss` in [0, 1].
inline bool dropCopy(std::uint64_t seed, double loss, std::size_t from, std::size_t to,
                     std::uint64_t message_hash, std::uint64_t occurrence) {
  std::uint64_t h = mix64(seed);
  h = mix64(h ^ message_hash);
  h = mix64(h ^ (static_cast<std::uint64_t>(from) << 32 | static_cast<std::uint64_t>(to)));
  h = mix64(h ^ occurrence);
  // The top 53 bits as a uniform double in [0, 1).
  const double u = static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
  return u < loss;
}

/// Counts the occurrences of each (from, to, message) and decides each copy.
class LossDecider {
 public:
  LossDecider(std::uint64_t seed, double loss) : seed_(seed), loss_(loss) {}
  bool drop(std::size_t from, std::size_t to, std::uint64_t message_hash) {
    const std::uint64_t k = seen_[{from, to, message_hash}]++;
    return dropCopy(seed_, loss_, from, to, message_hash, k);
  }

 private:
  std::uint64_t seed_;
  double loss_;
  std::map<std::tuple<std::size_t, std::size_t, std::uint64_t>, std::uint64_t> seen_;
};

}  // namespace coopnav::relay
