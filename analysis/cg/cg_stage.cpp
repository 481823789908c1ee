#include "cg/cg_stage.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "cg/cg_report.hpp"
#include "common/output.hpp"
#include "common/snapshot_loop.hpp"
#include "common/units.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

namespace {


// The index of v in values, appending it if absent.
std::size_t with(std::vector<double>& values, double v) {
  const auto it = std::find(values.begin(), values.end(), v);
  if (it != values.end()) return static_cast<std::size_t>(it - values.begin());
  values.push_back(v);
  return values.size() - 1;
}

const Body& intruder_body(const Snapshot& s, const std::string& path) {
  const int b = s.find_role("intruder");
  if (b < 0) throw CgError(path + ": " + s.no_body_with_role("intruder"));
  return s.bodies[static_cast<std::size_t>(b)];
}

// The snapshots whose full fields are stored: snapshot 0, `extra` and one
// every `every` of travel, always; then, for pre-rupture snapshots, that
// snapshot and the `follow` after it (the drop and the reloading: paper
// Figs. 8 and 11), for as many events, evenly spread, as keep the total
// within `max`.
std::vector<std::size_t> field_snapshots(const std::vector<double>& heights, const std::vector<std::int64_t>& pre,
                                         double every, std::size_t max, std::size_t extra, std::size_t follow) {
  std::set<std::size_t> chosen = {0, extra};
  if (every > 0.0) {
    double next = heights.front();
    for (std::size_t k = 0; k < heights.size(); ++k)
      if (heights[k] >= next) chosen.insert(k), next = heights[k] + every;
  }
  std::vector<std::size_t> starts;
  for (const std::int64_t k : pre)
    if (k >= 0 && (starts.empty() || starts.back() != static_cast<std::size_t>(k))) starts.push_back(static_cast<std::size_t>(k));
  const std::size_t room = max > chosen.size() ? (max - chosen.size()) / (follow + 1) : 0;
  const std::size_t n = std::min(room, starts.size());
  for (std::size_t q = 0; q < n; ++q) {
    const std::size_t i = n == 1 ? 0 : static_cast<std::size_t>(std::llround(static_cast<double>(q) * static_cast<double>(starts.size() - 1) /
                                                                           static_cast<double>(n - 1)));
    for (std::size_t f = 0; f <= follow && starts[i] + f < heights.size(); ++f) chosen.insert(starts[i] + f);
  }
  return {chosen.begin(), chosen.end()};
}

}  // namespace

Grains grains_of(const Snapshot& s, const std::vector<Vec2>* piv) {
  Grains g{s.position, s.mass, s.diameter, s.active, {s.velocity}};
  if (piv) g.velocities.emplace_back(*piv);
  return g;
}

PivVelocities piv_velocities(const Snapshot& s, const std::vector<Vec2>& disp, double window) {
  PivVelocities p{true, std::vector<Vec2>(disp.size())};
  for (std::size_t i = 0; i < disp.size() && p.ok; ++i)
    if (s.active[i]) {
      p.ok = std::isfinite(disp[i].x) && std::isfinite(disp[i].y);
      p.v[i] = {disp[i].x / window, disp[i].y / window};
    }
  if (!p.ok) p.v.assign(disp.size(), Vec2{});
  return p;
}

SnapshotBatch read_batch(const SnapshotSource& run, std::size_t k0, std::size_t k1, bool has_piv, double window) {
  SnapshotBatch b;
  for (std::size_t k = k0; k < k1; ++k) {
    b.snaps.push_back(run.snapshot(k));
    b.piv.push_back(has_piv ? piv_velocities(b.snaps.back(), run.displacement(k), window) : PivVelocities{false, {}});
  }
  return b;
}

void kernel_and_grid(const CgInput& in, const std::string& path, const Snapshot& s0, Setup& su) {
  const CgConfig& c = in.config;
  const double dx = c.spacing_mm / kMm;
  try {
    su.kernel = make_kernel(c.w_over_d * su.d, c.cutoff_over_w);
    double top = su.cell.floor;
    for (std::size_t i = 0; i < s0.size(); ++i)
      if (s0.active[i]) top = std::max(top, s0.position[i].y + 0.5 * s0.diameter[i]);
    const double height =
        c.height_mm > 0.0 ? c.height_mm / kMm : std::ceil((top - su.cell.floor + su.kernel.radius()) / dx) * dx;
    su.grid = make_grid(su.cell.left, su.cell.right, su.cell.floor, su.cell.floor + height, dx);
  } catch (const StageError& e) {  // common/cg_kernel.hpp's
    throw CgError((in.config_path.empty() ? std::string("config") : in.config_path) + " with " + path + ": " + e.what());
  }
}

double bulk_solid_fraction(const Setup& su, const Snapshot& s, const std::string& path, const std::string& config) {
  const Fields f = coarse_grain(su.grid, su.kernel, grains_of(s, nullptr));
  Region bulk;
  try {
    bulk = bulk_region(su.cell, bed_surface(s, su.cell, su.d).height, su.kernel.radius());
  } catch (const StageError& e) {
    throw CgError(path + ": snapshot " + std::to_string(s.index) + ": the bed is too small for the kernel of " +
                  (config.empty() ? std::string("the default settings") : config) + " (cut-off " +
                  format_mm(su.kernel.radius()) + "): " + e.what());
  }
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t j = 0; j < su.grid.ny; ++j)
    for (std::size_t i = 0; i < su.grid.nx; ++i)
      if (bulk.contains(su.grid.x(i), su.grid.y(j))) sum += f.phi[su.grid.at(i, j)], ++n;
  if (n == 0)
    throw CgError(path + ": no grid node in the bulk of the bed at snapshot " + std::to_string(s.index) +
                  " (grid.spacing_mm of " + (config.empty() ? std::string("the default settings") : config) + " too coarse)");
  return sum / static_cast<double>(n);
}

namespace {

// Everything about the run that does not change along it, from snapshot 0:
// the cell, d, the intruder and its velocity, kernel, grid, phi_ref, the
// sensitivity values.
Setup make_setup(const SnapshotSource& run, const Snapshot& s0, const CgInput& in) {
  const CgConfig& c = in.config;
  const std::string& path = run.path();
  Setup su;
  try {
    su.cell = find_cell(s0);
    su.d = mean_active_diameter(s0);
    su.grain_density = s0.mass.empty() ? 0.0 : s0.mass[0] / (std::numbers::pi * s0.diameter[0] * s0.diameter[0] / 4.0);
  } catch (const StageError& e) {
    throw CgError(path + ": " + e.what());
  }
  su.start = intruder_of(intruder_body(s0, path));
  {
    su.pull = pull_of(run);
    su.v_ref = c.reference_speed_mm_s > 0.0 ? c.reference_speed_mm_s / kMm : su.pull.speed();
    if (!(su.pull.speed() > 0.0)) throw CgError(path + ": the intruder '" + run.body_names()[su.pull.body] + "' does not move (/bodies/velocity = 0): no v* = |V|/V_intruder");
  }
  kernel_and_grid(in, path, s0, su);
  const double dx = su.grid.dx;
  su.window = run.displacement_window();
  su.centre_i = static_cast<std::size_t>(
      std::clamp(std::round((su.start.xc - su.grid.x0) / dx), 0.0, static_cast<double>(su.grid.nx - 1)));
  su.tip_nx = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(c.tip_window_width_mm / kMm / dx)));
  su.tip_ny = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(c.tip_window_height_mm / kMm / dx)));
  su.levels = c.levels, su.level0 = with(su.levels, c.level);
  for (const double v : c.fit_starts_w) su.starts.push_back(v * su.kernel.w);
  su.start0 = with(su.starts, c.fit_start_w * su.kernel.w);
  for (const double v : c.wall_bands_d) su.bands.push_back(v * su.d);
  su.band0 = with(su.bands, c.wall_band_d * su.d);
  for (const double v : c.region_heights_d) su.heights.push_back(v * su.d);
  su.height0 = with(su.heights, c.region_height_d * su.d);

  // reference solid fraction: the bulk of the bed at snapshot 0
  su.phi_ref = bulk_solid_fraction(su, s0, path, in.config_path);
  su.min_phi = c.mask_fraction * su.phi_ref;

  return su;
}

// The noise pre-pass: v* of the nodes at rest (rest_rows, outside the
// intruder's column by the kernel's cut-off beyond its tips), on the fields the
// cone is grown on: each averaged with the cone.frame_snapshots - 1 before it
// in the intruder's frame. Groups of that many consecutive snapshots, ending at
// snapshots spread evenly over the run, noise.snapshots coarse-grained in all
// (a group with a snapshot without the primary velocities is left out); v*
// sorted. The fields it coarse-grains go to `fields` (by snapshot), made as the
// main pass makes them (every velocity set), which takes them instead of
// making them again.
std::vector<double> rest_node_vstar(const SnapshotSource& run, const Setup& su, const CgConfig& c, bool has_piv,
                                    std::size_t primary, int threads, std::map<std::size_t, Fields>& fields) {
  const std::size_t S = run.snapshots(), K = std::min<std::size_t>(S, static_cast<std::size_t>(c.frame_snapshots));
  const std::size_t n = std::clamp<std::size_t>(static_cast<std::size_t>(c.noise_snapshots) / K, 1, S - K + 1);
  std::vector<std::size_t> ends, ks;
  for (std::size_t q = 0; q < n; ++q) {
    const std::size_t e = K - 1 + (n == 1 ? 0 : static_cast<std::size_t>(std::llround(static_cast<double>(q * (S - K)) / static_cast<double>(n - 1))));
    if (!ends.empty() && ends.back() == e) continue;
    ends.push_back(e);
    for (std::size_t k = e + 1 - K; k <= e; ++k)
      if (ks.empty() || ks.back() < k) ks.push_back(k);
  }
  std::map<std::size_t, Intruder> intruders;
  for_each_snapshot(
      run, ks, threads,
      [&](std::size_t, const Snapshot& s, const std::vector<Vec2>& disp) {
        std::pair<Intruder, std::optional<Fields>> result;
        result.first = intruder_of(s.bodies[static_cast<std::size_t>(s.find_role("intruder"))]);
        const PivVelocities p = has_piv ? piv_velocities(s, disp, su.window) : PivVelocities{false, {}};
        if (primary == kPiv && !p.ok) return result;
        result.second = coarse_grain(su.grid, su.kernel, grains_of(s, has_piv ? &p.v : nullptr));
        return result;
      },
      [&](std::size_t k, std::pair<Intruder, std::optional<Fields>>&& r) {
        if (!r.second) return;
        intruders.emplace(k, r.first);
        fields.emplace(k, std::move(*r.second));
      });
  std::vector<double> out;
  for (const std::size_t e : ends) {
    std::vector<const Fields*> group;
    std::vector<Vec2> at;
    for (std::size_t k = e + 1 - K; k <= e && intruders.count(k); ++k)
      group.push_back(&fields.at(k)), at.push_back(intruders.at(k).centre());
    if (group.size() < K) continue;
    const Fields averaged = K > 1 ? frame_average(su.grid, group, at) : Fields{};
    const std::vector<double> vstar = speed_ratio(velocity(K > 1 ? averaged : *group[0], primary, su.min_phi), 0.0, 0.0, su.v_ref);
    const Intruder& in = intruders.at(e);
    const RestRows rows = rest_rows(su, c, in);
    const double reach = 0.5 * in.length() + su.kernel.radius();
    for (std::size_t j = 0; j < su.grid.ny; ++j) {
      if (su.grid.y(j) < rows.low || su.grid.y(j) >= rows.high) continue;
      for (std::size_t i = 0; i < su.grid.nx; ++i) {
        const double v = vstar[su.grid.at(i, j)];
        if (std::abs(su.grid.x(i) - in.xc) >= reach && std::isfinite(v)) out.push_back(v);
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Every snapshot, in batches: read serially (HDF5), coarse-grained and measured
// in parallel. Each snapshot's result depends on its own data only (and, with
// averaging, on the previous snapshots' fields, summed serially or in a fixed
// order): the same for any thread count. Not common/snapshot_loop.hpp: the
// trailing average is a serial step between two parallel ones.
struct Measured {
  std::vector<SnapshotMeasure> ms;
  std::vector<std::uint8_t> piv_ok;  // the snapshot has PIV-like velocities
  double cg_seconds = 0.0;           // wall time in coarse_grain
};

// One of the last cone.frame_snapshots snapshots: its (lab-averaged) fields,
// its intruder's centre and whether its PIV set is valid (the intruder-frame
// average of the zones and the cone).
struct Framed {
  Fields fields;
  Vec2 at;
  bool piv = false;
};

Measured measure_all(const SnapshotSource& run, const Setup& su, const CgInput& in, bool has_piv, std::size_t primary,
                     const std::vector<std::size_t>& fields_at, int threads, std::map<std::size_t, Fields>& made) {
  const CgConfig& c = in.config;
  const std::string& path = run.path();
  const std::size_t S = run.snapshots(), K = static_cast<std::size_t>(c.frame_snapshots);
  Measured out{std::vector<SnapshotMeasure>(S), std::vector<std::uint8_t>(S, 0), 0.0};
  const std::size_t batch = static_cast<std::size_t>(std::max(1, 2 * threads));
  std::deque<Fields> history;  // raw fields of the previous snapshots (trailing average)
  std::deque<Framed> before;   // the K - 1 snapshots before the batch (intruder-frame average)
  for (std::size_t k0 = 0; k0 < S; k0 += batch) {
    const std::size_t k1 = std::min(S, k0 + batch);
    const auto [snaps, piv] = read_batch(run, k0, k1, has_piv, su.window);
    std::vector<Fields> raw(k1 - k0);
    const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::size_t q = 0; q < raw.size(); ++q) {
      const auto it = made.find(k0 + q);  // (the pre-pass's, from the same input)
      raw[q] = it != made.end() ? std::move(it->second)
                                : coarse_grain(su.grid, su.kernel, grains_of(snaps[q], has_piv ? &piv[q].v : nullptr));
    }
    out.cg_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // trailing averages (serial: they depend on the previous snapshots)
    std::vector<Fields> avg(raw.size());
    std::vector<std::uint8_t> avg_piv(raw.size());
    std::vector<Intruder> intruders(raw.size());
    for (std::size_t q = 0; q < raw.size(); ++q) {
      out.piv_ok[k0 + q] = piv[q].ok ? 1 : 0;
      history.push_back(std::move(raw[q]));
      if (history.size() > static_cast<std::size_t>(c.average_snapshots)) history.pop_front();
      avg[q] = history.front();
      for (std::size_t h = 1; h < history.size(); ++h) accumulate(avg[q], history[h]);
      scale(avg[q], 1.0 / static_cast<double>(history.size()));
      bool ok = true;
      for (std::size_t h = 0; h < history.size(); ++h) ok = ok && out.piv_ok[k0 + q - h];
      avg_piv[q] = ok ? 1 : 0;
      intruders[q] = intruder_of(intruder_body(snaps[q], path));
    }
    // the window of snapshot q: positions [q + T + 1 - m, q + T] of `before` followed by the batch
    const std::size_t T = before.size();
    const auto member = [&](std::size_t p) { return p < T ? &before[p].fields : &avg[p - T]; };
    const auto centre = [&](std::size_t p) { return p < T ? before[p].at : intruders[p - T].centre(); };
    const auto piv_valid = [&](std::size_t p) { return p < T ? before[p].piv : avg_piv[p - T] != 0; };
    std::vector<std::string> errors(raw.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::size_t q = 0; q < raw.size(); ++q) {
      const std::size_t k = k0 + q;
      const bool full = std::binary_search(fields_at.begin(), fields_at.end(), k);
      try {
        Fields moved;
        bool moved_piv = avg_piv[q] != 0;
        if (K > 1) {
          std::vector<const Fields*> fs;
          std::vector<Vec2> at;
          for (std::size_t p = q + T + 1 - std::min(K, q + T + 1); p <= q + T; ++p)
            fs.push_back(member(p)), at.push_back(centre(p)), moved_piv = moved_piv && piv_valid(p);
          moved = frame_average(su.grid, fs, at);
        }
        out.ms[k] = measure_snapshot(su, c, avg[q], avg_piv[q] != 0, K > 1 ? moved : avg[q], moved_piv, snaps[q],
                                     intruders[q], full, primary);
        if (primary == kPiv && piv[q].ok) add_rest_grain_noise(su, c, snaps[q], piv[q].v, out.ms[k]);
        if (primary == kInst || piv[q].ok)
          add_wall_profiles(su, c, avg[q], grains_of(snaps[q], has_piv ? &piv[q].v : nullptr), primary, out.ms[k]);
      } catch (const std::exception& e) {
        errors[q] = e.what();
      }
    }
    for (const std::string& e : errors)
      if (!e.empty()) throw CgError(e);
    for (std::size_t q = 0; q < avg.size() && K > 1; ++q) {
      before.push_back({std::move(avg[q]), intruders[q].centre(), avg_piv[q] != 0});
      if (before.size() > K - 1) before.pop_front();
    }
  }
  return out;
}

}  // namespace

std::vector<std::int64_t> pre_rupture_snapshots(const std::vector<double>& times, const std::vector<RuptureEvent>& events,
                                                double window) {
  std::vector<std::int64_t> out;
  for (std::size_t e = 0; e < events.size(); ++e) {
    std::int64_t best = -1;
    for (std::size_t k = 0; k < times.size(); ++k)
      if (times[k] - window >= events[e].load_start_time && times[k] <= events[e].peak_time) best = static_cast<std::int64_t>(k);
    out.push_back(best);
  }
  return out;
}

CgResult compute_cg(const CgInput& in) {
  validate(in.config, in.config_path.empty() ? "config" : in.config_path);
  const RunFileSource run(in.run_path);
  if (run.snapshots() == 0) throw CgError(run.path() + ": the run file has no snapshots");
  const std::vector<std::string>& roles = run.body_roles();
  if (std::find(roles.begin(), roles.end(), "intruder") == roles.end()) return compute_cg_lab(run, in);
  if (in.events_path.empty()) return compute_cg(run, nullptr, in);
  const std::vector<RuptureEvent> events = read_events(in.events_path);
  return compute_cg(run, &events, in);
}

CgResult compute_cg(const SnapshotSource& run, const std::vector<RuptureEvent>* events_in, const CgInput& in) {
  const CgConfig& c = in.config;
  validate(c, in.config_path.empty() ? "config" : in.config_path);
  const auto t_start = std::chrono::steady_clock::now();
  const std::string& path = run.path();
  if (run.snapshots() == 0) throw CgError(path + ": the run has no snapshots");
  const std::size_t S = run.snapshots();
  const std::vector<double>& times = run.snapshot_times();
  const Snapshot s0 = run.snapshot(0);
  Setup su = make_setup(run, s0, in);
  const int threads = in.threads > 0 ? in.threads : omp_get_max_threads();

  // ---- what is selected: loading phases, full fields ----
  const bool has_piv = run.has_displacements();
  const std::size_t primary = c.velocity == "piv" && has_piv ? kPiv : kInst;
  // the cone's level, raised to what the noise alone reaches at rest (and the
  // same for the sensitivity's false-alarm rates)
  std::map<std::size_t, Fields> made;  // the pre-pass's fields, taken by the main pass
  su.rest_nodes = rest_node_vstar(run, su, c, has_piv, primary, threads, made);
  for (const double a : c.cone_false_alarms) with(su.levels, cone_level(su, c, a));
  su.level0 = with(su.levels, cone_level(su, c, c.cone_false_alarm));
  su.level_fixed = with(su.levels, c.level);
  std::vector<double> heights(S);
  {
    const std::vector<Body> track = run.body_track(run.body_with_role("intruder"));
    for (std::size_t k = 0; k < S; ++k) heights[k] = track[k].centre().y - su.cell.floor;
  }
  const bool have_events = events_in != nullptr;
  std::vector<RuptureEvent> events;
  std::vector<std::int64_t> pre;
  if (have_events) {
    events = *events_in;
    pre = pre_rupture_snapshots(times, events, has_piv ? su.window : 0.0);
  }
  const std::int64_t after = first_after_travel(heights, c.after_travel_d * su.d);
  const std::vector<std::size_t> fields_at =
      field_snapshots(heights, pre, c.field_every_mm / kMm, static_cast<std::size_t>(c.field_max_snapshots),
                      after >= 0 ? static_cast<std::size_t>(after) : 0,
                      static_cast<std::size_t>(c.field_follow_snapshots));

  Measured m = measure_all(run, su, in, has_piv, primary, fields_at, threads, made);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  const StageRecord rec{.setup = std::move(su),
                        .config = c,
                        .ms = std::move(m.ms),
                        .times = times,
                        .heights = std::move(heights),
                        .piv_ok = std::move(m.piv_ok),
                        .has_piv = has_piv,
                        .primary = primary,
                        .have_events = have_events,
                        .events = std::move(events),
                        .pre = std::move(pre),
                        .after = after,
                        .fields_at = fields_at,
                        .seconds = seconds,
                        .cg_seconds = m.cg_seconds,
                        .threads = threads,
                        .run_path = path,
                        .events_path = in.events_path,
                        .config_path = in.config_path};
  CgResult r;
  r.metrics = {{"cg", cg_metrics(rec)}};
  r.h5 = cg_h5(rec, r.metrics);
  return r;
}

void write_cg(const CgResult& r, const std::string& out_dir) {
  namespace fs = std::filesystem;
  r.h5.write((fs::path(out_dir) / "cg.h5").string());
  write_file_atomic((fs::path(out_dir) / "metrics.json").string(), r.metrics.dump(2) + "\n");
}

}  // namespace dem2d::analysis
