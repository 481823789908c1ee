// Binning by intruder height and means over height bands: what the stages
// that follow the pull-off (network, friction) tabulate against the
// intruder's height. SI units (m).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem2d::analysis {

// Bins of intruder height [k w, (k+1) w), k >= 0, w > 0 (m); heights below 0
// go to bin 0. A height beyond kMaxBins bins (or NaN) is a StageError.
struct HeightBins {
  static constexpr std::size_t kMaxBins = 1000000;
  double width = 0.0;
  std::size_t index(double height) const;
  double lower(std::size_t k) const { return static_cast<double>(k) * width; }
};

// Mean of values by height bin; NaN values are skipped. count[k] = values used in bin k.
struct BinnedMean {
  std::vector<double> mean;
  std::vector<std::int64_t> count;
};
BinnedMean binned_mean(const HeightBins& bins, const std::vector<double>& heights, const std::vector<double>& values);

// The mean of `values` over the entries with lo <= heights < hi, skipping NaN;
// NaN if there are none. `used` (optional) receives the number of entries used.
double mean_in_band(const std::vector<double>& heights, const std::vector<double>& values, double lo, double hi,
                    std::int64_t* used = nullptr);

}  // namespace dem2d::analysis
