#include "cg/cg_snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dem2d::analysis {

namespace {

std::vector<float> to_f32(const std::vector<double>& v) { return {v.begin(), v.end()}; }

double median_of(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The intruder-frame velocity in a window of nodes centred on the intruder
// (the window's origin snapped to the nearest node): [tip_ny][tip_nx], NaN outside the grid.
std::vector<float> tip_window(const Setup& su, const Velocity& v, const Intruder& in, bool vertical) {
  const Grid& g = su.grid;
  const double i0 = std::round((in.xc - g.x0) / g.dx) - static_cast<double>(su.tip_nx / 2);
  const double j0 = std::round((in.yc - g.y0) / g.dx) - static_cast<double>(su.tip_ny / 2);
  std::vector<float> out(su.tip_nx * su.tip_ny, std::numeric_limits<float>::quiet_NaN());
  for (std::size_t b = 0; b < su.tip_ny; ++b)
    for (std::size_t a = 0; a < su.tip_nx; ++a) {
      const double i = i0 + static_cast<double>(a), j = j0 + static_cast<double>(b);
      if (i < 0 || j < 0 || i >= static_cast<double>(g.nx) || j >= static_cast<double>(g.ny)) continue;
      const std::size_t n = g.at(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
      out[b * su.tip_nx + a] =
          static_cast<float>(vertical ? v.vy[n] - su.pull.velocity.y : v.vx[n] - su.pull.velocity.x);
    }
  return out;
}

SourceMeasure measure_source(const Setup& su, const CgConfig& c, const Velocity& v, const Intruder& in,
                             std::vector<double>* wall_profiles /* [2][ny] of the primary band, or null */) {
  const Grid& g = su.grid;
  SourceMeasure m;
  m.valid = true;
  const std::vector<double> vstar = speed_ratio(v, 0.0, 0.0, su.v_ref);
  const double seed = c.seed_depth_d * su.d;
  m.zones = zone_areas(g, vstar, c.immobile_below, c.dragged_above);
  m.red = zone_extent(g, zone_from_intruder(g, vstar, c.dragged_above, in, seed), in);
  m.median_vstar = median_of(vstar);
  for (std::size_t l = 0; l < su.levels.size(); ++l) {
    const std::vector<std::uint8_t> zone = zone_from_intruder(g, vstar, su.levels[l], in, seed);
    if (l == su.level0) m.mobile = zone_extent(g, zone, in);
    for (const double start : su.starts)
      m.cone.push_back(fit_cone(g, zone, in, in.top + start, c.fit_min_span_d * su.d));
  }
  // wall bands: the profiles of each band width, then the mobile length per [level][band]
  std::vector<std::vector<double>> left, right;
  for (const double band : su.bands) {
    left.push_back(wall_profile(g, vstar, su.cell.left, band));
    right.push_back(wall_profile(g, vstar, su.cell.right, band));
  }
  if (wall_profiles) wall_profiles[0] = left[su.band0], wall_profiles[1] = right[su.band0];
  for (const double level : su.levels)
    for (std::size_t b = 0; b < su.bands.size(); ++b) {
      m.wall_left.push_back(mobile_length(g, left[b], in.yc, level));
      m.wall_right.push_back(mobile_length(g, right[b], in.yc, level));
    }
  return m;
}

}  // namespace

SnapshotMeasure measure_snapshot(const Setup& su, const CgConfig& c, const Fields& f, bool piv, const Fields& moving,
                                 bool moving_piv, const Snapshot& s, const Intruder& in, bool full_fields,
                                 std::size_t primary) {
  const Grid& g = su.grid;
  SnapshotMeasure m;
  m.time = s.time;
  m.intruder = in;
  m.height = in.yc - su.cell.floor;
  m.surface = bed_surface(s, su.cell, su.d).height;
  // dilatancy regions: following the intruder, and fixed where it started
  const double half = 0.5 * c.region_width_L * in.length(), offset = c.region_offset_w * su.kernel.w;
  for (const double h : su.heights) {
    const double y0 = in.top + offset, y0_fixed = su.start.top + offset;
    m.phi_follow.push_back(region_mean(g, f.phi, in.xc - half, in.xc + half, y0, y0 + h));
    m.phi_fixed.push_back(region_mean(g, f.phi, su.start.xc - half, su.start.xc + half, y0_fixed, y0_fixed + h));
  }
  m.centre_phi.resize(g.ny);
  for (std::size_t j = 0; j < g.ny; ++j) m.centre_phi[j] = static_cast<float>(f.phi[g.at(su.centre_i, j)]);
  if (full_fields) m.phi_field = to_f32(f.phi);
  for (std::size_t set = 0; set < 2; ++set) {
    m.centre_vy[set].assign(g.ny, std::numeric_limits<float>::quiet_NaN());
    for (auto& t : m.tip[set]) t.assign(su.tip_nx * su.tip_ny, std::numeric_limits<float>::quiet_NaN());
    if (full_fields)
      for (auto& fv : m.v_field[set]) fv.assign(g.size(), std::numeric_limits<float>::quiet_NaN());
    if (set == kPiv && !piv) continue;
    const Velocity v = velocity(f, set, su.min_phi);
    if (set == kInst || moving_piv) {
      const bool same = &moving == &f;
      const Velocity vm = same ? Velocity{} : velocity(moving, set, su.min_phi);
      std::vector<double> walls[2];
      m.src[set] = measure_source(su, c, same ? v : vm, m.intruder, set == primary ? walls : nullptr);
      if (set == primary)
        for (int w = 0; w < 2; ++w) m.wall_vstar[w] = to_f32(walls[w]);
    }
    for (std::size_t j = 0; j < g.ny; ++j) m.centre_vy[set][j] = static_cast<float>(v.vy[g.at(su.centre_i, j)]);
    m.tip[set][0] = tip_window(su, v, m.intruder, false);
    m.tip[set][1] = tip_window(su, v, m.intruder, true);
    if (full_fields) m.v_field[set][0] = to_f32(v.vx), m.v_field[set][1] = to_f32(v.vy);
  }
  for (int w = 0; w < 2; ++w) {
    if (m.wall_vstar[w].empty()) m.wall_vstar[w].assign(g.ny, std::numeric_limits<float>::quiet_NaN());
    m.wall_local[w].assign(g.ny, std::numeric_limits<float>::quiet_NaN());  // add_wall_profiles
    m.wall_gain[w] = m.wall_vx[w] = m.wall_vy[w] = m.wall_local[w];
  }
  return m;
}

double upper_quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double pos = std::ceil(q * static_cast<double>(sorted.size())) - 1.0;
  return sorted[static_cast<std::size_t>(std::clamp(pos, 0.0, static_cast<double>(sorted.size() - 1)))];
}

double cone_level(const Setup& su, const CgConfig& c, double false_alarm) {
  const double q = upper_quantile(su.rest_nodes, 1.0 - false_alarm);
  return std::isfinite(q) ? std::max(c.level, q) : c.level;
}

void add_wall_profiles(const Setup& su, const CgConfig& c, const Fields& f, const Grains& grains, std::size_t set,
                       SnapshotMeasure& m) {
  const Grid& g = su.grid;
  const double half = 0.5 * c.wall_band_d * su.d;
  const double xs[2] = {su.cell.left + half, su.cell.right - half};
  for (int w = 0; w < 2; ++w) {
    const auto i = static_cast<std::size_t>(std::clamp(std::round((xs[w] - g.x0) / g.dx), 0.0, static_cast<double>(g.nx - 1)));
    std::vector<std::uint8_t> valid(g.ny);
    for (std::size_t j = 0; j < g.ny; ++j) valid[j] = f.phi[g.at(i, j)] >= su.min_phi ? 1 : 0;
    const Kernel wide = make_kernel(c.wall_kernel_w * su.kernel.w, su.kernel.cutoff);
    LocalLinearExtras x;
    m.wall_local[w] = to_f32(local_linear_profile(g, wide, grains, set, xs[w], su.v_ref, valid, &x));
    m.wall_vx[w] = to_f32(x.vx), m.wall_vy[w] = to_f32(x.vy), m.wall_gain[w] = to_f32(x.gain);
  }
}

RestRows rest_rows(const Setup& su, const CgConfig& c, const Intruder& in) {
  const double margin = c.rest_margin_w * su.kernel.w;
  return {su.cell.floor + margin, in.yc - margin};
}

void add_rest_grain_noise(const Setup& su, const CgConfig& c, const Snapshot& s, const std::vector<Vec2>& v,
                          SnapshotMeasure& m) {
  const RestRows rows = rest_rows(su, c, m.intruder);
  const double band = c.wall_band_d * su.d;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec2 p = s.position[i];
    if (!s.active[i] || p.y < rows.low || p.y >= rows.high) continue;
    if (p.x - su.cell.left >= band && su.cell.right - p.x >= band) continue;
    m.rest_grain_ss += (v[i].x * v[i].x + v[i].y * v[i].y) / (su.v_ref * su.v_ref);
    ++m.rest_grains;
  }
}

}  // namespace dem2d::analysis
