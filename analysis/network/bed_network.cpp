// Stage `network` on a run without an intruder (a box, a silo, a fill): what
// needs no intruder. Definitions: analysis/network/README.md ("Runs without
// an intruder").
#include <cmath>
#include <limits>

#include "network/network_stage.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;
constexpr double kMm = 1e3;

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

}  // namespace

NetworkResult run_bed_network(const SnapshotSource& run, const NetworkInputs& in, const NetworkConfig& cfg,
                              const Study& study) {
  if (!in.events.empty() || !in.spectrum_metrics.empty())
    throw StageError(run.path() + ": the run has no body with role 'intruder': --events and --spectrum-metrics "
                     "(rupture events and the top layer of a pull-off) do not apply to it");
  const std::size_t S = run.snapshots();
  const FloorRule rule = floor_rule_from_name(cfg.floor_rule);
  const std::vector<std::size_t> figure = every_kth(S, static_cast<std::size_t>(cfg.figure_every));
  const auto min_contacts = static_cast<std::size_t>(cfg.anisotropy_min_contacts);
  const std::size_t variants = cfg.sensitivity_strong_threshold.size();

  std::vector<double> time, mean_fn, aniso, aniso_debiased, angle, floor_fy, left_fx, left_fy, right_fx, right_fy,
      other_fy, bed;
  std::vector<std::int64_t> contacts, strong_contacts, fabric_contacts;
  std::vector<std::uint8_t> span_strong, span_whole;
  std::vector<std::vector<std::uint8_t>> span_sens(variants);
  ForceSegments segments;
  double measured_d = 0.0;
  for (std::size_t k = 0; k < S; ++k) {
    const Snapshot s = run.snapshot(k);
    try {
      const PulloffGeometry geo = pulloff_geometry(s);
      if (k == 0) measured_d = mean_active_diameter(s);
      const std::vector<Partner> partners = classify_contacts(s, geo);
      const ContactGraph g = build_contact_graph(s, partners);
      const double strong = cfg.strong_threshold * g.mean_fn;
      time.push_back(s.time);
      bed.push_back(bed_height(s, geo));
      mean_fn.push_back(g.mean_fn);
      contacts.push_back(static_cast<std::int64_t>(g.edges()));
      strong_contacts.push_back(g.edges_above(strong));
      span_strong.push_back(percolation(g, strong, rule, g.left()).right);
      span_whole.push_back(percolation(g, 0.0, rule, g.left()).right);
      for (std::size_t v = 0; v < variants; ++v)
        span_sens[v].push_back(percolation(g, cfg.sensitivity_strong_threshold[v] * g.mean_fn, rule, g.left()).right);
      const Fabric f = region_fabric(s, partners, strong, geo.cell.floor, std::numeric_limits<double>::infinity(), min_contacts);
      aniso.push_back(f.anisotropy), aniso_debiased.push_back(f.debiased), angle.push_back(f.angle_deg);
      fabric_contacts.push_back(f.contacts);
      const BodyLoads load = body_loads(s, partners);
      floor_fy.push_back(load.floor.y), other_fy.push_back(load.other.y);
      left_fx.push_back(load.left.x), left_fy.push_back(load.left.y);
      right_fx.push_back(load.right.x), right_fy.push_back(load.right.y);
      if (std::binary_search(figure.begin(), figure.end(), k)) segments.add(s, partners, strong);
    } catch (const StageError& e) {
      throw StageError(run.path() + ": snapshot " + std::to_string(k) + ": " + e.what());
    }
  }

  const auto fraction = [](const std::vector<std::uint8_t>& flags) {
    std::int64_t n = 0;
    for (const std::uint8_t f : flags) n += f;
    return fraction_or_null(n, static_cast<std::int64_t>(flags.size()));
  };
  const std::size_t last = S - 1;
  // The weight the floor and the side walls carry (N/m, downwards positive).
  const double floor_load = -floor_fy[last], wall_load = -(left_fy[last] + right_fy[last]);
  json m;
  m["run_file"] = run.path();
  m["config_file"] = in.config;
  m["snapshots"] = S;
  m["intruder"] = false;
  m["intruder_note"] = "the run has no body with role 'intruder': percolation is measured from wall to wall; "
                       "the intruder's percolation, loss height, top layer, keystones and events are not defined";
  m["d_mm"] = study.mean_diameter * kMm;
  m["measured_mean_diameter_mm"] = measured_d * kMm;
  m["initial_bed_height_mm"] = bed.front() * kMm;
  m["final_bed_height_mm"] = bed[last] * kMm;
  m["spanning_fraction"] = fraction(span_strong);
  m["spanning_fraction_whole_network"] = fraction(span_whole);
  m["final"] = {{"time_s", time[last]},
                {"contacts", contacts[last]},
                {"strong_contacts", strong_contacts[last]},
                {"mean_fn_N_per_m", mean_fn[last]},
                {"spanning", span_strong[last] != 0},
                {"anisotropy", number_or_null(aniso[last])},
                {"anisotropy_debiased", number_or_null(aniso_debiased[last])},
                {"principal_angle_deg", number_or_null(angle[last])},
                {"floor_load_N_per_m", floor_load},
                {"wall_load_N_per_m", wall_load},
                {"other_bodies_load_N_per_m", -other_fy[last]},
                {"wall_load_fraction", number_or_null(wall_load / (wall_load + floor_load))}};
  json sens;
  for (std::size_t v = 0; v < variants; ++v)
    sens["spanning_fraction_vs_strong_threshold"].push_back(
        {{"strong_threshold", cfg.sensitivity_strong_threshold[v]}, {"spanning_fraction", fraction(span_sens[v])}});
  m["sensitivity"] = sens;
  m["config"] = to_json(cfg);

  NetworkResult r;
  r.metrics = {{"network", m}};
  r.h5 = H5Output("network", run.path());
  H5Output& h = r.h5;
  h.note("intruder", "none: the quantities of a run without an intruder");
  h.add("snapshots/time", time, "s", "snapshot time");
  h.add("snapshots/bed_height", bed, "m", "free surface above the floor's inner face");
  h.add("snapshots/contacts", contacts, "-", "contacts with fn > 0 (graph edges)");
  h.add("snapshots/strong_contacts", strong_contacts, "-", "contacts with fn > strong_threshold x mean_fn");
  h.add("snapshots/mean_fn", mean_fn, "N/m", "mean normal force over the graph's edges");
  h.add("spanning/strong", span_strong, "-", "1: the left wall is connected to the right wall through the strong network");
  h.add("spanning/whole", span_whole, "-", "1: the same through every contact with fn > 0");
  h.add("anisotropy/strong", aniso, "-", "2(l1-l2)/(l1+l2) of the strong grain-grain contacts above the floor (NaN: too few)");
  h.add("anisotropy/strong_debiased", aniso_debiased, "-", "the same less its finite-count bias");
  h.add("anisotropy/angle", angle, "deg", "major axis from +x (90 = vertical)");
  h.add("anisotropy/contacts", fabric_contacts, "-", "strong grain-grain contacts in the fabric");
  h.add("load/floor_fy", floor_fy, "N/m", "vertical force of the grains on the floor (negative: downwards)");
  h.add("load/left_fx", left_fx, "N/m", "horizontal force of the grains on the left wall");
  h.add("load/left_fy", left_fy, "N/m", "vertical force of the grains on the left wall");
  h.add("load/right_fx", right_fx, "N/m", "horizontal force of the grains on the right wall");
  h.add("load/right_fy", right_fy, "N/m", "vertical force of the grains on the right wall");
  h.add("load/other_fy", other_fy, "N/m", "vertical force of the grains on the other bodies (a hopper)");
  segments.write(h);
  return r;
}

}  // namespace dem2d::analysis
