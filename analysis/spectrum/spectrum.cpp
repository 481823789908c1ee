#include "spectrum/spectrum.hpp"

#include "common/fftw_lock.hpp"
#include "common/normal.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>
#include <sstream>

namespace dem2d::analysis {

namespace {

constexpr double kPi = 3.14159265358979323846;

double dbl(std::size_t n) { return static_cast<double>(n); }
std::size_t samples(double travel_d, double samples_per_d) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(travel_d * samples_per_d)));
}

// Linear-interpolated quantile q in [0, 1]; NaN for an empty set.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * dbl(v.size() - 1);
  const auto i = static_cast<std::size_t>(pos);
  return i + 1 < v.size() ? v[i] + (pos - dbl(i)) * (v[i + 1] - v[i]) : v[i];
}
double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

std::string num(double v, const char* unit = "") {
  std::ostringstream s;
  s << v << unit;
  return s.str();
}
std::string mm(double m) { return num(1e3 * m, " mm"); }

// A real-to-complex FFTW plan of size n with its own aligned buffers.
class RealFft {
 public:
  explicit RealFft(std::size_t n) : n_(n), in_(fftw_alloc_real(n)), out_(fftw_alloc_complex(n / 2 + 1)) {
    {
      const std::lock_guard<std::mutex> lock(fftw_planner_lock());
      plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(n), in_, out_, FFTW_ESTIMATE);
    }
    if (!in_ || !out_ || !plan_) throw std::runtime_error("FFTW: cannot plan a transform of size " + std::to_string(n));
  }
  ~RealFft() {
    {
      const std::lock_guard<std::mutex> lock(fftw_planner_lock());
      fftw_destroy_plan(plan_);
    }
    fftw_free(in_);
    fftw_free(out_);
  }
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  double* input() { return in_; }
  // |X_j|^2 added to acc[j], j = 0 .. n/2
  void add_power(std::vector<double>& acc) {
    fftw_execute(plan_);
    for (std::size_t j = 0; j <= n_ / 2; ++j) acc[j] += out_[j][0] * out_[j][0] + out_[j][1] * out_[j][1];
  }

 private:
  std::size_t n_;
  double* in_;
  fftw_complex* out_;
  fftw_plan plan_ = nullptr;
};

// Periodic (DFT-even) windows.
std::vector<double> window_values(std::size_t n, const std::string& kind) {
  std::vector<double> w(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * dbl(i) / dbl(n);
    if (kind == "hann") w[i] = 0.5 - 0.5 * std::cos(a);
    if (kind == "hamming") w[i] = 0.54 - 0.46 * std::cos(a);
    if (kind == "blackman") w[i] = 0.42 - 0.5 * std::cos(a) + 0.08 * std::cos(2.0 * a);
  }
  return w;
}

double digamma(double x) {
  double r = 0.0;
  for (; x < 6.0; x += 1.0) r -= 1.0 / x;
  const double f = 1.0 / (x * x);
  return r + std::log(x) - 0.5 / x - f * (1.0 / 12 - f * (1.0 / 120 - f / 252));
}

// x with P(chi2_nu > x) = p (Wilson-Hilferty; conservative by a few % at nu = 2 in the far tail).
double chi2_upper_quantile(double p, double nu) {
  const double a = 2.0 / (9.0 * nu);
  return nu * std::pow(std::max(0.0, 1.0 - a + normal_upper_quantile(p) * std::sqrt(a)), 3.0);
}

// Rows whose height lies in [low, high) (height increasing).
std::pair<std::size_t, std::size_t> rows_between(const std::vector<double>& h, double low, double high) {
  const auto b = std::lower_bound(h.begin(), h.end(), low), e = std::lower_bound(h.begin(), h.end(), high);
  return {static_cast<std::size_t>(b - h.begin()), static_cast<std::size_t>(std::max(b, e) - h.begin())};
}

// f falls by more than delta within `window` samples somewhere in [p, t].
// f falls by more than delta[j] within `window` samples from some j in [p, t].
bool falls_fast(const std::vector<double>& f, std::size_t p, std::size_t t, const std::vector<double>& delta,
                std::size_t window) {
  for (std::size_t j = p; j < t; ++j) {
    const auto last = f.begin() + static_cast<std::ptrdiff_t>(std::min(j + window, t)) + 1;
    if (f[j] - *std::min_element(f.begin() + static_cast<std::ptrdiff_t>(j) + 1, last) > delta[j]) return true;
  }
  return false;
}

[[noreturn]] void bad_profile(const std::string& source, const std::string& what) {
  throw SpectrumError(source + ": " + what);
}

// The profile checked; a last row covering a shorter interval (the run stopped
// inside it) is dropped. Sets rows_dropped, height_step, step_deviation.
DragProfile checked_profile(const DragProfile& in, double tolerance, const std::string& source, SpectrumResult& r) {
  const std::size_t n = in.height.size();
  if (n == 0) bad_profile(source, "the drag profile is empty");
  if (in.time.size() != n || in.drag.size() != n) bad_profile(source, "the drag profile's columns differ in length");
  if (n < 8) bad_profile(source, "the drag profile is too short: " + std::to_string(n) + " rows");
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(in.time[k]) || !std::isfinite(in.height[k]) || !std::isfinite(in.drag[k]))
      bad_profile(source, "row " + std::to_string(k) + " is not finite (time, height, drag = " + num(in.time[k]) +
                              " s, " + num(in.height[k]) + " m, " + num(in.drag[k]) + " N/m)");
  for (std::size_t k = 1; k < n; ++k)
    if (!(in.height[k] > in.height[k - 1]) || !(in.time[k] > in.time[k - 1]))
      bad_profile(source, "the intruder height (or time) does not increase at row " + std::to_string(k) + ": " +
                              mm(in.height[k - 1]) + " then " + mm(in.height[k]));
  DragProfile p = in;
  // The series is uniform in time and the intruder moves at constant V: the
  // steps of time and of height must both be uniform.
  for (const std::vector<double>* x : {&in.time, &in.height}) {
    std::vector<double> step(n - 1);
    for (std::size_t k = 1; k < n; ++k) step[k - 1] = (*x)[k] - (*x)[k - 1];
    const double typical = median(step);
    const char* unit = x == &in.time ? " s" : " m";
    if (step.back() < (1.0 - tolerance) * typical && p.time.size() == n) {
      for (auto* col : {&p.time, &p.height, &p.drag}) col->pop_back();
      r.rows_dropped = 1;
    }
    double worst = 0.0;
    for (std::size_t k = 0; k + 1 < p.time.size(); ++k) {
      const double dev = std::abs(step[k] / typical - 1.0);
      if (dev > tolerance)
        bad_profile(source, std::string("the series is not uniform in ") + (x == &in.time ? "time" : "height") +
                                ": step " + std::to_string(k + 1) + " is " + num(step[k], unit) +
                                ", the median step " + num(typical, unit) +
                                " (profile.uniform_tolerance = " + num(tolerance) + ")");
      worst = std::max(worst, dev);
    }
    if (x == &in.height) r.height_step = typical, r.step_deviation = worst;
  }
  return p;
}

std::size_t argmax(const std::vector<double>& x, std::size_t b, std::size_t e) {
  return static_cast<std::size_t>(std::max_element(x.begin() + static_cast<std::ptrdiff_t>(b),
                                                   x.begin() + static_cast<std::ptrdiff_t>(e)) - x.begin());
}
std::size_t argmin(const std::vector<double>& x, std::size_t b, std::size_t e) {
  return static_cast<std::size_t>(std::min_element(x.begin() + static_cast<std::ptrdiff_t>(b),
                                                   x.begin() + static_cast<std::ptrdiff_t>(e)) - x.begin());
}

Band make_band(const std::string& name, double low, double high, const SpectrumResult& r, double samples_per_d,
               const SpectrumConfig& c) {
  Band b{name, low, high, 0, 0, {}, {}};
  std::tie(b.begin, b.end) = rows_between(r.profile.height, low, high);
  const std::vector<double> x(r.fluctuation.begin() + static_cast<std::ptrdiff_t>(b.begin),
                              r.fluctuation.begin() + static_cast<std::ptrdiff_t>(b.end));
  b.psd = welch_psd(x, samples_per_d, std::min(samples(c.segment_d, samples_per_d), x.size()), c.overlap, c.window);
  b.peak = dominant_peak(b.psd, 1.0 / c.max_period_d, 1.0 / r.min_period_d, c.false_alarm);
  return b;
}

}  // namespace

// ---- building blocks ----------------------------------------------------

std::vector<double> running_median(const std::vector<double>& x, std::size_t half_width) {
  const std::size_t n = x.size();
  std::vector<double> out(n), buf;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t w = std::min({half_width, k, n - 1 - k});
    buf.assign(x.begin() + static_cast<std::ptrdiff_t>(k - w), x.begin() + static_cast<std::ptrdiff_t>(k + w + 1));
    std::nth_element(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(w), buf.end());
    out[k] = buf[w];
  }
  return out;
}

std::vector<double> running_rms(const std::vector<double>& x, std::size_t half_width) {
  const std::size_t n = x.size();
  std::vector<double> sum(n + 1, 0.0), out(n);
  for (std::size_t k = 0; k < n; ++k) sum[k + 1] = sum[k] + x[k] * x[k];
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t w = std::min({half_width, k, n - 1 - k});
    out[k] = std::sqrt(std::max(0.0, (sum[k + w + 1] - sum[k - w]) / dbl(2 * w + 1)));
  }
  return out;
}

double noise_level(const std::vector<double>& x, std::size_t begin, std::size_t end) {
  if (end > x.size() || end < begin + 3) return kNaN;
  std::vector<double> diff;
  for (std::size_t k = begin + 1; k < end; ++k) diff.push_back(x[k] - x[k - 1]);
  const double m = median(diff);
  for (double& v : diff) v = std::abs(v - m);
  return 1.4826 * median(diff) / std::sqrt(2.0);
}

LinearFit linear_fit(const std::vector<double>& x, const std::vector<double>& y) {
  LinearFit f;
  f.points = x.size();
  if (x.size() < 3 || y.size() != x.size()) return f;
  const double n = dbl(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n, my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0.0) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0.0 ? sxy * sxy / (sxx * syy) : kNaN;
  return f;
}

Psd welch_psd(const std::vector<double>& x, double sample_rate, std::size_t n, double overlap,
              const std::string& window) {
  Psd p;
  if (n < 4 || x.size() < n) return p;
  const std::size_t shift = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(dbl(n) * (1.0 - overlap))));
  const std::size_t segments = 1 + (x.size() - n) / shift;
  const std::vector<double> w = window_values(n, window);
  const double w2 = std::inner_product(w.begin(), w.end(), w.begin(), 0.0);
  RealFft fft(n);
  std::vector<double> acc(n / 2 + 1, 0.0);
  for (std::size_t s = 0; s < segments; ++s) {
    const double* seg = x.data() + s * shift;
    const double mean = std::accumulate(seg, seg + n, 0.0) / dbl(n);
    for (std::size_t i = 0; i < n; ++i) fft.input()[i] = (seg[i] - mean) * w[i];
    fft.add_power(acc);
  }
  const double scale = 1.0 / (dbl(segments) * sample_rate * w2);
  for (std::size_t j = 1; j <= n / 2; ++j) {
    p.frequency.push_back(dbl(j) * sample_rate / dbl(n));
    p.power.push_back((2 * j == n ? 1.0 : 2.0) * acc[j] * scale);
  }
  // Equivalent degrees of freedom (Welch 1967): 2K / (1 + 2 sum_j (1 - j/K) rho(j shift)^2).
  double corr = 0.0;
  for (std::size_t j = 1; j < segments && j * shift < n; ++j) {
    double rho = 0.0;
    for (std::size_t i = 0; i + j * shift < n; ++i) rho += w[i] * w[i + j * shift];
    corr += (1.0 - dbl(j) / dbl(segments)) * (rho / w2) * (rho / w2);
  }
  p.segments = segments;
  p.segment_samples = n;
  p.dof = 2.0 * dbl(segments) / (1.0 + 2.0 * corr);
  return p;
}

DominantPeak dominant_peak(const Psd& psd, double low, double high, double false_alarm) {
  DominantPeak r;
  const auto& k = psd.frequency;
  const std::size_t j0 = static_cast<std::size_t>(std::lower_bound(k.begin(), k.end(), low) - k.begin());
  const std::size_t j1 = static_cast<std::size_t>(std::upper_bound(k.begin(), k.end(), high) - k.begin());
  if (j1 < j0 + 3) return r;
  r.found = true;
  r.bins = j1 - j0;
  // Power-law background: least squares of ln P on ln k (a tiny floor keeps
  // exact zeros of noise-free signals finite), shifted by the mean of
  // ln(chi2_nu / nu) = digamma(nu/2) - ln(nu/2) so that it is a mean level.
  const double top = *std::max_element(psd.power.begin() + static_cast<std::ptrdiff_t>(j0),
                                       psd.power.begin() + static_cast<std::ptrdiff_t>(j1));
  std::vector<double> lx, ly, power;
  for (std::size_t j = j0; j < j1; ++j) {
    power.push_back(std::max(psd.power[j], 1e-12 * top));
    lx.push_back(std::log(k[j]));
    ly.push_back(std::log(power.back()));
  }
  const LinearFit bg = linear_fit(lx, ly);
  r.background_exponent = bg.slope;
  const double bias = digamma(psd.dof / 2.0) - std::log(psd.dof / 2.0);
  std::vector<double> excess(r.bins);
  for (std::size_t i = 0; i < r.bins; ++i) excess[i] = power[i] / std::exp(bg.intercept + bg.slope * lx[i] - bias);
  const std::size_t m = argmax(excess, 0, r.bins);
  const double dk = k[j0 + 1] - k[j0];
  double shift = 0.0;
  r.at_edge = m == 0 || m + 1 == r.bins;
  if (!r.at_edge) {
    const double a = std::log(excess[m - 1]), b = std::log(excess[m]), c = std::log(excess[m + 1]);
    if (a - 2.0 * b + c < 0.0) shift = std::clamp(0.5 * (a - c) / (a - 2.0 * b + c), -0.5, 0.5);
  }
  r.frequency = k[j0 + m] + shift * dk;
  r.period = 1.0 / r.frequency;
  r.peak_to_background = excess[m];
  r.peak_to_median = power[m] / median(power);
  const double per_bin = -std::expm1(std::log1p(-false_alarm) / dbl(r.bins));
  r.threshold = chi2_upper_quantile(per_bin, psd.dof) / psd.dof;
  r.significant = !r.at_edge && r.peak_to_background > r.threshold;  // a maximum at the edge is no peak
  // Width where the excess stays above half its peak (linear between bins; the range's edge if it does not fall).
  const double half = 0.5 * excess[m];
  std::size_t lo = m, hi = m;
  while (lo > 0 && excess[lo - 1] > half) --lo;
  while (hi + 1 < r.bins && excess[hi + 1] > half) ++hi;
  const double k_lo = k[j0 + lo] - (lo > 0 ? (excess[lo] - half) / (excess[lo] - excess[lo - 1]) * dk : 0.0);
  const double k_hi = k[j0 + hi] + (hi + 1 < r.bins ? (excess[hi] - half) / (excess[hi] - excess[hi + 1]) * dk : 0.0);
  r.half_max_low = k_lo;
  r.half_max_high = k_hi;
  r.half_width = 0.5 * (1.0 / k_lo - 1.0 / k_hi);
  r.quality = r.frequency / (k_hi - k_lo);
  return r;
}

Ringing find_ringing(const std::vector<double>& x, double time_step, const SpectrumConfig& c) {
  Ringing g;
  g.nyquist = 0.5 / time_step;
  const double rate = 1.0 / time_step;
  g.psd = welch_psd(x, rate, std::min(samples(c.ringing_segment_s, rate), x.size()), c.overlap, c.window);
  g.peak = dominant_peak(g.psd, c.ringing_min_frequency_hz, g.nyquist, c.false_alarm);
  g.searched = g.peak.found;
  if (!g.searched) return g;
  double power = 0.0;
  for (std::size_t j = 0; j < g.psd.frequency.size(); ++j)
    if (g.psd.frequency[j] >= g.peak.half_max_low && g.psd.frequency[j] <= g.peak.half_max_high) power += g.psd.power[j];
  g.line_rms = std::sqrt(power * g.psd.frequency[0]);  // bins are 1/segment apart, from 1/segment on
  return g;
}

std::vector<Pivot> zigzag(const std::vector<double>& x, const std::vector<double>& delta, std::size_t begin) {
  std::vector<Pivot> out;
  enum class Dir { unknown, rising, falling } dir = Dir::unknown;
  std::size_t hi = begin, lo = begin;
  for (std::size_t k = begin + 1; k < x.size(); ++k) {
    if (dir != Dir::falling && x[k] > x[hi]) hi = k;
    if (dir != Dir::rising && x[k] < x[lo]) lo = k;
    if (dir != Dir::falling && x[hi] - x[k] > delta[hi]) {
      out.push_back({hi, true});
      dir = Dir::falling;
      lo = k;
    } else if (dir != Dir::rising && x[k] - x[lo] > delta[lo]) {
      out.push_back({lo, false});
      dir = Dir::rising;
      hi = k;
    }
  }
  if (dir == Dir::falling) out.push_back({lo, false});
  return out;
}

std::vector<Pivot> zigzag(const std::vector<double>& x, double delta, std::size_t begin) {
  return zigzag(x, std::vector<double>(x.size(), delta), begin);
}

std::vector<Event> detect_events(const std::vector<double>& f, const std::vector<double>& delta, std::size_t window,
                                 std::size_t confirm, double confirm_fraction) {
  const std::vector<Pivot> pivots = zigzag(f, delta);
  std::vector<Event> out;
  // the level of the rows a..b: their median (confirm + 1 rows: no lone spike moves it)
  auto level = [&f](std::size_t a, std::size_t b) {
    std::vector<double> v(f.begin() + static_cast<std::ptrdiff_t>(a), f.begin() + static_cast<std::ptrdiff_t>(b) + 1);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  for (std::size_t i = 0; i + 1 < pivots.size(); ++i) {
    const std::size_t p = pivots[i].index, t = pivots[i + 1].index;
    if (!pivots[i].peak || !falls_fast(f, p, t, delta, window)) continue;
    if (confirm > 0) {  // the lowest level reached after the peak, up to the trough
      double after = std::numeric_limits<double>::infinity();
      for (std::size_t j = p + 1; j <= t; ++j) after = std::min(after, level(j, std::min(f.size() - 1, j + confirm)));
      if (level(p >= confirm ? p - confirm : 0, p) - after <= confirm_fraction * delta[p])
        continue;  // a spike, not a drop: the level before and after differ by less than the threshold
    }
    out.push_back({i > 0 ? pivots[i - 1].index : argmin(f, 0, p + 1), p, t});
  }
  return out;
}

std::vector<Event> detect_events(const std::vector<double>& f, double delta, std::size_t window, std::size_t confirm,
                                 double confirm_fraction) {
  return detect_events(f, std::vector<double>(f.size(), delta), window, confirm, confirm_fraction);
}

std::vector<double> local_noise_level(const std::vector<double>& x, std::size_t half_width) {
  const std::size_t n = x.size(), step = std::max<std::size_t>(1, half_width / 4);
  std::vector<double> at, level;  // at rows 0, step, 2 step, ... and the last
  for (std::size_t k = 0;; k = std::min(n - 1, k + step)) {
    const std::size_t a = k > half_width ? k - half_width : 0, b = std::min(n, k + half_width + 1);
    at.push_back(static_cast<double>(k));
    level.push_back(noise_level(x, a, b));
    if (k == n - 1) break;
  }
  std::vector<double> out(n);
  for (std::size_t k = 0, q = 0; k < n; ++k) {
    while (q + 2 < at.size() && at[q + 1] < static_cast<double>(k)) ++q;
    const double u = at.size() < 2 ? 0.0 : std::clamp((static_cast<double>(k) - at[q]) / (at[q + 1] - at[q]), 0.0, 1.0);
    out[k] = at.size() < 2 ? level[0] : level[q] + u * (level[q + 1] - level[q]);
  }
  return out;
}

std::vector<double> spacings(const SpectrumResult& r, double low, double high, double d,
                             const std::vector<std::uint8_t>& keep) {
  const auto& h = r.profile.height;
  std::vector<double> out;
  std::size_t last = SpectrumResult::npos;
  for (std::size_t i = 0; i < r.events.size(); ++i) {
    const double y = h[r.events[i].peak];
    if (!keep[i] || y < low || y >= high) continue;
    if (last != SpectrumResult::npos) out.push_back((y - h[r.events[last].peak]) / d);
    last = i;
  }
  return out;
}

// ---- the analysis ---------------------------------------------------------

namespace {

// What every step of the analysis uses: the bed height, samples per d, the
// band edges (bottom, middle, upper, top layer) and where the profile came from.
struct Context {
  double hb = 0.0, fs = 0.0;  // (m), samples per d
  double edges[5] = {};       // (m)
  const std::string& source;
};

// The trend, the fluctuation about it and its running rms.
void detrend(SpectrumResult& r, const SpectrumConfig& c, const Context& f) {
  const DragProfile& p = r.profile;
  r.trend = running_median(p.drag, samples(0.5 * c.trend_window_d, f.fs));
  r.fluctuation.resize(p.drag.size());
  for (std::size_t k = 0; k < p.drag.size(); ++k) r.fluctuation[k] = p.drag[k] - r.trend[k];
  r.envelope = running_rms(r.fluctuation, samples(0.5 * c.envelope_window_d, f.fs));
}

// The ringing, against time in the loading/rupture part; a significant one
// bounds the geometric search: only wavelengths with V / wavelength <= cutoff.
// Then the second part's spectrum, the noise (global and local) and the bands.
void spectra(SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c, const Context& f) {
  const DragProfile& p = r.profile;
  const std::vector<double>& h = p.height;
  const auto [ring_begin, ring_end] = rows_between(h, f.edges[1], f.edges[3]);
  r.ringing = find_ringing({r.fluctuation.begin() + static_cast<std::ptrdiff_t>(ring_begin),
                            r.fluctuation.begin() + static_cast<std::ptrdiff_t>(ring_end)},
                           (p.time.back() - p.time.front()) / dbl(h.size() - 1), c);
  r.min_period_d = c.min_period_d;
  if (r.ringing.peak.significant) {
    r.geometric_cutoff = c.ringing_cutoff_fraction * r.ringing.peak.frequency;
    r.min_period_d = std::max(c.min_period_d, r.speed / (r.geometric_cutoff * s.d));
  }
  r.second_part = make_band("second_part", f.edges[1], f.edges[3], r, f.fs, c);
  const double span_d = dbl(r.second_part.end - r.second_part.begin) / f.fs;
  if (span_d < 2.0 * c.max_period_d)
    bad_profile(f.source, "the drag profile is too short: the loading/rupture part [" + mm(r.second_part.low) + ", " +
                              mm(r.second_part.high) + ") holds " + num(span_d) + " d of travel, fewer than 2 x psd.max_period_d");
  r.noise = noise_level(r.fluctuation, r.second_part.begin, r.second_part.end);
  if (!(r.noise > 0.0))
    bad_profile(f.source, "the fluctuations have no measurable noise (MAD of first differences = 0): "
                          "the noise-relative thresholds are undefined");
  // the noise follows the load (the bed's ringing grows with it: ~2 % of it in
  // the study's runs), so a drop is judged against the noise where it happens
  r.local_noise = local_noise_level(r.fluctuation, samples(0.5 * c.trend_window_d, f.fs));
  for (double& v : r.local_noise) v = std::max(v, 1e-3 * r.noise);
  r.drop_delta = c.drop_threshold * r.noise;
  const char* names[] = {"bottom", "middle", "upper", "top_layer"};
  for (std::size_t b = 0; b < 4; ++b) r.bands.push_back(make_band(names[b], f.edges[b], f.edges[b + 1], r, f.fs, c));
}

// Events, their spacing in the second part, and their amplitude in the upper
// part; the rupture catalogue: the load each event carried, which the paper
// counts, the size distributions.
void ruptures(SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c, const Context& f) {
  const DragProfile& p = r.profile;
  const std::vector<double>& h = p.height;
  std::vector<double> delta(h.size());
  for (std::size_t k = 0; k < h.size(); ++k) delta[k] = c.drop_threshold * r.local_noise[k];
  r.events = detect_events(r.fluctuation, delta, samples(c.drop_window_d, f.fs),
                           static_cast<std::size_t>(c.confirm_samples), c.confirm_fraction);
  const auto inside = [&h](const Event& e, double low, double high) { return h[e.peak] >= low && h[e.peak] < high; };
  std::vector<double> amp_x, amp_y, drops, relative;
  for (const Event& e : r.events) {
    const double load = r.trend[e.peak], drop = p.drag[e.peak] - p.drag[e.drop_end];
    r.event_load.push_back(load);
    r.counted.push_back(load > 0.0 && drop >= c.min_relative_drop * load ? 1 : 0);
    if (inside(e, f.edges[1], f.edges[3])) {
      drops.push_back(drop);
      if (load > 0.0) relative.push_back(drop / load);
    }
    if (inside(e, f.edges[2], f.edges[3])) {
      amp_x.push_back(1e3 * h[e.peak]);
      amp_y.push_back(drop);
    }
  }
  r.spacing_d = spacings(r, f.edges[1], f.edges[3], s.d, std::vector<std::uint8_t>(r.events.size(), 1));
  r.rupture_spacing_d = spacings(r, f.edges[1], f.edges[3], s.d, r.counted);
  const SizeFitSettings sizes{static_cast<std::size_t>(c.size_min_tail), c.size_bootstrap, c.size_significance, 1,
                              c.size_min_decades, c.size_plausible_p};
  r.sizes = fit_sizes(drops, sizes);
  r.relative_sizes = fit_sizes(relative, sizes);
  r.amplitude_fit = linear_fit(amp_x, amp_y);
  const Band& upper = r.bands[2];
  std::vector<double> env_x, env_y;
  for (std::size_t k = upper.begin; k < upper.end; ++k) env_x.push_back(1e3 * h[k]), env_y.push_back(r.envelope[k]);
  r.envelope_fit = linear_fit(env_x, env_y);
}

// Bottom zone: the first high peak, the collapse after it, the next loading.
void bottom_zone(SpectrumResult& r, const SpectrumConfig& c) {
  const DragProfile& p = r.profile;
  const Band& bottom = r.bands[0];
  if (bottom.end <= bottom.begin) return;
  r.bottom_peak = argmax(p.drag, bottom.begin, bottom.end);
  const auto pivots = zigzag(p.drag, c.collapse_fraction * std::abs(p.drag[r.bottom_peak]), r.bottom_peak);
  const auto trough = std::find_if(pivots.begin(), pivots.end(), [](const Pivot& v) { return !v.peak; });
  if (trough != pivots.end()) {
    r.bottom_collapse = trough->index;
    if (trough + 1 != pivots.end()) r.bottom_reload = (trough + 1)->index;
  }
}

// Top layer: the change point of the fluctuations' variance, with its
// interval; and the envelope's definition, kept beside it: above the last
// height where the envelope reaches the noise floor.
void top_layer(SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c, const Context& f,
               TopLayerMemo& memo) {
  const DragProfile& p = r.profile;
  const std::vector<double>& h = p.height;
  const std::size_t n = h.size();
  const TopLayerSearch search{c.search_from_fraction * f.hb, f.hb - c.search_margin_d * s.d, samples(c.block_d, f.fs),
                              c.top_bootstrap, c.top_confidence, c.top_false_alarm, 1};
  r.top = memo.find(h, r.fluctuation, r.trend, search);
  r.top_found = r.top.found;
  if (r.top.searched && !r.top.found && r.top.outcome != "reaches the surface") {
    // a miss: is it evidence of absence? The power to find a layer of the
    // claimed depth planted into this run's own fluctuations, quiet above it:
    // Gaussian noise of power_noise_factor x the local noise level (from
    // first differences: the white part; the factor stands for a correlated
    // part that differences do not see)
    if (c.power_replicas > 0) {
      std::vector<double> quiet(n), planted;
      for (std::size_t k = 0; k < n; ++k) quiet[k] = c.power_noise_factor * r.local_noise[k];
      for (const double fr : c.power_depth_fractions) planted.push_back(f.hb * (1.0 - fr));
      TopLayerSearch ps = search;
      ps.bootstrap = c.power_bootstrap;
      r.top_power = memo.power(h, r.fluctuation, r.trend, quiet, ps, planted, c.power_replicas,
                               c.power_tolerance_d * s.d);
    }
    r.top.outcome = r.top_power.power >= c.min_power ? "none" : "undetermined";
  }
  if (r.top_found) {
    r.top_height = r.top.best.height;
    std::tie(r.top_begin, r.top_end) = rows_between(h, r.top_height, f.hb - c.fit_margin_d * s.d);
    std::vector<double> depth, drag;
    for (std::size_t k = r.top_begin; k < r.top_end; ++k) depth.push_back(1e3 * (f.hb - h[k])), drag.push_back(p.drag[k]);
    r.top_fit = linear_fit(depth, drag);
  }
  const double floor = c.floor_factor * r.noise;
  std::size_t above = 0;  // rows up to the last one at or above the floor
  for (std::size_t k = n; k-- > 0 && above == 0;)
    if (r.envelope[k] >= floor) above = k + 1;
  r.envelope_top_found = above < n;
  // the window centred on the last row above the floor just reaches the
  // fluctuating part: that part ends half a window lower
  const std::size_t env_half = samples(0.5 * c.envelope_window_d, f.fs);
  if (r.envelope_top_found)
    r.envelope_top_height = above == 0 ? h.front() : std::max(h.front(), h[above - 1] - dbl(env_half) * r.height_step);
}

}  // namespace

SpectrumResult analyse(const DragProfile& profile, const SpectrumScales& s, const SpectrumConfig& c,
                       const std::string& source, TopLayerMemo* memo) {
  check_spectrum_config(c, source + " (config)");
  SpectrumResult r;
  r.profile = checked_profile(profile, c.uniform_tolerance, source, r);
  const std::vector<double>& h = r.profile.height;
  const double hb = s.bed_height;
  const Context f{hb, s.d / r.height_step, {0.0, c.bottom_top * hb, c.middle_top * hb, c.upper_top * hb, hb}, source};
  r.speed = (h.back() - h.front()) / (r.profile.time.back() - r.profile.time.front());
  if (!(hb > h.front())) bad_profile(source, "the bed height " + mm(hb) + " is not above the first height " + mm(h.front()));
  if (c.min_period_d * f.fs < 2.0)
    bad_profile(source, "psd.min_period_d = " + num(c.min_period_d) +
                            " d is shorter than two height steps: the series is too coarse");
  detrend(r, c, f);
  spectra(r, s, c, f);
  ruptures(r, s, c, f);
  bottom_zone(r, c);
  TopLayerMemo own;
  top_layer(r, s, c, f, memo ? *memo : own);
  return r;
}

// ---- metrics ----------------------------------------------------------------

namespace {

using Json = nlohmann::ordered_json;

double at_speed(double period_d, double d, double v) { return v / (period_d * d); }

Json peak_json(const Band& b, const SpectrumScales& s, const SpectrumResult& r) {
  const DominantPeak& k = b.peak;
  const double run_speed = r.speed;
  return {{"range_mm", {1e3 * b.low, 1e3 * b.high}},
          {"travel_d", dbl(b.end - b.begin) * r.height_step / s.d},
          {"found", k.found},
          {"dominant_period_d", k.period},
          {"dominant_period_mm", 1e3 * k.period * s.d},
          {"frequency_hz_at_run_v", at_speed(k.period, s.d, run_speed)},
          {"frequency_hz_at_paper_v", at_speed(k.period, s.d, s.paper_speed)},
          {"significant", k.significant},
          {"peak_to_background", k.peak_to_background},
          {"significance_threshold", k.threshold},
          {"peak_to_median", k.peak_to_median},
          {"background_exponent", k.background_exponent},
          {"half_width_d", k.half_width},
          {"quality_factor", k.quality},
          {"at_range_edge", k.at_edge},
          {"segments", b.psd.segments},
          {"segment_d", dbl(b.psd.segment_samples) * r.height_step / s.d},
          {"dof", b.psd.dof},
          {"bins_searched", k.bins}};
}

Json ringing_json(const SpectrumResult& r, const SpectrumConfig& c) {
  const Ringing& g = r.ringing;
  const DominantPeak& k = g.peak;
  const std::string note =
      !g.searched      ? "fewer than 3 bins between min_frequency_hz and the Nyquist frequency; no cutoff on the geometric search"
      : !k.significant ? "no significant peak in the band; no cutoff on the geometric search"
                       : "significant: the geometric search keeps wavelengths with V / wavelength <= geometric_cutoff_hz "
                         "(a line above nyquist_hz appears folded below it: frequency_hz may be such an alias)";
  return {{"band_hz", {c.ringing_min_frequency_hz, g.nyquist}},
          {"nyquist_hz", g.nyquist},
          {"searched", g.searched},
          {"frequency_hz", k.frequency},
          {"period_s", k.period},
          {"significant", k.significant},
          {"peak_to_background", k.peak_to_background},
          {"significance_threshold", k.threshold},
          {"peak_to_median", k.peak_to_median},
          {"background_exponent", k.background_exponent},
          {"half_width_hz", 0.5 * (k.half_max_high - k.half_max_low)},
          {"quality_factor", k.quality},
          {"at_band_edge", k.at_edge},
          {"line_rms_N_per_m", g.line_rms},
          {"segments", g.psd.segments},
          {"segment_s", 0.5 * dbl(g.psd.segment_samples) / g.nyquist},
          {"dof", g.psd.dof},
          {"bins_searched", k.bins},
          {"cutoff_fraction", c.ringing_cutoff_fraction},
          {"geometric_cutoff_hz", r.geometric_cutoff},
          {"note", note}};
}

Json stats_json(const std::vector<double>& v) {
  const double mean = v.empty() ? kNaN : std::accumulate(v.begin(), v.end(), 0.0) / dbl(v.size());
  return {{"count", v.size()}, {"mean", mean}, {"median", median(v)}, {"q1", quantile(v, 0.25)}, {"q3", quantile(v, 0.75)}};
}


Json sizes_json(const SizeDistribution& z) {
  // the same keys whatever the fit (null where it does not apply): an
  // ensemble's members are compared key by key
  auto family = [](const FamilyFit& f, const std::string& name) -> Json {
    Json j = {{"log_likelihood", f.log_likelihood}, {"ks", f.ks}};
    if (name == "power_law") j["alpha"] = f.alpha;
    if (name == "lognormal") j["mu"] = f.mu, j["sigma"] = f.sigma;
    if (name == "exponential") j["lambda"] = f.lambda;
    return j;
  };
  Json j = {{"sizes", z.n}, {"fitted", z.fitted}};
  j["x_min"] = z.x_min;
  j["tail"] = z.tail;
  j["power_law"] = family(z.power_law, "power_law");
  j["power_law"]["p_value"] = z.power_law_p;
  j["lognormal"] = family(z.lognormal, "lognormal");
  j["exponential"] = family(z.exponential, "exponential");
  j["likelihood_ratios"] = Json::array();
  for (const Comparison& c : z.comparisons)
    j["likelihood_ratios"].push_back({{"a", c.a}, {"b", c.b}, {"ratio", c.ratio}, {"normalised", c.normalised},
                                      {"p", c.p}, {"favoured", c.favoured}});
  j["best"] = z.fitted ? z.best : "not fitted";
  j["tail_decades"] = z.decades;
  j["power_law_plausible"] = z.power_law_plausible;
  const bool undecided = z.fitted && z.best == "undecided";
  j["leading"] = undecided ? z.leading : "";
  j["tail_needed"] = undecided ? z.tail_needed : kNaN;
  j["decision"] = !undecided ? z.best
                  : std::isfinite(z.tail_needed) && z.tail_needed > static_cast<double>(z.tail)
                      ? "not decidable with " + std::to_string(z.tail) + " sizes in the tail: about " +
                            std::to_string(static_cast<long long>(std::ceil(z.tail_needed))) + " needed"
                      : "not decidable with " + std::to_string(z.tail) + " sizes in the tail";
  return j;
}

// A miss's power; the same keys when the layer was found or the power not
// estimated (null values): an ensemble's members are compared key by key.
Json power_json(const TopLayerPower& p, const SpectrumScales& s, const SpectrumConfig& c) {
  Json depths = Json::array(), found = Json::array();
  for (std::size_t i = 0; i < p.height.size(); ++i)
    depths.push_back(1e3 * (s.bed_height - p.height[i])), found.push_back(p.found_fraction[i]);
  return {{"power", p.power},
          {"min_power", c.min_power},
          {"planted_depth_mm", depths},
          {"found_fraction", found},
          {"replicas", p.replicas},
          {"tolerance_mm", 1e3 * p.tolerance},
          {"what", "fraction of plantings found: the run's fluctuations with a top layer planted at each depth "
                   "(its own noise above it), run through the same detector; null when a layer was found"}};
}

Json top_layer_json(const TopLayerFit& t, const SpectrumScales& s) {
  auto mm_or_nan = [](double m) { return 1e3 * m; };
  auto model = [&](const TopLayerModelFit& f) -> Json {
    return {{"height_mm", mm_or_nan(f.height)}, {"background_N_per_m", std::sqrt(f.background)},
            {"amplitude_at_top", f.c0}, {"slope_per_mm_of_depth", 1e-3 * f.c1},
            {"noise_over_load", std::sqrt(f.noise)}, {"residual", f.residual}};
  };
  return {{"outcome", t.outcome},
          {"p_value", t.p_value},
          {"residual_saved", t.statistic},
          {"null_model", t.null_model},
          {"model", t.model},
          {"height_mm", mm_or_nan(t.best.height)},
          {"interval_mm", {mm_or_nan(t.low), mm_or_nan(t.high)}},
          {"depth_interval_mm", {1e3 * (s.bed_height - t.high), 1e3 * (s.bed_height - t.low)}},
          {"blocks", t.block_height.size()},
          {"relative", model(t.relative)},
          {"absolute", model(t.absolute)}};
}

Json spacing_by_threshold(const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c) {
  const double low = c.bottom_top * s.bed_height, high = c.upper_top * s.bed_height;
  const auto& drag = r.profile.drag;
  auto row = [&](double value, const std::vector<std::uint8_t>& keep) -> Json {
    const std::vector<double> sp = spacings(r, low, high, s.d, keep);
    return {{"threshold", value},
            {"events", std::count(keep.begin(), keep.end(), std::uint8_t{1})},
            {"median_spacing_d", median(sp)},
            {"mean_spacing_d", sp.empty() ? kNaN : std::accumulate(sp.begin(), sp.end(), 0.0) / dbl(sp.size())}};
  };
  Json relative = Json::array(), sigma = Json::array();
  for (const double f : c.min_relative_drops) {
    std::vector<std::uint8_t> keep;
    for (std::size_t i = 0; i < r.events.size(); ++i) {
      const double load = r.event_load[i], drop = drag[r.events[i].peak] - drag[r.events[i].drop_end];
      keep.push_back(load > 0.0 && drop >= f * load ? 1 : 0);
    }
    relative.push_back(row(f, keep));
  }
  for (const double k : c.drop_thresholds) {
    std::vector<std::uint8_t> keep;
    for (const Event& e : r.events) keep.push_back(drag[e.peak] - drag[e.drop_end] >= k * r.local_noise[e.peak] ? 1 : 0);
    sigma.push_back(row(k, keep));
  }
  return {{"relative_drop", relative}, {"drop_over_noise", sigma},
          {"note", "events of the catalogue (drops above events.drop_threshold x sigma) kept by size; spacing of "
                   "consecutive kept events in the loading/rupture part"}};
}
}  // namespace

namespace {

// A point of the drag profile (row k; nulls for npos).
Json point_json(const SpectrumResult& r, std::size_t k, double intruder_depth) {
  if (k == SpectrumResult::npos) return {{"height_mm", nullptr}, {"drag_N_per_m", nullptr}, {"drag_N", nullptr}};
  const double drag = r.profile.drag[k];
  return {{"height_mm", 1e3 * r.profile.height[k]}, {"drag_N_per_m", drag}, {"drag_N", drag * intruder_depth}};
}

Json fit_json(const LinearFit& f, const char* unit) {
  return {{"slope", f.slope}, {"slope_unit", unit}, {"intercept", f.intercept}, {"r2", f.r2}, {"points", f.points}};
}

void add_profile(Json& m, const SpectrumResult& r, const SpectrumScales& s, double intruder_depth) {
  const auto& h = r.profile.height;
  // the profile
  m["rows"] = h.size();
  m["rows_dropped"] = r.rows_dropped;
  m["height_step_mm"] = 1e3 * r.height_step;
  m["height_step_max_relative_deviation"] = r.step_deviation;
  m["mean_diameter_mm"] = 1e3 * s.d;
  m["samples_per_d"] = s.d / r.height_step;
  m["speed_mm_s"] = 1e3 * r.speed;
  m["paper_speed_mm_s"] = 1e3 * s.paper_speed;
  m["bed_height_mm"] = 1e3 * s.bed_height;
  m["noise_level_N_per_m"] = r.noise;
  m["noise_over_load"] = r.noise / median({r.trend.begin() + static_cast<std::ptrdiff_t>(r.second_part.begin),
                                           r.trend.begin() + static_cast<std::ptrdiff_t>(r.second_part.end)});
  m["noise_level_N"] = r.noise * intruder_depth;
  m["drop_delta_N_per_m"] = r.drop_delta;
  m["drop_threshold_note"] = "each drop must exceed events.drop_threshold x the noise level around it (half the "
                             "trend window each side: the noise follows the load); drop_delta_N_per_m is that "
                             "threshold at the loading/rupture part's noise level";
}

void add_spectral(Json& m, const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c) {
  // spectrum
  m["dominant_period_d"] = r.second_part.peak.period;
  m["dominant_frequency_hz_at_1p2mm_s"] = at_speed(r.second_part.peak.period, s.d, s.paper_speed);
  m["dominant_period_significant"] = r.second_part.peak.significant;
  m["dominant_period_search_range_d"] = {r.min_period_d, c.max_period_d};
  m["dominant_period_search_max_frequency_hz_at_run_v"] = at_speed(r.min_period_d, s.d, r.speed);
  m["psd"] = peak_json(r.second_part, s, r);
  for (const Band& b : r.bands) m["bands"][b.name] = peak_json(b, s, r);
  // the bed's ringing, in time frequency (kept out of the dominant-period search)
  const double ringing_hz = r.ringing.peak.frequency;
  m["ringing_frequency_hz"] = ringing_hz;
  m["ringing_significant"] = r.ringing.peak.significant;
  m["ringing_period_d_at_run_speed"] = r.speed / (ringing_hz * s.d);  // its wavelength in travel
  m["ringing"] = ringing_json(r, c);
}

void add_ruptures(Json& m, const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c,
                  double intruder_depth) {
  const auto& drag = r.profile.drag;
  const double spacing = median(r.rupture_spacing_d);
  const Json spacing_stats = stats_json(r.rupture_spacing_d);
  const double mean_spacing = spacing_stats["mean"].is_number() ? spacing_stats["mean"].get<double>() : kNaN;
  const double event_spacing = median(r.spacing_d);
  std::vector<double> drops;
  for (const Event& e : r.events) drops.push_back(drag[e.peak] - drag[e.drop_end]);
  // events and the ruptures the paper counts
  m["event_count"] = r.events.size();
  m["rupture_rule"] = "a rupture: an event whose drop is at least " + num(c.min_relative_drop) +
                      " x the load it carried (the drag's trend at its peak)";
  m["rupture_count"] = std::count(r.counted.begin(), r.counted.end(), std::uint8_t{1});
  m["rupture_spacing"] = {{"unit", "d"}, {"stats", spacing_stats}};
  m["rupture_spacing_mean_d"] = mean_spacing;
  m["rupture_rate_hz_at_1p2mm_s"] = at_speed(mean_spacing, s.d, s.paper_speed);
  m["rupture_frequency_hz_at_run_v"] = at_speed(spacing, s.d, r.speed);
  m["event_spacing_d"] = event_spacing;
  m["event_frequency_hz_at_1p2mm_s"] = at_speed(event_spacing, s.d, s.paper_speed);
  m["event_spacing"] = {{"unit", "d"}, {"stats", stats_json(r.spacing_d)}};
  m["spacing_by_threshold"] = spacing_by_threshold(r, s, c);
  m["size_distribution"] = {{"drop_N_per_m", sizes_json(r.sizes)}, {"relative_drop", sizes_json(r.relative_sizes)}};
  m["drop_N_per_m"] = stats_json(drops);
  m["amplitude_fit_upper"] = fit_json(r.amplitude_fit, "N/m per mm");
  m["amplitude_slope_upper_N_per_mm"] = r.amplitude_fit.slope * intruder_depth;
  m["envelope_fit_upper"] = fit_json(r.envelope_fit, "N/m per mm");
}

void add_zones(Json& m, const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c,
               double intruder_depth) {
  const auto& h = r.profile.height;
  const double top_depth = s.bed_height - r.top_height;
  // bottom zone
  m["bottom"] = {{"first_peak", point_json(r, r.bottom_peak, intruder_depth)},
                 {"collapse", point_json(r, r.bottom_collapse, intruder_depth)},
                 {"next_loading", point_json(r, r.bottom_reload, intruder_depth)}};
  // top layer
  m["top_layer_found"] = r.top_found;
  m["top_layer_outcome"] = r.top.outcome;
  m["top_layer_depth_mm"] = r.top_found ? 1e3 * top_depth : kNaN;
  m["top_layer"] = top_layer_json(r.top, s);
  m["top_layer"]["power"] = power_json(r.top_power, s, c);
  m["top_layer_power"] = r.top_power.power;
  m["top_layer_envelope_height_mm"] = r.envelope_top_found ? 1e3 * r.envelope_top_height : kNaN;
  m["top_layer_envelope_found"] = r.envelope_top_found;
  m["top_layer_floor_N_per_m"] = c.floor_factor * r.noise;
  m["top_layer_depth_fit"] = fit_json(r.top_fit, "N/m per mm of depth");
  m["top_layer_depth_fit_slope_N_per_mm"] = r.top_fit.slope * intruder_depth;
  m["top_layer_fit_range_mm"] = {r.top_end > r.top_begin ? 1e3 * h[r.top_begin] : kNaN,
                                 r.top_end > r.top_begin ? 1e3 * h[r.top_end - 1] : kNaN};
}

}  // namespace

nlohmann::ordered_json spectrum_metrics(const SpectrumResult& r, const SpectrumScales& s, const SpectrumConfig& c,
                                        double intruder_depth) {
  const double spacing = median(r.rupture_spacing_d);
  Json m;
  // the metrics shared with the tolerance tests, first
  m["bottom_peak_height_mm"] = point_json(r, r.bottom_peak, intruder_depth)["height_mm"];
  m["amplitude_slope_upper"] = r.amplitude_fit.slope;
  m["amplitude_slope_upper_unit"] = "N/m per mm";
  m["amplitude_fit_r2_upper"] = r.amplitude_fit.r2;
  m["rupture_spacing_d"] = spacing;
  m["rupture_frequency_hz_at_1p2mm_s"] = at_speed(spacing, s.d, s.paper_speed);
  m["top_layer_height_mm"] = r.top_found ? 1e3 * r.top_height : kNaN;
  m["top_layer_depth_fit_r2"] = r.top_fit.r2;
  add_profile(m, r, s, intruder_depth);
  add_spectral(m, r, s, c);
  add_ruptures(m, r, s, c, intruder_depth);
  add_zones(m, r, s, c, intruder_depth);
  return m;
}

nlohmann::ordered_json sensitivity_table(const DragProfile& profile, const SpectrumScales& s, const SpectrumConfig& c,
                                         const std::string& source, TopLayerMemo* memo) {
  TopLayerMemo own;
  TopLayerMemo& searched = memo ? *memo : own;
  Json t = Json::object();
  auto vary = [&](const char* name, const std::vector<double>& values, double SpectrumConfig::*field) {
    for (const double v : values) {
      SpectrumConfig cv = c;
      cv.*field = v;
      cv.size_bootstrap = 0;  // the rows do not report the size distribution's goodness of fit
      cv.power_replicas = 0;  // nor a miss's power
      const SpectrumResult r = analyse(profile, s, cv, source, &searched);
      const Json m = spectrum_metrics(r, s, cv, 1.0);
      t[name].push_back({{"value", v},
                         {"event_count", m["event_count"]},
                         {"rupture_spacing_d", m["rupture_spacing_d"]},
                         {"rupture_spacing_mean_d", m["rupture_spacing_mean_d"]},
                         {"rupture_frequency_hz_at_1p2mm_s", m["rupture_frequency_hz_at_1p2mm_s"]},
                         {"amplitude_slope_upper", m["amplitude_slope_upper"]},
                         {"amplitude_fit_r2_upper", m["amplitude_fit_r2_upper"]},
                         {"dominant_period_d", m["dominant_period_d"]},
                         {"dominant_period_significant", m["dominant_period_significant"]},
                         {"dominant_period_search_min_d", m["dominant_period_search_range_d"][0]},
                         {"event_spacing_d", m["event_spacing_d"]},
                         {"top_layer_height_mm", m["top_layer_height_mm"]},
                         {"top_layer_interval_mm", m["top_layer"]["interval_mm"]},
                         {"top_layer_envelope_height_mm", m["top_layer_envelope_height_mm"]},
                         {"top_layer_depth_fit_r2", m["top_layer_depth_fit_r2"]}});
    }
  };
  vary("drop_threshold", c.drop_thresholds, &SpectrumConfig::drop_threshold);
  vary("floor_factor", c.floor_factors, &SpectrumConfig::floor_factor);
  vary("trend_window_d", c.trend_windows_d, &SpectrumConfig::trend_window_d);
  vary("ringing_cutoff_fraction", c.ringing_cutoff_fractions, &SpectrumConfig::ringing_cutoff_fraction);
  vary("min_relative_drop", c.min_relative_drops, &SpectrumConfig::min_relative_drop);
  vary("block_d", c.blocks_d, &SpectrumConfig::block_d);
  vary("search_from_fraction", c.search_from_fractions, &SpectrumConfig::search_from_fraction);
  // a miss's power against the quiet level assumed for a planted layer
  for (const double v : c.power_noise_factors) {
    SpectrumConfig cv = c;
    cv.power_noise_factor = v;
    cv.size_bootstrap = 0;
    const SpectrumResult r = analyse(profile, s, cv, source, &searched);
    t["power_noise_factor"].push_back({{"value", v}, {"top_layer_outcome", r.top.outcome},
                                       {"top_layer_power", r.top_power.power}});
  }
  return t;
}

}  // namespace dem2d::analysis
