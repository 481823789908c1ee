#include "friction/friction.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/snapshot_loop.hpp"
#include "common/stage_config.hpp"
#include "common/units.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;
constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

FrictionLaws friction_laws(const RunParameters& run, std::optional<double> mu_grain, std::optional<double> mu_wall,
                           const std::string& where) {
  if (!has(run.effects, effect::friction) && !(mu_grain && mu_wall))
    throw StageError(where + ": the run has no friction (effects.friction is off): mu* is undefined; give mu_grain "
                             "and mu_wall in the config to measure |F_t| / (mu F_n) anyway");
  FrictionLaws laws{run.effects, coefficients(run.grain_grain, run.dt), coefficients(run.grain_body, run.dt)};
  if (mu_grain) laws.grain.mu = *mu_grain;
  if (mu_wall) laws.wall.mu = *mu_wall;
  for (const double mu : {laws.grain.mu, laws.wall.mu})
    if (!(mu > 0.0)) throw StageError(where + ": a Coulomb coefficient is " + format_number(mu) + ": must be > 0");
  return laws;
}

std::vector<double> mu_star(const Contacts& c, const std::vector<Partner>& partners, const FrictionLaws& laws) {
  std::vector<double> out(c.size(), kNaN);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!(c.overlap[k] > 0.0)) continue;  // attracting across a gap: no friction
    const LawCoefficients& law = partners[k] == Partner::grain ? laws.grain : laws.wall;
    const double load = friction_load(law, laws.effects, c.fn[k], c.overlap[k]);
    if (load > 0.0) out[k] = std::abs(c.ft[k]) / (law.mu * load);
  }
  return out;
}

SnapshotFriction summarise_friction(const Contacts& c, const std::vector<Partner>& partners,
                                    const std::vector<double>& ms, const std::vector<double>& thresholds) {
  SnapshotFriction s;
  s.rows = static_cast<std::int64_t>(c.size());
  s.slipping.assign(thresholds.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (std::isnan(ms[k])) {
      ++s.zero_fn;
      continue;
    }
    const double v = ms[k];
    s.all.add(v);
    switch (partners[k]) {
      case Partner::grain: s.bulk.add(v); break;
      case Partner::left:
      case Partner::right: s.wall.add(v); break;
      case Partner::floor: s.floor.add(v); break;
      case Partner::intruder: s.intruder.add(v); break;
      case Partner::other: break;
    }
    for (std::size_t t = 0; t < thresholds.size(); ++t) s.slipping[t] += v >= thresholds[t];
    s.sliding_flag += c.sliding[k] != 0;
  }
  return s;
}

FrictionConfig load_friction_config(const std::string& path) {
  StageConfig f(path);
  FrictionConfig c;
  f.number("slip_threshold", c.slip_threshold, 0.0, 1.0, "slipping: mu* >= this");
  f.number("cone_angle_deg", c.cone_angle_deg, 1.0, 89.0, "beta of H_c = (L_c - L)/2 tan(beta), degrees");
  f.number("critical_height_mm", c.critical_height_mm, 0.0, 1e6, "H_c in mm, overrides cone_angle_deg");
  f.number("lower_band_top", c.lower_band_top, 0.0, 1.0, "lower part: height < this x H_c");
  f.number("bin_width_d", c.bin_width_d, 1e-3, 100.0, "height bins, mean diameters");
  f.integer("histogram_bins", c.histogram_bins, 1, 100000, "mu* histogram bins over [0, 1]");
  f.integer("figure_every", c.figure_every, 1, 1000000000, "per-contact data every k-th snapshot");
  f.number("mu_grain", c.mu_grain, 1e-9, 100.0, "grain-grain friction coefficient, overrides the scene's");
  f.number("mu_wall", c.mu_wall, 1e-9, 100.0, "grain-body friction coefficient, overrides the scene's");
  f.numbers("sensitivity_slip_threshold", c.sensitivity_slip_threshold, 0.0, 1.0, "mu* thresholds");
  f.numbers("sensitivity_lower_band_top", c.sensitivity_lower_band_top, 0.0, 1.0, "x H_c");
  f.reject_unknown();
  if (c.mu_grain.has_value() != c.mu_wall.has_value())
    throw StageError(path + ": give both mu_grain and mu_wall, or neither (then the scene's are used)");
  return c;
}

json to_json(const FrictionConfig& c) {
  const auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  return {{"slip_threshold", c.slip_threshold},
          {"cone_angle_deg", c.cone_angle_deg},
          {"critical_height_mm", opt(c.critical_height_mm)},
          {"lower_band_top", c.lower_band_top},
          {"bin_width_d", c.bin_width_d},
          {"histogram_bins", c.histogram_bins},
          {"figure_every", c.figure_every},
          {"mu_grain", opt(c.mu_grain)},
          {"mu_wall", opt(c.mu_wall)},
          {"sensitivity_slip_threshold", c.sensitivity_slip_threshold},
          {"sensitivity_lower_band_top", c.sensitivity_lower_band_top}};
}

namespace {

// What the loop over the snapshots gathers.
struct FrictionTrack {
  std::vector<double> thresholds;          // slip thresholds: the configured one first
  std::vector<double> time, height;        // (s), (m): the intruder's height, 0 without one
  std::vector<SnapshotFriction> snap;
  double bed0 = 0.0, hc = kNaN, top = kInf;  // (m): the initial surface, H_c, where "in the bed" ends
  bool with_intruder = false;
  std::vector<std::int64_t> hist_bulk, hist_wall, hist_all;  // mu* histograms over the bed's snapshots
  std::vector<double> depth_sum_bulk, depth_sum_wall;        // mu* summed per contact-height bin
  std::vector<std::int64_t> depth_n_bulk, depth_n_wall;
  std::vector<std::int64_t> fig_index, fig_start = {0};      // the figure's snapshots and their contacts
  std::vector<double> fx, fy, ffn, fft, fmu;
  std::vector<std::uint8_t> fpartner;
};

// Snapshot k's measures: mu* per contact, summarised, and where each contact
// touches (for the height bins and the figure); the cell's at the first snapshot.
struct SnapshotMu {
  double time = 0.0, height = 0.0;  // (s), intruder centre above the floor (m; 0 without one)
  std::vector<Partner> partners;
  std::vector<double> mu;           // mu* per contact (NaN: not a touching contact)
  std::vector<Vec2> point;          // contact points (m)
  std::vector<double> fn, ft;       // (N/m)
  double floor = 0.0;               // the floor's inner face (m)
  SnapshotFriction summary;
  double bed0 = 0.0, end_to_wall = 0.0;  // k = 0 only
  bool with_intruder = false;
};

SnapshotMu measure_snapshot(const Snapshot& s, std::size_t k, const FrictionLaws& mu,
                            const std::vector<double>& thresholds) {
  SnapshotMu m;
  const PulloffGeometry geo = pulloff_geometry(s);
  m.with_intruder = geo.has_intruder();
  if (k == 0) m.bed0 = bed_height(s, geo), m.end_to_wall = geo.end_to_wall();
  m.partners = classify_contacts(s, geo);
  m.mu = mu_star(s.contacts, m.partners, mu);
  m.time = s.time;
  m.height = m.with_intruder ? geo.height() : 0.0;
  m.summary = summarise_friction(s.contacts, m.partners, m.mu, thresholds);
  m.floor = geo.cell.floor;
  for (std::size_t c = 0; c < m.mu.size(); ++c) m.point.push_back(contact_point(s, c));
  m.fn = s.contacts.fn, m.ft = s.contacts.ft;
  return m;
}

// mu* histogrammed and binned by contact height while in the bed, and kept for the figure.
void fold_snapshot(std::size_t k, SnapshotMu&& m, const FrictionConfig& cfg, const HeightBins& depth_bins,
                   bool to_figure, FrictionTrack& t) {
  if (k == 0) {
    t.bed0 = m.bed0;
    t.with_intruder = m.with_intruder;
    if (t.with_intruder) {
      t.top = t.bed0;
      t.hc = cfg.critical_height_mm ? *cfg.critical_height_mm / kMm
                                    : m.end_to_wall * std::tan(cfg.cone_angle_deg * std::numbers::pi / 180.0);
    }
  }
  const std::vector<double>& ms = m.mu;
  const std::vector<Partner>& partners = m.partners;
  t.time.push_back(m.time);
  t.height.push_back(m.height);
  t.snap.push_back(m.summary);
  const std::size_t nbins = t.hist_all.size();
  if (t.height.back() < t.top) {
    for (std::size_t c = 0; c < ms.size(); ++c) {
      if (std::isnan(ms[c])) continue;
      const std::size_t b = std::min(nbins - 1, static_cast<std::size_t>(std::max(0.0, ms[c]) * static_cast<double>(nbins)));
      ++t.hist_all[b];
      const bool bulk = partners[c] == Partner::grain;
      const bool wall = partners[c] == Partner::left || partners[c] == Partner::right;
      if (bulk) ++t.hist_bulk[b];
      if (wall) ++t.hist_wall[b];
      if (!bulk && !wall) continue;
      std::vector<double>& sum = bulk ? t.depth_sum_bulk : t.depth_sum_wall;
      std::vector<std::int64_t>& n = bulk ? t.depth_n_bulk : t.depth_n_wall;
      const std::size_t z = depth_bins.index(m.point[c].y - m.floor);
      if (z >= sum.size()) sum.resize(z + 1, 0.0), n.resize(z + 1, 0);
      sum[z] += ms[c], ++n[z];
    }
  }
  if (to_figure) {
    t.fig_index.push_back(static_cast<std::int64_t>(k));
    for (std::size_t c = 0; c < ms.size(); ++c) {
      if (std::isnan(ms[c])) continue;
      t.fx.push_back(m.point[c].x), t.fy.push_back(m.point[c].y), t.ffn.push_back(m.fn[c]), t.fft.push_back(m.ft[c]);
      t.fmu.push_back(ms[c]), t.fpartner.push_back(static_cast<std::uint8_t>(partners[c]));
    }
    t.fig_start.push_back(static_cast<std::int64_t>(t.fx.size()));
  }
}

// The loop over the run's snapshots.
FrictionTrack track(const SnapshotSource& run, const FrictionLaws& mu, const FrictionConfig& cfg,
                    const HeightBins& depth_bins) {
  const std::size_t S = run.snapshots();
  FrictionTrack t;
  t.thresholds = {cfg.slip_threshold};
  for (const double x : cfg.sensitivity_slip_threshold)
    if (x != cfg.slip_threshold) t.thresholds.push_back(x);
  const auto nbins = static_cast<std::size_t>(cfg.histogram_bins);
  t.hist_bulk.assign(nbins, 0), t.hist_wall.assign(nbins, 0), t.hist_all.assign(nbins, 0);
  const std::vector<std::size_t> figure = every_kth(S, static_cast<std::size_t>(cfg.figure_every));
  for_each_snapshot(
      run, all_snapshots(run), 1, [&](std::size_t k, const Snapshot& s) { return measure_snapshot(s, k, mu, t.thresholds); },
      [&](std::size_t k, SnapshotMu&& m) {
        fold_snapshot(k, std::move(m), cfg, depth_bins, std::binary_search(figure.begin(), figure.end(), k), t);
      });
  return t;
}

// The mean of a per-snapshot series over the snapshots with the intruder in
// [lo, hi) (m), and that band in mm; null without an intruder.
json band_mean(const FrictionTrack& t, const std::vector<double>& v, double lo, double hi) {
  return t.with_intruder ? number_or_null(mean_in_band(t.height, v, lo, hi)) : json(nullptr);
}
json band_mm(const FrictionTrack& t, double lo, double hi) {
  return t.with_intruder ? json{lo * kMm, hi * kMm} : json(nullptr);
}

// How much of the contacts slip while the intruder is in the bed.
void slip_metrics(json& m, const FrictionTrack& t, const FrictionConfig& cfg) {
  const std::vector<double> slip = column_of(t.snap, [](const SnapshotFriction& f) { return f.slip_fraction(0); });
  std::int64_t in_bed = 0;
  m["slip_threshold"] = cfg.slip_threshold;
  m["slip_fraction"] = number_or_null(mean_in_band(t.height, slip, -kInf, t.top, &in_bed));
  m["slip_fraction_snapshots"] = in_bed;
  double mx = kNaN;
  std::int64_t rows = 0, zero = 0, used = 0, slipping = 0, flagged = 0;
  for (std::size_t k = 0; k < t.snap.size(); ++k) {
    if (!(t.height[k] < t.top)) continue;
    if (!std::isnan(slip[k]) && (std::isnan(mx) || slip[k] > mx)) mx = slip[k];
    rows += t.snap[k].rows, zero += t.snap[k].zero_fn, used += t.snap[k].all.count;
    slipping += t.snap[k].slipping[0], flagged += t.snap[k].sliding_flag;
  }
  m["slip_fraction_max"] = number_or_null(mx);
  m["slip_fraction_pooled"] = fraction_or_null(slipping, used);
  m["sliding_flag_fraction_pooled"] = fraction_or_null(flagged, used);
  m["contact_rows"] = rows;
  m["contacts_zero_fn_excluded"] = zero;
  m["zero_fn_fraction"] = fraction_or_null(zero, rows);
}

// The mean mu* per intruder-height band (H_c and the band below), and overall.
void band_metrics(json& m, const FrictionTrack& t, const FrictionConfig& cfg) {
  const std::vector<double> bulk = column_of(t.snap, [](const SnapshotFriction& f) { return f.bulk.mean(); });
  const std::vector<double> wall = column_of(t.snap, [](const SnapshotFriction& f) { return f.wall.mean(); });
  const std::vector<double> all = column_of(t.snap, [](const SnapshotFriction& f) { return f.all.mean(); });
  const double hc = t.hc, bed0 = t.bed0, lower_top = cfg.lower_band_top * hc;
  const bool with_intruder = t.with_intruder;
  const auto band = [&](const std::vector<double>& v, double lo, double hi) { return band_mean(t, v, lo, hi); };
  const auto mm_pair = [&](double lo, double hi) { return band_mm(t, lo, hi); };
  m["critical_height_mm"] = number_or_null(hc * kMm);
  m["critical_height_source"] = !with_intruder ? "none: no intruder"
                                : cfg.critical_height_mm
                                    ? "config critical_height_mm"
                                    : "(x_right - x_left - L)/2 tan(" + format_number(cfg.cone_angle_deg) + " deg), cell and intruder of the run";
  m["lower_band_mm"] = mm_pair(t.height.front(), lower_top);
  m["middle_band_mm"] = mm_pair(lower_top, hc);
  m["upper_band_mm"] = mm_pair(hc, bed0);
  m["mean_mu_star_lower"] = band(bulk, -kInf, lower_top);
  m["mean_mu_star_middle"] = band(bulk, lower_top, hc);
  m["mean_mu_star_upper"] = band(bulk, hc, bed0);
  m["mean_mu_star_lower_wall"] = band(wall, -kInf, lower_top);
  m["mean_mu_star_middle_wall"] = band(wall, lower_top, hc);
  m["mean_mu_star_upper_wall"] = band(wall, hc, bed0);
  m["mean_mu_star_lower_all"] = band(all, -kInf, lower_top);
  m["mean_mu_star_upper_all"] = band(all, hc, bed0);
  {
    // The last 10 % of the upper band: where the curves end up ("falling towards 0.24").
    const double lo = hc + 0.9 * (bed0 - hc);
    m["mean_mu_star_upper_end"] = band(bulk, lo, bed0);
    m["mean_mu_star_upper_end_wall"] = band(wall, lo, bed0);
    m["upper_end_band_mm"] = mm_pair(lo, bed0);
  }
  m["mean_mu_star_bulk"] = number_or_null(mean_in_band(t.height, bulk, -kInf, t.top));
  m["mean_mu_star_wall"] = number_or_null(mean_in_band(t.height, wall, -kInf, t.top));
  m["mean_mu_star_floor"] = number_or_null(
      mean_in_band(t.height, column_of(t.snap, [](const SnapshotFriction& f) { return f.floor.mean(); }), -kInf, t.top));
  m["mean_mu_star_intruder"] =
      with_intruder ? number_or_null(mean_in_band(t.height, column_of(t.snap, [](const SnapshotFriction& f) { return f.intruder.mean(); }), -kInf, t.top))
                    : json(nullptr);
}

// How the slip fraction and the lower band's mu* move with their thresholds.
json sensitivity(const FrictionTrack& t, const FrictionConfig& cfg) {
  const std::vector<double> bulk = column_of(t.snap, [](const SnapshotFriction& f) { return f.bulk.mean(); });
  const std::vector<double> wall = column_of(t.snap, [](const SnapshotFriction& f) { return f.wall.mean(); });
  const auto band = [&](const std::vector<double>& v, double lo, double hi) { return band_mean(t, v, lo, hi); };
  const auto mm_pair = [&](double lo, double hi) { return band_mm(t, lo, hi); };
  json sens;
  for (std::size_t k = 0; k < t.thresholds.size(); ++k) {
    const std::vector<double> v = column_of(t.snap, [k](const SnapshotFriction& f) { return f.slip_fraction(k); });
    double mx = 0.0;
    for (std::size_t i = 0; i < t.snap.size(); ++i)
      if (t.height[i] < t.top && !std::isnan(v[i])) mx = std::max(mx, v[i]);
    sens["slip_fraction"].push_back({{"threshold", t.thresholds[k]},
                                     {"slip_fraction", number_or_null(mean_in_band(t.height, v, -kInf, t.top))},
                                     {"slip_fraction_max", mx}});
  }
  std::sort(sens["slip_fraction"].begin(), sens["slip_fraction"].end(),
            [](const json& a, const json& b) { return a["threshold"].get<double>() < b["threshold"].get<double>(); });
  for (const double f : cfg.sensitivity_lower_band_top)
    sens["mean_mu_star_lower"].push_back({{"lower_band_top", f},
                                          {"band_mm", mm_pair(t.height.front(), f * t.hc)},
                                          {"bulk", band(bulk, -kInf, f * t.hc)},
                                          {"wall", band(wall, -kInf, f * t.hc)}});
  return sens;
}

// friction.h5's per-snapshot series.
void write_snapshots(H5Output& h, const FrictionTrack& t, const FrictionConfig& cfg) {
  const auto series = [&](auto get) { return column_of(t.snap, get); };
  h.add("snapshots/time", t.time, "s", "snapshot time");
  if (t.with_intruder) h.add("snapshots/height", t.height, "m", "intruder centre above the floor's inner face");
  std::vector<std::int64_t> counted, zero;
  for (const SnapshotFriction& f : t.snap) counted.push_back(f.all.count), zero.push_back(f.zero_fn);
  h.add("snapshots/contacts", counted, "-", "contacts with fn > 0");
  h.add("snapshots/zero_fn", zero, "-", "contacts with fn = 0 (excluded)");
  for (std::size_t k = 0; k < t.thresholds.size(); ++k)
    h.add("snapshots/slip_fraction_" + format_number(t.thresholds[k]),
          series([k](const SnapshotFriction& f) { return f.slip_fraction(k); }), "-",
          "fraction of the contacts with fn > 0 whose mu* >= " + format_number(t.thresholds[k]));
  h.add("snapshots/slip_fraction", series([](const SnapshotFriction& f) { return f.slip_fraction(0); }), "-",
        "the same at slip_threshold = " + format_number(cfg.slip_threshold));
  h.add("snapshots/mean_mu_star_bulk", series([](const SnapshotFriction& f) { return f.bulk.mean(); }), "-",
        "mean mu* of grain-grain contacts");
  h.add("snapshots/mean_mu_star_wall", series([](const SnapshotFriction& f) { return f.wall.mean(); }), "-",
        "mean mu* of grain-side wall contacts (left, right)");
  h.add("snapshots/mean_mu_star_floor", series([](const SnapshotFriction& f) { return f.floor.mean(); }), "-",
        "mean mu* of grain-floor contacts");
  h.add("snapshots/mean_mu_star_intruder", series([](const SnapshotFriction& f) { return f.intruder.mean(); }), "-",
        "mean mu* of grain-intruder contacts");
  h.add("snapshots/mean_mu_star_all", series([](const SnapshotFriction& f) { return f.all.mean(); }), "-",
        "mean mu* of all contacts with fn > 0");
}

// friction.h5's mu* against the contact point's height above the floor,
// pooled over the snapshots in the bed (how far friction is mobilised at each
// depth), and against the intruder's height.
void write_profiles(H5Output& h, const FrictionTrack& t, const HeightBins& bins) {
  const auto depth_mean = [](const std::vector<double>& sum, const std::vector<std::int64_t>& n) {
    std::vector<double> out(sum.size(), kNaN);
    for (std::size_t z = 0; z < sum.size(); ++z)
      if (n[z] > 0) out[z] = sum[z] / static_cast<double>(n[z]);
    return out;
  };
  const std::size_t nz = std::max(t.depth_sum_bulk.size(), t.depth_sum_wall.size());
  std::vector<double> lower, upper, sum_bulk = t.depth_sum_bulk, sum_wall = t.depth_sum_wall;
  std::vector<std::int64_t> n_bulk = t.depth_n_bulk, n_wall = t.depth_n_wall;
  for (std::size_t z = 0; z < nz; ++z) lower.push_back(bins.lower(z)), upper.push_back(bins.lower(z + 1));
  sum_bulk.resize(nz, 0.0), sum_wall.resize(nz, 0.0), n_bulk.resize(nz, 0), n_wall.resize(nz, 0);
  h.add("depth/lower", lower, "m", "contact-point height bin above the floor's inner face, lower edge");
  h.add("depth/upper", upper, "m", "the bin's upper edge");
  h.add("depth/contacts_bulk", n_bulk, "-", "grain-grain contacts with fn > 0 in the bin (snapshots in the bed)");
  h.add("depth/contacts_wall", n_wall, "-", "grain-side wall contacts with fn > 0 in the bin");
  h.add("depth/mean_mu_star_bulk", depth_mean(sum_bulk, n_bulk), "-", "mean mu* of the bin's grain-grain contacts");
  h.add("depth/mean_mu_star_wall", depth_mean(sum_wall, n_wall), "-", "mean mu* of the bin's side-wall contacts");
  if (!t.with_intruder) return;
  const BinnedMean pb = binned_mean(bins, t.height, column_of(t.snap, [](const SnapshotFriction& f) { return f.bulk.mean(); }));
  const BinnedMean pw = binned_mean(bins, t.height, column_of(t.snap, [](const SnapshotFriction& f) { return f.wall.mean(); }));
  std::vector<double> blower, bupper, wall_mean(pb.mean.size(), kNaN);
  for (std::size_t b = 0; b < pb.mean.size(); ++b) {
    blower.push_back(bins.lower(b)), bupper.push_back(bins.lower(b + 1));
    if (b < pw.mean.size()) wall_mean[b] = pw.mean[b];
  }
  h.add("profile/lower", blower, "m", "intruder height bin lower edge");
  h.add("profile/upper", bupper, "m", "intruder height bin upper edge");
  h.add("profile/snapshots", pb.count, "-", "snapshots in the bin");
  h.add("profile/mean_mu_star_bulk", pb.mean, "-", "mean over the bin's snapshots of the bulk mean mu*");
  h.add("profile/mean_mu_star_wall", wall_mean, "-", "the same for the side-wall contacts");
}

// friction.h5's mu* histograms and the figure's per-contact data.
void write_histograms_and_figure(H5Output& h, const FrictionTrack& t) {
  const std::size_t nbins = t.hist_all.size();
  std::vector<double> edges;
  for (std::size_t b = 0; b <= nbins; ++b) edges.push_back(static_cast<double>(b) / static_cast<double>(nbins));
  h.add("histogram/edges", edges, "-", "mu* bin edges (the last bin also holds mu* >= 1)");
  h.add("histogram/all", t.hist_all, "-", "contacts with fn > 0, snapshots with the intruder below the initial surface (every snapshot without an intruder)");
  h.add("histogram/bulk", t.hist_bulk, "-", "grain-grain contacts");
  h.add("histogram/wall", t.hist_wall, "-", "grain-side wall contacts");
  h.add("figure/snapshot", t.fig_index, "-", "snapshots with per-contact data");
  h.add("figure/start", t.fig_start, "-", "contacts of figure/snapshot[m]: rows start[m] .. start[m+1]-1");
  h.add("figure/x", t.fx, "m", "contact point");
  h.add("figure/y", t.fy, "m", "contact point");
  h.add("figure/fn", t.ffn, "N/m", "normal force (> 0)");
  h.add("figure/ft", t.fft, "N/m", "tangential force on grain i");
  h.add("figure/mu_star", t.fmu, "-", "|ft| / (mu fn)");
  h.add("figure/partner", t.fpartner, "-", "0 grain, 1 left, 2 right, 3 floor, 4 intruder, 5 other");
}

}  // namespace

FrictionResult run_friction(const std::string& run_path, const std::string& config_path, const FrictionConfig& cfg,
                            const Study& study) {
  const RunFileSource source(run_path);
  const RunReader& run = source.run();
  const std::size_t S = run.snapshots();
  if (S == 0) throw StageError(run.path() + ": the run file has no snapshots");
  const FrictionLaws mu = friction_laws(run.parameters(), cfg.mu_grain, cfg.mu_wall, run.path());
  const std::string mu_source =
      cfg.mu_grain ? "config " + config_path : "the run's scene ([contact] friction, [contact.wall] friction)";
  const HeightBins bins{cfg.bin_width_d * study.mean_diameter};  // contact and intruder heights alike
  const FrictionTrack t = track(source, mu, cfg, bins);

  json m;
  m["run_file"] = run.path();
  m["config_file"] = config_path;
  m["snapshots"] = S;
  m["mu_grain"] = mu.grain.mu;
  m["mu_wall"] = mu.wall.mu;
  m["mu_source"] = mu_source;
  m["initial_bed_height_mm"] = t.bed0 * kMm;
  m["intruder"] = t.with_intruder;
  if (!t.with_intruder)
    m["intruder_note"] = "the run has no body with role 'intruder': every snapshot counts as in the bed, and the "
                         "intruder-height bands (critical height H_c) are not defined (null)";
  slip_metrics(m, t, cfg);
  band_metrics(m, t, cfg);
  m["sensitivity"] = sensitivity(t, cfg);
  m["config"] = to_json(cfg);

  FrictionResult r;
  r.metrics = {{"friction", m}};
  r.h5 = H5Output("friction", run.path());
  write_snapshots(r.h5, t, cfg);
  write_profiles(r.h5, t, bins);
  write_histograms_and_figure(r.h5, t);
  return r;
}

}  // namespace dem2d::analysis
