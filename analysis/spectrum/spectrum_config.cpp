#include "spectrum/spectrum_config.hpp"

#include "common/stage_config.hpp"

namespace dem2d::analysis {

SpectrumConfig load_spectrum_config(const std::string& path) {
  SpectrumConfig c;
  try {
    StageConfig file(path);
    using E = StageConfig::Ends;
    constexpr double kD = 1e4;  // bound of lengths of travel in d
    StageConfig profile = file.table("profile");
    profile.number("uniform_tolerance", c.uniform_tolerance, 0.0, 0.5, "relative deviation", E::open_low);
    profile.number("trend_window_d", c.trend_window_d, 0.0, kD, "d of travel", E::open_low);
    profile.reject_unknown();
    StageConfig psd = file.table("psd");
    psd.number("segment_d", c.segment_d, 0.0, kD, "d of travel", E::open_low);
    psd.number("overlap", c.overlap, 0.0, 1.0, "fraction of a segment", E::open_high);
    psd.choice("window", c.window, {"hann", "hamming", "blackman", "rectangular"}, "window function");
    psd.number("min_period_d", c.min_period_d, 0.0, kD, "d of travel", E::open_low);
    psd.number("max_period_d", c.max_period_d, 0.0, kD, "d of travel", E::open_low);
    psd.number("false_alarm", c.false_alarm, 0.0, 1.0, "probability", E::open);
    psd.reject_unknown();
    StageConfig ringing = file.table("ringing");
    ringing.number("min_frequency_hz", c.ringing_min_frequency_hz, 0.0, 1e9, "Hz", E::open_low);
    ringing.number("segment_s", c.ringing_segment_s, 0.0, 1e6, "s", E::open_low);
    ringing.number("cutoff_fraction", c.ringing_cutoff_fraction, 0.0, 1.0, "fraction of the ringing frequency", E::open);
    ringing.reject_unknown();
    StageConfig events = file.table("events");
    events.number("drop_threshold", c.drop_threshold, 0.0, 1e6, "multiple of the noise level", E::open_low);
    events.number("drop_window_d", c.drop_window_d, 0.0, kD, "d of travel", E::open_low);
    events.integer("confirm_samples", c.confirm_samples, 0, 1000000, "rows");
    events.number("confirm_fraction", c.confirm_fraction, 0.0, 1.0, "fraction of the drop threshold", E::open_low);
    events.reject_unknown();
    StageConfig ruptures = file.table("ruptures");
    ruptures.number("min_relative_drop", c.min_relative_drop, 0.0, 1e6, "fraction of the load");
    ruptures.reject_unknown();
    StageConfig sizes = file.table("size_distribution");
    sizes.integer("min_tail", c.size_min_tail, 3, 1000000, "sizes");
    sizes.integer("bootstrap", c.size_bootstrap, 0, 1000000, "synthetic sets");
    sizes.number("significance", c.size_significance, 0.0, 1.0, "probability", E::open);
    sizes.number("min_decades", c.size_min_decades, 0.0, 100.0, "decades");
    sizes.number("plausible_p", c.size_plausible_p, 0.0, 1.0, "probability", E::open_high);
    sizes.reject_unknown();
    StageConfig top = file.table("top_layer");
    top.number("block_d", c.block_d, 0.0, kD, "d of travel", E::open_low);
    top.number("search_from_fraction", c.search_from_fraction, 0.0, 1.0, "fraction of the bed height", E::open_high);
    top.number("search_margin_d", c.search_margin_d, 0.0, kD, "d of travel");
    top.integer("bootstrap", c.top_bootstrap, 0, 1000000, "resamples");
    top.number("confidence", c.top_confidence, 0.0, 1.0, "probability", E::open);
    top.number("false_alarm", c.top_false_alarm, 0.0, 1.0, "probability", E::open);
    top.number("envelope_window_d", c.envelope_window_d, 0.0, kD, "d of travel", E::open_low);
    top.number("floor_factor", c.floor_factor, 0.0, 1e6, "multiple of the noise level", E::open_low);
    top.number("fit_margin_d", c.fit_margin_d, 0.0, kD, "d of travel");
    top.numbers("power_depth_fractions", c.power_depth_fractions, 0.0, 1.0, "fraction of the bed height", E::open);
    top.integer("power_replicas", c.power_replicas, 0, 100000, "plantings per depth");
    top.integer("power_bootstrap", c.power_bootstrap, 1, 1000000, "resamples");
    top.number("power_tolerance_d", c.power_tolerance_d, 0.0, kD, "d of travel", E::open_low);
    top.number("min_power", c.min_power, 0.0, 1.0, "probability", E::open);
    top.number("power_noise_factor", c.power_noise_factor, 0.0, 1e3, "multiple of the local noise level",
               E::open_low);
    top.reject_unknown();
    StageConfig bands = file.table("bands");
    bands.number("bottom_top", c.bottom_top, 0.0, 1.0, "fraction of the bed height", E::open_low);
    bands.number("middle_top", c.middle_top, 0.0, 1.0, "fraction of the bed height", E::open_low);
    bands.number("upper_top", c.upper_top, 0.0, 1.0, "fraction of the bed height", E::open_low);
    bands.reject_unknown();
    StageConfig bottom = file.table("bottom");
    bottom.number("collapse_fraction", c.collapse_fraction, 0.0, 1.0, "fraction of the peak", E::open);
    bottom.reject_unknown();
    StageConfig sensitivity = file.table("sensitivity");
    sensitivity.numbers("drop_thresholds", c.drop_thresholds, 0.0, 1e6, "multiple of the noise level", E::open_low);
    sensitivity.numbers("floor_factors", c.floor_factors, 0.0, 1e6, "multiple of the noise level", E::open_low);
    sensitivity.numbers("trend_windows_d", c.trend_windows_d, 0.0, kD, "d of travel", E::open_low);
    sensitivity.numbers("ringing_cutoff_fractions", c.ringing_cutoff_fractions, 0.0, 1.0,
                        "fraction of the ringing frequency", E::open);
    sensitivity.numbers("min_relative_drops", c.min_relative_drops, 0.0, 1e6, "fraction of the load");
    sensitivity.numbers("blocks_d", c.blocks_d, 0.0, kD, "d of travel", E::open_low);
    sensitivity.numbers("search_from_fractions", c.search_from_fractions, 0.0, 1.0, "fraction of the bed height",
                        E::open_high);
    sensitivity.numbers("power_noise_factors", c.power_noise_factors, 0.0, 1e3, "multiple of the local noise level",
                        E::open_low);
    sensitivity.reject_unknown();
    file.reject_unknown();
  } catch (const StageError& e) {
    throw SpectrumError(e.what());
  }
  check_spectrum_config(c, path);
  return c;
}

void check_spectrum_config(const SpectrumConfig& c, const std::string& source) {
  auto require = [&source](bool ok, const std::string& what) {
    if (!ok) throw SpectrumError(source + ": " + what);
  };
  require(c.bottom_top < c.middle_top && c.middle_top < c.upper_top,
          "bands: need bottom_top < middle_top < upper_top (fractions of the bed height)");
  require(c.min_period_d < c.max_period_d, "psd: need min_period_d < max_period_d");
  require(c.max_period_d < c.segment_d, "psd: need max_period_d < segment_d (a segment must hold the longest period)");
}

}  // namespace dem2d::analysis
