#include "planted/drag_signal.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace dem2d::planted {

namespace {

// The typical event size at height h (N/m).
double typical_size(const DragScenario& s, double h) {
  if (h >= s.bed_height) return 0.0;
  switch (s.amplitude) {
    case Amplitude::load: return s.fraction * load_at(s, h);
    case Amplitude::abrupt: return h < s.top ? s.fraction * load_at(s, h) : 0.0;
    case Amplitude::fade: {
      if (h >= s.top) return 0.0;
      const double h0 = s.top - s.fade_length;
      return h < h0 ? s.fraction * load_at(s, h) : s.fraction * load_at(s, h0) * (s.top - h) / s.fade_length;
    }
    case Amplitude::constant: return s.fraction * load_at(s, 0.1 * s.bed_height);
    case Amplitude::none: return 0.0;
  }
  return 0.0;
}

// A size around `typical` drawn from the scenario's distribution.
double draw_size(const DragScenario& s, double typical, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  switch (s.sizes) {
    case Sizes::fixed: return typical;
    case Sizes::exponential: return -typical * std::log(1.0 - u(rng));
    case Sizes::lognormal: return typical * std::exp(s.size_shape * std::normal_distribution<double>(0.0, 1.0)(rng));
    case Sizes::power_law: return typical * std::pow(1.0 - u(rng), -1.0 / (s.size_shape - 1.0));
    case Sizes::power_law_body:
      if (u(rng) < 0.5) return typical * (0.2 + 0.8 * u(rng));
      return typical * std::pow(1.0 - u(rng), -1.0 / (s.size_shape - 1.0));
  }
  return typical;
}

// Sawtooth events at heights from `from` on, spaced spacing_d (with jitter):
// each loads linearly from the previous drop to its peak, then drops by its
// size within one row. Adds to f; records the peaks.
void add_sawtooth(const DragScenario& s, double spacing_d, double jitter, bool main_events, std::vector<double>& f,
                  const std::vector<double>& h, std::mt19937_64& rng, PlantedDrag* out) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> peaks, sizes;
  for (double y = s.event_from + spacing_d * s.d; y < s.bed_height; y += spacing_d * s.d * (1.0 + jitter * u(rng))) {
    const double typical = main_events ? typical_size(s, y) : s.slip_fraction * load_at(s, y);
    if (typical <= 0.0) continue;
    peaks.push_back(y);
    sizes.push_back(draw_size(s, typical, rng));
  }
  // each event: a rise of `size` over the travel since the previous peak, then the drop
  std::size_t e = 0;
  double previous = s.event_from;
  for (std::size_t k = 0; k < h.size(); ++k) {
    while (e < peaks.size() && h[k] >= peaks[e]) previous = peaks[e++];
    if (e >= peaks.size()) break;
    if (h[k] < s.event_from) continue;
    const double phase = (h[k] - previous) / (peaks[e] - previous);  // 0 after a drop, 1 at the peak
    f[k] += sizes[e] * phase;  // a rise by the size, then a drop by it
  }
  if (out)
    for (std::size_t i = 0; i < peaks.size(); ++i) out->event_height.push_back(peaks[i]), out->event_size.push_back(sizes[i]);
}

// A unit white-noise sample: Gaussian (nu = 0), or Student-t with nu = 1, 2
// or 3 degrees of freedom scaled so that its median absolute value (the t's
// upper quartile) is the Gaussian's, 0.6745.
double white_noise(double nu, std::mt19937_64& rng) {
  if (nu <= 0.0) return std::normal_distribution<double>(0.0, 1.0)(rng);
  if (nu != 1.0 && nu != 2.0 && nu != 3.0) throw std::invalid_argument("tails_nu must be 0, 1, 2 or 3");
  const double quartile = nu == 1.0 ? 1.0 : nu == 2.0 ? std::sqrt(2.0 / 3.0) : 0.7648923284;
  return std::student_t_distribution<double>(nu)(rng) * 0.6744897502 / quartile;
}

}  // namespace

double load_at(const DragScenario& s, double h) {
  if (h >= s.bed_height) return s.carried;
  return s.peak_load * std::exp(-h / s.relax) + s.slope * (s.bed_height - h) + s.carried;
}

PlantedDrag make_drag(const DragScenario& s) {
  PlantedDrag out;
  analysis::DragProfile& p = out.profile;
  std::mt19937_64 rng(s.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const std::size_t n = static_cast<std::size_t>((s.end - s.start) / (s.speed * s.row_s));
  std::vector<double> f(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    p.time.push_back(static_cast<double>(k) * s.row_s);
    p.height.push_back(s.start + s.speed * p.time.back());
  }
  if (s.amplitude != Amplitude::none) add_sawtooth(s, s.spacing_d, s.jitter, true, f, p.height, rng, &out);
  if (s.slip_fraction > 0.0) add_sawtooth(s, s.slip_spacing_d, 0.5, false, f, p.height, rng, nullptr);
  // AR(1) background with correlation length correlation_d (in rows: samples of d)
  const double rows_per_d = s.d / (s.speed * s.row_s);
  const double phi = std::exp(-1.0 / std::max(1e-9, s.correlation_d * rows_per_d));
  double ar = gauss(rng) * s.correlated, ar_relative = gauss(rng);
  for (std::size_t k = 0; k < n; ++k) {
    ar = phi * ar + std::sqrt(1.0 - phi * phi) * s.correlated * gauss(rng);
    ar_relative = phi * ar_relative + std::sqrt(1.0 - phi * phi) * gauss(rng);
    const double load = load_at(s, p.height[k]);
    p.drag.push_back(load + f[k] + (s.white + s.white_relative * load) * white_noise(s.tails_nu, rng) + ar +
                     s.correlated_relative * load * ar_relative);
  }
  return out;
}

}  // namespace dem2d::planted
