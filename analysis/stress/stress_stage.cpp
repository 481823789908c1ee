#include "stress/stress_stage.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "common/snapshot_loop.hpp"
#include "common/snapshot_source.hpp"
#include "common/units.hpp"
#include "frame/cell.hpp"
#include "frame/pulloff_frame.hpp"
#include "runfile/run_parameters.hpp"
#include "stress/stress_balance.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;

struct Setup {
  Grid grid;
  Kernel kernel;
  Cell cell;
  double margin = 0.0;  // the body's box's margin beyond its outline (m)
  Vec2 gravity;
  int body = -1;      // the body of the force check (config body.role), -1 none
  int intruder = -1;  // the intruder, -1 none
};

// What one snapshot gives.
struct Measured {
  double time = 0.0, height = kNaN;  // the body's centre above the floor's face (m)
  Vec2 recorded, quasi_static, exact, inertia;  // N/m (NaN without the body)
  std::optional<StressFields> fields;          // kept for the maps and the profile at rest
};

Vec2 nan2() { return {kNaN, kNaN}; }

// the fields' identity to quadrature, relative to the largest recorded load (a defect beyond it)
constexpr double kExactResidualLimit = 1e-2;

Measured measure(const Setup& su, const Snapshot& s, bool keep) {
  Measured m;
  m.time = s.time;
  StressFields f = coarse_grain_stress(su.grid, su.kernel, s);
  m.recorded = m.quasi_static = m.exact = m.inertia = nan2();
  if (su.body >= 0) {
    const Body& in = s.bodies[static_cast<std::size_t>(su.body)];
    m.height = in.centre().y - su.cell.floor;
    const BodyBalance F = body_balance(su.grid, su.kernel, f, s, su.body, su.margin, su.gravity);
    m.recorded = F.recorded, m.exact = F.exact, m.quasi_static = F.quasi_static, m.inertia = F.inertia;
  }
  if (keep) m.fields = std::move(f);
  return m;
}

Setup setup(const RunFileSource& source, const Snapshot& s0, const StressConfig& c) {
  const RunReader& run = source.run();
  Setup su;
  su.cell = find_cell(s0);
  su.intruder = s0.find_role("intruder");
  su.body = s0.find_role(c.body_role);
  if (su.body < 0 && c.body_role != "intruder") throw StageError(s0.no_body_with_role(c.body_role));
  su.gravity = {run.parameters().gx, run.parameters().gy};
  su.margin = c.box_margin_mm / kMm;
  const double dx = c.spacing_mm / kMm;
  su.kernel = make_kernel(c.w_over_d * mean_active_diameter(s0), c.cutoff_over_w);
  // the cell widened by the kernel's reach, so that a box around the body holds its contacts' kernels
  // even beside a wall or the floor (the fields beyond a face are the grains' kernels reaching through it)
  double top = su.cell.floor;
  for (std::size_t i = 0; i < s0.size(); ++i)
    if (s0.active[i]) top = std::max(top, s0.position[i].y + 0.5 * s0.diameter[i]);
  const double reach = su.kernel.radius() + su.margin + 2.0 * dx;
  su.grid = make_grid(su.cell.left - reach, su.cell.right + reach, su.cell.floor - reach, top + reach, dx);
  return su;
}

// pressure (sigma_xx + sigma_yy)/2 and shear, the symmetric deviator's magnitude
// sqrt(((sigma_xx - sigma_yy)/2)^2 + ((sigma_xy + sigma_yx)/2)^2), of the whole stress
double pressure(const StressFields& f, std::size_t n) { return 0.5 * (f.total(kXX, n) + f.total(kYY, n)); }
double shear(const StressFields& f, std::size_t n) {
  return std::hypot(0.5 * (f.total(kXX, n) - f.total(kYY, n)), 0.5 * (f.total(kXY, n) + f.total(kYX, n)));
}

// The stress's force on the body against the recorded one, over the snapshots with a load: their
// means (the grains' acceleration in the box averages out over a pull-off, its momentum does not grow),
// three-valued with the difference's standard error: holds if |mean difference| + 2 SE is within the
// tolerance, fails if |mean difference| - 2 SE is beyond it, undetermined between (more snapshots)
json force_check(const std::vector<Measured>& ms, const StressConfig& c, bool has_body) {
  double peak = 0.0, exact_err = 0.0, pooled = 0.0, inertia = 0.0, load = 0.0;
  std::vector<double> diff, rec;
  for (const Measured& m : ms) {
    if (!has_body) break;  // no box was measured
    peak = std::max(peak, std::abs(m.recorded.y));
    exact_err = std::max(exact_err, std::hypot(m.exact.x - m.recorded.x, m.exact.y - m.recorded.y));
    if (std::abs(m.recorded.y) < c.min_load_n) continue;
    diff.push_back(m.quasi_static.y - m.recorded.y);
    rec.push_back(m.recorded.y);
    pooled += std::abs(m.quasi_static.y - m.recorded.y);
    inertia += std::abs(m.inertia.y);
    load += std::abs(m.recorded.y);
  }
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? kNaN : s / static_cast<double>(v.size());
  };
  const std::size_t n = diff.size();
  const double md = mean(diff), mr = mean(rec);
  double var = 0.0;
  for (double x : diff) var += (x - md) * (x - md);
  const double se = n > 1 ? std::sqrt(var / static_cast<double>(n - 1) / static_cast<double>(n)) : kNaN;
  json j;
  j["snapshots_used"] = n;
  j["min_load_n"] = c.min_load_n;
  j["tolerance"] = c.tolerance;
  j["mean_recorded_n"] = mr;
  j["mean_stress_n"] = n > 0 ? mr + md : kNaN;
  j["mean_relative_error"] = n > 0 ? std::abs(md / mr) : kNaN;
  j["mean_relative_standard_error"] = se / std::abs(mr);
  j["snapshot_relative_error"] = n > 0 ? pooled / load : kNaN;
  j["inertia_share"] = n > 0 ? inertia / load : kNaN;
  // second order in the grid spacing: 1.6e-3 at 1 mm, 4.1e-4 at 0.5 mm (the quick run)
  j["exact_residual"] = peak > 0.0 ? exact_err / peak : kNaN;
  std::string verdict = "undetermined", why;
  const double band = c.tolerance * std::abs(mr);
  if (!has_body) {
    why = "the run has no body with role '" + c.body_role + "'";
  } else if (n < 2) {
    why = "fewer than 2 snapshots with a recorded load of min_load_n or more";
  } else if (!(j["exact_residual"].get<double>() <= kExactResidualLimit)) {
    verdict = "fails";
    why = "the fields do not balance the contact forces (exact_residual above " + std::to_string(kExactResidualLimit) +
          "): a defect of the stage or a grid too coarse for the kernel";
  } else if (std::abs(md) + 2.0 * se <= band) {
    verdict = "holds";
    why = "the mean vertical force from the stress is within the tolerance of the recorded one, with twice its standard error";
  } else if (std::abs(md) - 2.0 * se > band) {
    verdict = "fails";
    why = "the mean vertical force from the stress differs from the recorded one by more than the tolerance, beyond twice its standard error";
  } else {
    why = "the difference of the means is within twice its standard error of the tolerance: the grains' acceleration "
          "in the box (inertia_share) is too large for this many snapshots";
  }
  j["verdict"] = verdict;
  j["why"] = why;
  return j;
}

}  // namespace

StressResult run_stress(const std::string& run_path, const std::string& config_path, const StressConfig& cfg,
                        const Study& study, int threads) {
  const RunFileSource source(run_path);
  const RunReader& run = source.run();
  const std::size_t S = run.snapshots();
  if (S == 0) throw StageError(run.path() + ": the run file has no snapshots");
  const Snapshot s0 = run.snapshot(0);
  Setup su;
  try {
    su = setup(source, s0, cfg);
  } catch (const StageError& e) {
    throw StageError((config_path.empty() ? std::string("config") : config_path) + " with " + run.path() + ": " + e.what());
  }
  const std::vector<std::size_t> ks = every_kth(S, static_cast<std::size_t>(cfg.every));
  const std::vector<std::size_t> map_ks = spread_over(ks, static_cast<std::size_t>(cfg.maps));
  const int t = threads > 0 ? threads : omp_get_max_threads();

  std::vector<Measured> ms;
  std::vector<std::size_t> kept;  // snapshots of the maps (and 0, the bed at rest)
  std::vector<StressFields> maps;
  for_each_snapshot(
      source, ks, t,
      [&](std::size_t k, const Snapshot& s) {
        const bool keep = k == 0 || std::binary_search(map_ks.begin(), map_ks.end(), k);
        return measure(su, s, keep);
      },
      [&](std::size_t k, Measured&& m) {
        if (m.fields) kept.push_back(k), maps.push_back(std::move(*m.fields)), m.fields.reset();
        ms.push_back(std::move(m));
      });

  const Grid& g = su.grid;
  json m;
  m["run_file"] = run.path();
  m["config_file"] = config_path;
  m["snapshots"] = ks.size();
  m["kernel_w_mm"] = su.kernel.w * kMm;
  m["grid"] = {{"nx", g.nx}, {"ny", g.ny}, {"spacing_mm", g.dx * kMm}};
  m["intruder"] = su.intruder >= 0;
  m["body_role"] = cfg.body_role;
  m["force_check"] = force_check(ms, cfg, su.body >= 0);
  // the bed at rest: pressure and lateral ratio K = sigma_xx / sigma_yy at the intruder's first height, mean
  // over the middle half of the cell
  const StressFields& rest = maps.front();
  const double x0 = su.cell.left + 0.25 * (su.cell.right - su.cell.left), x1 = su.cell.right - 0.25 * (su.cell.right - su.cell.left);
  const Grid::Range mid = g.columns(x0, x1);
  std::vector<double> sxx(g.ny, 0.0), syy(g.ny, 0.0), prof_y(g.ny);
  for (std::size_t j = 0; j < g.ny; ++j) {
    prof_y[j] = g.y(j) - su.cell.floor;
    for (std::size_t i = mid.first; i < mid.last; ++i) sxx[j] += rest.total(kXX, g.at(i, j)), syy[j] += rest.total(kYY, g.at(i, j));
    sxx[j] /= static_cast<double>(mid.last - mid.first), syy[j] /= static_cast<double>(mid.last - mid.first);
  }
  if (su.intruder >= 0) {
    const Body& in = s0.bodies[static_cast<std::size_t>(su.intruder)];
    const Grid::Range row = g.rows(in.centre().y, 1e300);
    const std::size_t j = std::min(row.first, g.ny - 1);
    m["rest_pressure_at_intruder_pa"] = 0.5 * (sxx[j] + syy[j]);
    m["rest_lateral_ratio_at_intruder"] = syy[j] != 0.0 ? sxx[j] / syy[j] : kNaN;
  }
  m["study_mean_diameter_mm"] = study.mean_diameter * kMm;
  m["config"] = to_json(cfg);

  StressResult r;
  r.metrics = {{"stress", m}};
  H5Output& h = r.h5;
  h = H5Output("stress", run.path());
  std::vector<double> gx(g.nx), gy(g.ny);
  for (std::size_t i = 0; i < g.nx; ++i) gx[i] = g.x(i);
  for (std::size_t j = 0; j < g.ny; ++j) gy[j] = g.y(j);
  h.add("grid/x", gx, "m", "node x (the cell widened by the kernel's reach on every side)");
  h.add("grid/y", gy, "m", "node y");
  h.note("cell_left", su.cell.left), h.note("cell_right", su.cell.right), h.note("cell_floor", su.cell.floor);
  h.note("kernel_w", su.kernel.w), h.note("kernel_cutoff_over_w", su.kernel.cutoff);
  const auto column = [&](auto get) { return column_of(ms, get); };
  std::vector<std::int64_t> snap(ks.begin(), ks.end());
  h.add("series/snapshot", snap, "-", "snapshot index in the run file");
  h.add("series/time", column([](const Measured& x) { return x.time; }), "s", "time");
  h.add("series/body_height", column([](const Measured& x) { return x.height; }), "m",
        "the body's centre (role " + cfg.body_role + ") above the floor's face (NaN without it)");
  h.note("body_role", cfg.body_role);
  const auto pair = [&](const char* name, Vec2 Measured::*v, const char* what) {
    std::vector<double> out;
    for (const Measured& x : ms) out.push_back((x.*v).x), out.push_back((x.*v).y);
    h.add(std::string("series/") + name, out, "N/m", what, {ms.size(), 2});
  };
  pair("force_recorded", &Measured::recorded, "the grains' force on the body, the sum of its contacts' (the run's body_force at this step)");
  pair("force_stress", &Measured::quasi_static,
       "the same from the stress: - oint (sigma_c + sum m v v G) . n + int rho g - the other bodies' push, over the box");
  pair("force_exact", &Measured::exact, "- oint sigma_c . n - int net - the other bodies' push: the fields' identity");
  pair("inertia", &Measured::inertia, "int sum m a G over the box: what force_stress leaves out");
  std::vector<std::int64_t> mk(kept.begin(), kept.end());
  h.add("maps/snapshot", mk, "-", "snapshots of the maps (0 first: the bed at rest)");
  const std::size_t M = maps.size(), nodes = g.size();
  std::vector<float> sig(M * 4 * nodes), pr(M * nodes), sh(M * nodes);
  for (std::size_t q = 0; q < M; ++q)
    for (std::size_t n = 0; n < nodes; ++n) {
      for (std::size_t c = 0; c < 4; ++c) sig[(q * 4 + c) * nodes + n] = static_cast<float>(maps[q].total(static_cast<Component>(c), n));
      pr[q * nodes + n] = static_cast<float>(pressure(maps[q], n));
      sh[q * nodes + n] = static_cast<float>(shear(maps[q], n));
    }
  h.add("maps/sigma", sig, "Pa", "stress sigma_ab (contact + kinetic, compression positive), components xx, xy, yx, yy",
        {M, 4, g.ny, g.nx});
  h.add("maps/pressure", pr, "Pa", "(sigma_xx + sigma_yy) / 2", {M, g.ny, g.nx});
  h.add("maps/shear", sh, "Pa", "sqrt(((sigma_xx - sigma_yy)/2)^2 + ((sigma_xy + sigma_yx)/2)^2)", {M, g.ny, g.nx});
  h.add("rest/height", prof_y, "m", "node height above the floor's face");
  h.add("rest/sigma_xx", sxx, "Pa", "the bed at rest (snapshot 0): sigma_xx, mean over the middle half of the cell");
  h.add("rest/sigma_yy", syy, "Pa", "the same, sigma_yy");
  return r;
}

}  // namespace dem2d::analysis
