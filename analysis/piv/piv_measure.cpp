#include "piv/piv_measure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cg/cg_field.hpp"

namespace dem2d::analysis {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

View view_at(const PairSetup& su, Vec2 centre) {
  return View{centre, su.scale, su.camera.width, su.camera.height};
}

// Masked (1): outside the cell (the walls' and floor's faces and wall_margin inside them), above the free
// surface less surface_margin (per pixel column: the highest grain top within a grain diameter either side),
// and the intruder's outline widened by mask_margin. In frame B's pixels; the intruder and the camera move
// together, so one mask serves both frames (the paper's fixed mask zone).
Mask roi_mask(const PairSetup& su, const View& view, const Snapshot& s, const Intruder& in) {
  const std::size_t W = view.width, H = view.height;
  Mask m{W, H, std::vector<std::uint8_t>(W * H, 0)};
  constexpr double kAbove = std::numeric_limits<double>::infinity();
  std::vector<double> top(W, kAbove);  // pixel row of the highest grain top over each column
  for (std::size_t g = 0; g < s.size(); ++g) {
    if (!s.active[g]) continue;
    const Vec2 p = view.px(s.position[g]);
    const double r = 0.5 * s.diameter[g] * view.scale;
    const long i0 = std::max(0L, static_cast<long>(std::ceil(p.x - r))), i1 = std::min(static_cast<long>(W) - 1, static_cast<long>(std::floor(p.x + r)));
    for (long i = i0; i <= i1; ++i) {
      const double dx = static_cast<double>(i) - p.x;
      top[static_cast<std::size_t>(i)] = std::min(top[static_cast<std::size_t>(i)], p.y - std::sqrt(std::max(0.0, r * r - dx * dx)));
    }
  }
  const long reach = static_cast<long>(std::ceil(su.d * view.scale));
  std::vector<double> surface(W, kAbove);
  for (long i = 0; i < static_cast<long>(W); ++i)
    for (long q = std::max(0L, i - reach); q <= std::min(static_cast<long>(W) - 1, i + reach); ++q)
      surface[static_cast<std::size_t>(i)] = std::min(surface[static_cast<std::size_t>(i)], top[static_cast<std::size_t>(q)]);
  const double half = in.top - in.yc, ax = in.left + half, bx = in.right - half, reach_in = half + su.mask_margin;
  const double margin_px = su.surface_margin * view.scale;
  for (std::size_t j = 0; j < H; ++j)
    for (std::size_t i = 0; i < W; ++i) {
      const Vec2 w = view.world({static_cast<double>(i), static_cast<double>(j)});
      const double sx = std::clamp(w.x, ax, bx);
      const bool out = w.x < su.cell.left + su.wall_margin || w.x > su.cell.right - su.wall_margin ||
                       w.y < su.cell.floor + su.wall_margin || !(static_cast<double>(j) >= surface[i] + margin_px) ||
                       std::hypot(w.x - sx, w.y - in.yc) < reach_in;
      m.px[j * W + i] = out ? 1 : 0;
    }
  return m;
}

// The PIV's vector grid in the lab frame at frame B: node (i, j) is vector (i, ny - 1 - j) (image rows run down).
Grid world_grid(const VectorField& f, const View& view) {
  Grid g;
  g.nx = f.nx, g.ny = f.ny, g.dx = f.step / view.scale;
  const Vec2 low = view.world({f.x(0), f.y(f.ny - 1)});
  g.x0 = low.x, g.y0 = low.y;
  return g;
}

double median_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d;
  for (std::size_t q = 0; q < a.size(); ++q)
    if (!std::isnan(a[q]) && !std::isnan(b[q])) d.push_back(std::abs(a[q] - b[q]));
  if (d.empty()) return kNaN;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t q = 0; q < a.size(); ++q)
    if (!std::isnan(a[q]) && !std::isnan(b[q])) s += (a[q] - b[q]) * (a[q] - b[q]), ++n;
  return n > 0 ? std::sqrt(s / static_cast<double>(n)) : kNaN;
}

// lambda_ci of the nodes within `radius` of c (NaN nodes left out)
std::vector<float> disc(const Grid& g, const std::vector<double>& swirl, Vec2 c, double radius) {
  std::vector<float> out;
  const Grid::Range cols = g.columns(c.x - radius, c.x + radius), rows = g.rows(c.y - radius, c.y + radius);
  for (std::size_t j = rows.first; j < rows.last; ++j)
    for (std::size_t i = cols.first; i < cols.last; ++i) {
      const double v = swirl[g.at(i, j)];
      if (!std::isnan(v) && std::hypot(g.x(i) - c.x, g.y(j) - c.y) <= radius) out.push_back(static_cast<float>(v));
    }
  return out;
}

}  // namespace

std::vector<double> swirl_strength(const Grid& g, const std::vector<double>& vx, const std::vector<double>& vy,
                                   double min_share) {
  std::vector<double> out(g.size(), kNaN);
  if (g.nx < 3 || g.ny < 3) return out;
  const double h2 = 2.0 * g.dx;
  for (std::size_t j = 1; j + 1 < g.ny; ++j)
    for (std::size_t i = 1; i + 1 < g.nx; ++i) {
      const std::size_t e = g.at(i + 1, j), w = g.at(i - 1, j), n = g.at(i, j + 1), s = g.at(i, j - 1);
      const double ux = (vx[e] - vx[w]) / h2, uy = (vx[n] - vx[s]) / h2;
      const double wx = (vy[e] - vy[w]) / h2, wy = (vy[n] - vy[s]) / h2;
      if (std::isnan(ux + uy + wx + wy)) continue;
      const double tr = ux + wy, det = ux * wy - uy * wx, disc = 4.0 * det - tr * tr;
      const double lambda = disc > 0.0 ? 0.5 * std::sqrt(disc) : 0.0;
      const double norm = std::sqrt(ux * ux + uy * uy + wx * wx + wy * wy);
      out[g.at(i, j)] = lambda > 0.0 && lambda >= min_share * norm ? lambda : 0.0;
    }
  return out;
}

PairMeasure measure_pair(const PairSetup& su, const Snapshot& s, const std::vector<Vec2>& disp, double interval,
                         unsigned seed, bool keep_maps, bool keep_frames) {
  PairMeasure m;
  m.time = s.time;
  if (disp.size() != s.size()) {
    m.why = "no frame A: it would lie before the run's first snapshot";
    return m;
  }
  for (std::size_t g = 0; g < s.size(); ++g)
    if (s.active[g] && !(std::isfinite(disp[g].x) && std::isfinite(disp[g].y))) {
      m.why = "a grain without a displacement (frame A lies before the run's start, or the grain was not in the bed then)";
      return m;
    }
  const Intruder in = intruder_of(s.bodies[static_cast<std::size_t>(su.intruder)]);
  m.in = in;
  m.height = in.yc - su.cell.floor;
  // frame B: the snapshot; frame A: the grains and the camera one frame interval earlier
  auto t0 = std::chrono::steady_clock::now();
  const View vb = view_at(su, {in.xc, in.yc});
  const View va = view_at(su, {in.xc - su.V.x * interval, in.yc - su.V.y * interval});
  std::vector<Vec2> before(s.size());
  for (std::size_t g = 0; g < s.size(); ++g) before[g] = {s.position[g].x - disp[g].x, s.position[g].y - disp[g].y};
  Image a = render(va, su.camera, before, s.diameter, s.active, 2 * seed + 1);
  Image b = render(vb, su.camera, s.position, s.diameter, s.active, 2 * seed + 2);
  const Mask mask = roi_mask(su, vb, s, in);
  m.render_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  VectorField f = piv(a, b, mask, su.piv, 1, &m.passes);
  m.piv_s = seconds_since(t0);
  const Grid g = world_grid(f, vb);
  m.grid = g;
  m.replaced = f.count(Vector::replaced);
  // the image displacement is the grains' less the camera's: lab velocity = u / (scale interval) + V, y up
  std::vector<double> vx[2], vy[2];
  for (auto* v : {vx, vy}) v[kPivSide].assign(g.size(), kNaN);
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const std::size_t q = (g.ny - 1 - j) * f.nx + i, n = g.at(i, j);
      const auto pi = static_cast<std::size_t>(std::lround(f.x(i))), pj = static_cast<std::size_t>(std::lround(f.y(g.ny - 1 - j)));
      if (f.status[q] == Vector::none || mask.at(pi, pj)) continue;  // no vector, or its centre masked
      vx[kPivSide][n] = f.u[q] / (su.scale * interval) + su.V.x;
      vy[kPivSide][n] = -f.v[q] / (su.scale * interval) + su.V.y;
      ++m.vectors;
    }

  // the coarse-grained field of the grains' displacements over the same interval, on the same nodes
  t0 = std::chrono::steady_clock::now();
  std::vector<Vec2> vpiv(s.size());
  for (std::size_t p = 0; p < s.size(); ++p) vpiv[p] = {disp[p].x / interval, disp[p].y / interval};
  Grains grains{s.position, s.mass, s.diameter, s.active, {vpiv}};
  const Fields cg = coarse_grain(g, su.kernel, grains);
  std::vector<double> phi_roi;
  for (std::size_t n = 0; n < g.size(); ++n)
    if (!std::isnan(vx[kPivSide][n])) phi_roi.push_back(cg.phi[n]);
  double phi_ref = 0.0;
  if (!phi_roi.empty()) {
    std::nth_element(phi_roi.begin(), phi_roi.begin() + static_cast<long>(phi_roi.size() / 2), phi_roi.end());
    phi_ref = phi_roi[phi_roi.size() / 2];
  }
  const Velocity vc = velocity(cg, 0, su.cg.mask_fraction * phi_ref);
  vx[kCgSide] = vc.vx, vy[kCgSide] = vc.vy;
  m.cg_s = seconds_since(t0);

  // the nodes both have
  for (std::size_t n = 0; n < g.size(); ++n) {
    if (std::isnan(vx[kPivSide][n]) || std::isnan(vx[kCgSide][n])) {
      for (std::size_t k = 0; k < 2; ++k) vx[k][n] = vy[k][n] = kNaN;
    } else {
      ++m.common;
    }
  }
  m.surface = kNaN;
  for (std::size_t g2 = 0; g2 < s.size(); ++g2)
    if (s.active[g2] && std::abs(s.position[g2].x - in.xc) < 0.5 * (su.cell.right - su.cell.left))
      m.surface = std::isnan(m.surface) ? s.position[g2].y + 0.5 * s.diameter[g2] - su.cell.floor
                                        : std::max(m.surface, s.position[g2].y + 0.5 * s.diameter[g2] - su.cell.floor);
  if (m.common == 0) {
    m.why = "no node has both a PIV vector and a coarse-grained velocity";
    return m;
  }
  std::vector<double> vstar[2], vframe[2];
  const Vec2 left_tip{in.left, in.yc}, right_tip{in.right, in.yc};
  for (std::size_t k = 0; k < 2; ++k) {
    const Velocity v{vx[k], vy[k]};
    vstar[k] = speed_ratio(v, 0.0, 0.0, su.v_ref);
    vframe[k] = speed_ratio(v, su.V.x, su.V.y, su.v_ref);
    Side& sd = m.side[k];
    sd.zones = zone_areas(g, vstar[k], su.cg.immobile_below, su.cg.dragged_above);
    const auto zone = zone_from_intruder(g, vstar[k], su.cg.level, in, su.cg.seed_depth_d * su.d);
    sd.cone = fit_cone(g, zone, in, in.top + su.cg.fit_start_w * su.kernel.w, su.cg.fit_min_span_d * su.d);
    sd.beta = sd.cone.beta_deg(kVerticalEdgeDeg);
    std::vector<double> swirl = swirl_strength(g, vx[k], vy[k], su.min_swirl_share);
    for (double& x : swirl) x *= su.d / su.v_ref;  // x V / d
    for (std::size_t j = 0; j < g.ny; ++j)
      if (g.y(j) < in.yc - su.rest_below)
        for (std::size_t i = 0; i < g.nx; ++i)
          if (!std::isnan(swirl[g.at(i, j)])) sd.rest_swirl.push_back(static_cast<float>(swirl[g.at(i, j)]));
    sd.tip_swirl[0] = disc(g, swirl, left_tip, su.tip_radius);
    sd.tip_swirl[1] = disc(g, swirl, right_tip, su.tip_radius);
    // the control discs: the region at rest's lower corners, inside the region of interest
    const double r = su.tip_radius, low = std::max(g.y0, su.cell.floor + su.wall_margin) + r;
    if (low + r < in.yc - su.rest_below) {
      sd.control_swirl[0] = disc(g, swirl, {su.cell.left + su.wall_margin + r, low}, r);
      sd.control_swirl[1] = disc(g, swirl, {su.cell.right - su.wall_margin - r, low}, r);
    }
    if (keep_maps) {
      sd.vstar_frame.assign(vframe[k].begin(), vframe[k].end());
      sd.swirl = std::move(swirl);
    }
  }
  m.rms_vstar = rms_difference(vstar[kPivSide], vstar[kCgSide]);
  m.rms_vstar_frame = rms_difference(vframe[kPivSide], vframe[kCgSide]);
  m.median_vstar = median_abs_difference(vstar[kPivSide], vstar[kCgSide]);
  if (keep_frames) m.a = std::move(a), m.b = std::move(b);
  m.valid = true;
  return m;
}

}  // namespace dem2d::analysis
