// The step test on per-snapshot flags (analysis/common/flag_step.hpp): the
// flip rate on each side, and the power to find a planted
// step, against series whose truth is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/flag_step.hpp"

namespace dem2d::analysis {
namespace {

// n snapshots, heights 0 ... 0.1 m, surface 0.14 m; yes below `step` (m) with
// probability 1 - flip_below, no above it with probability 1 - flip_above.
FlagProfile series(int n, double step, double flip_below, double flip_above, std::uint64_t seed) {
  FlagProfile f;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    const double h = 0.1 * k / (n - 1);
    const bool yes = h < step;
    f.heights.push_back(h);
    f.surfaces.push_back(0.14);
    f.flags.push_back(u(rng) < (yes ? flip_below : flip_above) ? !yes : yes);
  }
  return f;
}

double fitted(const FlagProfile& p) { return step_down(p.heights, p.flags).height; }

TEST(FlagStep, FlipRateIsTheMinorityOnASide) {
  const auto all = [](std::size_t) { return true; };
  for (const double e : {0.0, 0.05, 0.2, 0.4}) {
    const FlagProfile f = series(20000, 1.0, e, 0.0, 3);  // all below the step
    EXPECT_NEAR(flip_rate(f, all), e, 0.01) << e;        // 3 sd at e = 0.4
  }
  // a profile wholly yes or wholly no is not noisy, whatever it should have been
  EXPECT_EQ(flip_rate(series(100, 1.0, 0.0, 0.0, 3), all), 0.0);
  EXPECT_EQ(flip_rate(series(100, -1.0, 0.0, 0.0, 3), all), 0.0);
  // more than half wrong reads as less than half; a selection of one or none: 0
  EXPECT_NEAR(flip_rate(series(20000, 1.0, 0.7, 0.0, 3), all), 0.3, 0.01);
  EXPECT_EQ(flip_rate(series(100, 1.0, 0.5, 0.0, 3), [](std::size_t i) { return i == 7; }), 0.0);
  EXPECT_EQ(flip_rate(series(100, 1.0, 0.5, 0.0, 3), [](std::size_t) { return false; }), 0.0);
}

TEST(FlagStep, PowerFollowsTheFlagsNoise) {
  const double depth = 0.078, tol = 0.009;  // the paper's H_c below a 0.14 m surface; 3 d
  // a step at the planted depth with 5 % flips each side: found every time
  const FlagProfile clean = series(200, 0.14 - depth, 0.05, 0.05, 7);
  EXPECT_LT(step_p_value(clean, 200), 0.01);
  const StepPower c = step_power(clean, depth, tol, 0.01, 200, 20, fitted);
  EXPECT_NEAR(c.flip_below, 0.05, 0.06);  // 3 sd of a rate from 124 snapshots
  EXPECT_NEAR(c.flip_above, 0.05, 0.07);  // ... and from 76
  EXPECT_GE(c.power, 0.95);
  // coin flips: nothing could be found in them
  const StepPower noisy = step_power(series(200, 0.0, 0.5, 0.5, 8), depth, tol, 0.01, 200, 20, fitted);
  EXPECT_GT(std::max(noisy.flip_below, noisy.flip_above), 0.35);
  EXPECT_LE(noisy.power, 0.3);
  // a step below every snapshot (deeper than the surface's height) is never found
  EXPECT_EQ(step_power(clean, 0.15, tol, 0.01, 200, 20, fitted).power, 0.0);
  // yes in every one of 200 snapshots: the flags are not noisy, a step would
  // have been seen (a none here is evidence of absence) ...
  const FlagProfile everywhere = series(200, 1.0, 0.0, 0.0, 9);
  const StepPower e = step_power(everywhere, depth, tol, 0.01, 200, 20, fitted);
  EXPECT_EQ(e.flip_below + e.flip_above, 0.0);
  EXPECT_EQ(e.power, 1.0);
  // ... but not in 4 snapshots: no split of 4 is significant at 1 %
  EXPECT_EQ(step_power(series(4, 1.0, 0.0, 0.0, 9), depth, tol, 0.01, 200, 20, fitted).power, 0.0);
  // no flags, no power
  EXPECT_TRUE(std::isnan(step_power(FlagProfile{}, depth, tol, 0.01, 200, 20, fitted).power));
}

// The power read from one series predicts how often the test finds the step
// in independent series of the same process (here one where it is found
// about half the time).
TEST(FlagStep, PowerFromOneSeriesPredictsTheFoundRate) {
  const double depth = 0.078, tol = 0.009, step = 0.14 - depth;
  int found = 0;
  const int series_count = 40;
  double predicted = 0.0;
  for (int s = 0; s < series_count; ++s) {
    const FlagProfile f = series(40, step, 0.35, 0.1, 100 + s);
    const double h = fitted(f);
    found += std::isfinite(h) && step_p_value(f, 200) < 0.01 && std::abs(0.14 - h - depth) <= tol;
    predicted += step_power(f, depth, tol, 0.01, 200, 20, fitted).power / series_count;
  }
  const double rate = static_cast<double>(found) / series_count;
  EXPECT_GT(rate, 0.2);
  EXPECT_LT(rate, 0.8);
  EXPECT_NEAR(predicted, rate, 0.15) << "found " << found << " of " << series_count;
}

}  // namespace
}  // namespace dem2d::analysis
