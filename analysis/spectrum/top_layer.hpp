// The top layer (R4, docs/paper.md): the height above which the loading/rupture
// fluctuations of the drag vanish, found as a change point with an interval.
// Definitions and reasons: analysis/spectrum/README.md, "Top layer".
//
// The drag fluctuation's variance is measured in blocks of travel and fitted
// by what is left where no ruptures occur, a stationary background B (any
// correlated part) and a noise that follows the load L (the bed's ringing
// grows with its load: ~2 % of it in the study's runs), plus the ruptures'
// amplitude, which falls linearly to zero at the change point H_top and is
// zero above it:
//
//   var_b = (sqrt(B) + sqrt(e) L_b)^2 + a(H_b)^2,   a(H) = g(H) (c0 + c1 (H_top - H))  for H < H_top,  0 above,
//
// with c0 >= 0 (an abrupt end) and c1 >= 0 (a linear fade; the amplitude
// does not grow towards the change point), and g = 1 (the
// amplitude itself is linear: "absolute") or g = the local load, the drag's
// trend (the amplitude relative to the load is linear: "relative"; events whose
// size follows the load to the surface then have no change point). Fitted by
// least squares on ln var_b (a variance's error is relative), H_top on a fine
// grid, the model with the smaller residual kept. The interval is a wild
// bootstrap of the residuals (Rademacher signs: each block keeps its own
// spread). A change point is reported only when it is significant: the
// residual it saves is compared with what it saves on data made of the fit
// without one plus that fit's residuals in shuffled order (a permutation
// test). The fit without one keeps the fluctuations' size, relative to the
// load or absolute, up to the range's end (no fade: c1 = 0), or has none at
// all. A miss's power: top_layer_power.
// Pure functions of arrays: no files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dem2d::analysis {

struct TopLayerSearch {
  double low = 0.0, high = 0.0;  // m: the heights searched, [low, high)
  std::size_t block_rows = 0;    // rows per block
  int bootstrap = 200;           // resamples for the interval (0: none)
  double confidence = 0.95;      // of the interval
  double false_alarm = 0.01;     // a change point is significant when its p-value is below this
  std::uint64_t seed = 1;        // of the bootstrap: the same input gives the same interval
  bool interval = true;          // false: no interval (low = high = the change point), e.g. for the power
  // true: only found or not (and where) is wanted: the permutations stop once
  // enough of them reach the statistic that p cannot fall below false_alarm
  // (the same decision as all of them would give; p_value is then NaN)
  bool decision_only = false;
  bool operator==(const TopLayerSearch&) const = default;
};

struct TopLayerModelFit {
  double height = std::numeric_limits<double>::quiet_NaN();  // H_top (m)
  double background = 0.0;  // B, (N/m)^2
  double c0 = 0.0, c1 = 0.0;  // amplitude at H_top (x g) and its slope per m of depth (x g)
  double noise = 0.0;         // e: the noise's variance over the load's square
  double residual = std::numeric_limits<double>::infinity();  // sum of squared ln residuals
};

struct TopLayerFit {
  bool searched = false;   // at least 4 blocks in the range
  // found: the change point lowers the residual more than it does on data
  // without one (p < false_alarm, a permutation test under the null of no
  // change point in the range), and it and its interval end below the
  // range's end
  bool found = false;
  std::string outcome;     // "found", "no significant vanishing", "reaches the surface", "not searched"
  double p_value = std::numeric_limits<double>::quiet_NaN();
  double statistic = std::numeric_limits<double>::quiet_NaN();  // the residual the change point saves
  std::string model;       // "relative" or "absolute": the one kept
  TopLayerModelFit best, relative, absolute;
  TopLayerModelFit null;   // the better model without a change point in the range (H_top at its end)
  std::string null_model;  // its kind, "relative" or "absolute"
  double low = std::numeric_limits<double>::quiet_NaN(), high = std::numeric_limits<double>::quiet_NaN();  // interval (m)
  // the blocks, for the figure: centre height (m), variance and model ((N/m)^2), mean load (N/m)
  std::vector<double> block_height, block_variance, block_model, block_load;
};

// heights h (increasing, m), fluctuation f and trend (N/m), all [n].
TopLayerFit find_top_layer(const std::vector<double>& h, const std::vector<double>& f, const std::vector<double>& trend,
                           const TopLayerSearch& s);

// The detector's power on this series: how often it finds a top layer of the
// claimed kind planted into the series' own fluctuations. For each planted
// height H and replica, the fluctuation above H is replaced by Gaussian noise
// of rms `quiet` (N/m, per row: the background a layer would leave) and the
// detector is run with `s` (no interval); a replica counts when it finds a
// layer within `tolerance` (m) of H. Replicas are seeded from s.seed and
// their index: the result does not depend on the thread count.
struct TopLayerPower {
  std::vector<double> height;          // m, planted heights
  std::vector<double> found_fraction;  // at each height
  int replicas = 0;
  double tolerance = 0.0;              // m
  double power = std::numeric_limits<double>::quiet_NaN();  // the smallest found fraction
};
TopLayerPower top_layer_power(const std::vector<double>& h, const std::vector<double>& f,
                              const std::vector<double>& trend, const std::vector<double>& quiet,
                              const TopLayerSearch& s, const std::vector<double>& planted, int replicas,
                              double tolerance);

// The results of find_top_layer and top_layer_power for inputs already
// searched: a stage analyses one series many times (the sensitivity table
// changes one setting at a time, most of which leave the top layer's inputs as
// they were). A result is reused only for exactly the same inputs, so it is
// the result a new search would give.
class TopLayerMemo {
 public:
  TopLayerFit find(const std::vector<double>& h, const std::vector<double>& f, const std::vector<double>& trend,
                   const TopLayerSearch& s);
  TopLayerPower power(const std::vector<double>& h, const std::vector<double>& f, const std::vector<double>& trend,
                      const std::vector<double>& quiet, const TopLayerSearch& s, const std::vector<double>& planted,
                      int replicas, double tolerance);

 private:
  struct Inputs {
    std::vector<double> h, f, trend, quiet, planted;
    TopLayerSearch search;
    int replicas = 0;
    double tolerance = 0.0;
    bool operator==(const Inputs&) const = default;
  };
  std::vector<std::pair<Inputs, TopLayerFit>> fits_;
  std::vector<std::pair<Inputs, TopLayerPower>> powers_;
};

}  // namespace dem2d::analysis
