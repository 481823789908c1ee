#include "spectrum/size_distribution.hpp"

#include "common/normal.hpp"
#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

namespace dem2d::analysis {

namespace {

const double kSqrt2 = std::sqrt(2.0);

double normal_cdf(double z) { return 0.5 * std::erfc(-z / kSqrt2); }
// ln of the standard normal upper tail, accurate far out
double log_normal_upper(double z) {
  if (z < 5.0) return std::log(0.5 * std::erfc(z / kSqrt2));
  return -0.5 * z * z - std::log(z * std::sqrt(2.0 * std::numbers::pi)) + std::log1p(-1.0 / (z * z));
}

// Largest distance between the empirical CDF of sorted x and cdf.
template <class Cdf>
double ks_distance(const std::vector<double>& x, Cdf cdf) {
  double d = 0.0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double c = cdf(x[i]);
    d = std::max({d, std::abs(c - static_cast<double>(i) / n), std::abs(static_cast<double>(i + 1) / n - c)});
  }
  return d;
}

// ln p(x) of each family on the tail (x >= x_min)
double ln_power_law(double x, double alpha, double x_min) {
  return std::log((alpha - 1.0) / x_min) - alpha * std::log(x / x_min);
}
double ln_exponential(double x, double lambda, double x_min) { return std::log(lambda) - lambda * (x - x_min); }
double ln_lognormal(double x, double mu, double sigma, double x_min) {
  const double z = (std::log(x) - mu) / sigma;
  return -0.5 * z * z - std::log(sigma * x * std::sqrt(2.0 * std::numbers::pi)) - log_normal_upper((std::log(x_min) - mu) / sigma);
}

// The lognormal truncated below at x_min: maximum likelihood by Nelder-Mead in (mu, ln sigma).
FamilyFit fit_lognormal(const std::vector<double>& t, double x_min) {
  auto nll = [&](double mu, double ls) {
    const double sigma = std::exp(ls);
    if (!(sigma > 1e-6 && sigma < 1e3)) return std::numeric_limits<double>::infinity();
    double s = 0.0;
    for (const double x : t) s -= ln_lognormal(x, mu, sigma, x_min);
    return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
  };
  double m = 0.0, q = 0.0;
  for (const double x : t) m += std::log(x);
  m /= static_cast<double>(t.size());
  for (const double x : t) q += (std::log(x) - m) * (std::log(x) - m);
  const double ls0 = 0.5 * std::log(std::max(q / static_cast<double>(t.size()), 1e-6));
  // simplex in (mu, ln sigma)
  std::array<std::array<double, 2>, 3> v{{{m, ls0}, {m + 0.5, ls0}, {m, ls0 + 0.5}}};
  std::array<double, 3> fv{nll(v[0][0], v[0][1]), nll(v[1][0], v[1][1]), nll(v[2][0], v[2][1])};
  for (int it = 0; it < 2000; ++it) {
    std::array<int, 3> o{0, 1, 2};
    std::sort(o.begin(), o.end(), [&](int a, int b) { return fv[a] < fv[b]; });
    const auto best = v[o[0]], mid = v[o[1]], worst = v[o[2]];
    if (std::abs(fv[o[2]] - fv[o[0]]) < 1e-12 * (1.0 + std::abs(fv[o[0]]))) break;
    const std::array<double, 2> c{0.5 * (best[0] + mid[0]), 0.5 * (best[1] + mid[1])};
    auto at = [&](double u) { return std::array<double, 2>{c[0] + u * (worst[0] - c[0]), c[1] + u * (worst[1] - c[1])}; };
    const auto r = at(-1.0);
    const double fr = nll(r[0], r[1]);
    if (fr < fv[o[0]]) {
      const auto e = at(-2.0);
      const double fe = nll(e[0], e[1]);
      if (fe < fr) v[o[2]] = e, fv[o[2]] = fe; else v[o[2]] = r, fv[o[2]] = fr;
    } else if (fr < fv[o[1]]) {
      v[o[2]] = r, fv[o[2]] = fr;
    } else {
      const auto k = at(fr < fv[o[2]] ? -0.5 : 0.5);
      const double fk = nll(k[0], k[1]);
      if (fk < std::min(fr, fv[o[2]])) {
        v[o[2]] = k, fv[o[2]] = fk;
      } else {  // shrink towards the best
        for (const int i : {o[1], o[2]}) {
          v[i] = {0.5 * (v[i][0] + best[0]), 0.5 * (v[i][1] + best[1])};
          fv[i] = nll(v[i][0], v[i][1]);
        }
      }
    }
  }
  const int b = static_cast<int>(std::min_element(fv.begin(), fv.end()) - fv.begin());
  FamilyFit f;
  f.family = "lognormal";
  f.mu = v[b][0], f.sigma = std::exp(v[b][1]), f.log_likelihood = -fv[b];
  const double tail = std::exp(log_normal_upper((std::log(x_min) - f.mu) / f.sigma));
  f.ks = ks_distance(t, [&](double x) {
    return (normal_cdf((std::log(x) - f.mu) / f.sigma) - (1.0 - tail)) / tail;
  });
  return f;
}

struct PowerLaw {
  double x_min = kNaN, alpha = kNaN, ks = std::numeric_limits<double>::infinity();
  std::size_t tail = 0;
};

// x_min minimising the KS distance of the fitted power law over the sorted sizes.
PowerLaw scan_power_law(const std::vector<double>& x, std::size_t min_tail) {
  PowerLaw best;
  for (std::size_t i = 0; i + min_tail <= x.size(); ++i) {
    if (i > 0 && x[i] == x[i - 1]) continue;
    const std::vector<double> t(x.begin() + static_cast<std::ptrdiff_t>(i), x.end());
    const double a = power_law_alpha(t, x[i]);
    if (!std::isfinite(a)) continue;
    const double d = ks_distance(t, [&](double v) { return 1.0 - std::pow(v / x[i], 1.0 - a); });
    if (d < best.ks) best = {x[i], a, d, t.size()};
  }
  return best;
}

Comparison compare(const std::string& a, const std::string& b, const std::vector<double>& la,
                   const std::vector<double>& lb, double significance) {
  Comparison c;
  c.a = a, c.b = b;
  const std::size_t n = la.size();
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) d[i] = la[i] - lb[i];
  c.ratio = std::accumulate(d.begin(), d.end(), 0.0);
  const double mean = c.ratio / static_cast<double>(n);
  double var = 0.0;
  for (const double v : d) var += (v - mean) * (v - mean);
  var /= static_cast<double>(n);
  const double sd = std::sqrt(var);
  c.normalised = sd > 0.0 ? c.ratio / (std::sqrt(static_cast<double>(n)) * sd) : 0.0;
  c.p = std::erfc(std::abs(c.normalised) / kSqrt2);
  c.favoured = c.p < significance ? (c.ratio > 0.0 ? a : b) : "neither";
  return c;
}

}  // namespace

double power_law_alpha(const std::vector<double>& t, double x_min) {
  double s = 0.0;
  for (const double v : t) s += std::log(v / x_min);
  return s > 0.0 ? 1.0 + static_cast<double>(t.size()) / s : kNaN;
}

SizeDistribution fit_sizes(const std::vector<double>& sizes, const SizeFitSettings& s) {
  SizeDistribution out;
  std::vector<double> x;
  for (const double v : sizes)
    if (std::isfinite(v) && v > 0.0) x.push_back(v);
  std::sort(x.begin(), x.end());
  out.n = x.size();
  if (x.size() < s.min_tail) return out;
  const PowerLaw pl = scan_power_law(x, s.min_tail);
  if (!std::isfinite(pl.alpha)) return out;
  out.fitted = true;
  out.x_min = pl.x_min;
  out.tail = pl.tail;
  const std::vector<double> t(x.end() - static_cast<std::ptrdiff_t>(pl.tail), x.end());
  const double n = static_cast<double>(t.size());

  out.power_law.family = "power_law";
  out.power_law.alpha = pl.alpha;
  out.power_law.ks = pl.ks;
  out.exponential.family = "exponential";
  out.exponential.lambda = 1.0 / (std::accumulate(t.begin(), t.end(), 0.0) / n - pl.x_min);
  out.exponential.ks = ks_distance(t, [&](double v) { return 1.0 - std::exp(-out.exponential.lambda * (v - pl.x_min)); });
  out.lognormal = fit_lognormal(t, pl.x_min);

  std::vector<double> lp, le, ll;
  for (const double v : t) {
    lp.push_back(ln_power_law(v, pl.alpha, pl.x_min));
    le.push_back(ln_exponential(v, out.exponential.lambda, pl.x_min));
    ll.push_back(ln_lognormal(v, out.lognormal.mu, out.lognormal.sigma, pl.x_min));
  }
  out.power_law.log_likelihood = std::accumulate(lp.begin(), lp.end(), 0.0);
  out.exponential.log_likelihood = std::accumulate(le.begin(), le.end(), 0.0);
  out.comparisons = {compare("power_law", "lognormal", lp, ll, s.significance),
                     compare("power_law", "exponential", lp, le, s.significance),
                     compare("lognormal", "exponential", ll, le, s.significance)};
  for (const char* f : {"power_law", "lognormal", "exponential"}) {
    bool wins_all = true;
    for (const Comparison& c : out.comparisons)
      if ((c.a == f || c.b == f) && c.favoured != f) wins_all = false;
    if (wins_all) out.best = f;
  }
  out.decades = std::log10(t.back() / pl.x_min);
  if (out.best.empty()) {
    out.best = "undecided";
    // the leading family and the tail its weaker comparison would need
    const std::pair<const char*, double> total[] = {{"power_law", out.power_law.log_likelihood},
                                                    {"lognormal", out.lognormal.log_likelihood},
                                                    {"exponential", out.exponential.log_likelihood}};
    out.leading =
        std::max_element(std::begin(total), std::end(total), [](auto& a, auto& b) { return a.second < b.second; })->first;
    const double z_crit = normal_upper_quantile(0.5 * s.significance);  // two-sided
    out.tail_needed = 0.0;
    for (const Comparison& c : out.comparisons)
      if (c.a == out.leading || c.b == out.leading) {
        const double z = std::abs(c.normalised);
        out.tail_needed = std::max(out.tail_needed, z > 0.0 ? n * (z_crit / z) * (z_crit / z)
                                                            : std::numeric_limits<double>::infinity());
      }
  }

  // goodness of fit of the power law: semi-parametric bootstrap (CSN section 4.1)
  if (s.bootstrap > 0) {
    std::mt19937_64 rng(s.seed);
    const std::size_t below = x.size() - pl.tail;
    auto uniform = [&rng]() { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
    int larger = 0;
    std::vector<double> y(x.size());
    for (int r = 0; r < s.bootstrap; ++r) {
      for (double& v : y) {
        if (below > 0 && uniform() * static_cast<double>(x.size()) < static_cast<double>(below))
          v = x[static_cast<std::size_t>(uniform() * static_cast<double>(below))];
        else
          v = pl.x_min * std::pow(1.0 - uniform(), -1.0 / (pl.alpha - 1.0));
      }
      std::sort(y.begin(), y.end());
      if (scan_power_law(y, s.min_tail).ks >= pl.ks) ++larger;
    }
    out.power_law_p = static_cast<double>(larger) / static_cast<double>(s.bootstrap);
  }
  out.power_law_plausible = out.power_law_p >= s.plausible_p && out.decades >= s.min_decades;
  // a power law that is not plausible (too narrow a tail, or rejected) is not the best family
  if (out.best == "power_law" && !out.power_law_plausible) out.best = "undecided", out.leading = "power_law";
  return out;
}

}  // namespace dem2d::analysis
