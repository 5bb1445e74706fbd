#include "coopnav/band/two_lanes.hpp"

namespace coopnav {
namespace {

/// One step of a busy wait: the CPU's spin hint, and now and then the rest of the time slice, so
/// that a poller on a loaded machine lets the thread it waits for run.
void spinPause(unsigned* spins) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
  if ((++*spins & 255u) == 0) std::this_thread::yield();
}

}  // namespace

TwoLanes::TwoLanes() : worker_([this] { workerLoop(); }) {}

TwoLanes::~TwoLanes() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_one();
  worker_.join();
}

void TwoLanes::awake() {
  if (polling_.exchange(true)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  wake_.notify_one();
}

void TwoLanes::rest() { polling_.store(false); }

void TwoLanes::runErased(void* fn, Call call) {
  fn_ = fn;
  call_ = call;
  const std::uint64_t generation = (state_.load(std::memory_order_relaxed) >> 1) + 1;
  state_.store(generation << 1, std::memory_order_release);
  if (!polling_.load(std::memory_order_relaxed)) {
    std::lock_guard<std::mutex> lock(mutex_);
    wake_.notify_one();
  }
  call(fn, 0);
  std::uint64_t untaken = generation << 1;
  if (state_.compare_exchange_strong(untaken, untaken | 1u, std::memory_order_acq_rel)) {
    call(fn, 1);
    return;
  }
  unsigned spins = 0;
  while (done_.load(std::memory_order_acquire) != generation) spinPause(&spins);
}

void TwoLanes::workerLoop() {
  std::uint64_t seen = 0;  // the last generation looked at
  unsigned spins = 0;
  for (;;) {
    std::uint64_t s = state_.load(std::memory_order_acquire);
    if ((s >> 1) != seen && (s & 1u) == 0) {
      seen = s >> 1;
      // fn_ and call_ were written before the release that published this generation, and the
      // caller rewrites them only after this lane is done (or taken by itself).
      if (state_.compare_exchange_strong(s, s | 1u, std::memory_order_acq_rel)) {
        call_(fn_, 1);
        worker_lanes_.fetch_add(1, std::memory_order_relaxed);
        done_.store(seen, std::memory_order_release);
      }
      continue;
    }
    if (stop_.load()) return;
    if (polling_.load(std::memory_order_relaxed)) {
      spinPause(&spins);
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [&] {
      const std::uint64_t now = state_.load(std::memory_order_acquire);
      return stop_.load() || polling_.load() || ((now >> 1) != seen && (now & 1u) == 0);
    });
  }
}

}  // namespace coopnav
