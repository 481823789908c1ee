// Stage `cg` on a run without an intruder (a box settling, a silo or hopper
// discharging, a fill): the coarse-grained fields on a fixed grid over the
// cell, in the lab frame, and per snapshot the bed's mean solid fraction, its
// speeds and, with a reference speed, its mobility zones. What is defined
// relative to the intruder (cone, wall mobility, dilatancy, intruder frame)
// is not. Definitions: analysis/cg/README.md ("Runs without an intruder").
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cg/cg_stage.hpp"
#include "common/snapshot_loop.hpp"
#include "common/stage_output.hpp"   // number_or_null
#include "common/units.hpp"
#include "core/number_text.hpp"
#include "runfile/h5.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;

// One snapshot's bed: the nodes with phi >= the mask.
struct LabMeasure {
  double surface = 0.0;        // free surface above the floor (m)
  double area = 0.0;           // bed nodes x dx^2 (m^2)
  double phi = kNaN;           // mean solid fraction of the bed nodes
  double mean_speed = kNaN;    // mean |V| of the bed nodes (m/s)
  double max_speed = kNaN;
  ZoneAreas zones;             // with a reference speed (m^2)
  std::vector<float> phi_field, vx_field, vy_field;  // only for the stored snapshots
};

LabMeasure measure(const Setup& su, const Fields& f, std::size_t set, const Snapshot& s, bool full) {
  LabMeasure m;
  m.surface = bed_surface(s, su.cell, su.d).height;
  const Velocity v = velocity(f, set, su.min_phi);
  double phi = 0.0, speed = 0.0, top = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < su.grid.size(); ++k) {
    if (std::isnan(v.vx[k])) continue;
    const double u = std::hypot(v.vx[k], v.vy[k]);
    phi += f.phi[k], speed += u, top = std::max(top, u), ++n;
  }
  m.area = static_cast<double>(n) * su.grid.dx * su.grid.dx;
  if (n > 0) {
    m.phi = phi / static_cast<double>(n);
    m.mean_speed = speed / static_cast<double>(n);
    m.max_speed = top;
  }
  if (su.v_ref > 0.0) m.zones = zone_areas(su.grid, speed_ratio(v, 0.0, 0.0, su.v_ref), su.levels[0], su.levels[1]);
  if (full) {
    m.phi_field.assign(f.phi.begin(), f.phi.end());
    m.vx_field.assign(v.vx.begin(), v.vx.end());
    m.vy_field.assign(v.vy.begin(), v.vy.end());
  }
  return m;
}

Setup lab_setup(const SnapshotSource& run, const CgInput& in) {
  const CgConfig& c = in.config;
  const std::string& path = run.path();
  const Snapshot s0 = run.snapshot(0);
  Setup su;
  try {
    su.cell = find_cell(s0);
    su.d = mean_active_diameter(s0);
  } catch (const StageError& e) {
    throw CgError(path + ": " + e.what());
  }
  kernel_and_grid(in, path, s0, su);
  // The bed's reference solid fraction where it is packed: at the last snapshot.
  su.phi_ref = bulk_solid_fraction(su, run.snapshot(run.snapshots() - 1), path, in.config_path);
  su.min_phi = c.mask_fraction * su.phi_ref;
  su.v_ref = c.reference_speed_mm_s / kMm;
  su.levels = {c.immobile_below, c.dragged_above};
  su.window = run.displacement_window();
  return su;
}

// Full fields for at most field_max_snapshots snapshots, evenly spaced (and the last).
std::vector<std::size_t> lab_fields_at(std::size_t S, int max_snapshots) {
  std::vector<std::size_t> fields_at;
  if (max_snapshots > 0) {
    const auto room = static_cast<std::size_t>(max_snapshots);
    fields_at = every_kth(S, std::max<std::size_t>(1, (S + room - 1) / room));
    if (fields_at.size() > room) fields_at.erase(fields_at.end() - 2);  // the last one stays
  }
  return fields_at;
}

struct LabRun {
  Setup su;
  std::size_t set = kInst;  // the velocity set of the measures
  std::vector<std::size_t> fields_at;
  std::vector<LabMeasure> ms;
  std::vector<double> times;
  std::vector<std::uint8_t> piv_ok;
  int threads = 1;
  double seconds = 0.0;
};

// Every snapshot through the stages' snapshot loop (common/snapshot_loop.hpp):
// each result depends on its own snapshot only (any thread count).
void measure_lab(const SnapshotSource& run, bool has_piv, LabRun& L) {
  struct LabMeasured {
    LabMeasure m;
    double time = 0.0;
    bool piv_ok = false;
  };
  for_each_snapshot(
      run, all_snapshots(run), L.threads,
      [&](std::size_t k, const Snapshot& s, const std::vector<Vec2>& disp) {
        const PivVelocities piv = has_piv ? piv_velocities(s, disp, L.su.window) : PivVelocities{false, {}};
        // A snapshot without PIV-like velocities (the first ones) uses the instantaneous ones.
        const Fields f = coarse_grain(L.su.grid, L.su.kernel, grains_of(s, has_piv ? &piv.v : nullptr));
        const bool full = std::binary_search(L.fields_at.begin(), L.fields_at.end(), k);
        return LabMeasured{measure(L.su, f, piv.ok ? L.set : kInst, s, full), s.time, piv.ok};
      },
      [&](std::size_t, LabMeasured&& x) {
        L.ms.push_back(std::move(x.m)), L.times.push_back(x.time), L.piv_ok.push_back(x.piv_ok);
      });
}

json lab_metrics(const LabRun& L, const std::string& path, const CgInput& in) {
  const Setup& su = L.su;
  const LabMeasure& last = L.ms.back();
  const bool zones = su.v_ref > 0.0;
  const auto zone_fraction = [&](double area) { return zones && last.area > 0.0 ? json(area / last.area) : json(nullptr); };
  json m;
  m["run_file"] = path;
  m["config_file"] = in.config_path;
  m["intruder"] = false;
  m["intruder_note"] = "the run has no body with role 'intruder': lab-frame fields, solid fraction and zones only; "
                       "the cone angle, wall mobility, dilatancy and intruder-frame window are not defined";
  m["frame"] = "lab";
  m["grid"] = {{"nx", su.grid.nx}, {"ny", su.grid.ny}, {"spacing_mm", su.grid.dx * kMm},
               {"height_mm", static_cast<double>(su.grid.ny) * su.grid.dx * kMm},
               {"w_mm", su.kernel.w * kMm}, {"cutoff_mm", su.kernel.radius() * kMm},
               {"mean_diameter_mm", su.d * kMm}, {"phi_ref", su.phi_ref}, {"mask_phi", su.min_phi}};
  m["phi_ref_source"] = "bulk of the bed at the last snapshot";
  m["velocity_source"] = L.set == kPiv ? "piv" : "instantaneous";
  m["snapshots"] = L.ms.size();
  m["snapshots_with_piv"] = static_cast<std::size_t>(std::count(L.piv_ok.begin(), L.piv_ok.end(), 1));
  m["field_snapshots"] = L.fields_at.size();
  m["reference_speed_mm_s"] = zones ? json(su.v_ref * kMm) : json(nullptr);
  if (!zones) m["zones_note"] = "no zones.reference_speed_mm_s: v* = |V| / V_ref needs a reference speed without an intruder";
  m["final"] = {{"time_s", L.times.back()},
                {"bed_height_mm", last.surface * kMm},
                {"bed_area_mm2", last.area * kMm * kMm},
                {"bed_solid_fraction", number_or_null(last.phi)},
                {"mean_speed_mm_s", number_or_null(last.mean_speed * kMm)},
                {"max_speed_mm_s", number_or_null(last.max_speed * kMm)},
                {"immobile_fraction", zone_fraction(last.zones.immobile)},
                {"intermediate_fraction", zone_fraction(last.zones.cone)},
                {"mobile_fraction", zone_fraction(last.zones.dragged)}};
  m["cost"] = {{"seconds", L.seconds}, {"threads", L.threads}};
  return m;
}

H5Output lab_h5(const LabRun& L, const std::string& path, const json& metrics) {
  const Setup& su = L.su;
  const std::vector<LabMeasure>& ms = L.ms;
  H5Output h("cg", path);
  h.note("format", std::string("dem2d-cg-lab-2"));
  h.note("frame", std::string("lab"));
  h.note("velocity_source", metrics["cg"]["velocity_source"].get<std::string>());
  h.note("metrics", metrics.dump());
  h.note("floor_y", su.cell.floor);
  const auto per = [&](auto get) { return column_of(ms, get); };
  add_grid(h, su.grid, "node y (run-file frame)");
  h.add("snapshots/time", L.times, "s", "snapshot time");
  h.add("snapshots/bed_height", per([](const LabMeasure& x) { return x.surface; }), "m", "free surface above the floor's inner face");
  h.add("snapshots/bed_area", per([](const LabMeasure& x) { return x.area; }), "m^2", "area of the nodes with phi >= mask_phi");
  h.add("snapshots/bed_solid_fraction", per([](const LabMeasure& x) { return x.phi; }), "-", "mean phi of the bed nodes");
  h.add("snapshots/mean_speed", per([](const LabMeasure& x) { return x.mean_speed; }), "m/s", "mean |V| of the bed nodes");
  h.add("snapshots/max_speed", per([](const LabMeasure& x) { return x.max_speed; }), "m/s", "largest |V| of the bed nodes");
  if (su.v_ref > 0.0) {
    h.add("zones/immobile_area", per([](const LabMeasure& x) { return x.zones.immobile; }), "m^2", "bed nodes with v* < zones.immobile_below");
    h.add("zones/intermediate_area", per([](const LabMeasure& x) { return x.zones.cone; }), "m^2", "bed nodes in between");
    h.add("zones/mobile_area", per([](const LabMeasure& x) { return x.zones.dragged; }), "m^2", "bed nodes with v* > zones.dragged_above");
  }
  {
    std::vector<double> at;
    std::vector<float> phi, vx, vy;
    for (const std::size_t k : L.fields_at) {
      at.push_back(static_cast<double>(k));
      phi.insert(phi.end(), ms[k].phi_field.begin(), ms[k].phi_field.end());
      vx.insert(vx.end(), ms[k].vx_field.begin(), ms[k].vx_field.end());
      vy.insert(vy.end(), ms[k].vy_field.begin(), ms[k].vy_field.end());
    }
    const std::vector<hsize_t> dims = {L.fields_at.size(), su.grid.ny, su.grid.nx};
    h.add("fields/snapshot", at, "-", "snapshot index of each stored field");
    h.add("fields/phi", std::move(phi), "-", "solid fraction [field, y, x]", dims);
    h.add("fields/vx", std::move(vx), "m/s", "lab-frame velocity x (NaN outside the bed)", dims);
    h.add("fields/vy", std::move(vy), "m/s", "lab-frame velocity y (NaN outside the bed)", dims);
  }
  return h;
}

}  // namespace

CgResult compute_cg_lab(const SnapshotSource& run, const CgInput& in) {
  const auto t_start = std::chrono::steady_clock::now();
  LabRun L;
  L.su = lab_setup(run, in);
  const bool has_piv = run.has_displacements();
  L.set = in.config.velocity == "piv" && has_piv ? kPiv : kInst;
  L.fields_at = lab_fields_at(run.snapshots(), in.config.field_max_snapshots);
  L.threads = in.threads > 0 ? in.threads : omp_get_max_threads();
  measure_lab(run, has_piv, L);
  L.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  CgResult r;
  r.metrics = {{"cg", lab_metrics(L, run.path(), in)}};
  r.h5 = lab_h5(L, run.path(), r.metrics);
  return r;
}

}  // namespace dem2d::analysis
