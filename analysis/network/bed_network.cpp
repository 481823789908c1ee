// Stage `network` on a run without an intruder (a box, a silo, a fill): what
// needs no intruder. Definitions: analysis/network/README.md ("Runs without
// an intruder").
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/snapshot_loop.hpp"
#include "common/units.hpp"
#include "network/network_stage.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;

// The force the grains put on the cell's bodies (N/m): minus the contact
// force on the grain, fn n + ft t with t = z x n = (-ny, nx).
struct BodyLoads {
  Vec2 floor, left, right, other;
};
BodyLoads body_loads(const Snapshot& s, const std::vector<Partner>& partners) {
  BodyLoads out;
  const Contacts& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (partners[k] == Partner::grain) continue;
    Vec2& sum = partners[k] == Partner::floor ? out.floor
                : partners[k] == Partner::left ? out.left
                : partners[k] == Partner::right ? out.right
                                                : out.other;
    sum.x -= c.fn[k] * c.nx[k] - c.ft[k] * c.ny[k];
    sum.y -= c.fn[k] * c.ny[k] + c.ft[k] * c.nx[k];
  }
  return out;
}

// One snapshot's network: the graph's size and mean force, spanning from wall
// to wall, the fabric above the floor, the loads on the cell's bodies.
struct BedSnapshot {
  double time = 0.0, bed = 0.0, mean_fn = 0.0;
  std::int64_t contacts = 0, strong_contacts = 0;
  std::uint8_t span_strong = 0, span_whole = 0;
  std::vector<std::uint8_t> span_sens;  // per sensitivity strong threshold
  Fabric fabric;
  BodyLoads load;
  ForceSegments segments;  // empty unless to the figure
  double measured_d = 0.0;  // k = 0 only
};

BedSnapshot measure_snapshot(const Snapshot& s, std::size_t k, const NetworkConfig& cfg, bool to_figure) {
  BedSnapshot b;
  const FloorRule rule = floor_rule_from_name(cfg.floor_rule);
  const PulloffGeometry geo = pulloff_geometry(s);
  if (k == 0) b.measured_d = mean_active_diameter(s);
  const std::vector<Partner> partners = classify_contacts(s, geo);
  const ContactGraph g = build_contact_graph(s, partners);
  const double strong = cfg.strong_threshold * g.mean_fn;
  b.time = s.time;
  b.bed = bed_height(s, geo);
  b.mean_fn = g.mean_fn;
  b.contacts = static_cast<std::int64_t>(g.edges());
  b.strong_contacts = g.edges_above(strong);
  b.span_strong = percolation(g, strong, rule, g.left()).right;
  b.span_whole = percolation(g, 0.0, rule, g.left()).right;
  for (const double f : cfg.sensitivity_strong_threshold)
    b.span_sens.push_back(percolation(g, f * g.mean_fn, rule, g.left()).right);
  b.fabric = region_fabric(s, partners, strong, geo.cell.floor, std::numeric_limits<double>::infinity(),
                           static_cast<std::size_t>(cfg.anisotropy_min_contacts));
  b.load = body_loads(s, partners);
  if (to_figure) b.segments.add(s, partners, strong);
  return b;
}

// The fraction of the snapshots whose flag is set.
template <class Flag>
json fraction(const std::vector<BedSnapshot>& bs, Flag flag) {
  std::int64_t n = 0;
  for (const BedSnapshot& b : bs) n += flag(b);
  return fraction_or_null(n, static_cast<std::int64_t>(bs.size()));
}

json bed_metrics_json(const std::vector<BedSnapshot>& bs, const std::string& run_path, const NetworkInputs& in,
                      const NetworkConfig& cfg, const Study& study) {
  const BedSnapshot& last = bs.back();
  // The weight the floor and the side walls carry (N/m, downwards positive).
  const double floor_load = -last.load.floor.y, wall_load = -(last.load.left.y + last.load.right.y);
  json m;
  m["run_file"] = run_path;
  m["config_file"] = in.config;
  m["snapshots"] = bs.size();
  m["intruder"] = false;
  m["intruder_note"] = "the run has no body with role 'intruder': percolation is measured from wall to wall; "
                       "the intruder's percolation, loss height, top layer, keystones and events are not defined";
  m["d_mm"] = study.mean_diameter * kMm;
  m["measured_mean_diameter_mm"] = bs.front().measured_d * kMm;
  m["initial_bed_height_mm"] = bs.front().bed * kMm;
  m["final_bed_height_mm"] = last.bed * kMm;
  m["spanning_fraction"] = fraction(bs, [](const BedSnapshot& b) { return b.span_strong; });
  m["spanning_fraction_whole_network"] = fraction(bs, [](const BedSnapshot& b) { return b.span_whole; });
  m["final"] = {{"time_s", last.time},
                {"contacts", last.contacts},
                {"strong_contacts", last.strong_contacts},
                {"mean_fn_N_per_m", last.mean_fn},
                {"spanning", last.span_strong != 0},
                {"anisotropy", number_or_null(last.fabric.anisotropy)},
                {"anisotropy_debiased", number_or_null(last.fabric.debiased)},
                {"principal_angle_deg", number_or_null(last.fabric.angle_deg)},
                {"floor_load_N_per_m", floor_load},
                {"wall_load_N_per_m", wall_load},
                {"other_bodies_load_N_per_m", -last.load.other.y},
                {"wall_load_fraction", number_or_null(wall_load / (wall_load + floor_load))}};
  json sens;
  for (std::size_t v = 0; v < cfg.sensitivity_strong_threshold.size(); ++v)
    sens["spanning_fraction_vs_strong_threshold"].push_back(
        {{"strong_threshold", cfg.sensitivity_strong_threshold[v]},
         {"spanning_fraction", fraction(bs, [v](const BedSnapshot& b) { return b.span_sens[v]; })}});
  m["sensitivity"] = sens;
  m["config"] = to_json(cfg);
  return m;
}

void write_bed_series(H5Output& h, const std::vector<BedSnapshot>& bs) {
  using I = std::int64_t;
  using U = std::uint8_t;
  h.note("intruder", "none: the quantities of a run without an intruder");
  h.add("snapshots/time", column_of(bs, [](const BedSnapshot& b) { return b.time; }), "s", "snapshot time");
  h.add("snapshots/bed_height", column_of(bs, [](const BedSnapshot& b) { return b.bed; }), "m", "free surface above the floor's inner face");
  h.add("snapshots/contacts", column_of<I>(bs, [](const BedSnapshot& b) { return b.contacts; }), "-", "contacts with fn > 0 (graph edges)");
  h.add("snapshots/strong_contacts", column_of<I>(bs, [](const BedSnapshot& b) { return b.strong_contacts; }), "-", "contacts with fn > strong_threshold x mean_fn");
  h.add("snapshots/mean_fn", column_of(bs, [](const BedSnapshot& b) { return b.mean_fn; }), "N/m", "mean normal force over the graph's edges");
  h.add("spanning/strong", column_of<U>(bs, [](const BedSnapshot& b) { return b.span_strong; }), "-", "1: the left wall is connected to the right wall through the strong network");
  h.add("spanning/whole", column_of<U>(bs, [](const BedSnapshot& b) { return b.span_whole; }), "-", "1: the same through every contact with fn > 0");
  h.add("anisotropy/strong", column_of(bs, [](const BedSnapshot& b) { return b.fabric.anisotropy; }), "-", "2(l1-l2)/(l1+l2) of the strong grain-grain contacts above the floor (NaN: too few)");
  h.add("anisotropy/strong_debiased", column_of(bs, [](const BedSnapshot& b) { return b.fabric.debiased; }), "-", "the same less its finite-count bias");
  h.add("anisotropy/angle", column_of(bs, [](const BedSnapshot& b) { return b.fabric.angle_deg; }), "deg", "major axis from +x (90 = vertical)");
  h.add("anisotropy/contacts", column_of<I>(bs, [](const BedSnapshot& b) { return b.fabric.contacts; }), "-", "strong grain-grain contacts in the fabric");
  h.add("load/floor_fy", column_of(bs, [](const BedSnapshot& b) { return b.load.floor.y; }), "N/m", "vertical force of the grains on the floor (negative: downwards)");
  h.add("load/left_fx", column_of(bs, [](const BedSnapshot& b) { return b.load.left.x; }), "N/m", "horizontal force of the grains on the left wall");
  h.add("load/left_fy", column_of(bs, [](const BedSnapshot& b) { return b.load.left.y; }), "N/m", "vertical force of the grains on the left wall");
  h.add("load/right_fx", column_of(bs, [](const BedSnapshot& b) { return b.load.right.x; }), "N/m", "horizontal force of the grains on the right wall");
  h.add("load/right_fy", column_of(bs, [](const BedSnapshot& b) { return b.load.right.y; }), "N/m", "vertical force of the grains on the right wall");
  h.add("load/other_fy", column_of(bs, [](const BedSnapshot& b) { return b.load.other.y; }), "N/m", "vertical force of the grains on the other bodies (a hopper)");
}

}  // namespace

NetworkResult run_bed_network(const SnapshotSource& run, const NetworkInputs& in, const NetworkConfig& cfg,
                              const Study& study) {
  if (!in.events.empty() || !in.spectrum_metrics.empty())
    throw StageError(run.path() + ": the run has no body with role 'intruder': --events and --spectrum-metrics "
                     "(rupture events and the top layer of a pull-off) do not apply to it");
  const std::vector<std::size_t> figure = every_kth(run.snapshots(), static_cast<std::size_t>(cfg.figure_every));
  std::vector<BedSnapshot> bs;
  ForceSegments segments;
  for_each_snapshot(
      run, all_snapshots(run), 1,
      [&](std::size_t k, const Snapshot& s) {
        return measure_snapshot(s, k, cfg, std::binary_search(figure.begin(), figure.end(), k));
      },
      [&](std::size_t, BedSnapshot&& b) {
        if (!b.segments.snapshot.empty()) segments.append(b.segments);
        b.segments = ForceSegments{};
        bs.push_back(std::move(b));
      });
  NetworkResult r;
  r.metrics = {{"network", bed_metrics_json(bs, run.path(), in, cfg, study)}};
  r.h5 = H5Output("network", run.path());
  write_bed_series(r.h5, bs);
  segments.write(r.h5);
  return r;
}

}  // namespace dem2d::analysis
