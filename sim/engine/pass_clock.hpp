// Where a step's time goes: each thread's wall time per pass of
// kernels::advance, summed over the steps, when a caller asks for it
// (`dem2d bench --passes`). Off (the default), a pass's end is one test of a
// null pointer the thread holds: ~10 a step, against ~4e4 cycles of a
// 1600-grain step on one thread.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <vector>

#include "core/aligned_vector.hpp"

namespace dem2d {

// The passes of a step, in the order they run (kernels.hpp).
enum class Pass : std::size_t {
  wait_drift,   // the barrier after the drift, and the rebuild test
  rebuild,      // a rebuild (serial) with its two barriers
  pairs,        // grain-grain forces (own rows)
  walls,        // grain-body forces (own rows)
  wait_forces,  // the barrier after the force loops
  ledger,       // the energy ledger's close_step and its barrier
  gather,       // per-grain sums (with the claim of shared lines)
  integrate,    // close this step, open the next (kick, drift)
  bodies,       // thread 0: body force sums, the next step's body positions
  count
};
inline constexpr std::size_t kPasses = static_cast<std::size_t>(Pass::count);
inline constexpr std::array<const char*, kPasses> kPassNames{
    "wait (drift, rebuild test)", "rebuild", "pair forces", "wall forces", "wait (forces)",
    "energy ledger", "gather", "integrate", "bodies (thread 0)"};

// One thread's totals (ns), on its own cache line.
struct alignas(kCacheLine) PassTotals {
  std::array<double, kPasses> ns{};
};

// The clock of one thread inside advance: end(p) adds the time since the
// last end to pass p.
class PassClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit PassClock(PassTotals* totals) : totals_(totals) {
    if (totals_) last_ = Clock::now();
  }
  void end(Pass p) {
    if (!totals_) return;
    const Clock::time_point now = Clock::now();
    totals_->ns[static_cast<std::size_t>(p)] += std::chrono::duration<double, std::nano>(now - last_).count();
    last_ = now;
  }

 private:
  PassTotals* totals_;
  Clock::time_point last_{};
};

}  // namespace dem2d
