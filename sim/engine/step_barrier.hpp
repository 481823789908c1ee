// The barrier between the phases of a step (kernels.hpp: advance). A thread
// that arrives first spins (as long as recent waits needed, within bounds),
// which is all a wait takes when every thread has a core, and then sleeps until the last one arrives
// (std::atomic::wait, a futex on Linux), giving its core away: when the
// machine has fewer free cores than the run's threads (two runs side by
// side), a spinning waiter held the very core its late partner was queued
// for, and every step cost a scheduler time slice. (Yielding the core with
// sched_yield instead was not enough: 3 threads on 2 cores ran 8x slower.)
// Memory: everything a thread wrote before wait() is seen by every thread
// after it (release on arrival, acquire on leaving), as with omp barrier.
#pragma once

#include <atomic>

namespace dem2d {

class StepBarrier {
 public:
  // n: the threads that call wait() (all of the parallel region's)
  void reset(int n) {
    n_ = n;
    arrived_.store(0, std::memory_order_relaxed);
  }

  void wait() {
    const unsigned gen = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == n_) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_acq_rel);  // releases the others
      generation_.notify_all();
      return;
    }
    // the spin adapts: longer while waits end in it (every thread has a core), shorter while they do
    // not (a late thread is waiting for a core: spinning would keep it waiting)
    const int budget = spin_budget_.load(std::memory_order_relaxed);
    for (int spin = 0; spin < budget; ++spin) {
      if (generation_.load(std::memory_order_acquire) != gen) {
        if (budget < kMaxSpins) spin_budget_.store(2 * budget, std::memory_order_relaxed);
        return;
      }
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
    if (budget > kMinSpins) spin_budget_.store(budget / 2, std::memory_order_relaxed);
    while (generation_.load(std::memory_order_acquire) == gen)
      generation_.wait(gen, std::memory_order_acquire);  // (a futex: the core goes to whoever is late)
  }

 private:
  // pause instructions before sleeping: a pause takes ~10 ns (older cores) to ~40 ns (Skylake and later)
  static constexpr int kMinSpins = 64, kMaxSpins = 16384;
  int n_ = 1;
  std::atomic<int> spin_budget_{1024};
  std::atomic<int> arrived_{0};
  std::atomic<unsigned> generation_{0};
};

}  // namespace dem2d
