// Settings of stage `spectrum` (data/spectrum.toml; every key documented there
// and in analysis/spectrum/README.md). Lengths of travel are in units of d.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace dem2d::analysis {

// A problem with the input: the run file, the drag profile or the configuration.
struct SpectrumError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SpectrumConfig {
  // [profile]
  double uniform_tolerance = 0.01;  // -
  double trend_window_d = 4.0;      // d
  // [psd]
  double segment_d = 8.0;  // d
  double overlap = 0.5;    // -
  std::string window = "hann";
  double min_period_d = 0.1, max_period_d = 2.0;  // d
  double false_alarm = 0.01;                      // -
  // [ringing]: the bed's elastic ringing, in time frequency
  double ringing_min_frequency_hz = 10.0;  // Hz: searched from here up to the series' Nyquist frequency
  double ringing_segment_s = 1.0;        // s, Welch segment in time
  double ringing_cutoff_fraction = 0.5;  // geometric periods only below this fraction of the ringing frequency
  // [events]
  double drop_threshold = 7.0;  // x sigma
  double drop_window_d = 0.1;   // d
  int confirm_samples = 2;      // rows whose medians before and after a drop must differ (0: no check)
  double confirm_fraction = 0.5;  // by this fraction of the drop threshold
  // [ruptures]: the events the paper counts
  double min_relative_drop = 0.1;  // drop >= this x the load (the drag's trend at the peak)
  // [size_distribution]
  int size_min_tail = 10;          // fewest sizes above x_min
  int size_bootstrap = 200;        // synthetic sets for the power law's p-value
  double size_significance = 0.05; // a likelihood ratio decides below this p
  double size_min_decades = 1.0;   // decades the power law's tail must span to be plausible
  double size_plausible_p = 0.1;   // goodness-of-fit p that makes it plausible
  // [top_layer]: the change point (top_layer.hpp) and the envelope's old definition
  double block_d = 1.0;               // d: variance blocks
  double search_from_fraction = 0.3;  // of the bed height: where the search starts
  double search_margin_d = 2.0;       // d: the search ends this far below the bed surface
  int top_bootstrap = 200;            // resamples for the interval
  double top_confidence = 0.95;       // of the interval
  double top_false_alarm = 0.01;      // significance of the change point
  double envelope_window_d = 1.0;  // d
  double floor_factor = 2.0;       // x sigma
  double fit_margin_d = 1.0;       // d
  // the power of a "none": a layer planted at these depths (fractions of the
  // bed height) into the run's own fluctuations, found within the tolerance
  std::vector<double> power_depth_fractions{0.3};  // -
  int power_replicas = 20;        // plantings per depth (0: no power, the outcome of a miss is "undetermined")
  int power_bootstrap = 200;      // permutations of each planting's significance test
  double power_tolerance_d = 3.0; // d
  double min_power = 0.8;         // a miss is "none" at this power or more, else "undetermined"
  double power_noise_factor = 1.25;  // the planted layer's noise over the local noise level
  // [bands]: fractions of the bed height
  double bottom_top = 0.10, middle_top = 0.52, upper_top = 0.70;
  // [bottom]
  double collapse_fraction = 0.2;  // of the first peak's drag
  // [sensitivity]
  std::vector<double> drop_thresholds{5.0, 7.0, 10.0, 15.0, 20.0};
  std::vector<double> floor_factors{1.5, 2.0, 3.0};
  std::vector<double> trend_windows_d{3.0, 4.0, 6.0};
  std::vector<double> ringing_cutoff_fractions{0.35, 0.5, 0.7};
  std::vector<double> min_relative_drops{0.03, 0.05, 0.1, 0.2, 0.3};
  std::vector<double> blocks_d{0.5, 1.0, 2.0};
  std::vector<double> search_from_fractions{0.2, 0.3, 0.4};
  std::vector<double> power_noise_factors{1.0, 1.25, 1.5, 2.0};
};

// Reads a config file; keys not given keep their defaults. Unknown keys, wrong
// types and values out of range are errors (SpectrumError "FILE:LINE:COL: key = value: ...").
SpectrumConfig load_spectrum_config(const std::string& path);

// Checks the relations between keys (bands ordered, period range, ...); throws
// SpectrumError naming `source` (the file the config came from).
void check_spectrum_config(const SpectrumConfig& c, const std::string& source);

}  // namespace dem2d::analysis
