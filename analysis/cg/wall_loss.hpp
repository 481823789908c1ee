// The walls' mobility loss as a test on per-snapshot flags (is a wall
// moving?), common/flag_step's step test with the walls' flags: the height
// that best splits mobile snapshots (below) from immobile ones (above), its
// permutation p-value, and where no significant loss is found the test's
// power to find one planted at a given depth in flags as mixed as the run's.
// The flags come from cg_report.cpp. SI units (m).
#pragma once

#include <cstddef>
#include <limits>

#include "common/flag_step.hpp"

namespace dem2d::analysis {

// Wall mobility lost: the intruder height separating loading snapshots whose
// walls move (flags) from those whose walls do not.
struct WallLoss : FlagProfile {
  StepFit fit;
  double depth = std::numeric_limits<double>::quiet_NaN(), surface = depth;  // surface - height at the loss (m)
  std::size_t mobile = 0;
};

// The loss test's power (common/flag_step.hpp step_power) with the step fit
// as the detector.
inline StepPower loss_power(const WallLoss& w, double depth, double tolerance, double false_alarm, int permutations,
                            int replicas) {
  return step_power(w, depth, tolerance, false_alarm, permutations, replicas,
                    [](const FlagProfile& p) { return step_down(p.heights, p.flags).height; });
}

}  // namespace dem2d::analysis
