#pragma once
/// @file Two lanes of work run side by side: the calling thread and one worker. SparseLm splits
/// its residual blocks into two lanes whose writes never meet (sparse_lm.hpp), so that a cycle's
/// evaluations take two cores where the robot has them, with the same result to the last bit
/// as one thread: what each lane computes and the order of every sum are fixed by the problem,
/// never by which thread ran a lane or when.
///
/// The caller never waits for a worker that has not started: after its own lane it claims the
/// other one unless the worker already has, so a busy machine (or a worker that is asleep) only
/// costs the parallelism, not a stall. While a solve is under way (between awake() and rest())
/// the worker polls for the next lane instead of sleeping, because waking a sleeping thread
/// takes tens of microseconds and a solve hands out ~100 lanes of ~20-100 µs each.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <type_traits>

namespace coopnav {

class TwoLanes {
 public:
  TwoLanes();
  /// Stops and joins the worker.
  ~TwoLanes();
  TwoLanes(const TwoLanes&) = delete;
  TwoLanes& operator=(const TwoLanes&) = delete;

  /// Runs f(0) and f(1), f(1) on the worker when it takes it first, and returns when both are
  /// done. f must not throw (a lane that threw on the worker would end the program) and must
  /// not call run() again.
  template <typename F>
  void run(F&& f) {
    using Fn = std::remove_reference_t<F>;
    runErased(&f, [](void* p, int lane) { (*static_cast<Fn*>(p))(lane); });
  }

  /// The worker polls for lanes until rest() (call before a burst of run()s).
  void awake();
  /// The worker may sleep until the next awake() or run().
  void rest();

  /// Lanes the worker has run since construction (tests: whether it took part).
  std::uint64_t workerLanes() const { return worker_lanes_.load(std::memory_order_relaxed); }

 private:
  using Call = void (*)(void*, int);
  void runErased(void* fn, Call call);
  void workerLoop();

  // The published lane: generation << 1 | taken. The worker and the caller race to set `taken`
  // on the current generation; whoever wins runs lane 1.
  std::atomic<std::uint64_t> state_{0};
  std::atomic<std::uint64_t> done_{0};  ///< generation of the last lane 1 the worker finished
  void* fn_{nullptr};
  Call call_{nullptr};
  std::atomic<bool> polling_{false};
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> worker_lanes_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread worker_;
};

}  // namespace coopnav
