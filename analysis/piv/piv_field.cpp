#include "piv/piv_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "piv/piv_correlate.hpp"

namespace dem2d::analysis {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double>& v) {
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(h), v.end());
  const double upper = v[h];
  if (v.size() % 2) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<long>(h)));
}

}  // namespace

std::size_t VectorField::count(Vector s) const { return static_cast<std::size_t>(std::count(status.begin(), status.end(), s)); }

VectorField window_grid(std::size_t width, std::size_t height, int n, double overlap) {
  VectorField f;
  const auto N = static_cast<std::size_t>(n);
  f.step = std::max(1.0, std::round(n * (1.0 - overlap)));
  if (N > width || N > height) return f;
  const auto st = static_cast<std::size_t>(f.step);
  f.nx = (width - N) / st + 1, f.ny = (height - N) / st + 1;
  // centred in the image: the leftover pixels split on both sides
  const double left = std::floor(0.5 * static_cast<double>(width - N - (f.nx - 1) * st));
  const double top = std::floor(0.5 * static_cast<double>(height - N - (f.ny - 1) * st));
  f.x0 = left + 0.5 * (n - 1), f.y0 = top + 0.5 * (n - 1);
  f.u.assign(f.nx * f.ny, kNone), f.v.assign(f.nx * f.ny, kNone);
  f.status.assign(f.nx * f.ny, Vector::none);
  return f;
}

std::size_t replace_outliers(VectorField& f, double threshold, double epsilon) {
  std::vector<std::uint8_t> outlier(f.u.size(), 0);
  std::vector<double> nu, nv, ru, rv;
  const auto neighbours = [&](std::size_t i, std::size_t j) {
    nu.clear(), nv.clear();
    for (long dj = -1; dj <= 1; ++dj)
      for (long di = -1; di <= 1; ++di) {
        const long a = static_cast<long>(i) + di, b = static_cast<long>(j) + dj;
        if ((di == 0 && dj == 0) || a < 0 || b < 0 || a >= static_cast<long>(f.nx) || b >= static_cast<long>(f.ny)) continue;
        const std::size_t k = static_cast<std::size_t>(b) * f.nx + static_cast<std::size_t>(a);
        if (f.status[k] == Vector::none) continue;
        nu.push_back(f.u[k]), nv.push_back(f.v[k]);
      }
  };
  for (std::size_t j = 0; j < f.ny; ++j)
    for (std::size_t i = 0; i < f.nx; ++i) {
      const std::size_t k = j * f.nx + i;
      if (f.status[k] == Vector::none) continue;
      neighbours(i, j);
      if (nu.size() < 2) continue;
      ru.clear(), rv.clear();
      std::vector<double> cu = nu, cv = nv;
      const double mu = median(cu), mv = median(cv);
      for (std::size_t q = 0; q < nu.size(); ++q) ru.push_back(std::abs(nu[q] - mu)), rv.push_back(std::abs(nv[q] - mv));
      const double su = median(ru) + epsilon, sv = median(rv) + epsilon;
      if (std::hypot((f.u[k] - mu) / su, (f.v[k] - mv) / sv) > threshold) outlier[k] = 1;
    }
  // replaced by the median of their neighbours that are not outliers themselves
  std::size_t replaced = 0;
  VectorField out = f;
  for (std::size_t j = 0; j < f.ny; ++j)
    for (std::size_t i = 0; i < f.nx; ++i) {
      const std::size_t k = j * f.nx + i;
      if (!outlier[k]) continue;
      nu.clear(), nv.clear();
      for (long dj = -1; dj <= 1; ++dj)
        for (long di = -1; di <= 1; ++di) {
          const long a = static_cast<long>(i) + di, b = static_cast<long>(j) + dj;
          if (a < 0 || b < 0 || a >= static_cast<long>(f.nx) || b >= static_cast<long>(f.ny)) continue;
          const std::size_t q = static_cast<std::size_t>(b) * f.nx + static_cast<std::size_t>(a);
          if (q == k || outlier[q] || f.status[q] == Vector::none) continue;
          nu.push_back(f.u[q]), nv.push_back(f.v[q]);
        }
      ++replaced;
      if (nu.empty()) {
        out.u[k] = out.v[k] = kNone, out.status[k] = Vector::none;
      } else {
        out.u[k] = median(nu), out.v[k] = median(nv), out.status[k] = Vector::replaced;
      }
    }
  f = std::move(out);
  return replaced;
}

Predictor::Predictor(const VectorField& f) : field(f) {
  // fill the vectors that are none with their neighbours' mean, outwards until none is left
  VectorField& g = field;
  bool any = false;
  for (Vector s : g.status) any = any || s != Vector::none;
  std::vector<std::uint8_t> known(g.u.size());
  for (std::size_t k = 0; k < g.u.size(); ++k) known[k] = any ? g.status[k] != Vector::none : 1;
  if (!any) std::fill(g.u.begin(), g.u.end(), 0.0), std::fill(g.v.begin(), g.v.end(), 0.0);
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::uint8_t> next = known;
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i) {
        const std::size_t k = j * g.nx + i;
        if (known[k]) continue;
        double su = 0.0, sv = 0.0;
        int c = 0;
        for (long dj = -1; dj <= 1; ++dj)
          for (long di = -1; di <= 1; ++di) {
            const long a = static_cast<long>(i) + di, b = static_cast<long>(j) + dj;
            if (a < 0 || b < 0 || a >= static_cast<long>(g.nx) || b >= static_cast<long>(g.ny)) continue;
            const std::size_t q = static_cast<std::size_t>(b) * g.nx + static_cast<std::size_t>(a);
            if (known[q]) su += g.u[q], sv += g.v[q], ++c;
          }
        if (c > 0) g.u[k] = su / c, g.v[k] = sv / c, next[k] = 1, changed = true;
      }
    known = std::move(next);
  }
}

Predictor::Cell Predictor::cell(double x, std::size_t n, double x0, double step) {
  const double f = std::clamp((x - x0) / step, 0.0, static_cast<double>(n - 1));
  Cell c;
  c.i = std::min(static_cast<std::size_t>(f), n > 1 ? n - 2 : 0);
  c.t = n > 1 ? f - static_cast<double>(c.i) : 0.0;
  c.i1 = std::min(c.i + 1, n - 1);
  return c;
}

void Predictor::at(const Cell& cx, const Cell& cy, double& u, double& v) const {
  const VectorField& g = field;
  const auto lerp = [&](const std::vector<double>& q) {
    const double a = q[cy.i * g.nx + cx.i] * (1 - cx.t) + q[cy.i * g.nx + cx.i1] * cx.t;
    const double b = q[cy.i1 * g.nx + cx.i] * (1 - cx.t) + q[cy.i1 * g.nx + cx.i1] * cx.t;
    return a * (1 - cy.t) + b * cy.t;
  };
  u = lerp(g.u), v = lerp(g.v);
}

void Predictor::at(double x, double y, double& u, double& v) const {
  at(column(x), row(y), u, v);
}

VectorField piv(const Image& raw_a, const Image& raw_b, const Mask& mask, const PivSettings& s, int threads, int* passes) {
  if (raw_a.width != raw_b.width || raw_a.height != raw_b.height)
    throw std::invalid_argument("PIV: images of " + std::to_string(raw_a.width) + " x " + std::to_string(raw_a.height) + " and " +
                                std::to_string(raw_b.width) + " x " + std::to_string(raw_b.height) + " px");
  if (s.windows.empty()) throw std::invalid_argument("PIV: no pass");
  // a window is measured only within the largest window of an unmasked pixel (a window more than half
  // masked gives no vector): the images are deformed there, and high-passed within twice that reach
  // (the deformation samples them up to a displacement away; PIV finds none beyond half a window)
  const auto reach = static_cast<std::size_t>(*std::max_element(s.windows.begin(), s.windows.end()));
  std::size_t c0 = 0, c1 = raw_a.width, r0 = 0, r1 = raw_a.height;
  if (!mask.px.empty()) {
    c0 = raw_a.width, c1 = 0, r0 = raw_a.height, r1 = 0;
    for (std::size_t j = 0; j < raw_a.height; ++j)
      for (std::size_t i = 0; i < raw_a.width; ++i)
        if (!mask.at(i, j)) c0 = std::min(c0, i), c1 = std::max(c1, i + 1), r0 = std::min(r0, j), r1 = std::max(r1, j + 1);
    c0 = c0 > reach ? c0 - reach : 0, r0 = r0 > reach ? r0 - reach : 0;
    c1 = std::min(raw_a.width, c1 + reach), r1 = std::min(raw_a.height, r1 + reach);
  }
  const PixelBox filtered{c0 > reach ? c0 - reach : 0, c1 + reach, r0 > reach ? r0 - reach : 0, r1 + reach};
  const Image a = highpass(raw_a, s.highpass_px, filtered), b = highpass(raw_b, s.highpass_px, filtered);
  std::unique_ptr<Predictor> predictor;
  VectorField f;
  Image da, db;  // the images deformed by the predictor
  std::vector<int> plan = s.windows;
  for (std::size_t pass = 0; pass < plan.size(); ++pass) {
    const int n = plan[pass];
    f = window_grid(a.width, a.height, n, s.overlap);
    if (f.nx == 0 || f.ny == 0)
      throw std::invalid_argument("PIV: a window of " + std::to_string(n) + " px does not fit the " + std::to_string(a.width) +
                                  " x " + std::to_string(a.height) + " px image");
    const Image* ia = &a;
    const Image* ib = &b;
    if (predictor) {
      da = a, db = b;
      std::vector<Predictor::Cell> columns(c1 > c0 ? c1 - c0 : 0);
      for (std::size_t i = c0; i < c1; ++i) columns[i - c0] = predictor->column(static_cast<double>(i));
#pragma omp parallel for schedule(static) num_threads(threads)
      for (std::size_t j = r0; j < r1; ++j) {
        const double y = static_cast<double>(j);
        const Predictor::Cell cy = predictor->row(y);
        for (std::size_t i = c0; i < c1; ++i) {
          const double x = static_cast<double>(i);
          double u, v;
          predictor->at(columns[i - c0], cy, u, v);
          da.at(i, j) = static_cast<float>(a.sample(x - 0.5 * u, y - 0.5 * v));
          db.at(i, j) = static_cast<float>(b.sample(x + 0.5 * u, y + 0.5 * v));
        }
      }
      ia = &da, ib = &db;
    }
    const auto N = static_cast<std::size_t>(n);
#pragma omp parallel num_threads(threads)
    {
      WindowCorrelation corr(n);
#pragma omp for schedule(static)
      for (std::size_t wj = 0; wj < f.ny; ++wj)
        for (std::size_t wi = 0; wi < f.nx; ++wi) {
          const std::size_t x0 = static_cast<std::size_t>(f.x(wi) - 0.5 * (n - 1)), y0 = static_cast<std::size_t>(f.y(wj) - 0.5 * (n - 1));
          std::size_t excluded = 0;
          for (std::size_t q = 0; q < N; ++q)
            for (std::size_t p = 0; p < N; ++p) {
              const std::size_t k = q * N + p;
              corr.a()[k] = ia->at(x0 + p, y0 + q);
              corr.b()[k] = ib->at(x0 + p, y0 + q);
              corr.excluded()[k] = mask.at(x0 + p, y0 + q);
              excluded += corr.excluded()[k];
            }
          const std::size_t w = wj * f.nx + wi;
          if (static_cast<double>(excluded) > s.max_excluded * static_cast<double>(N * N)) continue;
          const WindowCorrelation::Peak pk = corr.correlate();
          if (!pk.found) continue;
          double pu = 0.0, pv = 0.0;
          if (predictor) predictor->at(f.x(wi), f.y(wj), pu, pv);
          f.u[w] = pu + pk.dx, f.v[w] = pv + pk.dy, f.status[w] = Vector::measured;
        }
    }
    replace_outliers(f, s.median_threshold, s.median_epsilon);
    // the last pass again while the field still moves
    if (pass + 1 == plan.size() && predictor && plan.size() < s.windows.size() + static_cast<std::size_t>(s.max_repeats)) {
      const VectorField& g = predictor->field;
      double change = 0.0;
      std::size_t count = 0;
      if (g.nx == f.nx && g.ny == f.ny)
        for (std::size_t k = 0; k < f.u.size(); ++k)
          if (f.status[k] != Vector::none)
            change += (f.u[k] - g.u[k]) * (f.u[k] - g.u[k]) + (f.v[k] - g.v[k]) * (f.v[k] - g.v[k]), ++count;
      if (count == 0 || std::sqrt(change / static_cast<double>(count)) > s.converged_px) plan.push_back(n);
    }
    predictor = std::make_unique<Predictor>(f);
  }
  if (passes) *passes = static_cast<int>(plan.size());
  return f;
}

}  // namespace dem2d::analysis
