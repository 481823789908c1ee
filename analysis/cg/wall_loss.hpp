// The walls' mobility loss as a test on per-snapshot flags (is a wall
// moving?): the height that best splits mobile snapshots (below) from
// immobile ones (above), its permutation p-value, and where no significant
// loss is found the test's power to find one planted at a given depth with
// the run's own flag errors. Pure functions of the flags; the flags come from
// cg_report.cpp. SI units (m).
#pragma once

#include <cstddef>
#include <vector>

#include "cg/cg_measure.hpp"  // StepFit, kNaN

namespace dem2d::analysis {

// Wall mobility lost: the intruder height separating loading snapshots whose
// walls move from those whose walls do not.
struct WallLoss {
  StepFit fit;
  double depth = kNaN, surface = kNaN;  // surface - height at the loss (m)
  std::size_t mobile = 0;
  std::vector<double> heights;   // intruder heights of the snapshots used (m)
  std::vector<double> surfaces;  // their free surfaces (m)
  std::vector<bool> flags;       // mobile or not
};

// The free surface (m) of the used snapshot whose intruder height is nearest
// `height` (the first of equals); NaN without snapshots.
double surface_near(const WallLoss& w, double height);

// The permutation p-value of the step fit's gain over calling every snapshot
// the majority class: the fraction of shuffles of the flags over the heights
// (fixed seed) whose step fit gains as much (+1 smoothing); NaN without flags
// or permutations.
double loss_p_value(const WallLoss& w, int permutations);

// The loss test's power where it found none: flags with a loss planted at
// `depth` below each snapshot's surface (mobile below it), each flag flipped
// with the run's own error rates were that the truth (the run's flags that
// contradict it: immobile below the planted loss, mobile above it), tested as
// the run's flags; the fraction of `replicas` series found significant
// (p < false_alarm) with the depth within `tolerance`. A loss planted outside
// the snapshots' heights is never found (power 0). NaN without flags.
// (The error rates of the run's best split would be fitted to the flags:
// too small, and the power too high.)
struct LossPower {
  double power = kNaN, depth = kNaN;
  double missed = kNaN, false_mobile = kNaN;  // the error rates applied
  int replicas = 0;
};
LossPower loss_power(const WallLoss& w, double depth, double tolerance, double false_alarm, int permutations,
                     int replicas);

}  // namespace dem2d::analysis
