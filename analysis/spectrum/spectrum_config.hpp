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
  // [top_layer]
  double envelope_window_d = 1.0;  // d
  double floor_factor = 2.0;       // x sigma
  double fit_margin_d = 1.0;       // d
  // [bands]: fractions of the bed height
  double bottom_top = 0.10, middle_top = 0.52, upper_top = 0.70;
  // [bottom]
  double collapse_fraction = 0.2;  // of the first peak's drag
  // [sensitivity]
  std::vector<double> drop_thresholds{5.0, 7.0, 10.0, 15.0, 20.0};
  std::vector<double> floor_factors{1.5, 2.0, 3.0};
  std::vector<double> trend_windows_d{3.0, 4.0, 6.0};
  std::vector<double> ringing_cutoff_fractions{0.35, 0.5, 0.7};
};

// Reads a config file; keys not given keep their defaults. Unknown keys, wrong
// types and values out of range are errors (SpectrumError "FILE:LINE:COL: key = value: ...").
SpectrumConfig load_spectrum_config(const std::string& path);

// Checks the relations between keys (bands ordered, period range, ...); throws
// SpectrumError naming `source` (the file the config came from).
void check_spectrum_config(const SpectrumConfig& c, const std::string& source);

}  // namespace dem2d::analysis
