// Times in seconds become step counts here, and only here. A count is at
// most kMaxSteps = 2^53 (9.0e15 steps: every step then still has its own
// double-precision time; 285 years of simulated time at dt = 1 us); the scene
// reader refuses a time that would need more (scene/scene_toml.cpp), so the
// clamp below never changes a valid scene's counts. Sums of a few such counts
// (next check = this one + an interval) stay far inside int64.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace dem2d {

inline constexpr std::int64_t kMaxSteps = std::int64_t{1} << 53;

// round(seconds / dt), within [0, kMaxSteps] (NaN: kMaxSteps).
inline std::int64_t steps_in(double seconds, double dt) {
  const double n = seconds / dt;
  if (!(n < static_cast<double>(kMaxSteps))) return kMaxSteps;
  return n > 0.0 ? std::llround(n) : 0;
}
// ceil(seconds / dt), within [0, kMaxSteps].
inline std::int64_t steps_up(double seconds, double dt) {
  const double n = std::ceil(seconds / dt);
  if (!(n < static_cast<double>(kMaxSteps))) return kMaxSteps;
  return n > 0.0 ? static_cast<std::int64_t>(n) : 0;
}
// An interval of at least one step.
inline std::int64_t steps_every(double seconds, double dt) { return std::max<std::int64_t>(1, steps_in(seconds, dt)); }

}  // namespace dem2d
