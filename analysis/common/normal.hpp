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

// Student's t quantile of probability 0.975 with `dof` >= 1 degrees of
// freedom: tabulated to 30, then the Cornish-Fisher expansion (error < 1e-4).
inline double student_t975(int dof) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959964, v = dof;
  return z + (z * z * z + z) / (4 * v) + (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96 * v * v);
}

}  // namespace dem2d::analysis
