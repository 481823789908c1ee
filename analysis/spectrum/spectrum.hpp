// Stage `spectrum` (issue 4): the drag on the intruder against its height,
// split into a slow trend and fluctuations; the fluctuations' power spectrum
// in the travel domain (Welch, FFTW); the loading/rupture events; the bottom
// zone's first peak and the top layer where the fluctuations vanish.
// Definitions and their reasons: analysis/spectrum/README.md.
//
// Everything here works on a DragProfile in memory (no files), so that it can
// be tested on synthetic signals. Units: SI (m, s, N/m) unless a name says
// otherwise; "_d" means in units of d, the mean grain diameter, as a length
// of travel; wavenumbers are in cycles per d. The series is uniform in time and
// in travel (constant V): the geometric periods are sought against travel, the
// bed's elastic ringing against time.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/units.hpp"
#include "frame/drag_profile.hpp"
#include "spectrum/size_distribution.hpp"
#include "spectrum/spectrum_config.hpp"
#include "spectrum/top_layer.hpp"

namespace dem2d::analysis {


// ---- building blocks ----------------------------------------------------

// Median of x over the window [k - h, k + h] shrunk symmetrically at the
// ends (h' = min(h, k, n-1-k)): a monotone signal is returned unchanged.
std::vector<double> running_median(const std::vector<double>& x, std::size_t half_width);
// Root mean square over the same symmetric windows.
std::vector<double> running_rms(const std::vector<double>& x, std::size_t half_width);
// Robust noise level of x[begin, end): 1.4826 MAD(first differences) / sqrt(2),
// the standard deviation of white noise that would give those differences.
double noise_level(const std::vector<double>& x, std::size_t begin, std::size_t end);

struct LinearFit {
  double slope = kNaN, intercept = kNaN, r2 = kNaN;  // y = intercept + slope x
  std::size_t points = 0;                            // NaN results below 3 points
};
LinearFit linear_fit(const std::vector<double>& x, const std::vector<double>& y);

// One-sided power spectral density by Welch's method: segments of
// segment_samples with the given overlap, each windowed after removing its
// mean; |FFT|^2 averaged. x is sampled `sample_rate` times per unit of its
// axis: per d of travel (frequency = wavenumber, cycles per d) or per second
// (frequency in Hz). Frequencies from 1/segment up to Nyquist (the zero bin is
// left out); power in (unit of x)^2 per (cycle per unit of the axis), so that
// sum(power) * df = variance.
struct Psd {
  std::vector<double> frequency, power;
  std::size_t segments = 0, segment_samples = 0;
  double dof = 0.0;  // equivalent degrees of freedom of one bin (chi-square), overlap included
};
Psd welch_psd(const std::vector<double>& x, double sample_rate, std::size_t segment_samples, double overlap,
              const std::string& window);

// The dominant peak of a PSD in the frequency range [low, high] (the PSD's
// axis: cycles per d, or Hz): among the bins in that range, the one whose power
// stands highest above a power law fitted to the PSD over the range (log-log
// least squares, corrected for the mean of log chi-square), refined by a
// parabola through ln(excess) at it and its neighbours. Significant when that
// excess exceeds the chi-square quantile that pure noise with that background
// exceeds in any of the M bins with probability false_alarm, and the bin is not
// at the range's edge (there it need not be a local maximum).
struct DominantPeak {
  bool found = false;  // false when the range holds fewer than 3 bins
  double frequency = kNaN, period = kNaN;  // in the PSD's axis: cycles per d and d, or Hz and s
  double peak_to_background = kNaN, threshold = kNaN;  // excess ratio and its significance threshold
  double peak_to_median = kNaN;                        // peak power / median power of the range
  double background_exponent = kNaN;                   // the background is P ~ frequency^exponent
  double half_max_low = kNaN, half_max_high = kNaN;    // frequencies where the excess falls to half its peak
  double half_width = kNaN;  // half the width, in period, where the excess is above half its peak
  double quality = kNaN;     // frequency / full width at half maximum (in frequency)
  bool significant = false, at_edge = false;
  std::size_t bins = 0;
};
DominantPeak dominant_peak(const Psd& psd, double low, double high, double false_alarm);

// The bed's elastic ringing after slips: a fixed time frequency (tens to
// hundreds of Hz, growing with the contact stiffness), whatever the pull speed.
// The dominant peak of the spectrum of x (the drag fluctuation, rows every
// time_step seconds) against time frequency (Welch, segments of
// ringing.segment_s, overlap and window as [psd]) between
// ringing.min_frequency_hz and the series' Nyquist frequency.
struct Ringing {
  double nyquist = kNaN;   // Hz, 1 / (2 time_step): a ringing above it appears folded below it
  bool searched = false;   // the band holds at least 3 bins
  Psd psd;                 // frequency in Hz, power in (unit of x)^2 per Hz
  DominantPeak peak;       // frequency in Hz, period in s
  double line_rms = kNaN;  // unit of x: sqrt(sum power df) over the peak's full width at half maximum
};
Ringing find_ringing(const std::vector<double>& x, double time_step, const SpectrumConfig& c);

// Alternating extrema of x from `begin` on with hysteresis delta: a peak is
// confirmed when x falls more than delta below it, a trough when x rises more
// than delta above it. A last trough not yet confirmed by a rise is kept.
struct Pivot {
  std::size_t index;
  bool peak;
};
std::vector<Pivot> zigzag(const std::vector<double>& x, double delta, std::size_t begin = 0);
// The same with a hysteresis per sample (that of the candidate extremum).
std::vector<Pivot> zigzag(const std::vector<double>& x, const std::vector<double>& delta, std::size_t begin = 0);

// Loading/rupture events of the fluctuation f: every zigzag peak -> trough
// leg (hysteresis delta) in which f falls by more than delta within `window`
// samples somewhere, and (confirm > 0) whose level falls for good: the median
// of the confirm + 1 samples up to the peak exceeds by more than
// confirm_fraction x delta the lowest median of confirm + 1 consecutive
// samples between the peak and the trough (a lone spike of heavy-tailed noise
// falls and comes straight back: no median of three holds it; a median has
// no noise extremes to lean on, hence a fraction of delta). Indices into f.
struct Event {
  std::size_t load_start, peak, drop_end;
};
std::vector<Event> detect_events(const std::vector<double>& f, double delta, std::size_t window,
                                 std::size_t confirm = 0, double confirm_fraction = 0.5);
// The same with a threshold per sample (the local noise level x drop_threshold).
std::vector<Event> detect_events(const std::vector<double>& f, const std::vector<double>& delta, std::size_t window,
                                 std::size_t confirm = 0, double confirm_fraction = 0.5);

// The noise level of x at every sample: noise_level over [k - half_width,
// k + half_width] (shrunk at the ends), evaluated every quarter half-width
// and interpolated linearly.
std::vector<double> local_noise_level(const std::vector<double>& x, std::size_t half_width);

// ---- the analysis of one pull-off ----------------------------------------

struct SpectrumScales {
  double d = 0.003;              // m, the unit of travel (mean grain diameter)
  double bed_height = 0.150;     // m, H_bed
  double paper_speed = 0.0012;   // m/s, V of the study
};

struct Band {
  std::string name;
  double low = 0.0, high = 0.0;     // m, heights [low, high)
  std::size_t begin = 0, end = 0;   // rows
  Psd psd;
  DominantPeak peak;
};

struct SpectrumResult {
  DragProfile profile;           // as analysed (a shorter last row dropped)
  std::size_t rows_dropped = 0;
  double height_step = 0.0;      // m, median
  double step_deviation = 0.0;   // largest relative deviation of a height step from the median
  double speed = 0.0;            // m/s, dH/dt
  std::vector<double> trend, fluctuation, envelope;  // N/m
  double noise = 0.0;            // N/m, sigma of the fluctuation in the second part
  std::vector<double> local_noise;  // N/m, sigma around each row (half the trend window each side): events' scale
  double drop_delta = 0.0;       // N/m, drop_threshold x sigma (the second part's; each drop is judged on
                                 // drop_threshold x local_noise)
  Ringing ringing;               // the bed's ringing, found in the second part's time spectrum
  double geometric_cutoff = kNaN;  // Hz: cutoff_fraction x a significant ringing's frequency (NaN: no cutoff)
  double min_period_d = kNaN;    // d: the dominant-period search's lower bound: psd.min_period_d, raised to
                                 // V / (geometric_cutoff d) so that no searched period lies in the ringing
  Band second_part;              // [bottom_top, upper_top) H_bed: the loading/rupture regime
  std::vector<Band> bands;       // bottom, middle, upper, top_layer
  std::vector<Event> events;     // over the whole profile
  std::vector<double> spacing_d; // consecutive event peaks both in the second part (d)
  // the rupture catalogue: per event, the load it carried (the trend at its peak,
  // N/m) and whether the paper would count it (drop >= min_relative_drop x load)
  std::vector<double> event_load;
  std::vector<std::uint8_t> counted;
  std::vector<double> rupture_spacing_d;  // consecutive counted ruptures both in the second part (d)
  SizeDistribution sizes;           // drops (N/m) of the events in the second part
  SizeDistribution relative_sizes;  // their drop / load
  LinearFit amplitude_fit;       // event drop (N/m) against peak height (mm), upper part
  LinearFit envelope_fit;        // envelope (N/m) against height (mm), upper part
  // bottom zone: rows of the first high peak, the collapse and the next peak (npos if none)
  std::size_t bottom_peak = npos, bottom_collapse = npos, bottom_reload = npos;
  // top layer: the change point of the fluctuations' variance (top_layer.hpp)
  TopLayerFit top;               // its outcome: found, none (a miss with power), undetermined (a miss without)
  TopLayerPower top_power;       // a miss's power (top_layer_power); empty when found
  bool top_found = false;        // top.found
  double top_height = kNaN;      // m, top.best.height when found
  // the envelope's definition (before the change point): the last height where
  // the envelope reaches floor_factor x sigma, less half a window
  bool envelope_top_found = false;  // false when the envelope is still above the floor at the end
  double envelope_top_height = kNaN;  // m
  std::size_t top_begin = 0, top_end = 0;  // rows of the depth fit
  LinearFit top_fit;             // drag (N/m) against depth H_bed - H (mm)
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
};

// Checks the profile (non-empty, finite, height increasing with uniform steps,
// long enough) and analyses it. Errors are SpectrumErrors starting with `source`.
// memo: top-layer searches already made on this profile (the same inputs give
// the same result; nullptr: none kept).
SpectrumResult analyse(const DragProfile& profile, const SpectrumScales& scales, const SpectrumConfig& config,
                       const std::string& source, TopLayerMemo* memo = nullptr);

// The "spectrum" metrics (without the sensitivity table). Lengths in mm, travel in d.
nlohmann::ordered_json spectrum_metrics(const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c,
                                        double intruder_depth);

// Median spacing (d) of consecutive events both in [low, high) and both
// kept by `keep`; NaN below two such events.
std::vector<double> spacings(const SpectrumResult& r, double low, double high, double d,
                             const std::vector<std::uint8_t>& keep);

// The key numbers again with one setting changed at a time (config.sensitivity).
nlohmann::ordered_json sensitivity_table(const DragProfile& profile, const SpectrumScales& scales,
                                         const SpectrumConfig& config, const std::string& source,
                                         TopLayerMemo* memo = nullptr);

}  // namespace dem2d::analysis
