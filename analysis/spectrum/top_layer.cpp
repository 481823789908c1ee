#include "spectrum/top_layer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

#include "common/units.hpp"

namespace dem2d::analysis {

namespace {


// The blocks' data: centre height, ln variance, load factor g.
struct Blocks {
  std::vector<double> h, lnv, v, load;
};

constexpr int kParams = 4;
using Params = std::array<double, kParams>;  // ln B, c0, c1, sqrt(e) (the noise's rms per unit load)

// var_b for the model at H_top (x in metres of depth below H_top):
// (sqrt(B) + sqrt(e) L_b)^2 + a_b^2, a_b = g_b (c0 + c1 x) below H_top.
struct Model {
  const std::vector<double>& h;
  const std::vector<double>& g;
  const std::vector<double>& load;
  double top;
  bool fade = true;  // false: c1 = 0, the amplitude (x g) the same at every depth
  double amplitude(std::size_t b, const Params& p) const {
    const double x = top - h[b];
    return x > 0.0 ? g[b] * (p[1] + p[2] * x) : 0.0;
  }
  // the rms of what is left without ruptures: a stationary part plus a part
  // following the load, added as amplitudes (a white noise of rms s0 + s1 L,
  // as the bed's ringing grows with its load)
  // (sqrt_b: exp(p[0] / 2), sqrt(B), computed once per parameter set)
  double noise_rms(std::size_t b, const Params& p, double sqrt_b) const { return sqrt_b + p[3] * load[b]; }
  double value(std::size_t b, const Params& p, double sqrt_b) const {
    const double a = amplitude(b, p);
    const double sd = noise_rms(b, p, sqrt_b);
    return sd * sd + a * a;
  }
  // c0 >= 0 and c1 >= 0: the amplitude is >= 0 and does not grow towards
  // the change point (the paper's "decreases almost linearly"; a growing one
  // would fit any noise bump below H_top); e >= 0
  void project(Params& p) const {
    p[1] = std::max(p[1], 0.0);
    p[2] = fade ? std::max(p[2], 0.0) : 0.0;
    p[3] = std::max(p[3], 0.0);
  }
};

// The sum of squared ln residuals at p, and the residuals (r, resized to the blocks).
double sum_squares(const Model& m, const std::vector<double>& lnv, const Params& p, std::vector<double>& r) {
  const double sqrt_b = std::exp(0.5 * p[0]);
  r.resize(lnv.size());
  double s = 0.0;
  for (std::size_t b = 0; b < lnv.size(); ++b) {
    r[b] = lnv[b] - std::log(m.value(b, p, sqrt_b));
    s += r[b] * r[b];
  }
  return s;
}

// Solves A x = y (Gaussian elimination with partial pivoting); false if singular.
bool solve(std::array<Params, kParams> a, Params y, Params& x) {
  for (int c = 0; c < kParams; ++c) {
    int piv = c;
    for (int r = c + 1; r < kParams; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    if (!(std::abs(a[piv][c]) > 0.0)) return false;
    std::swap(a[c], a[piv]);
    std::swap(y[c], y[piv]);
    for (int r = c + 1; r < kParams; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < kParams; ++k) a[r][k] -= f * a[c][k];
      y[r] -= f * y[c];
    }
  }
  for (int c = kParams - 1; c >= 0; --c) {
    double sum = y[c];
    for (int k = c + 1; k < kParams; ++k) sum -= a[c][k] * x[k];
    x[c] = sum / a[c][c];
  }
  return true;
}

// The model at a fixed H_top fitted by projected Levenberg-Marquardt from a
// starting point read off the data: the background from the quiet blocks, the
// amplitude from a straight line through the active ones' excess.
TopLayerModelFit fit_at(const Blocks& k, const std::vector<double>& g, const std::vector<double>& lnv,
                        const std::vector<double>& v, double top, bool fade = true) {
  const std::size_t n = lnv.size();
  double x_max = 0.0;
  std::vector<std::size_t> quiet, active;
  for (std::size_t b = 0; b < n; ++b) {
    const double x = top - k.h[b];
    (x > 0.0 && g[b] > 0.0 ? active : quiet).push_back(b);
    x_max = std::max(x_max, x);
  }
  const Model m{k.h, g, k.load, top, fade};
  // start: B from the quiet blocks (or the lowest tenth of all), a line through sqrt(var - B) / g
  std::vector<double> base;
  for (const std::size_t b : quiet) base.push_back(lnv[b]);
  if (base.empty()) {
    base = lnv;
    std::sort(base.begin(), base.end());
    base.resize(std::max<std::size_t>(1, base.size() / 10));
  }
  Params p{std::accumulate(base.begin(), base.end(), 0.0) / static_cast<double>(base.size()), 0.0, 0.0, 0.0};
  {
    double sx = 0, sy = 0, sxx = 0, sxy = 0, w = 0;
    for (const std::size_t b : active) {
      const double x = top - k.h[b], y = std::sqrt(std::max(v[b] - std::exp(p[0]), 0.0)) / g[b];
      sx += x, sy += y, sxx += x * x, sxy += x * y, w += 1.0;
    }
    if (fade && w >= 2.0 && sxx * w - sx * sx > 0.0) {
      p[2] = (w * sxy - sx * sy) / (w * sxx - sx * sx);
      p[1] = (sy - p[2] * sx) / w;
    } else if (w > 0.0) {
      p[1] = sy / w;
    }
    m.project(p);
    if (!active.empty() && p[1] + p[2] * 0.5 * x_max <= 0.0) {
      double gmax = 0.0;
      for (const std::size_t b : active) gmax = std::max(gmax, g[b]);
      p[1] = 0.1 * std::exp(0.5 * p[0]) / gmax;  // a small amplitude: the gradient is not zero
    }
  }
  std::vector<double> resid, trial;  // the ln residuals at p, and at a trial step
  double s = sum_squares(m, lnv, p, resid), lambda = 1e-3;
  for (int it = 0; it < 40; ++it) {
    std::array<Params, kParams> jtj{};
    Params jtr{};
    const double sqrt_b = std::exp(0.5 * p[0]);
    for (std::size_t b = 0; b < n; ++b) {
      const double x = top - k.h[b], a = m.amplitude(b, p), mv = m.value(b, p, sqrt_b), r = resid[b];
      // d(ln model)/d(params): the residual's derivatives with the sign flipped
      const double sd = m.noise_rms(b, p, sqrt_b);
      Params j{sd * sqrt_b / mv, 0.0, 0.0, 2.0 * sd * k.load[b] / mv};
      if (x > 0.0) j[1] = 2.0 * a * g[b] / mv, j[2] = fade ? 2.0 * a * g[b] * x / mv : 0.0;
      for (int i = 0; i < kParams; ++i) {
        jtr[i] += j[i] * r;
        for (int q = 0; q < kParams; ++q) jtj[i][q] += j[i] * j[q];
      }
    }
    bool improved = false;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      auto a = jtj;
      for (int i = 0; i < kParams; ++i) a[i][i] += lambda * (jtj[i][i] > 0.0 ? jtj[i][i] : 1.0);
      Params step{};
      if (!solve(a, jtr, step)) {
        lambda *= 10.0;
        continue;
      }
      Params q;
      for (int i = 0; i < kParams; ++i) q[i] = p[i] + step[i];
      m.project(q);
      const double sq = sum_squares(m, lnv, q, trial);
      if (sq < s) {
        const double gain = s - sq;
        p = q, s = sq, improved = true, lambda = std::max(lambda / 3.0, 1e-12);
        resid.swap(trial);
        if (gain < 1e-6 * (1.0 + s)) it = 40;  // converged
      } else {
        lambda *= 4.0;
      }
    }
    if (!improved) break;
  }
  return {top, std::exp(p[0]), p[1], p[2], p[3] * p[3], s};
}

// The best H_top of one model: the candidate grid a block apart, then a
// quarter block apart around the best of those (ties: the highest, so that a
// flat objective says "no vanishing" rather than "at the bottom").
TopLayerModelFit best_fit(const Blocks& k, const std::vector<double>& g, const std::vector<double>& lnv,
                          const std::vector<double>& candidates) {
  std::vector<double> v(lnv.size());
  for (std::size_t b = 0; b < v.size(); ++b) v[b] = std::exp(lnv[b]);
  TopLayerModelFit best;
  std::size_t at = 0;
  auto consider = [&](std::size_t c) {
    const TopLayerModelFit f = fit_at(k, g, lnv, v, candidates[c]);
    if (f.residual < best.residual * (1.0 - 1e-12)) best = f, at = c;
  };
  const std::size_t last = candidates.size() - 1;
  for (std::size_t c = last + 1; c-- > 0;)  // coarse: every fourth and the last, downwards
    if (c == last || c % 4 == 0) consider(c);
  const std::size_t lo = at >= 3 ? at - 3 : 0, hi = std::min(last, at + 3);
  for (std::size_t c = hi + 1; c-- > lo;)
    if (c % 4 != 0 && c != last) consider(c);
  return best;
}

// The better of the two models without a change: the fluctuations keep their
// size (relative to the load, or absolute) up to the range's end (c1 = 0: a
// size fading linearly to zero at the range's end is a vanishing, and a null
// that allows it fits a layer some d below the surface as well as none).
TopLayerModelFit null_fit(const Blocks& k, const std::vector<double>& ones, const std::vector<double>& lnv, double end,
                          bool* relative) {
  std::vector<double> v(lnv.size());
  for (std::size_t b = 0; b < v.size(); ++b) v[b] = std::exp(lnv[b]);
  const TopLayerModelFit r = fit_at(k, k.load, lnv, v, end, false), a = fit_at(k, ones, lnv, v, end, false);
  if (relative) *relative = r.residual <= a.residual;
  return r.residual <= a.residual ? r : a;
}

// ln of the model's values at the blocks.
std::vector<double> ln_model(const Blocks& k, const std::vector<double>& g, const TopLayerModelFit& f) {
  const Model m{k.h, g, k.load, f.height};
  const Params p{std::log(f.background), f.c0, f.c1, std::sqrt(f.noise)};
  const double sqrt_b = std::exp(0.5 * p[0]);
  std::vector<double> out;
  for (std::size_t b = 0; b < k.h.size(); ++b) out.push_back(std::log(m.value(b, p, sqrt_b)));
  return out;
}

double quantile_of(std::vector<double> x, double q) {
  std::sort(x.begin(), x.end());
  const double pos = q * static_cast<double>(x.size() - 1);
  const auto i = static_cast<std::size_t>(pos);
  return i + 1 < x.size() ? x[i] + (pos - static_cast<double>(i)) * (x[i + 1] - x[i]) : x[i];
}

}  // namespace

TopLayerFit find_top_layer(const std::vector<double>& h, const std::vector<double>& f, const std::vector<double>& trend,
                           const TopLayerSearch& s) {
  TopLayerFit out;
  out.outcome = "not searched";
  const std::size_t r0 = static_cast<std::size_t>(std::lower_bound(h.begin(), h.end(), s.low) - h.begin());
  const std::size_t r1 = static_cast<std::size_t>(std::lower_bound(h.begin(), h.end(), s.high) - h.begin());
  if (s.block_rows < 2 || r1 <= r0) return out;
  Blocks k;
  for (std::size_t b0 = r0; b0 + s.block_rows <= r1; b0 += s.block_rows) {
    double mean = 0.0, load = 0.0, hc = 0.0;
    for (std::size_t i = b0; i < b0 + s.block_rows; ++i) mean += f[i], load += trend[i], hc += h[i];
    const double n = static_cast<double>(s.block_rows);
    mean /= n, load /= n, hc /= n;
    double var = 0.0;
    for (std::size_t i = b0; i < b0 + s.block_rows; ++i) var += (f[i] - mean) * (f[i] - mean);
    var /= n;
    k.h.push_back(hc);
    k.v.push_back(std::max(var, 1e-300));
    k.lnv.push_back(std::log(k.v.back()));
    k.load.push_back(std::max(load, 0.0));
  }
  if (k.h.size() < 4) return out;
  out.searched = true;
  // candidates: a quarter block apart, from the range's start to its end
  const double block_height = (k.h.back() - k.h.front()) / static_cast<double>(k.h.size() - 1);
  std::vector<double> candidates;
  for (double t = s.low; t <= s.high + 1e-12; t += 0.25 * block_height) candidates.push_back(t);
  const std::vector<double> ones(k.h.size(), 1.0);
  out.relative = best_fit(k, k.load, k.lnv, candidates);
  out.absolute = best_fit(k, ones, k.lnv, candidates);
  const bool relative = out.relative.residual <= out.absolute.residual;
  out.model = relative ? "relative" : "absolute";
  out.best = relative ? out.relative : out.absolute;
  const std::vector<double>& g = relative ? k.load : ones;
  out.block_height = k.h, out.block_variance = k.v, out.block_load = k.load;
  for (const double lm : ln_model(k, g, out.best)) out.block_model.push_back(std::exp(lm));

  std::mt19937_64 rng(s.seed);
  auto sign = [&rng]() { return (rng() >> 63) ? 1.0 : -1.0; };
  // Is there a vanishing at all? The null hypothesis: no change point inside
  // the range (the fluctuations keep their size up to its end, or there are
  // none). Statistic: how much the change point lowers the residual; its
  // distribution under the null from the null fit with its residuals shuffled.
  bool null_relative = true;
  const TopLayerModelFit null = null_fit(k, ones, k.lnv, candidates.back(), &null_relative);
  out.null = null;
  out.null_model = null_relative ? "relative" : "absolute";
  out.statistic = null.residual - out.best.residual;
  if (s.bootstrap > 0) {
    // null data: the null fit plus its own residuals in shuffled order. Under
    // the null the order carries nothing; a real change point leaves a misfit
    // ordered in height that shuffling breaks up (a permutation test of the
    // residuals' arrangement, exact in size whatever their distribution).
    const std::vector<double> fitted = ln_model(k, null_relative ? k.load : ones, null);
    const std::vector<double> best_fitted = ln_model(k, g, out.best);
    std::vector<double> resid(k.h.size());
    for (std::size_t b = 0; b < k.h.size(); ++b) resid[b] = k.lnv[b] - fitted[b];
    int as_large = 0;
    bool decided = false;  // decision_only: p >= false_alarm whatever the permutations left would give
    std::vector<double> lnv(k.h.size());
    for (int r = 0; r < s.bootstrap && !decided; ++r) {
      for (std::size_t b = resid.size(); b-- > 1;) std::swap(resid[b], resid[static_cast<std::size_t>(rng() % (b + 1))]);
      for (std::size_t b = 0; b < k.h.size(); ++b) lnv[b] = fitted[b] + resid[b];
      const double best = std::min(best_fit(k, k.load, lnv, candidates).residual, best_fit(k, ones, lnv, candidates).residual);
      if (null_fit(k, ones, lnv, candidates.back(), nullptr).residual - best >= out.statistic) ++as_large;
      decided = s.decision_only && (as_large + 1.0) / (s.bootstrap + 1.0) >= s.false_alarm;
    }
    out.p_value = decided ? kNaN : (as_large + 1.0) / (s.bootstrap + 1.0);
    // the interval of H_top: a wild bootstrap of the best fit's residuals
    // (none for the power's plantings, which need only found or not, and where)
    std::vector<double> tops;
    for (int r = 0; r < s.bootstrap && s.interval; ++r) {
      for (std::size_t b = 0; b < k.h.size(); ++b) lnv[b] = best_fitted[b] + sign() * (k.lnv[b] - best_fitted[b]);
      tops.push_back(best_fit(k, g, lnv, candidates).height);
    }
    const double tail = 0.5 * (1.0 - s.confidence);
    out.low = tops.empty() ? out.best.height : quantile_of(tops, tail);
    out.high = tops.empty() ? out.best.height : quantile_of(tops, 1.0 - tail);
  } else {
    out.p_value = out.statistic > 0.0 ? 0.0 : 1.0;
    out.low = out.high = out.best.height;
  }
  const double surface = s.high - 0.5 * block_height;
  const bool significant = out.p_value < s.false_alarm;  // (false when not computed past the decision)
  out.found = significant && out.high < surface && out.best.height < surface;
  // the interval reported: at least half a block either side, the blocks'
  // resolution (the variance of a block cannot tell where in it the events
  // stop; the bootstrap interval alone held the planted height in 4 of 10
  // abrupt ends)
  out.low = std::min(out.low, out.best.height - 0.5 * block_height);
  out.high = std::max(out.high, out.best.height + 0.5 * block_height);
  out.outcome = out.found ? "found" : !significant ? "no significant vanishing" : "reaches the surface";  // the caller
  // turns "no significant vanishing" into "none" or "undetermined" by its power (top_layer_power)
  return out;
}

TopLayerPower top_layer_power(const std::vector<double>& h, const std::vector<double>& f,
                              const std::vector<double>& trend, const std::vector<double>& quiet,
                              const TopLayerSearch& s, const std::vector<double>& planted, int replicas,
                              double tolerance) {
  TopLayerPower out;
  out.height = planted, out.replicas = replicas, out.tolerance = tolerance;
  const int trials = static_cast<int>(planted.size()) * replicas;
  std::vector<std::uint8_t> hit(static_cast<std::size_t>(std::max(trials, 0)), 0);
#pragma omp parallel for schedule(dynamic, 1)
  for (int t = 0; t < trials; ++t) {
    const double top = planted[static_cast<std::size_t>(t / replicas)];
    std::mt19937_64 rng(s.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(t) + 1);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<double> g = f;
    for (std::size_t k = 0; k < h.size(); ++k)
      if (h[k] >= top) g[k] = quiet[k] * gauss(rng);
    TopLayerSearch search = s;
    search.seed = s.seed + static_cast<std::uint64_t>(t) + 1;
    search.interval = false;  // found or not, and where: the interval is not needed
    search.decision_only = true;
    const TopLayerFit fit = find_top_layer(h, g, trend, search);
    hit[static_cast<std::size_t>(t)] = fit.found && std::abs(fit.best.height - top) <= tolerance;
  }
  for (std::size_t i = 0; i < planted.size(); ++i) {
    int n = 0;
    for (int r = 0; r < replicas; ++r) n += hit[i * static_cast<std::size_t>(replicas) + static_cast<std::size_t>(r)];
    out.found_fraction.push_back(replicas > 0 ? static_cast<double>(n) / replicas : std::numeric_limits<double>::quiet_NaN());
  }
  if (!out.found_fraction.empty()) out.power = *std::min_element(out.found_fraction.begin(), out.found_fraction.end());
  return out;
}

TopLayerFit TopLayerMemo::find(const std::vector<double>& h, const std::vector<double>& f,
                               const std::vector<double>& trend, const TopLayerSearch& s) {
  Inputs in{h, f, trend, {}, {}, s};
  for (const auto& [key, fit] : fits_)
    if (key == in) return fit;
  fits_.emplace_back(std::move(in), find_top_layer(h, f, trend, s));
  return fits_.back().second;
}

TopLayerPower TopLayerMemo::power(const std::vector<double>& h, const std::vector<double>& f,
                                  const std::vector<double>& trend, const std::vector<double>& quiet,
                                  const TopLayerSearch& s, const std::vector<double>& planted, int replicas,
                                  double tolerance) {
  Inputs in{h, f, trend, quiet, planted, s, replicas, tolerance};
  for (const auto& [key, power] : powers_)
    if (key == in) return power;
  powers_.emplace_back(std::move(in), top_layer_power(h, f, trend, quiet, s, planted, replicas, tolerance));
  return powers_.back().second;
}

}  // namespace dem2d::analysis
