#include "cg/cg_field.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/units.hpp"
#include "core/hot_loop.hpp"

namespace dem2d::analysis {

DEM2D_HOT Fields coarse_grain(const Grid& g, const Kernel& kernel, const Grains& grains) {
  const std::size_t nodes = g.size(), sets = grains.velocities.size();
  Fields f;
  f.rho.assign(nodes, 0.0);
  f.phi.assign(nodes, 0.0);
  f.px.assign(sets, std::vector<double>(nodes, 0.0));
  f.py.assign(sets, std::vector<double>(nodes, 0.0));
  const double R = kernel.radius(), R2 = R * R, inv2w2 = 1.0 / (2.0 * kernel.w * kernel.w);
  const double norm = 1.0 / kernel.volume();
  const auto span = static_cast<std::size_t>(std::ceil(2.0 * R / g.dx)) + 2;
  std::vector<double> gx(span), gy(span), c(2 + 2 * sets);
  std::vector<double*> rows(c.size());

  for (std::size_t p = 0; p < grains.position.size(); ++p) {
    if (!grains.active[p]) continue;
    const Vec2 r = grains.position[p];
    // node ranges within R of the grain, clipped to the grid
    const auto lo = [&](double v, double v0, std::size_t n) {
      return static_cast<std::size_t>(std::clamp(std::ceil((v - R - v0) / g.dx), 0.0, static_cast<double>(n)));
    };
    const auto hi = [&](double v, double v0, std::size_t n) {  // one past the last
      return static_cast<std::size_t>(std::clamp(std::floor((v + R - v0) / g.dx) + 1.0, 0.0, static_cast<double>(n)));
    };
    const std::size_t i0 = lo(r.x, g.x0, g.nx), i1 = hi(r.x, g.x0, g.nx);
    const std::size_t j0 = lo(r.y, g.y0, g.ny), j1 = hi(r.y, g.y0, g.ny);
    if (i0 >= i1 || j0 >= j1) continue;
    for (std::size_t i = i0; i < i1; ++i) {
      const double X = g.x(i) - r.x;
      gx[i - i0] = std::exp(-X * X * inv2w2);
    }
    const double m = grains.mass[p], d = grains.diameter[p];
    c[0] = m * norm;
    c[1] = 0.25 * std::numbers::pi * d * d * norm;
    for (std::size_t s = 0; s < sets; ++s) {
      c[2 + 2 * s] = m * grains.velocities[s][p].x * norm;
      c[3 + 2 * s] = m * grains.velocities[s][p].y * norm;
    }
    for (std::size_t j = j0; j < j1; ++j) {
      const double Y = g.y(j) - r.y, room = R2 - Y * Y;
      if (room < 0.0) continue;
      // columns with X^2 <= R^2 - Y^2 (X = x_i - r.x)
      const double half = std::sqrt(room);
      const std::size_t a = std::max(i0, lo(r.x + R - half, g.x0, g.nx));
      const std::size_t b = std::min(i1, hi(r.x - R + half, g.x0, g.nx));
      if (a >= b) continue;
      const double gyj = std::exp(-Y * Y * inv2w2);
      const std::size_t row = g.at(0, j);
      rows[0] = f.rho.data() + row;
      rows[1] = f.phi.data() + row;
      for (std::size_t s = 0; s < sets; ++s) {
        rows[2 + 2 * s] = f.px[s].data() + row;
        rows[3 + 2 * s] = f.py[s].data() + row;
      }
      const double* wx = gx.data() - i0;
      for (std::size_t q = 0; q < c.size(); ++q) {
        double* out = rows[q];
        const double k = c[q] * gyj;
        for (std::size_t i = a; i < b; ++i) out[i] += k * wx[i];
      }
    }
  }
  return f;
}

void accumulate(Fields& sum, const Fields& add) {
  const auto plus = [](std::vector<double>& a, const std::vector<double>& b) {
    for (std::size_t n = 0; n < a.size(); ++n) a[n] += b[n];
  };
  plus(sum.rho, add.rho);
  plus(sum.phi, add.phi);
  for (std::size_t s = 0; s < sum.px.size(); ++s) plus(sum.px[s], add.px[s]), plus(sum.py[s], add.py[s]);
}

void scale(Fields& f, double factor) {
  const auto times = [factor](std::vector<double>& a) {
    for (double& v : a) v *= factor;
  };
  times(f.rho);
  times(f.phi);
  for (auto& v : f.px) times(v);
  for (auto& v : f.py) times(v);
}

namespace {

// Adds `in` moved by (sx, sy) metres, times `weight`, into `out`: out(i, j) +=
// weight x in at (x_i - sx, y_j - sy), bilinear between the nodes, 0 beyond the grid.
void add_moved(std::vector<double>& out, const std::vector<double>& in, const Grid& g, double sx, double sy, double weight) {
  const double u = -sx / g.dx, v = -sy / g.dx;  // where a node's value comes from, in nodes
  const double fu = std::floor(u), fv = std::floor(v), a = u - fu, b = v - fv;
  const double w[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  const auto nx = static_cast<long long>(g.nx), ny = static_cast<long long>(g.ny);
  // beyond the grid (or a shift that is not a number): nothing to add
  if (!(std::abs(fu) < static_cast<double>(nx + 1) && std::abs(fv) < static_cast<double>(ny + 1))) return;
  for (int c = 0; c < 4; ++c) {
    if (w[c] == 0.0) continue;
    const long long si = static_cast<long long>(fu) + (c & 1), sj = static_cast<long long>(fv) + (c >> 1);
    const long long i0 = std::max(0LL, -si), i1 = std::min(nx, nx - si);
    const long long j0 = std::max(0LL, -sj), j1 = std::min(ny, ny - sj);
    const double wc = weight * w[c];
    for (long long j = j0; j < j1; ++j) {
      double* o = out.data() + j * nx;
      const double* s = in.data() + (j + sj) * nx + si;
      for (long long i = i0; i < i1; ++i) o[i] += wc * s[i];
    }
  }
}

}  // namespace

Fields frame_average(const Grid& g, const std::vector<const Fields*>& fields, const std::vector<Vec2>& at) {
  const Fields& last = *fields.back();
  Fields out{std::vector<double>(last.rho.size(), 0.0), std::vector<double>(last.phi.size(), 0.0),
             std::vector<std::vector<double>>(last.px.size(), std::vector<double>(last.rho.size(), 0.0)),
             std::vector<std::vector<double>>(last.py.size(), std::vector<double>(last.rho.size(), 0.0))};
  const double weight = 1.0 / static_cast<double>(fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const Fields& f = *fields[k];
    const double sx = at.back().x - at[k].x, sy = at.back().y - at[k].y;
    add_moved(out.rho, f.rho, g, sx, sy, weight);
    add_moved(out.phi, f.phi, g, sx, sy, weight);
    for (std::size_t s = 0; s < out.px.size(); ++s) {
      add_moved(out.px[s], f.px[s], g, sx, sy, weight);
      add_moved(out.py[s], f.py[s], g, sx, sy, weight);
    }
  }
  return out;
}

Velocity velocity(const Fields& f, std::size_t set, double min_phi) {
  Velocity v;
  v.vx.assign(f.rho.size(), kNaN);
  v.vy.assign(f.rho.size(), kNaN);
  for (std::size_t n = 0; n < f.rho.size(); ++n)
    if (f.phi[n] >= min_phi && f.rho[n] > 0.0) {
      v.vx[n] = f.px[set][n] / f.rho[n];
      v.vy[n] = f.py[set][n] / f.rho[n];
    }
  return v;
}

}  // namespace dem2d::analysis
