#include "frame/height_bins.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "common/stage_error.hpp"
#include "common/stage_output.hpp"  // format_number

namespace dem2d::analysis {

std::size_t HeightBins::index(double height) const {
  const double k = height > 0.0 ? std::floor(height / width) : 0.0;
  if (!(k < static_cast<double>(kMaxBins)))  // (NaN too)
    throw StageError("height " + format_number(height) + " m falls in bin " + format_number(k) + " of width " +
                     format_number(width) + " m: more than " + std::to_string(kMaxBins) +
                     " height bins (a bin width too small for this run?)");
  return static_cast<std::size_t>(k);
}

BinnedMean binned_mean(const HeightBins& bins, const std::vector<double>& heights, const std::vector<double>& values) {
  BinnedMean out;
  std::vector<double> sum;
  for (std::size_t k = 0; k < heights.size() && k < values.size(); ++k) {
    if (std::isnan(values[k])) continue;
    const std::size_t b = bins.index(heights[k]);
    if (b >= sum.size()) sum.resize(b + 1, 0.0), out.count.resize(b + 1, 0);
    sum[b] += values[k];
    ++out.count[b];
  }
  out.mean.resize(sum.size());
  for (std::size_t b = 0; b < sum.size(); ++b)
    out.mean[b] = out.count[b] > 0 ? sum[b] / static_cast<double>(out.count[b]) : std::numeric_limits<double>::quiet_NaN();
  return out;
}

double mean_in_band(const std::vector<double>& heights, const std::vector<double>& values, double lo, double hi,
                    std::int64_t* used) {
  double sum = 0.0;
  std::int64_t n = 0;
  for (std::size_t k = 0; k < heights.size() && k < values.size(); ++k)
    if (heights[k] >= lo && heights[k] < hi && !std::isnan(values[k])) sum += values[k], ++n;
  if (used) *used = n;
  return n > 0 ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace dem2d::analysis
