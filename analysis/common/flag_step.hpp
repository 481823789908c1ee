// A step in per-snapshot yes/no flags against the intruder's height ("yes"
// below, "no" above: the walls move, the force network percolates), as a
// test: the best split, its permutation p-value, and the test's power to find
// a step planted at a given depth below the surface in flags as mixed as the
// run's own. Pure functions of the flags; the cg stage (wall mobility) and the
// network stage (percolation) make the flags. SI units (m).
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace dem2d::analysis {

// The height that best separates "yes" observations (expected below it) from
// "no" ones (above): the split of the sorted heights with the fewest
// misclassified observations (a yes above or a no below); ties: the middle of
// the optimal splits. height NaN if all observations are in one class.
struct StepFit {
  double height = std::numeric_limits<double>::quiet_NaN();
  int misclassified = 0, count = 0;
};
StepFit step_down(const std::vector<double>& heights, const std::vector<bool>& flags);

// One flag per snapshot, with the intruder's height and the free surface
// (the height depths are measured from; a constant where only the bed's
// initial height is known).
struct FlagProfile {
  std::vector<double> heights;   // intruder heights (m)
  std::vector<double> surfaces;  // free surface at each snapshot (m)
  std::vector<bool> flags;       // yes / no
};

// The free surface (m) of the snapshot whose intruder height is nearest
// `height` (the first of equals); NaN without snapshots.
double surface_near(const FlagProfile& f, double height);

// The permutation p-value of the step fit's gain over calling every snapshot
// the majority class: the fraction of shuffles of the flags over the heights
// (fixed seed) whose step fit gains as much (+1 smoothing); NaN without flags
// or permutations.
double step_p_value(const FlagProfile& f, int permutations);

// How often a flag is wrong at random among the snapshots `in` selects: the
// fraction in the minority (yes or no, whichever is fewer). A side that is
// wholly yes or wholly no has rate 0 whatever the claim says it should be (a
// bias is not noise: the claim is then tested against clean flags). More than
// half wrong cannot be told from less than half (a signal present in fewer
// than half of the snapshots reads as one present in more than half, and the
// power is too high for it). 0 without snapshots.
double flip_rate(const FlagProfile& f, const std::function<bool(std::size_t)>& in);

// The test's power to find a step planted at `depth` below each snapshot's
// surface: flags yes below it and no above, each flipped at the run's own
// flip rate on its side (flip_rate above and below the planted step: the
// paper's claim with the run's own mixing, not the run's flags resampled,
// which would find a step only where the run already has one), tested
// as the run's flags are; the fraction of `replicas` series with a
// significant step (p < false_alarm) that `locate` (the detector's step
// height, NaN: none) puts within `tolerance` of the planted depth. A step
// planted outside the snapshots' heights is never found (power 0). NaN
// without flags.
struct StepPower {
  double power = std::numeric_limits<double>::quiet_NaN(), depth = power;
  double flip_below = power, flip_above = power;  // the flip rates applied
  int replicas = 0;
};
using StepLocator = std::function<double(const FlagProfile&)>;
StepPower step_power(const FlagProfile& f, double depth, double tolerance, double false_alarm, int permutations,
                     int replicas, const StepLocator& locate);

}  // namespace dem2d::analysis
