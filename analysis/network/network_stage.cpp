#include "network/network_stage.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <set>

#include "common/json_input.hpp"
#include "common/snapshot_loop.hpp"
#include "common/stage_config.hpp"
#include "common/units.hpp"
#include "network/percolation_loss.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;
constexpr double kInf = std::numeric_limits<double>::infinity();

json mm_or_null(const std::optional<double>& metres) { return metres ? json(*metres * kMm) : json(nullptr); }
json mm_or_null(double metres) { return number_or_null(metres * kMm); }

// One percolation definition: strong threshold factor (0: the whole network) and floor rule.
struct Variant {
  std::string name;
  double factor = 1.0;
  FloorRule rule = FloorRule::vertex_removed;
  std::vector<std::uint8_t> left, right;
  std::vector<std::uint8_t> flags(bool both) const {
    std::vector<std::uint8_t> out(left.size());
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = both ? (left[k] && right[k]) : (left[k] || right[k]);
    return out;
  }
};

// Everything kept per snapshot for the run-level summaries.
struct Track {
  std::vector<double> time, height, intruder_y, mean_fn;
  std::vector<std::int64_t> contacts, strong_contacts;
  std::vector<Fabric> fabric_strong, fabric_all;
  std::vector<std::vector<Fabric>> fabric_region;  // strong, per sensitivity region height
  std::vector<std::vector<std::int32_t>> touching;  // grains touching the intruder (fn > 0)
  std::vector<KeystoneAnalysis> keystones;
  std::vector<std::vector<Vec2>> position;
};

// For one keystone share and ejection distance: which events are explained.
struct EventCheck {
  EventWindow window;
  std::vector<std::int32_t> keystones;
  Displacement moved;
  bool explained = false, ends_below = false;
  bool any_touching_moved = false;  // control: any grain touching the intruder moved as far
};

EventCheck check_event(const Track& t, const std::vector<double>& diameter, const RuptureEvent& e, double max_gap,
                       double share, double eject_d) {
  EventCheck c;
  c.window = event_window(t.time, e, max_gap);
  if (!c.window.resolved) return c;
  const auto a = static_cast<std::size_t>(c.window.before), b = static_cast<std::size_t>(c.window.after);
  c.keystones = t.keystones[a].keystones(share);
  c.moved = largest_displacement(c.keystones, t.position[a], t.position[b], diameter);
  c.explained = c.moved.grain >= 0 && c.moved.over_d > eject_d;
  c.ends_below = c.explained && t.position[b][static_cast<std::size_t>(c.moved.grain)].y < t.intruder_y[b];
  const Displacement any = largest_displacement(t.touching[a], t.position[a], t.position[b], diameter);
  c.any_touching_moved = any.grain >= 0 && any.over_d > eject_d;
  return c;
}

struct EventSummary {
  std::int64_t events = 0, resolved = 0, with_keystones = 0, explained = 0, explained_below = 0, any_touching = 0;
  double fraction = kNaN;              // explained / resolved
  double fraction_with_keystones = kNaN;  // explained / resolved events with keystones at onset
  double baseline = kNaN;              // same test on windows that contain no drop
  std::int64_t baseline_windows = 0;
  std::int64_t window_snapshots = 0;   // median snapshots per event window
  std::vector<EventCheck> checks;
};

// Windows of the events' median length that overlap no drop [peak, drop end]
// and start with the intruder in the bed: how often a keystone at the window's
// start moved more than eject_d diameters anyway.
void baseline(const Track& t, const std::vector<double>& diameter, const std::vector<RuptureEvent>& events,
              double bed_height, double share, double eject_d, EventSummary& s) {
  std::vector<std::int64_t> lengths;
  for (const EventCheck& c : s.checks)
    if (c.window.resolved) lengths.push_back(c.window.after - c.window.before);
  if (lengths.empty()) return;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  const auto m = static_cast<std::size_t>(std::max<std::int64_t>(lengths[lengths.size() / 2], 1));
  s.window_snapshots = static_cast<std::int64_t>(m);
  std::int64_t hit = 0;
  for (std::size_t k = 0; k + m < t.time.size(); ++k) {
    if (!(t.height[k] < bed_height)) continue;
    const double t0 = t.time[k], t1 = t.time[k + m];
    const bool overlaps = std::any_of(events.begin(), events.end(), [&](const RuptureEvent& e) {
      return e.peak_time <= t1 && e.drop_end_time >= t0;
    });
    if (overlaps) continue;
    ++s.baseline_windows;
    const Displacement d = largest_displacement(t.keystones[k].keystones(share), t.position[k], t.position[k + m], diameter);
    hit += d.grain >= 0 && d.over_d > eject_d;
  }
  if (s.baseline_windows > 0) s.baseline = static_cast<double>(hit) / static_cast<double>(s.baseline_windows);
}

EventSummary summarise_events(const Track& t, const std::vector<double>& diameter,
                              const std::vector<RuptureEvent>& events, double bed_height, const NetworkConfig& cfg,
                              double share, double eject_d) {
  EventSummary s;
  s.events = static_cast<std::int64_t>(events.size());
  for (const RuptureEvent& e : events) {
    s.checks.push_back(check_event(t, diameter, e, cfg.event_max_gap_s, share, eject_d));
    const EventCheck& c = s.checks.back();
    s.resolved += c.window.resolved;
    s.with_keystones += c.window.resolved && !c.keystones.empty();
    s.explained += c.explained;
    s.explained_below += c.ends_below;
    s.any_touching += c.any_touching_moved;
  }
  if (s.resolved > 0) s.fraction = static_cast<double>(s.explained) / static_cast<double>(s.resolved);
  if (s.with_keystones > 0)
    s.fraction_with_keystones = static_cast<double>(s.explained) / static_cast<double>(s.with_keystones);
  baseline(t, diameter, events, bed_height, share, eject_d, s);
  return s;
}

double mean_of(const std::vector<Fabric>& f, const std::vector<double>& heights, double lo, double hi,
               double Fabric::*field, std::int64_t* used = nullptr) {
  std::vector<double> v;
  for (const Fabric& x : f) v.push_back(x.*field);
  return mean_in_band(heights, v, lo, hi, used);
}

// Mean major-axis direction (an axis: angles modulo 180 deg, averaged as 2 theta), deg in [0, 180).
double circular_mean_angle(const std::vector<Fabric>& f, const std::vector<double>& heights, double lo, double hi) {
  double c = 0.0, s = 0.0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (!(heights[k] >= lo && heights[k] < hi) || std::isnan(f[k].angle_deg)) continue;
    const double a = 2.0 * f[k].angle_deg * std::numbers::pi / 180.0;
    c += std::cos(a), s += std::sin(a);
  }
  if (c == 0.0 && s == 0.0) return kNaN;
  double deg = 0.5 * std::atan2(s, c) * 180.0 / std::numbers::pi;
  return deg < 0.0 ? deg + 180.0 : deg;
}

}  // namespace

NetworkConfig load_network_config(const std::string& path) {
  StageConfig f(path);
  NetworkConfig c;
  f.number("strong_threshold", c.strong_threshold, 0.0, 100.0, "strong contacts: fn > this x the snapshot's mean fn");
  f.choice("floor_rule", c.floor_rule, {"vertex_removed", "bottom_layer_removed"}, "how the floor is kept out of paths");
  f.choice("walls", c.walls, {"both", "either"}, "percolating: the intruder reaches both side walls, or either");
  f.number("bin_width_d", c.bin_width_d, 1e-3, 100.0, "height bins, mean diameters");
  f.number("loss_level", c.loss_level, 0.0, 1.0, "percolating fraction that defines the loss height");
  f.number("loss_false_alarm", c.loss_false_alarm, 0.0, 1.0, "a loss: the step test's p-value below this");
  f.integer("loss_permutations", c.loss_permutations, 1, 1000000, "permutations of the step test");
  f.number("power_depth_end_to_wall", c.power_depth_end_to_wall, 0.0, 100.0,
           "a none's power: loss planted this x (L_c - L)/2 below the surface");
  f.number("power_tolerance_d", c.power_tolerance_d, 0.0, 100.0, "planted loss found within this, mean diameters");
  f.integer("power_replicas", c.power_replicas, 1, 100000, "planted series for the power");
  f.number("min_power", c.min_power, 0.0, 1.0, "a none with less power is undetermined");
  f.number("anisotropy_region_height", c.anisotropy_region_height, 1e-3, 100.0,
           "region above the intruder, in end-to-wall distances");
  f.integer("anisotropy_min_contacts", c.anisotropy_min_contacts, 1, 1000000, "strong contacts needed in the region");
  f.number("keystone_end_zone_d", c.keystone_end_zone_d, 0.0, 100.0, "intruder end zone, mean diameters");
  f.number("keystone_share", c.keystone_share, 1e-6, 1.0, "share of the max flow to a wall");
  f.number("ejection_distance_d", c.ejection_distance_d, 0.0, 100.0, "keystone displacement, own diameters");
  f.number("event_max_gap_s", c.event_max_gap_s, 0.0, 1e6, "largest snapshot gap to an event time, s");
  f.integer("figure_every", c.figure_every, 1, 1000000000, "force-network segments every k-th snapshot");
  f.numbers("sensitivity_strong_threshold", c.sensitivity_strong_threshold, 0.0, 100.0, "x mean fn");
  f.numbers("sensitivity_bin_width_d", c.sensitivity_bin_width_d, 1e-3, 100.0, "mean diameters");
  f.numbers("sensitivity_anisotropy_region_height", c.sensitivity_anisotropy_region_height, 1e-3, 100.0,
            "end-to-wall distances");
  f.numbers("sensitivity_anisotropy_min_contacts", c.sensitivity_anisotropy_min_contacts, 1.0, 1e6, "contacts");
  f.numbers("sensitivity_keystone_share", c.sensitivity_keystone_share, 1e-6, 1.0, "share of the max flow");
  f.numbers("sensitivity_ejection_distance_d", c.sensitivity_ejection_distance_d, 0.0, 100.0, "own diameters");
  f.reject_unknown();
  return c;
}

json to_json(const NetworkConfig& c) {
  return {{"strong_threshold", c.strong_threshold},
          {"floor_rule", c.floor_rule},
          {"walls", c.walls},
          {"bin_width_d", c.bin_width_d},
          {"loss_level", c.loss_level},
          {"loss_false_alarm", c.loss_false_alarm},
          {"loss_permutations", c.loss_permutations},
          {"power_depth_end_to_wall", c.power_depth_end_to_wall},
          {"power_tolerance_d", c.power_tolerance_d},
          {"power_replicas", c.power_replicas},
          {"min_power", c.min_power},
          {"anisotropy_region_height", c.anisotropy_region_height},
          {"anisotropy_min_contacts", c.anisotropy_min_contacts},
          {"keystone_end_zone_d", c.keystone_end_zone_d},
          {"keystone_share", c.keystone_share},
          {"ejection_distance_d", c.ejection_distance_d},
          {"event_max_gap_s", c.event_max_gap_s},
          {"figure_every", c.figure_every},
          {"sensitivity_strong_threshold", c.sensitivity_strong_threshold},
          {"sensitivity_bin_width_d", c.sensitivity_bin_width_d},
          {"sensitivity_anisotropy_region_height", c.sensitivity_anisotropy_region_height},
          {"sensitivity_anisotropy_min_contacts", c.sensitivity_anisotropy_min_contacts},
          {"sensitivity_keystone_share", c.sensitivity_keystone_share},
          {"sensitivity_ejection_distance_d", c.sensitivity_ejection_distance_d}};
}

double read_top_layer_height_mm(const std::string& path) {
  const nlohmann::json j = read_json(path, "spectrum metrics");
  if (!j.contains("spectrum") || !j["spectrum"].is_object()) return kNaN;
  const nlohmann::json& v = j["spectrum"].value("top_layer_height_mm", nlohmann::json(nullptr));
  if (v.is_null()) return kNaN;
  if (!v.is_number()) throw StageError(path + ": spectrum.top_layer_height_mm = " + v.dump() + ": expected a number");
  return v.get<double>();
}

NetworkResult run_network(const NetworkInputs& in, const NetworkConfig& cfg, const Study& study) {
  const RunFileSource run(in.run);
  if (run.snapshots() == 0) throw StageError(run.path() + ": the run file has no snapshots");
  const std::vector<std::string>& roles = run.body_roles();
  if (std::find(roles.begin(), roles.end(), "intruder") == roles.end()) return run_bed_network(run, in, cfg, study);
  std::vector<RuptureEvent> events;
  if (!in.events.empty()) events = read_events(in.events);
  const double spectrum_top_mm = in.spectrum_metrics.empty() ? kNaN : read_top_layer_height_mm(in.spectrum_metrics);
  return run_network(run, events, spectrum_top_mm, in, cfg, study);
}

namespace {

// The percolation variants: the configured strong network, its sensitivity
// thresholds, the other floor rule, the whole network; S snapshots each.
std::vector<Variant> percolation_variants(const NetworkConfig& cfg, std::size_t S) {
  const FloorRule rule = floor_rule_from_name(cfg.floor_rule);
  const FloorRule other_rule = rule == FloorRule::vertex_removed ? FloorRule::bottom_layer_removed : FloorRule::vertex_removed;
  std::vector<Variant> variants = {{"strong", cfg.strong_threshold, rule, {}, {}}};
  for (const double f : cfg.sensitivity_strong_threshold)
    if (f != cfg.strong_threshold) variants.push_back({"strong_x" + format_number(f), f, rule, {}, {}});
  variants.push_back({std::string("strong_") + floor_rule_name(other_rule), cfg.strong_threshold, other_rule, {}, {}});
  variants.push_back({"whole", 0.0, rule, {}, {}});
  for (Variant& v : variants) v.left.assign(S, 0), v.right.assign(S, 0);
  return variants;
}

// Snapshots whose force network goes to the figure data: every k-th and the
// one before each event's peak.
std::set<std::size_t> figure_snapshots(const SnapshotSource& run, const std::vector<RuptureEvent>& events,
                                       const NetworkConfig& cfg) {
  std::set<std::size_t> figure;
  for (const std::size_t k : every_kth(run.snapshots(), static_cast<std::size_t>(cfg.figure_every))) figure.insert(k);
  for (const RuptureEvent& e : events)
    if (const EventWindow w = event_window(run.snapshot_times(), e, cfg.event_max_gap_s); w.before >= 0)
      figure.insert(static_cast<std::size_t>(w.before));
  return figure;
}

// What the snapshot loop gathers.
struct Tracked {
  Track t;
  std::vector<Variant> variants;
  ForceSegments segments;
  double measured_d = 0.0, bed0 = 0.0, end_to_wall = 0.0;  // (m), at the first snapshot
  std::vector<double> diameter;                             // (m) [N]
};

// Snapshot k's measures: its contact graph's percolation for every variant,
// the fabric above the intruder, the grains touching it, its keystones, its
// force segments if it goes to the figure; the cell's at the first snapshot.
struct NetworkSnapshot {
  double time = 0.0, height = 0.0, intruder_y = 0.0, mean_fn = 0.0;
  std::int64_t contacts = 0, strong_contacts = 0;
  std::vector<Percolation> percolation;  // per variant
  Fabric fabric_strong, fabric_all;
  std::vector<Fabric> fabric_region;
  std::vector<std::int32_t> touching;
  KeystoneAnalysis keystones;
  std::vector<Vec2> position;
  ForceSegments segments;               // empty unless to the figure
  double measured_d = 0.0, bed0 = 0.0, end_to_wall = 0.0;  // k = 0 only
  std::vector<double> diameter;                             // k = 0 only
};

NetworkSnapshot measure_snapshot(const Snapshot& s, std::size_t k, const NetworkConfig& cfg, double d_mean,
                                 bool to_figure, const std::vector<Variant>& variants) {
  NetworkSnapshot n;
  const FloorRule rule = floor_rule_from_name(cfg.floor_rule);
  const PulloffGeometry geo = pulloff_geometry(s);
  if (k == 0) {
    n.measured_d = mean_active_diameter(s);
    n.bed0 = bed_height(s, geo);
    n.end_to_wall = geo.end_to_wall();
    n.diameter = s.diameter;
  }
  const std::vector<Partner> partners = classify_contacts(s, geo);
  const ContactGraph g = build_contact_graph(s, partners);
  const double strong = cfg.strong_threshold * g.mean_fn;
  n.time = s.time, n.height = geo.height(), n.intruder_y = geo.centre.y, n.mean_fn = g.mean_fn;
  n.contacts = static_cast<std::int64_t>(g.edges());
  n.strong_contacts = g.edges_above(strong);
  for (const Variant& v : variants) n.percolation.push_back(percolation(g, v.factor * g.mean_fn, v.rule, g.intruder()));
  const double y0 = n.intruder_y, y1 = y0 + cfg.anisotropy_region_height * geo.end_to_wall();
  const auto min_contacts = static_cast<std::size_t>(cfg.anisotropy_min_contacts);
  n.fabric_strong = region_fabric(s, partners, strong, y0, y1, min_contacts);
  n.fabric_all = region_fabric(s, partners, 0.0, y0, y1, min_contacts);
  for (const double h : cfg.sensitivity_anisotropy_region_height)
    n.fabric_region.push_back(region_fabric(s, partners, strong, y0, y0 + h * geo.end_to_wall(), min_contacts));
  for (const auto e : boost::make_iterator_range(boost::out_edges(g.intruder(), g.graph)))
    if (boost::target(e, g.graph) < g.grains) n.touching.push_back(static_cast<std::int32_t>(boost::target(e, g.graph)));
  n.keystones = analyse_keystones(g, s, geo, strong, rule, cfg.keystone_end_zone_d * d_mean);
  n.position = s.position;
  if (to_figure) n.segments.add(s, partners, strong);
  return n;
}

void fold_snapshot(std::size_t k, NetworkSnapshot&& n, Tracked& out) {
  Track& t = out.t;
  if (k == 0) {
    out.measured_d = n.measured_d, out.bed0 = n.bed0, out.end_to_wall = n.end_to_wall;
    out.diameter = std::move(n.diameter);
  }
  t.time.push_back(n.time), t.height.push_back(n.height), t.intruder_y.push_back(n.intruder_y);
  t.mean_fn.push_back(n.mean_fn), t.contacts.push_back(n.contacts), t.strong_contacts.push_back(n.strong_contacts);
  for (std::size_t v = 0; v < out.variants.size(); ++v)
    out.variants[v].left[k] = n.percolation[v].left, out.variants[v].right[k] = n.percolation[v].right;
  t.fabric_strong.push_back(n.fabric_strong), t.fabric_all.push_back(n.fabric_all);
  t.fabric_region.resize(n.fabric_region.size());
  for (std::size_t r = 0; r < n.fabric_region.size(); ++r) t.fabric_region[r].push_back(n.fabric_region[r]);
  t.touching.push_back(std::move(n.touching));
  t.keystones.push_back(std::move(n.keystones));
  t.position.push_back(std::move(n.position));
  if (!n.segments.snapshot.empty()) out.segments.append(n.segments);
}

// The loop over the run's snapshots.
Tracked track(const SnapshotSource& run, const std::vector<RuptureEvent>& events, const NetworkConfig& cfg,
              double d_mean) {
  Tracked out;
  out.variants = percolation_variants(cfg, run.snapshots());
  const std::set<std::size_t> figure = figure_snapshots(run, events, cfg);
  for_each_snapshot(
      run, all_snapshots(run), 1,
      [&](std::size_t k, const Snapshot& s) { return measure_snapshot(s, k, cfg, d_mean, figure.count(k) > 0, out.variants); },
      [&](std::size_t k, NetworkSnapshot&& n) { fold_snapshot(k, std::move(n), out); });
  return out;
}

// The top layer's height (m; NaN: none), where it came from, and the top of
// the range called "below the top layer".
struct TopLayer {
  double height = kNaN;
  std::string source;
  double below_hi = 0.0;
};

TopLayer top_layer(double spectrum_top_mm, const std::optional<double>& loss, const NetworkInputs& in, double bed0) {
  TopLayer top;
  if (std::isfinite(spectrum_top_mm)) {
    top.height = spectrum_top_mm / kMm;
    top.source = "spectrum metrics (" + in.spectrum_metrics + ": spectrum.top_layer_height_mm)";
  } else if (loss) {
    top.height = *loss;
    top.source = std::string(in.spectrum_metrics.empty() ? "no --spectrum-metrics given"
                                                         : "spectrum.top_layer_height_mm absent or null") +
                 ": this stage's percolation-loss height";
  } else {
    top.source = "none: no spectrum top layer and percolation is never lost; 'below the top layer' = the whole pull-off";
  }
  top.below_hi = std::isfinite(top.height) ? top.height : bed0;
  return top;
}

// The fabric of the strong network above the intruder, in and below the top layer.
void anisotropy_metrics(json& m, const Track& t, double top, double bed0, double below_hi) {
  std::int64_t n_top = 0, n_top_all = 0;
  const double top_aniso = std::isfinite(top) ? mean_of(t.fabric_strong, t.height, top, bed0, &Fabric::anisotropy, &n_top) : kNaN;
  m["top_layer_anisotropy"] = number_or_null(top_aniso);
  m["top_layer_anisotropy_snapshots"] = n_top;
  {
    std::int64_t in_top = 0;
    for (const double h : t.height) in_top += std::isfinite(top) && h >= top && h < bed0;
    m["top_layer_snapshots_too_few_strong_contacts"] = in_top - n_top;
  }
  m["top_layer_anisotropy_debiased"] =
      number_or_null(std::isfinite(top) ? mean_of(t.fabric_strong, t.height, top, bed0, &Fabric::debiased) : kNaN);
  m["top_layer_anisotropy_noise"] =
      number_or_null(std::isfinite(top) ? mean_of(t.fabric_strong, t.height, top, bed0, &Fabric::noise) : kNaN);
  m["anisotropy_below_top_layer"] = number_or_null(mean_of(t.fabric_strong, t.height, -kInf, below_hi, &Fabric::anisotropy));
  m["anisotropy_below_top_layer_debiased"] =
      number_or_null(mean_of(t.fabric_strong, t.height, -kInf, below_hi, &Fabric::debiased));
  m["anisotropy_below_top_layer_noise"] = number_or_null(mean_of(t.fabric_strong, t.height, -kInf, below_hi, &Fabric::noise));
  m["principal_angle_below_top_layer_deg"] = number_or_null(circular_mean_angle(t.fabric_strong, t.height, -kInf, below_hi));
  m["top_layer_anisotropy_all_contacts"] = number_or_null(
      std::isfinite(top) ? mean_of(t.fabric_all, t.height, top, bed0, &Fabric::anisotropy, &n_top_all) : kNaN);
  m["anisotropy_below_top_layer_all_contacts"] =
      number_or_null(mean_of(t.fabric_all, t.height, -kInf, below_hi, &Fabric::anisotropy));
  m["top_layer_anisotropy_all_contacts_debiased"] = number_or_null(
      std::isfinite(top) ? mean_of(t.fabric_all, t.height, top, bed0, &Fabric::debiased) : kNaN);
  m["anisotropy_below_top_layer_all_contacts_debiased"] =
      number_or_null(mean_of(t.fabric_all, t.height, -kInf, below_hi, &Fabric::debiased));
  if (std::isfinite(top) && n_top == 0)
    m["top_layer_anisotropy_note"] = "no snapshot above the top-layer height has anisotropy_min_contacts strong "
                                     "contacts above the intruder: the strong network is (nearly) absent there";

}

// Keystones at the rupture events (--events): which explain a drop.
EventSummary event_metrics(json& m, const Track& t, const std::vector<double>& diameter,
                           const std::vector<RuptureEvent>& events, const NetworkInputs& in, const NetworkConfig& cfg,
                           double bed0, const std::vector<std::uint8_t>& flags) {
  const std::size_t S = t.time.size();
  std::int64_t with_keys = 0, in_bed = 0;
  for (std::size_t k = 0; k < S; ++k)
    if (t.height[k] < bed0) ++in_bed, with_keys += !t.keystones[k].keystones(cfg.keystone_share).empty();
  m["snapshots_with_keystones_fraction"] = fraction_or_null(with_keys, in_bed);
  EventSummary ev;
  if (events.empty() && in.events.empty()) {
    m["keystone_explained_fraction"] = nullptr;
    m["keystone_note"] = "no --events file given: the rupture events were not checked";
  } else {
    ev = summarise_events(t, diameter, events, bed0, cfg, cfg.keystone_share, cfg.ejection_distance_d);
    m["keystone_explained_fraction"] = number_or_null(ev.fraction);
    m["events"] = ev.events;
    m["events_resolved"] = ev.resolved;
    m["events_with_keystones_at_peak"] = ev.with_keystones;
    m["events_explained"] = ev.explained;
    m["events_explained_ending_below_intruder_centre"] = ev.explained_below;
    m["events_any_intruder_grain_displaced"] = ev.any_touching;
    m["any_intruder_grain_displaced_fraction"] = fraction_or_null(ev.any_touching, ev.resolved);
    std::int64_t perc_peak = 0, perc_lost = 0;
    for (const EventCheck& c : ev.checks) {
      if (!c.window.resolved) continue;
      const auto a = static_cast<std::size_t>(c.window.before), b = static_cast<std::size_t>(c.window.after);
      perc_peak += flags[a];
      perc_lost += flags[a] && !flags[b];
    }
    m["events_percolating_at_peak"] = perc_peak;
    m["events_percolation_lost_after_drop"] = perc_lost;
    m["keystone_explained_fraction_of_events_with_keystones"] = number_or_null(ev.fraction_with_keystones);
    m["keystone_displaced_fraction_outside_drops"] = number_or_null(ev.baseline);
    m["baseline_windows"] = ev.baseline_windows;
    m["baseline_window_snapshots"] = ev.window_snapshots;
  }

  return ev;
}

LossTestSettings loss_settings(const NetworkConfig& cfg, const HeightBins& bins, double d_mean, double end_to_wall) {
  LossTestSettings s;
  s.bins = bins, s.level = cfg.loss_level;
  s.false_alarm = cfg.loss_false_alarm, s.permutations = static_cast<int>(cfg.loss_permutations);
  s.depth = cfg.power_depth_end_to_wall * end_to_wall, s.tolerance = cfg.power_tolerance_d * d_mean;
  s.replicas = static_cast<int>(cfg.power_replicas), s.min_power = cfg.min_power;
  return s;
}

void loss_metrics(json& m, const LossTest& lt, const NetworkConfig& cfg) {
  m["percolation_loss_height_mm"] = mm_or_null(lt.height);
  m["percolation_loss_rule_height_mm"] = mm_or_null(lt.rule_height);
  m["percolation_loss_p_value"] = number_or_null(lt.p_value);
  m["percolation_loss_outcome"] = lt.outcome;
  m["percolation_loss_power"] = number_or_null(lt.power.power);
  m["percolation_loss_power_detail"] = {{"planted_depth_mm", mm_or_null(lt.power.depth)},
                                        {"flip_rate_below", number_or_null(lt.power.flip_below)},
                                        {"flip_rate_above", number_or_null(lt.power.flip_above)},
                                        {"replicas", lt.power.replicas},
                                        {"min_power", cfg.min_power}};
}

// How the metrics move with the settings' thresholds.
json sensitivity(const Tracked& tr, const std::vector<RuptureEvent>& events, const NetworkInputs& in,
                 const NetworkConfig& cfg, double d_mean, double top, double below_hi) {
  const Track& t = tr.t;
  const std::vector<Variant>& variants = tr.variants;
  const double bed0 = tr.bed0;
  const std::vector<double>& diameter = tr.diameter;
  const HeightBins bins{cfg.bin_width_d * d_mean};
  const std::vector<std::uint8_t> flags = variants.front().flags(cfg.walls == "both");
  const PercolationProfile profile = percolation_profile(bins, t.height, flags);
  json sens;
  for (const Variant& v : variants) {
    for (const bool b : {true, false}) {
      const std::vector<std::uint8_t> fl = v.flags(b);
      const std::optional<double> h = loss_height(percolation_profile(bins, t.height, fl), cfg.loss_level);
      sens["percolation"].push_back({{"network", v.factor == 0.0 ? "whole" : "strong"},
                                     {"strong_threshold", v.factor},
                                     {"floor_rule", floor_rule_name(v.rule)},
                                     {"walls", b ? "both" : "either"},
                                     {"loss_height_mm", mm_or_null(h)},
                                     {"fraction_below_top_layer", number_or_null(flagged_fraction(t.height, fl, -kInf, below_hi))}});
    }
  }
  for (const double w : cfg.sensitivity_bin_width_d) {
    const std::optional<double> h = loss_height(percolation_profile(HeightBins{w * d_mean}, t.height, flags), cfg.loss_level);
    sens["loss_height_vs_bin_width"].push_back({{"bin_width_d", w}, {"loss_height_mm", mm_or_null(h)}});
  }
  for (std::size_t r = 0; r < t.fabric_region.size(); ++r) {
    const std::vector<Fabric>& f = t.fabric_region[r];
    std::int64_t used = 0;
    const double top_a = std::isfinite(top) ? mean_of(f, t.height, top, bed0, &Fabric::anisotropy, &used) : kNaN;
    sens["anisotropy_vs_region_height"].push_back(
        {{"region_height", cfg.sensitivity_anisotropy_region_height[r]},
         {"top_layer", number_or_null(top_a)},
         {"top_layer_debiased", number_or_null(std::isfinite(top) ? mean_of(f, t.height, top, bed0, &Fabric::debiased) : kNaN)},
         {"top_layer_snapshots", used},
         {"below_top_layer", number_or_null(mean_of(f, t.height, -kInf, below_hi, &Fabric::anisotropy))},
         {"below_top_layer_debiased", number_or_null(mean_of(f, t.height, -kInf, below_hi, &Fabric::debiased))}});
  }
  for (const double n : cfg.sensitivity_anisotropy_min_contacts) {
    std::vector<Fabric> f = t.fabric_strong;
    for (Fabric& x : f)
      if (static_cast<double>(x.contacts) < n) x = Fabric{};
    std::int64_t used = 0;
    const double top_a = std::isfinite(top) ? mean_of(f, t.height, top, bed0, &Fabric::anisotropy, &used) : kNaN;
    sens["anisotropy_vs_min_contacts"].push_back(
        {{"min_contacts", n},
         {"top_layer", number_or_null(top_a)},
         {"top_layer_snapshots", used},
         {"below_top_layer", number_or_null(mean_of(f, t.height, -kInf, below_hi, &Fabric::anisotropy))}});
  }
  for (const double level : {0.25, 0.5, 0.75}) {
    const std::optional<double> h = loss_height(profile, level);
    sens["loss_height_vs_level"].push_back({{"level", level}, {"loss_height_mm", mm_or_null(h)}});
  }
  if (!in.events.empty()) {
    for (const double share : cfg.sensitivity_keystone_share)
      for (const double ej : cfg.sensitivity_ejection_distance_d) {
        const EventSummary e = summarise_events(t, diameter, events, bed0, cfg, share, ej);
        sens["keystones"].push_back({{"keystone_share", share},
                                     {"ejection_distance_d", ej},
                                     {"explained_fraction", number_or_null(e.fraction)},
                                     {"events_with_keystones", e.with_keystones},
                                     {"displaced_fraction_outside_drops", number_or_null(e.baseline)}});
      }
  }
  return sens;
}

// network.h5: the per-snapshot series, percolation, profile, fabric, keystones, events.
// network.h5's keystones: the max flows, the keystones and the candidates per snapshot.
void write_keystones(H5Output& h, const Track& t, const NetworkConfig& cfg) {
  std::vector<double> flow_l, flow_r, c_share_l, c_share_r;
  std::vector<std::int64_t> k_start = {0}, c_start = {0};
  std::vector<std::int32_t> k_grain, c_grain, c_end;
  for (const KeystoneAnalysis& a : t.keystones) {
    flow_l.push_back(a.flow_left), flow_r.push_back(a.flow_right);
    for (const std::int32_t g : a.keystones(cfg.keystone_share)) k_grain.push_back(g);
    k_start.push_back(static_cast<std::int64_t>(k_grain.size()));
    for (const KeystoneCandidate& c : a.candidates)
      c_grain.push_back(c.grain), c_end.push_back(c.end), c_share_l.push_back(c.share_left), c_share_r.push_back(c.share_right);
    c_start.push_back(static_cast<std::int64_t>(c_grain.size()));
  }
  h.add("keystones/flow_left", flow_l, "N/m", "max flow intruder -> left wall, strong network, capacities fn");
  h.add("keystones/flow_right", flow_r, "N/m", "max flow intruder -> right wall");
  h.add("keystones/start", k_start, "-", "keystones of snapshot k: grain[start[k] .. start[k+1]-1]");
  h.add("keystones/grain", k_grain, "-", "keystone grain ids (share >= keystone_share)");
  h.add("keystones/candidate_start", c_start, "-", "candidates of snapshot k: rows start[k] .. start[k+1]-1");
  h.add("keystones/candidate_grain", c_grain, "-", "grain on a strong contact with an intruder end");
  h.add("keystones/candidate_end", c_end, "-", "-1: end a (bodies/intruder a), +1: end b");
  h.add("keystones/candidate_share_left", c_share_l, "-", "share of the max flow to the left wall through it");
  h.add("keystones/candidate_share_right", c_share_r, "-", "share of the max flow to the right wall through it");
}

// network.h5's events: each rupture's snapshots, keystones and what moved.
void write_events(H5Output& h, const EventSummary& ev, const std::vector<RuptureEvent>& events) {
  std::vector<double> peak, drop, disp;
  std::vector<std::int64_t> before, after, nkeys;
  std::vector<std::int32_t> grain;
  std::vector<std::uint8_t> resolved, explained, below;
  for (std::size_t e = 0; e < ev.checks.size(); ++e) {
    const EventCheck& c = ev.checks[e];
    peak.push_back(events[e].peak_time), drop.push_back(events[e].drop_end_time);
    before.push_back(c.window.before), after.push_back(c.window.after);
    resolved.push_back(c.window.resolved), nkeys.push_back(static_cast<std::int64_t>(c.keystones.size()));
    grain.push_back(c.moved.grain), disp.push_back(c.window.resolved && c.moved.grain >= 0 ? c.moved.over_d : kNaN);
    explained.push_back(c.explained), below.push_back(c.ends_below);
  }
  h.add("events/peak_time", peak, "s", "from the events file");
  h.add("events/drop_end_time", drop, "s", "from the events file");
  h.add("events/snapshot_before", before, "-", "last snapshot at or before the peak (-1: none)");
  h.add("events/snapshot_after", after, "-", "first snapshot at or after the drop's end (-1: none)");
  h.add("events/resolved", resolved, "-", "1: both snapshots within event_max_gap_s");
  h.add("events/keystones", nkeys, "-", "keystones at snapshot_before");
  h.add("events/moved_grain", grain, "-", "the keystone that moved most (-1: none)");
  h.add("events/moved_over_d", disp, "-", "its displacement / its diameter");
  h.add("events/explained", explained, "-", "1: moved_over_d > ejection_distance_d");
  h.add("events/ends_below_intruder", below, "-", "1: explained and that grain ends below the intruder's centre");
  std::vector<std::uint8_t> any;
  for (const EventCheck& c : ev.checks) any.push_back(c.any_touching_moved);
  h.add("events/any_intruder_grain_displaced", any, "-",
        "1: some grain touching the intruder at snapshot_before moved more than ejection_distance_d diameters");
}

void write_network_h5(H5Output& h, const Tracked& tr, const PercolationProfile& profile, const EventSummary& ev,
                      const std::vector<RuptureEvent>& events, const NetworkConfig& cfg) {
  const Track& t = tr.t;
  h.add("snapshots/time", t.time, "s", "snapshot time");
  h.add("snapshots/height", t.height, "m", "intruder centre above the floor's inner face");
  h.add("snapshots/mean_fn", t.mean_fn, "N/m", "mean normal force over the contacts with fn > 0");
  h.add("snapshots/contacts", t.contacts, "-", "contacts with fn > 0 (graph edges)");
  h.add("snapshots/strong_contacts", t.strong_contacts, "-", "contacts with fn > strong_threshold x mean_fn");
  for (const Variant& v : tr.variants) {
    const std::string what = (v.factor == 0.0 ? std::string("whole network (fn > 0)")
                                              : "strong network (fn > " + format_number(v.factor) + " x mean)") +
                             ", floor rule " + floor_rule_name(v.rule);
    h.add("percolation/" + v.name + "/left", v.left, "-", "1: intruder connected to the left wall through the " + what);
    h.add("percolation/" + v.name + "/right", v.right, "-", "1: intruder connected to the right wall through the " + what);
  }
  h.add("profile/lower", profile.lower, "m", "height bin lower edge (bins with snapshots)");
  h.add("profile/upper", profile.upper, "m", "height bin upper edge");
  h.add("profile/snapshots", profile.snapshots, "-", "snapshots in the bin");
  h.add("profile/percolating_fraction", profile.fraction, "-",
        std::string("fraction of the bin's snapshots percolating (strong network, ") + cfg.walls + " walls)");
  const auto column = [&](const std::vector<Fabric>& f, double Fabric::*field) {
    std::vector<double> v;
    for (const Fabric& x : f) v.push_back(x.*field);
    return v;
  };
  std::vector<std::int64_t> n_region;
  for (const Fabric& f : t.fabric_strong) n_region.push_back(f.contacts);
  h.add("anisotropy/strong", column(t.fabric_strong, &Fabric::anisotropy), "-",
        "2(l1-l2)/(l1+l2) of the strong grain-grain contacts above the intruder (NaN: too few)");
  h.add("anisotropy/strong_angle", column(t.fabric_strong, &Fabric::angle_deg), "deg", "major axis from +x (90 vertical)");
  h.add("anisotropy/strong_noise", column(t.fabric_strong, &Fabric::noise), "-", "sqrt(pi/n): isotropic noise level");
  h.add("anisotropy/strong_debiased", column(t.fabric_strong, &Fabric::debiased), "-", "sqrt(max(0, a^2 - 4/n))");
  h.add("anisotropy/strong_contacts", n_region, "-", "strong grain-grain contacts in the region");
  h.add("anisotropy/all", column(t.fabric_all, &Fabric::anisotropy), "-", "same for all grain-grain contacts with fn > 0");
  h.add("anisotropy/all_angle", column(t.fabric_all, &Fabric::angle_deg), "deg", "major axis from +x");

  write_keystones(h, t, cfg);
  tr.segments.write(h);
  if (!ev.checks.empty()) write_events(h, ev, events);
}

}  // namespace

NetworkResult run_network(const SnapshotSource& run, const std::vector<RuptureEvent>& events, double spectrum_top_mm,
                          const NetworkInputs& in, const NetworkConfig& cfg, const Study& study) {
  const std::size_t S = run.snapshots();
  if (S == 0) throw StageError(run.path() + ": the run has no snapshots");
  const double d_mean = study.mean_diameter;  // "d" of the settings
  const Tracked tr = track(run, events, cfg, d_mean);
  const Track& t = tr.t;
  const std::vector<Variant>& variants = tr.variants;
  const double measured_d = tr.measured_d, bed0 = tr.bed0, end_to_wall = tr.end_to_wall;

  // Percolation against height and the loss height.
  const bool both = cfg.walls == "both";
  const HeightBins bins{cfg.bin_width_d * d_mean};
  const std::vector<std::uint8_t> flags = variants.front().flags(both);
  const PercolationProfile profile = percolation_profile(bins, t.height, flags);
  const LossTest lt = percolation_loss(t.height, flags, bed0, loss_settings(cfg, bins, d_mean, end_to_wall));
  const std::optional<double>& loss = lt.height;
  const TopLayer layer = top_layer(spectrum_top_mm, loss, in, bed0);
  const double top = layer.height, below_hi = layer.below_hi;
  const std::string& top_source = layer.source;

  json m;
  m["run_file"] = run.path();
  m["config_file"] = in.config;
  m["events_file"] = in.events.empty() ? json(nullptr) : json(in.events);
  m["spectrum_metrics_file"] = in.spectrum_metrics.empty() ? json(nullptr) : json(in.spectrum_metrics);
  m["snapshots"] = S;
  m["intruder"] = true;
  m["d_mm"] = d_mean * kMm;
  m["measured_mean_diameter_mm"] = measured_d * kMm;
  m["initial_bed_height_mm"] = bed0 * kMm;
  m["end_to_wall_distance_mm"] = end_to_wall * kMm;
  loss_metrics(m, lt, cfg);
  m["top_layer_height_mm"] = mm_or_null(top);
  m["top_layer_source"] = top_source;

  std::int64_t n_below = 0;
  m["percolating_fraction_below_top_layer"] = number_or_null(flagged_fraction(t.height, flags, -kInf, below_hi, &n_below));
  m["snapshots_below_top_layer"] = n_below;
  m["percolating_fraction_above_top_layer"] = number_or_null(flagged_fraction(t.height, flags, below_hi, bed0));
  m["whole_network_percolating_fraction_below_top_layer"] =
      number_or_null(flagged_fraction(t.height, variants.back().flags(both), -kInf, below_hi));

  anisotropy_metrics(m, t, top, bed0, below_hi);
  const EventSummary ev = event_metrics(m, t, tr.diameter, events, in, cfg, bed0, flags);
  m["sensitivity"] = sensitivity(tr, events, in, cfg, d_mean, top, below_hi);
  m["config"] = to_json(cfg);

  NetworkResult r;
  r.metrics = {{"network", m}};
  r.h5 = H5Output("network", run.path());
  write_network_h5(r.h5, tr, profile, ev, events, cfg);
  return r;
}

}  // namespace dem2d::analysis
