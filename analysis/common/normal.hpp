// The standard normal distribution's upper quantile, for the detectors'
// significance thresholds.
#pragma once

#include <cmath>

namespace dem2d::analysis {

// z with P(Z > z) = p for a standard normal Z (bisection on erfc; p in (0, 1)).
inline double normal_upper_quantile(double p) {
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace dem2d::analysis
