#include "cg/cg_measure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace dem2d::analysis {

std::vector<double> speed_ratio(const Velocity& v, double frame_vx, double frame_vy, double v_ref) {
  std::vector<double> s(v.vx.size());
  for (std::size_t n = 0; n < s.size(); ++n) s[n] = std::hypot(v.vx[n] - frame_vx, v.vy[n] - frame_vy) / v_ref;
  return s;
}

ZoneAreas zone_areas(const Grid& g, const std::vector<double>& vstar, double lo, double hi) {
  ZoneAreas a;
  const double cell = g.dx * g.dx;
  for (const double v : vstar) {
    if (std::isnan(v)) continue;
    (v < lo ? a.immobile : v > hi ? a.dragged : a.cone) += cell;
  }
  return a;
}

std::vector<std::uint8_t> zone_from_intruder(const Grid& g, const std::vector<double>& vstar, double level,
                                             const Intruder& in, double seed_depth) {
  std::vector<std::uint8_t> zone(g.size(), 0);
  std::vector<std::size_t> stack;
  const auto push = [&](std::size_t n) {
    if (!zone[n] && vstar[n] >= level) zone[n] = 1, stack.push_back(n);  // (NaN >= level is false)
  };
  for (std::size_t j = 0; j < g.ny; ++j) {
    if (g.y(j) < in.top || g.y(j) > in.top + seed_depth) continue;
    for (std::size_t i = 0; i < g.nx; ++i)
      if (g.x(i) >= in.left && g.x(i) <= in.right) push(g.at(i, j));
  }
  while (!stack.empty()) {
    const std::size_t n = stack.back();
    stack.pop_back();
    const std::size_t i = n % g.nx, j = n / g.nx;
    if (i > 0) push(n - 1);
    if (i + 1 < g.nx) push(n + 1);
    if (j > 0) push(n - g.nx);
    if (j + 1 < g.ny) push(n + g.nx);
  }
  return zone;
}

ZoneExtent zone_extent(const Grid& g, const std::vector<std::uint8_t>& zone, const Intruder& in) {
  ZoneExtent e;
  for (std::size_t n = 0; n < zone.size(); ++n) {
    if (!zone[n]) continue;
    e.area += g.dx * g.dx;
    const double h = g.y(n / g.nx) - in.top;
    e.height = std::isnan(e.height) ? h : std::max(e.height, h);
  }
  return e;
}

namespace {

// Least-squares line x = a + b y through the points; fills slope, x at y0, rms.
void fit_line(const std::vector<double>& ys, const std::vector<double>& xs, double outward, double y0,
              double min_span, EdgeFit& e) {
  e.points = static_cast<int>(ys.size());
  if (ys.size() < 2 || ys.back() - ys.front() < min_span) return;
  const double n = static_cast<double>(ys.size());
  const double my = std::accumulate(ys.begin(), ys.end(), 0.0) / n;
  const double mx = std::accumulate(xs.begin(), xs.end(), 0.0) / n;
  double syy = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < ys.size(); ++k) {
    syy += (ys[k] - my) * (ys[k] - my);
    sxy += (ys[k] - my) * (xs[k] - mx);
  }
  const double b = sxy / syy, a = mx - b * my;
  double ss = 0.0;
  for (std::size_t k = 0; k < ys.size(); ++k) ss += std::pow(xs[k] - (a + b * ys[k]), 2);
  e.slope = b * outward;
  e.x_at_y0 = a + b * y0;
  e.rms = std::sqrt(ss / n);
  // = atan2(1, slope) in degrees, but exactly 90 for a vertical edge (slope 0 or -0)
  e.beta_deg = kVerticalEdgeDeg - std::atan(e.slope) * 180.0 / std::numbers::pi;
}

// Mean of the values a and b that are used (NaN if neither).
double mean_of_used(double a, bool use_a, double b, bool use_b) {
  return use_a && use_b ? 0.5 * (a + b) : use_a ? a : use_b ? b : kNaN;
}

}  // namespace

double ConeFit::beta_deg(double max_deg) const {
  return mean_of_used(left.beta_deg, !std::isnan(left.beta_deg) && !left.excluded(max_deg), right.beta_deg,
                      !std::isnan(right.beta_deg) && !right.excluded(max_deg));
}

double ConeFit::wall_y(double max_deg) const {
  return mean_of_used(left.wall_y, left.meets_wall && !left.excluded(max_deg), right.wall_y,
                      right.meets_wall && !right.excluded(max_deg));
}

ConeFit fit_cone(const Grid& g, const std::vector<std::uint8_t>& zone, const Intruder& in, double y_start,
                 double min_span) {
  ConeFit fit;
  std::vector<double> yl, xl, yr, xr;
  bool open_l = true, open_r = true;
  for (std::size_t j = 0; j < g.ny && (open_l || open_r); ++j) {
    if (g.y(j) < y_start) continue;
    std::size_t lo = g.nx, hi = 0;
    for (std::size_t i = 0; i < g.nx; ++i)
      if (zone[g.at(i, j)]) lo = std::min(lo, i), hi = std::max(hi, i);
    if (lo == g.nx) break;  // the zone ended below this row
    if (open_l) {
      if (lo == 0) {
        open_l = false, fit.left.meets_wall = true, fit.left.wall_y = g.y(j);
      } else if (g.x(lo) >= in.xc) {
        open_l = false;
      } else {
        yl.push_back(g.y(j)), xl.push_back(g.x(lo));
      }
    }
    if (open_r) {
      if (hi == g.nx - 1) {
        open_r = false, fit.right.meets_wall = true, fit.right.wall_y = g.y(j);
      } else if (g.x(hi) <= in.xc) {
        open_r = false;
      } else {
        yr.push_back(g.y(j)), xr.push_back(g.x(hi));
      }
    }
  }
  fit_line(yl, xl, -1.0, y_start, min_span, fit.left);
  fit_line(yr, xr, +1.0, y_start, min_span, fit.right);
  return fit;
}

std::vector<double> wall_profile(const Grid& g, const std::vector<double>& vstar, double x_face, double band) {
  std::vector<double> out(g.ny, kNaN);
  for (std::size_t j = 0; j < g.ny; ++j) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double v = vstar[g.at(i, j)];
      if (std::abs(g.x(i) - x_face) < band && !std::isnan(v)) sum += v, ++n;
    }
    if (n > 0) out[j] = sum / n;
  }
  return out;
}

namespace {

// The grains near a node column, listed per row (compressed rows): row j lists, in the order of
// `near`, those within one row of reaching it (|dy| <= R + dx); the exact cut-off is tested where
// they are used. Each row then visits its own grains, not the whole column's.
struct RowLists {
  std::vector<std::size_t> first, grain;  // row j's grains: grain[first[j] .. first[j + 1])
};

RowLists row_lists(const Grid& g, const Grains& grains, const std::vector<std::size_t>& near, double R) {
  const auto rows_of = [&](std::size_t i) {  // [a, b): the rows within R + dx of grain i
    const double y = (grains.position[i].y - g.y0) / g.dx, reach = R / g.dx + 1.0;
    if (!std::isfinite(y)) return std::pair{std::size_t{0}, g.ny};  // every row (and its fit) sees it
    const double a = std::clamp(std::floor(y - reach), 0.0, static_cast<double>(g.ny));
    const double b = std::clamp(std::ceil(y + reach) + 1.0, 0.0, static_cast<double>(g.ny));
    return std::pair{static_cast<std::size_t>(a), static_cast<std::size_t>(b)};
  };
  RowLists l;
  l.first.assign(g.ny + 1, 0);
  for (const std::size_t i : near) {
    const auto [a, b] = rows_of(i);
    for (std::size_t j = a; j < b; ++j) ++l.first[j + 1];
  }
  std::partial_sum(l.first.begin(), l.first.end(), l.first.begin());
  l.grain.resize(l.first.back());
  std::vector<std::size_t> fill(l.first.begin(), l.first.end() - 1);
  for (const std::size_t i : near) {
    const auto [a, b] = rows_of(i);
    for (std::size_t j = a; j < b; ++j) l.grain[fill[j]++] = i;
  }
  return l;
}

}  // namespace

std::vector<double> local_linear_profile(const Grid& g, const Kernel& k, const Grains& grains, std::size_t set,
                                         double x, double v_ref, const std::vector<std::uint8_t>& valid,
                                         LocalLinearExtras* extras) {
  std::vector<double> out(g.ny, kNaN);
  if (extras) extras->vx.assign(g.ny, kNaN), extras->vy = extras->vx, extras->gain = extras->vx;
  const double R = k.radius(), volume = k.volume();
  std::vector<std::size_t> near;  // grains within the cut-off of the column
  for (std::size_t i = 0; i < grains.position.size(); ++i)
    if (grains.active[i] && std::abs(grains.position[i].x - x) <= R) near.push_back(i);
  const RowLists rows = row_lists(g, grains, near, R);
  const auto& v = grains.velocities[set];
  struct Term {
    double w, dx, dy;
  };
  std::vector<Term> terms;  // one row's grains within the cut-off, in the order summed
  for (std::size_t j = 0; j < g.ny; ++j) {
    if (!valid[j]) continue;
    const double y = g.y(j);
    // weighted normal equations of v ~ a + b dx + c dy, both components at once
    double A[3][3] = {}, bx[3] = {}, by[3] = {};
    terms.clear();
    for (std::size_t n = rows.first[j]; n < rows.first[j + 1]; ++n) {
      const std::size_t i = rows.grain[n];
      const double dy = grains.position[i].y - y;
      if (std::abs(dy) > R) continue;  // (beyond the cut-off: the same test as r > R, without the root)
      const double dx = grains.position[i].x - x, r = std::hypot(dx, dy);
      if (r > R) continue;
      const double w = grains.mass[i] * k.inside(r, volume), f[3] = {1.0, dx, dy};  // m_i G(r)
      terms.push_back({w, dx, dy});
      for (int a = 0; a < 3; ++a) {
        bx[a] += w * f[a] * v[i].x, by[a] += w * f[a] * v[i].y;
        for (int b = 0; b < 3; ++b) A[a][b] += w * f[a] * f[b];
      }
    }
    // Cramer's rule for the intercept; singular (or nearly) -> NaN
    auto det3 = [](const double m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double D = det3(A);
    if (!(std::abs(D) > 1e-12 * A[0][0] * A[1][1] * A[2][2]) || !(A[0][0] > 0.0)) continue;
    auto intercept = [&](const double b[3]) {
      double M[3][3];
      for (int a = 0; a < 3; ++a) M[a][0] = b[a], M[a][1] = A[a][1], M[a][2] = A[a][2];
      return det3(M) / D;
    };
    const double vx = intercept(bx) / v_ref, vy = intercept(by) / v_ref;
    out[j] = std::hypot(vx, vy);
    if (!extras) continue;
    extras->vx[j] = vx, extras->vy[j] = vy;
    // the intercept is sum_i l_i v_i with l_i = w_i (first row of A^-1) . f_i:
    // its noise per component, for unit independent noise per grain, is |l|
    const double r[3] = {(A[1][1] * A[2][2] - A[1][2] * A[2][1]) / D, (A[0][2] * A[2][1] - A[0][1] * A[2][2]) / D,
                         (A[0][1] * A[1][2] - A[0][2] * A[1][1]) / D};
    double ll = 0.0;
    for (const Term& t : terms) {
      const double l = t.w * (r[0] + r[1] * t.dx + r[2] * t.dy);
      ll += l * l;
    }
    extras->gain[j] = std::sqrt(ll);
  }
  return out;
}

double mobile_length(const Grid& g, const std::vector<double>& profile, double y_from, double level) {
  double length = 0.0;
  for (std::size_t j = 0; j < g.ny; ++j)
    if (g.y(j) >= y_from && profile[j] >= level) length += g.dx;
  return length;
}

double region_mean(const Grid& g, const std::vector<double>& field, double xmin, double xmax, double ymin,
                   double ymax) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t j = 0; j < g.ny; ++j) {
    if (g.y(j) < ymin || g.y(j) > ymax) continue;
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double v = field[g.at(i, j)];
      if (g.x(i) >= xmin && g.x(i) <= xmax && !std::isnan(v)) sum += v, ++n;
    }
  }
  return n > 0 ? sum / n : kNaN;
}

}  // namespace dem2d::analysis
