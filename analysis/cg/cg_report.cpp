#include "cg/cg_report.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>

#include "cg/wall_loss.hpp"
#include "common/normal.hpp"
#include "common/snapshot_loop.hpp"  // column_of
#include "common/units.hpp"
#include "core/number_text.hpp"

namespace dem2d::analysis {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = 180.0 / std::numbers::pi;
using json = nlohmann::ordered_json;

double mean_of(const std::vector<double>& v, std::size_t* count = nullptr) {
  double s = 0.0;
  std::size_t n = 0;
  for (const double x : v)
    if (!std::isnan(x)) s += x, ++n;
  if (count) *count = n;
  return n ? s / static_cast<double>(n) : kNaN;
}

double std_of(const std::vector<double>& v) {
  std::size_t n = 0;
  const double m = mean_of(v, &n);
  if (n < 2) return kNaN;
  double s = 0.0;
  for (const double x : v)
    if (!std::isnan(x)) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(n - 1));
}

// A cut-off that keeps every edge: any fitted edge has beta < 180 degrees.
constexpr double kEveryEdgeDeg = 180.0;

double fraction(std::size_t part, std::size_t whole) {
  return whole ? static_cast<double>(part) / static_cast<double>(whole) : kNaN;
}

// The cone over a selection of snapshots, from the edges that the cut-off
// max_deg keeps (EdgeFit::excluded; kVerticalEdgeDeg leaves out the edges that
// narrow upwards, kEveryEdgeDeg none): a snapshot's angle is the mean of its
// kept edges, and mean, sd and count are over the snapshots that have one;
// left and right over each side's kept edges; where the kept edges meet the
// walls (above the intruder's centre) and the angle of the chord from the tip
// to that point, atan(meet / half_gap); how far outside the tips the kept
// fitted lines pass at the intruder's top face. Then the excluded edges: their
// number and angles, and the snapshots that have one.
struct BetaStats {
  double mean = kNaN, sd = kNaN, left = kNaN, right = kNaN;
  std::size_t count = 0;
  double meet = kNaN, chord = kNaN, offset = kNaN;
  std::size_t meet_count = 0;
  std::size_t edges = 0, excluded = 0;              // edges with an angle; of them excluded
  double excluded_mean = kNaN, excluded_sd = kNaN;  // the excluded edges' angles
  std::size_t fitted_snapshots = 0;                 // snapshots with an edge angle; of them those with
  std::size_t with_excluded = 0, all_excluded = 0;  // one excluded edge or more, and with every edge excluded
};

// `gate`: an edge counts only where the cone fitted at that index (the
// noise-calibrated level) has that side's edge too (SIZE_MAX: no gate).
constexpr std::size_t kNoGate = static_cast<std::size_t>(-1);
BetaStats beta_stats(const std::vector<SnapshotMeasure>& ms, const std::vector<std::size_t>& sel, std::size_t src,
                     std::size_t cone, double half_gap, double max_deg, std::size_t gate = kNoGate) {
  std::vector<double> b, l, r, meet, chord, offset, out;
  BetaStats st;
  for (const std::size_t k : sel) {
    const SourceMeasure& s = ms[k].src[src];
    if (!s.valid) continue;
    ConeFit c = s.cone[cone];
    if (gate != kNoGate) {  // a side the calibrated zone does not show is noise
      if (std::isnan(s.cone[gate].left.beta_deg)) c.left = EdgeFit{};
      if (std::isnan(s.cone[gate].right.beta_deg)) c.right = EdgeFit{};
    }
    const Intruder& in = ms[k].intruder;
    const auto kept = [&](const EdgeFit& e, double v) { return e.excluded(max_deg) ? kNaN : v; };
    b.push_back(c.beta_deg(max_deg));
    l.push_back(kept(c.left, c.left.beta_deg));
    r.push_back(kept(c.right, c.right.beta_deg));
    meet.push_back(c.wall_y(max_deg) - in.yc);
    chord.push_back(std::atan2(meet.back(), half_gap) * kDeg);
    offset.push_back(mean_of({kept(c.left, in.left - c.left.x_at_y0), kept(c.right, c.right.x_at_y0 - in.right)}));
    std::size_t fitted = 0, excluded = 0;
    for (const EdgeFit* e : {&c.left, &c.right}) {
      if (std::isnan(e->beta_deg)) continue;
      ++fitted;
      if (e->excluded(max_deg)) ++excluded, out.push_back(e->beta_deg);
    }
    st.edges += fitted, st.excluded += excluded;
    st.fitted_snapshots += fitted > 0;
    st.with_excluded += excluded > 0;
    st.all_excluded += excluded > 0 && excluded == fitted;
  }
  st.mean = mean_of(b, &st.count);
  st.sd = std_of(b);
  st.left = mean_of(l);
  st.right = mean_of(r);
  st.meet = mean_of(meet, &st.meet_count);
  st.chord = mean_of(chord);
  st.offset = mean_of(offset);
  st.excluded_mean = mean_of(out);
  st.excluded_sd = std_of(out);
  return st;
}

// `length(m)`: the mean mobile length of snapshot m's two walls (m).
WallLoss wall_loss(const std::vector<SnapshotMeasure>& ms, const std::vector<std::size_t>& sel, std::size_t src,
                   const std::function<double(const SnapshotMeasure&)>& length, double min_length) {
  WallLoss w;
  for (const std::size_t k : sel) {
    const SnapshotMeasure& m = ms[k];
    if (!m.src[src].valid || m.intruder.top - m.intruder.yc + m.height >= m.surface) continue;  // out of the bed
    const double len = length(m);
    w.heights.push_back(m.height);
    w.surfaces.push_back(m.surface);
    w.flags.push_back(len >= min_length && len > 0.0);
  }
  w.fit = step_down(w.heights, w.flags);
  w.mobile = static_cast<std::size_t>(std::count(w.flags.begin(), w.flags.end(), true));
  if (!std::isnan(w.fit.height)) {
    w.surface = surface_near(w, w.fit.height);  // the loading snapshot's nearest in height
    w.depth = w.surface - w.fit.height;
  }
  return w;
}
WallLoss wall_loss(const std::vector<SnapshotMeasure>& ms, const std::vector<std::size_t>& sel, std::size_t src,
                   std::size_t wall_index, double min_length) {
  return wall_loss(ms, sel, src, [&](const SnapshotMeasure& m) {
    return 0.5 * (m.src[src].wall_left[wall_index] + m.src[src].wall_right[wall_index]);
  }, min_length);
}

// A wall column pooled over a group of snapshots: per row, v* = |mean of the
// plane's velocities| over the snapshots with a value there, and that mean's
// noise gain sqrt(sum g^2) / n (independent noise from snapshot to snapshot).
struct Pooled {
  std::vector<double> vstar, gain;
};
Pooled pooled(const std::vector<SnapshotMeasure>& ms, const std::vector<std::size_t>& group, int w, std::size_t ny) {
  std::vector<double> sx(ny, 0.0), sy(ny, 0.0), sg(ny, 0.0);
  std::vector<int> n(ny, 0);
  for (const std::size_t k : group) {
    const SnapshotMeasure& m = ms[k];
    if (m.wall_vx[w].size() != ny) continue;  // no profile (a source without velocities)
    for (std::size_t j = 0; j < ny; ++j)
      if (std::isfinite(m.wall_vx[w][j]) && std::isfinite(m.wall_vy[w][j]) && m.wall_gain[w][j] > 0.0f)
        sx[j] += m.wall_vx[w][j], sy[j] += m.wall_vy[w][j], sg[j] += double(m.wall_gain[w][j]) * m.wall_gain[w][j], ++n[j];
  }
  Pooled p{std::vector<double>(ny, kNaN), std::vector<double>(ny, kNaN)};
  for (std::size_t j = 0; j < ny; ++j)
    if (n[j] > 0) p.vstar[j] = std::hypot(sx[j], sy[j]) / n[j], p.gain[j] = std::sqrt(sg[j]) / n[j];
  return p;
}

// The snapshots of `among` whose intruder height lies within `half` of snapshot k's.
std::vector<std::size_t> pool_of(const std::vector<SnapshotMeasure>& ms, const std::vector<std::size_t>& among,
                                 std::size_t k, double half) {
  std::vector<std::size_t> group;
  for (const std::size_t q : among)
    if (std::abs(ms[q].height - ms[k].height) <= half) group.push_back(q);
  return group;
}

// The windows of `rows` rows of a pooled wall column between heights low and
// high: the mean v* and the mean noise gain of each (windows with a gap are skipped).
struct Window {
  double vstar, gain;
};
std::vector<Window> windows(const Grid& g, const Pooled& p, double low, double high, std::size_t rows) {
  std::vector<Window> out;
  for (std::size_t j = 0; j + rows <= g.ny; ++j) {
    if (g.y(j) < low || g.y(j + rows - 1) >= high) continue;
    Window w{0.0, 0.0};
    bool ok = true;
    for (std::size_t q = j; q < j + rows && ok; ++q) ok = std::isfinite(p.vstar[q]), w.vstar += p.vstar[q], w.gain += p.gain[q];
    if (ok) out.push_back({w.vstar / static_cast<double>(rows), w.gain / static_cast<double>(rows)});
  }
  return out;
}

// The walls' PIV noise: the wall columns' pooled v* (over wall.pool_d of
// travel) averaged over windows of min_mobile_d x d in the rows at rest
// (rest_rows, below every pooled snapshot's intruder), both walls, every
// snapshot with the primary velocities, each over the window's noise gain
// (sorted: v* per unit gain, what the noise alone gives); and the grains' own
// noise there (add_rest_grain_noise).
struct WallNoise {
  std::size_t window_rows = 1;
  double pool_d = 0.0;                    // the pooling over intruder travel (d, full width)
  std::vector<double> rest;               // window v* / window gain at rest, sorted
  double grain_rms = kNaN;                // per grain, rms per component, x V_ref
  std::size_t grains = 0;
  double level_min = kNaN, level_max = kNaN;  // the snapshots' mobility levels (set by calibrated_wall_loss)
};

WallNoise wall_noise(const StageRecord& r, double pool_d) {
  WallNoise n;
  n.window_rows = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(r.config.wall_min_mobile_d * r.setup.d / r.setup.grid.dx)));
  n.pool_d = pool_d;
  const double half = 0.5 * pool_d * r.setup.d;
  std::vector<std::size_t> valid;
  double ss = 0.0;
  for (std::size_t k = 0; k < r.ms.size(); ++k) {
    if (!r.ms[k].src[r.primary].valid) continue;
    valid.push_back(k);
    ss += r.ms[k].rest_grain_ss;
    n.grains += r.ms[k].rest_grains;
  }
  for (const std::size_t k : valid) {
    const std::vector<std::size_t> group = pool_of(r.ms, valid, k, half);
    RestRows rows = rest_rows(r.setup, r.config, r.ms[k].intruder);
    for (const std::size_t q : group) rows.high = std::min(rows.high, rest_rows(r.setup, r.config, r.ms[q].intruder).high);
    for (int w = 0; w < 2; ++w)
      for (const Window& x : windows(r.setup.grid, pooled(r.ms, group, w, r.setup.grid.ny), rows.low, rows.high, n.window_rows))
        n.rest.push_back(x.vstar / x.gain);
  }
  std::sort(n.rest.begin(), n.rest.end());
  if (n.grains > 0) n.grain_rms = std::sqrt(ss / (2.0 * static_cast<double>(n.grains)));
  return n;
}

// A snapshot's walls move when a wall window of its pooled columns above the
// intruder's centre reaches max(cone.level, q x its noise gain), q the
// (1 - false_alarm / M) quantile of v* per unit gain at rest, M = 2 walls x
// the independent windows above the centre: where the fit is noisier (at the
// free surface, where the kernel is cut and the plane extrapolated) the level
// rises with it.
WallLoss calibrated_wall_loss(const StageRecord& r, const std::vector<std::size_t>& sel, WallNoise& n,
                              double false_alarm) {
  const Grid& g = r.setup.grid;
  const double window = static_cast<double>(n.window_rows) * g.dx, correlation = 2.0 * r.setup.kernel.w;
  const double half = 0.5 * n.pool_d * r.setup.d;
  n.level_min = kInf, n.level_max = -kInf;
  std::vector<std::size_t> usable;
  for (const std::size_t k : sel)
    if (r.ms[k].src[r.primary].valid) usable.push_back(k);
  return wall_loss(r.ms, sel, r.primary, [&](const SnapshotMeasure& m) {
    const std::vector<std::size_t> group = pool_of(r.ms, usable, static_cast<std::size_t>(&m - r.ms.data()), half);
    std::vector<Window> scan[2];
    for (int w = 0; w < 2; ++w) scan[w] = windows(g, pooled(r.ms, group, w, g.ny), m.intruder.yc, kInf, n.window_rows);
    const double scanned = 0.5 * static_cast<double>(scan[0].size() + scan[1].size()) * g.dx;  // per wall
    const double independent = std::max(1.0, 2.0 * scanned / std::max(window, correlation));
    const double q = upper_quantile(n.rest, 1.0 - false_alarm / independent);
    bool mobile = false;
    for (const auto& side : scan)
      for (const Window& x : side) {
        const double level = std::isfinite(q) ? std::max(r.config.level, q * x.gain) : r.config.level;
        n.level_min = std::min(n.level_min, level), n.level_max = std::max(n.level_max, level);
        mobile = mobile || x.vstar >= level;
      }
    return mobile ? 2.0 * r.config.wall_min_mobile_d * r.setup.d : 0.0;  // "mobile": a length >= min_length
  }, r.config.wall_min_mobile_d * r.setup.d);
}

nlohmann::ordered_json nullable(double v) { return std::isnan(v) ? nlohmann::ordered_json() : nlohmann::ordered_json(v); }

// The snapshots the cone and wall metrics use: the pre-rupture ones with events, else all.
std::vector<std::size_t> selection(const StageRecord& r, bool all) {
  std::vector<std::size_t> sel;
  if (all || !r.have_events) {
    for (std::size_t k = 0; k < r.ms.size(); ++k) sel.push_back(k);
  } else {
    for (const std::int64_t k : r.pre)
      if (k >= 0) sel.push_back(static_cast<std::size_t>(k));
  }
  return sel;
}

double half_gap(const Setup& su) { return 0.5 * ((su.cell.right - su.cell.left) - su.start.length()); }

}  // namespace

std::int64_t first_after_travel(const std::vector<double>& heights, double travel) {
  for (std::size_t k = 0; k < heights.size(); ++k)
    if (heights[k] - heights[0] >= travel) return static_cast<std::int64_t>(k);
  return -1;
}

namespace {

// What every section of the metrics uses: the record, the snapshot selections
// and the headline fits (the cone's angle, the wall losses and their noise).
struct Summary {
  explicit Summary(const StageRecord& rec)
      : r(rec), all(selection(rec, true)), sel(selection(rec, false)), cone0(rec.setup.cone0()),
        gate(rec.setup.cone_gate()), gap(half_gap(rec.setup)) {}
  const StageRecord& r;
  std::vector<std::size_t> all, sel;  // every snapshot; the loading ones
  std::size_t cone0 = 0, gate = 0;
  double gap = 0.0;
  BetaStats beta, every_edge;
  // beta as reported: the mean over the snapshots when there are enough and
  // its 95 % t-interval is narrow enough (cone.min_snapshots,
  // cone.max_interval_deg), else NaN and the outcome says why
  double beta_value = kNaN, beta_half = kNaN;
  std::string beta_outcome;
  WallLoss fixed_wall, wall;
  WallNoise noise;
  double loss_p = kNaN;
  bool loss_significant = false;
  StepPower loss_power;  // of the loss test at the paper's depth in flags as mixed as the run's
};

// beta as reported (x.beta_value), or why not (x.beta_outcome): the mean over
// at least cone.min_snapshots snapshots with a 95 % t-interval within
// +-cone.max_interval_deg.
void decide_beta(Summary& x, const CgConfig& c) {
  const std::size_t n = x.beta.count;
  if (n >= 2) x.beta_half = student_t975(static_cast<int>(n) - 1) * x.beta.sd / std::sqrt(static_cast<double>(n));
  if (n == 0) {
    x.beta_outcome = "undetermined: no loading snapshot has a cone edge (nothing mobilised above the noise, or too "
                     "noisy); the power to see a cone at this run's noise is not measured";
  } else if (n < static_cast<std::size_t>(c.min_snapshots)) {
    x.beta_outcome = "undetermined: an angle in " + std::to_string(n) + " loading snapshot(s), fewer than "
                     "cone.min_snapshots = " + std::to_string(c.min_snapshots);
  } else if (!(x.beta_half <= c.max_interval_deg)) {
    x.beta_outcome = "undetermined: the mean's 95 % interval is +-" + format_number(x.beta_half) +
                     " deg, wider than cone.max_interval_deg = " + format_number(c.max_interval_deg);
  } else {
    x.beta_outcome = "found";
    x.beta_value = x.beta.mean;
  }
}

Summary summarise(const StageRecord& r) {
  const Setup& su = r.setup;
  const CgConfig& c = r.config;
  Summary x(r);
  x.beta = beta_stats(r.ms, x.sel, r.primary, x.cone0, x.gap, kVerticalEdgeDeg, x.gate);
  x.every_edge = beta_stats(r.ms, x.sel, r.primary, x.cone0, x.gap, kEveryEdgeDeg, x.gate);
  decide_beta(x, c);
  x.fixed_wall = wall_loss(r.ms, x.sel, r.primary, su.wall_fixed(), c.wall_min_mobile_d * su.d);
  // each snapshot alone, unless the noise lifts the walls' level above cone.level somewhere:
  // then pooled over wall.pool_d of travel (steady mobility is kept, intermittent mobility
  // averaged; at the study's noise the snapshots stand alone)
  x.noise = wall_noise(r, 0.0);
  x.wall = calibrated_wall_loss(r, x.sel, x.noise, c.wall_false_alarm);
  if (c.wall_pool_d > 0.0 && x.noise.level_max > c.level) {
    x.noise = wall_noise(r, c.wall_pool_d);
    x.wall = calibrated_wall_loss(r, x.sel, x.noise, c.wall_false_alarm);
  }
  x.loss_p = step_p_value(x.wall, c.wall_permutations);
  x.loss_significant = std::isfinite(x.wall.fit.height) && x.loss_p < c.wall_loss_false_alarm;
  if (!x.loss_significant) x.wall.depth = kNaN;
  // measured found or not (a miss is read by it; beside a find it says how sure a rerun would be to find it)
  x.loss_power = loss_power(x.wall, x.gap * std::tan(c.wall_power_cone_angle_deg / kDeg), c.wall_power_tolerance_d * su.d,
                            c.wall_loss_false_alarm, c.wall_permutations, c.wall_power_replicas);
  return x;
}

// Dilatancy: the change of the solid fraction in region h (following the
// intruder or fixed at its start) from snapshot 0 to snapshot k; NaN if k < 0.
double delta_phi(const std::vector<SnapshotMeasure>& ms, std::int64_t k, std::size_t h, bool follow) {
  if (k < 0) return kNaN;
  const SnapshotMeasure& m = ms[static_cast<std::size_t>(k)];
  return (follow ? m.phi_follow[h] : m.phi_fixed[h]) - (follow ? ms[0].phi_follow[h] : ms[0].phi_fixed[h]);
}

void add_headline(json& m, const Summary& x) {
  const StageRecord& r = x.r;
  m["cone_angle_deg"] = nullable(x.beta_value);
  m["cone_angle_outcome"] = x.beta_outcome;
  m["wall_mobility_length_mm"] = nullable(x.wall.depth * kMm);
  m["dilatancy_delta_phi"] = nullable(delta_phi(r.ms, r.after, r.setup.height0, true));
  m["velocity_source"] = kSourceName[r.primary];
  m["velocity_note"] =
      r.primary == kPiv ? "every metric uses PIV-like velocities: each grain's displacement over the displacement_window "
                          "before the snapshot divided by it; the instantaneous ones appear in the sensitivity tables"
      : r.has_piv ? "every metric uses the instantaneous velocities (/snapshots/velocity), as configured"
                  : "the run file has no displacements (/snapshots/displacement absent or displacement_window = 0): "
                    "every metric uses the instantaneous velocities (/snapshots/velocity), which carry the bed's ringing";
  m["loading_selection"] = r.have_events ? "pre_rupture" : "all_snapshots";
  m["loading_note"] =
      r.have_events ? "cone and wall metrics over the snapshots just before each rupture: the last snapshot k with "
                      "load_start_time <= t_k - displacement_window and t_k <= peak_time of each event"
                    : "no --events file: cone and wall metrics over all snapshots (loading and slip frames mixed)";
  m["events"] = r.have_events ? json(r.events.size()) : json();
  m["events_with_snapshot"] = r.have_events ? x.sel.size() : 0;
}

void add_cone(json& m, const Summary& x) {
  const BetaStats& beta = x.beta;
  m["cone_angle_measured_deg"] = nullable(beta.mean);
  m["cone_angle_interval_deg"] = {nullable(beta.mean - x.beta_half), nullable(beta.mean + x.beta_half)};
  m["cone_angle_sd_deg"] = nullable(beta.sd);
  m["cone_angle_snapshots"] = beta.count;
  m["cone_angle_left_deg"] = nullable(beta.left);
  m["cone_angle_right_deg"] = nullable(beta.right);
  m["cone_opening_angle_deg"] = nullable(180.0 - 2.0 * x.beta_value);
  m["cone_angle_all_snapshots_deg"] =
      nullable(beta_stats(x.r.ms, x.all, x.r.primary, x.cone0, x.gap, kVerticalEdgeDeg, x.gate).mean);
  m["cone_edge_note"] = "every cone number (angle, sides, bands, wall meeting, chord, offset, H_c from beta) uses "
                        "the fitted edges that do not narrow upwards (beta <= 90 deg; vertical kept); the narrowing "
                        "ones (beta > 90) are left out, counted and described by the metrics named *narrowing*";
  m["cone_fitted_edges"] = beta.edges;
  m["cone_narrowing_edges"] = beta.excluded;
  m["cone_narrowing_edge_fraction"] = nullable(fraction(beta.excluded, beta.edges));
  m["cone_angle_narrowing_mean_deg"] = nullable(beta.excluded_mean);
  m["cone_angle_narrowing_sd_deg"] = nullable(beta.excluded_sd);
  m["cone_fitted_snapshots"] = beta.fitted_snapshots;
  m["cone_snapshots_with_narrowing_edge"] = beta.with_excluded;
  m["cone_narrowing_snapshot_fraction"] = nullable(fraction(beta.with_excluded, beta.fitted_snapshots));
  m["cone_snapshots_only_narrowing"] = beta.all_excluded;
  m["cone_excluded_snapshot_fraction"] = nullable(fraction(beta.all_excluded, beta.fitted_snapshots));
  m["cone_angle_including_narrowing_deg"] = nullable(x.every_edge.mean);
  m["cone_angle_including_narrowing_sd_deg"] = nullable(x.every_edge.sd);
  m["cone_wall_meet_above_intruder_mm"] = nullable(beta.meet * kMm);
  m["cone_wall_meet_snapshots"] = beta.meet_count;
  m["cone_angle_from_wall_meet_deg"] = nullable(beta.chord);
  m["cone_edge_offset_at_intruder_mm"] = nullable(beta.offset * kMm);
  m["wall_mobility_length_from_beta_mm"] = nullable(x.gap * std::tan(x.beta_value / kDeg) * kMm);
}

void add_wall(json& m, const Summary& x) {
  const WallLoss& wall = x.wall;
  m["wall_mobility_loss_height_mm"] = nullable(wall.fit.height * kMm);
  m["wall_mobility_surface_mm"] = nullable(wall.surface * kMm);
  m["wall_mobility_snapshots"] = wall.fit.count;
  m["wall_mobility_mobile_snapshots"] = wall.mobile;
  m["wall_mobility_misclassified"] = wall.fit.misclassified;
  m["wall_mobility_loss_p_value"] = nullable(x.loss_p);
  const StepPower& pw = x.loss_power;
  const std::string verdict = std::isfinite(pw.power) && pw.power >= x.r.config.wall_min_power ? "none" : "undetermined";
  m["wall_mobility_outcome"] =
      x.loss_significant ? "found"
      : std::isfinite(wall.fit.height) ? verdict + ": no significant loss (the split of mobile from immobile "
                                         "snapshots is not better than the same flags shuffled over the heights); "
                                         "power " + format_number(pw.power) + " to find one at the paper's depth"
                                       : verdict + ": no loss, the walls are mobile in every loading snapshot or in "
                                         "none; power " + format_number(pw.power) + " to find one at the paper's depth";
  m["wall_mobility_power"] = nullable(pw.power);
  m["wall_mobility_power_detail"] = {{"planted_depth_mm", nullable(pw.depth * kMm)},
                                     {"flip_rate_below", nullable(pw.flip_below)},
                                     {"flip_rate_above", nullable(pw.flip_above)},
                                     {"replicas", pw.replicas},
                                     {"min_power", x.r.config.wall_min_power}};
  m["wall_mobility_level_range"] = {nullable(x.noise.level_min), nullable(x.noise.level_max)};
  m["wall_mobility_pool_d"] = x.noise.pool_d;
  m["wall_mobility_level_note"] = "per window: max(cone.level, q x the local-linear fit's noise gain there), q the "
                                  "(1 - noise.wall_false_alarm / M) quantile of the windowed v* per unit gain at "
                                  "rest, M the independent windows scanned; the profiles pooled over "
                                  "wall_mobility_pool_d of travel (0: each snapshot alone) only when the noise "
                                  "lifts a level above cone.level";
  m["wall_mobility_length_fixed_level_mm"] = nullable(x.fixed_wall.depth * kMm);
  m["wall_mobility_fixed_level_note"] =
      "the definition before the noise calibration: mobile where the mean of the two walls' lengths with v* >= "
      "cone.level is at least wall.min_mobile_d; no significance test";
}

void add_noise(json& m, const Summary& x) {
  const Setup& su = x.r.setup;
  m["cone_level"] = su.levels[su.level0];
  m["cone_level_note"] = "max(cone.level, the (1 - noise.cone_false_alarm) quantile of v* at single nodes at rest)";
  m["piv_noise"] = {{"region", "rows from noise.rest_margin_w x w above the floor to as far below the intruder's "
                               "centre; nodes outside the intruder's column by 4 w, wall-band windows, grains "
                               "within wall.band_d of a wall"},
                    {"rest_nodes", su.rest_nodes.size()},
                    {"node_vstar_median", nullable(upper_quantile(su.rest_nodes, 0.5))},
                    {"node_vstar_q99", nullable(upper_quantile(su.rest_nodes, 0.99))},
                    {"node_vstar_q999", nullable(upper_quantile(su.rest_nodes, 0.999))},
                    {"rest_wall_windows", x.noise.rest.size()},
                    {"wall_window_vstar_median", nullable(upper_quantile(x.noise.rest, 0.5))},
                    {"wall_window_vstar_q99", nullable(upper_quantile(x.noise.rest, 0.99))},
                    {"grain_rms_over_v", nullable(x.noise.grain_rms)},
                    {"grain_samples", x.noise.grains},
                    {"unit", "x V_ref (the intruder's speed)"}};
  m["half_gap_mm"] = x.gap * kMm;
}

void add_dilatancy(json& m, const Summary& x) {
  const StageRecord& r = x.r;
  const Setup& su = r.setup;
  const std::vector<SnapshotMeasure>& ms = r.ms;
  const std::size_t h0 = su.height0;
  const std::int64_t k_after = r.after;
  const auto after = static_cast<std::size_t>(std::max<std::int64_t>(k_after, 0));
  m["dilatancy_phi_before"] = nullable(ms[0].phi_follow[h0]);
  m["dilatancy_phi_after"] = k_after >= 0 ? nullable(ms[after].phi_follow[h0]) : json();
  m["dilatancy_time_after_s"] = k_after >= 0 ? json(r.times[after]) : json();
  m["dilatancy_travel_after_mm"] = k_after >= 0 ? json((r.heights[after] - r.heights[0]) * kMm) : json();
  m["dilatancy_region_mm"] = {r.config.region_width_L * su.start.length() * kMm,
                              r.config.region_offset_w * su.kernel.w * kMm, su.heights[h0] * kMm};
  if (r.have_events && r.events.size() > 0) {
    // the first snapshot after the end of the first rupture's drop
    const RuptureEvent& first = *std::min_element(
        r.events.begin(), r.events.end(), [](const RuptureEvent& a, const RuptureEvent& b) { return a.peak_time < b.peak_time; });
    std::int64_t k_drop = -1;
    for (std::size_t k = 0; k < ms.size() && k_drop < 0; ++k)
      if (r.times[k] >= first.drop_end_time) k_drop = static_cast<std::int64_t>(k);
    m["dilatancy_delta_phi_after_first_rupture"] = nullable(delta_phi(ms, k_drop, h0, true));
  }
}

// Zone areas over the selected snapshots, then per band of intruder height.
void add_zones(json& m, const Summary& x) {
  const std::vector<SnapshotMeasure>& ms = x.r.ms;
  std::vector<double> im, co, dr, red, mob;
  for (const std::size_t k : x.sel) {
    const SourceMeasure& s = ms[k].src[x.r.primary];
    if (!s.valid) continue;
    im.push_back(s.zones.immobile), co.push_back(s.zones.cone), dr.push_back(s.zones.dragged);
    red.push_back(s.red.height), mob.push_back(s.mobile.area);
  }
  m["zone_area_immobile_mm2"] = nullable(mean_of(im) * kMm * kMm);
  m["zone_area_cone_mm2"] = nullable(mean_of(co) * kMm * kMm);
  m["zone_area_dragged_mm2"] = nullable(mean_of(dr) * kMm * kMm);
  m["red_zone_extent_mm"] = nullable(mean_of(red) * kMm);
  m["mobilised_zone_area_mm2"] = nullable(mean_of(mob) * kMm * kMm);
}

json height_bands(const Summary& x) {
  const std::vector<SnapshotMeasure>& ms = x.r.ms;
  const std::vector<double>& edges = x.r.config.bands_mm;
  const std::size_t primary = x.r.primary;
  json bands = json::array();
  for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
    std::vector<std::size_t> in_band;
    std::vector<double> red, cone_area;
    for (const std::size_t k : x.sel)
      if (ms[k].height * kMm >= edges[b] && ms[k].height * kMm < edges[b + 1]) {
        in_band.push_back(k);
        if (ms[k].src[primary].valid)
          red.push_back(ms[k].src[primary].red.height), cone_area.push_back(ms[k].src[primary].zones.cone);
      }
    const BetaStats bs = beta_stats(ms, in_band, primary, x.cone0, x.gap, kVerticalEdgeDeg, x.gate);
    bands.push_back({{"height_mm", {edges[b], edges[b + 1]}},
                     {"snapshots", in_band.size()},
                     {"cone_angle_deg", nullable(bs.mean)},
                     {"cone_angle_sd_deg", nullable(bs.sd)},
                     {"cone_angle_snapshots", bs.count},
                     {"narrowing_edge_fraction", nullable(fraction(bs.excluded, bs.edges))},
                     {"red_zone_extent_mm", nullable(mean_of(red) * kMm)},
                     {"zone_area_cone_mm2", nullable(mean_of(cone_area) * kMm * kMm)}});
  }
  return bands;
}

// ---- sensitivity: one parameter at a time around the configured values ----

json edge_cutoff_rows(const Summary& x) {
  json rows = json::array();
  for (const double max_deg : x.r.config.max_edge_angles_deg) {
    const BetaStats a = beta_stats(x.r.ms, x.sel, x.r.primary, x.cone0, x.gap, max_deg, x.gate);
    rows.push_back({{"max_edge_angle_deg", max_deg},
                    {"excluded_edge_fraction", nullable(fraction(a.excluded, a.edges))},
                    {"cone_angle_deg", nullable(a.mean)},
                    {"sd_deg", nullable(a.sd)},
                    {"snapshots", a.count},
                    {"cone_angle_from_wall_meet_deg", nullable(a.chord)},
                    {"wall_meet_snapshots", a.meet_count},
                    {"wall_mobility_length_from_beta_mm", nullable(x.gap * std::tan(a.mean / kDeg) * kMm)}});
  }
  return rows;
}

// The cone angle by velocity set, level and fit start (each varied alone).
void add_cone_rows(json& rows, const Summary& x, std::size_t set) {
  const Setup& su = x.r.setup;
  const std::size_t nstart = su.starts.size();
  for (std::size_t l = 0; l < su.levels.size(); ++l)
    for (std::size_t st = 0; st < nstart; ++st) {
      if (l != su.level0 && st != su.start0) continue;
      const BetaStats a = beta_stats(x.r.ms, x.sel, set, l * nstart + st, x.gap, kVerticalEdgeDeg);
      const BetaStats b = beta_stats(x.r.ms, x.all, set, l * nstart + st, x.gap, kVerticalEdgeDeg);
      rows.push_back({{"velocity", kSourceName[set]},
                      {"level", su.levels[l]},
                      {"fit_start_w", su.starts[st] / su.kernel.w},
                      {"cone_angle_deg", nullable(a.mean)},
                      {"sd_deg", nullable(a.sd)},
                      {"snapshots", a.count},
                      {"narrowing_edge_fraction", nullable(fraction(a.excluded, a.edges))},
                      {"cone_angle_all_snapshots_deg", nullable(b.mean)},
                      {"cone_angle_from_wall_meet_deg", nullable(a.chord)},
                      {"wall_meet_snapshots", a.meet_count},
                      {"wall_mobility_length_from_beta_mm", nullable(x.gap * std::tan(a.mean / kDeg) * kMm)}});
    }
}

// The fixed-level wall loss by velocity set, level and band width (each varied alone).
void add_wall_rows(json& rows, const Summary& x, std::size_t set) {
  const Setup& su = x.r.setup;
  const std::size_t nband = su.bands.size();
  for (std::size_t l = 0; l < su.levels.size(); ++l)
    for (std::size_t b = 0; b < nband; ++b) {
      if (l != su.level0 && b != su.band0) continue;
      const WallLoss w = wall_loss(x.r.ms, x.sel, set, l * nband + b, x.r.config.wall_min_mobile_d * su.d);
      rows.push_back({{"velocity", kSourceName[set]},
                      {"level", su.levels[l]},
                      {"band_d", su.bands[b] / su.d},
                      {"wall_mobility_length_mm", nullable(w.depth * kMm)},
                      {"loss_height_mm", nullable(w.fit.height * kMm)},
                      {"misclassified", w.fit.misclassified},
                      {"snapshots", w.fit.count}});
    }
}

json dilatancy_rows(const Summary& x) {
  const Setup& su = x.r.setup;
  const CgConfig& c = x.r.config;
  json rows = json::array();
  for (const double t : c.after_travels_d)
    for (std::size_t h = 0; h < su.heights.size(); ++h)
      for (const bool follow : {true, false}) {
        if ((t != c.after_travel_d && h != su.height0) || (!follow && (t != c.after_travel_d || h != su.height0)))
          continue;
        rows.push_back({{"after_travel_d", t},
                        {"region_height_d", su.heights[h] / su.d},
                        {"region", follow ? "following the intruder" : "fixed at its start position"},
                        {"delta_phi", nullable(delta_phi(x.r.ms, first_after_travel(x.r.heights, t * su.d), h, follow))}});
      }
  return rows;
}

json false_alarm_rows(const Summary& x) {
  const CgConfig& c = x.r.config;
  json rows = json::array();
  for (const double a : c.wall_false_alarms) {
    WallNoise nq = x.noise;
    const WallLoss w = calibrated_wall_loss(x.r, x.sel, nq, a);
    const double p = step_p_value(w, c.wall_permutations);
    const bool sig = std::isfinite(w.fit.height) && p < c.wall_loss_false_alarm;
    rows.push_back({{"wall_false_alarm", a},
                    {"level_range", {nullable(nq.level_min), nullable(nq.level_max)}},
                    {"wall_mobility_length_mm", sig ? nullable(w.depth * kMm) : json()},
                    {"loss_height_mm", nullable(w.fit.height * kMm)},
                    {"loss_p_value", nullable(p)},
                    {"misclassified", w.fit.misclassified},
                    {"snapshots", w.fit.count}});
  }
  return rows;
}

json sensitivity(const Summary& x) {
  json cone_rows = json::array(), wall_rows = json::array();
  for (const std::size_t set : {kInst, kPiv}) {
    if (set == kPiv && !x.r.has_piv) continue;
    add_cone_rows(cone_rows, x, set);
    add_wall_rows(wall_rows, x, set);
  }
  return {{"cone_angle", cone_rows},
          {"cone_angle_edge_cutoff", edge_cutoff_rows(x)},
          {"wall_mobility", wall_rows},
          {"wall_mobility_false_alarm", false_alarm_rows(x)},
          {"dilatancy", dilatancy_rows(x)}};
}

// The grid, the speeds and the cost; where the inputs came from.
void add_setup(json& m, const StageRecord& r) {
  const Setup& su = r.setup;
  const double dx = su.grid.dx;
  const double S = static_cast<double>(r.ms.size());
  m["grid"] = {{"nx", su.grid.nx},
               {"ny", su.grid.ny},
               {"spacing_mm", dx * kMm},
               {"width_mm", (su.cell.right - su.cell.left) * kMm},
               {"height_mm", static_cast<double>(su.grid.ny) * dx * kMm},
               {"w_mm", su.kernel.w * kMm},
               {"w_over_dx", su.kernel.w / dx},
               {"cutoff_mm", su.kernel.radius() * kMm},
               {"mean_diameter_mm", su.d * kMm},
               {"phi_ref", su.phi_ref},
               {"mask_phi", su.min_phi},
               {"frame", "fixed grid (lab frame); intruder-frame velocities are V - V_intruder on the same nodes"}};
  m["intruder"] = true;
  m["intruder_speed_mm_s"] = su.pull.speed() * kMm;
  m["reference_speed_mm_s"] = su.v_ref * kMm;
  m["displacement_window_s"] = su.window;
  m["snapshots"] = r.ms.size();
  m["snapshots_with_piv"] = static_cast<std::size_t>(std::count(r.piv_ok.begin(), r.piv_ok.end(), 1));
  m["field_snapshots"] = r.fields_at.size();
  m["cost"] = {{"seconds", r.seconds},
               {"seconds_per_snapshot", r.seconds / S},
               {"coarse_graining_seconds_per_snapshot", r.cg_seconds / S},
               {"threads", r.threads}};
  m["run_file"] = r.run_path;
  m["events_file"] = r.events_path;
  m["config_file"] = r.config_path;
}

}  // namespace

json cg_metrics(const StageRecord& r) {
  const Summary x = summarise(r);
  json m;
  add_headline(m, x);
  add_cone(m, x);
  add_wall(m, x);
  add_noise(m, x);
  add_dilatancy(m, x);
  add_zones(m, x);
  m["by_height_band"] = height_bands(x);
  // ringing: the median v* over the bed (most of it immobile) in the selected snapshots
  for (const std::size_t set : {kInst, kPiv}) {
    std::vector<double> med;
    for (const std::size_t k : x.sel)
      if (r.ms[k].src[set].valid) med.push_back(r.ms[k].src[set].median_vstar);
    m[std::string("median_vstar_") + kSourceName[set]] = nullable(mean_of(med));
  }
  m["sensitivity"] = sensitivity(x);
  add_setup(m, r);
  return m;
}

namespace {

// /snapshots: one value per snapshot, and per velocity set.
void add_snapshot_series(H5Output& h, const StageRecord& r) {
  const Setup& su = r.setup;
  const std::size_t S = r.ms.size(), cone0 = su.cone0(), wall0 = su.wall_fixed();
  const auto per = [&](auto get) { return column_of(r.ms, get); };
  h.add("snapshots/time", r.times, "s", "snapshot time");
  h.add("snapshots/intruder_height", per([](const SnapshotMeasure& x) { return x.height; }), "m", "intruder centre above the floor's face");
  h.add("snapshots/surface_height", per([](const SnapshotMeasure& x) { return x.surface; }), "m", "free surface above the floor: mean over columns ~d wide of the highest grain top");
  h.add("snapshots/phi_region", per([&](const SnapshotMeasure& x) { return x.phi_follow[su.height0]; }), "-", "solid fraction in the dilatancy region following the intruder");
  h.add("snapshots/piv_valid", std::vector<std::int64_t>(r.piv_ok.begin(), r.piv_ok.end()), "-", "1 if the snapshot has PIV-like velocities (every active grain has a displacement)");
  {
    std::vector<std::int64_t> ev(S, -1);
    for (std::size_t e = 0; e < r.pre.size(); ++e)
      if (r.pre[e] >= 0) ev[static_cast<std::size_t>(r.pre[e])] = static_cast<std::int64_t>(e);
    h.add("snapshots/pre_rupture_event", ev, "-", "event whose loading phase this snapshot ends, -1 if none");
  }
  for (const std::size_t set : {kInst, kPiv}) {
    const std::string p = std::string("snapshots/") + kSourceName[set] + "/";
    const auto src = [&](auto get) {
      return per([&](const SnapshotMeasure& x) { return x.src[set].valid ? get(x.src[set]) : kNaN; });
    };
    h.add(p + "area_immobile", src([](const SourceMeasure& s) { return s.zones.immobile; }), "m^2", "area of the nodes with v* < zones.immobile_below");
    h.add(p + "area_cone", src([](const SourceMeasure& s) { return s.zones.cone; }), "m^2", "area of the nodes in between (the cone)");
    h.add(p + "area_dragged", src([](const SourceMeasure& s) { return s.zones.dragged; }), "m^2", "area of the nodes with v* > zones.dragged_above");
    h.add(p + "red_extent", src([](const SourceMeasure& s) { return s.red.height; }), "m", "highest node of the dragged zone grown from the intruder, above its top face");
    h.add(p + "beta", src([&](const SourceMeasure& s) { return s.cone[cone0].beta_deg(kVerticalEdgeDeg); }), "deg", "mean of the snapshot's edge angles that widen upwards (<= 90 deg); NaN if none");
    h.add(p + "beta_left", src([&](const SourceMeasure& s) { return s.cone[cone0].left.beta_deg; }), "deg", "fitted edge angle from the horizontal, narrowing edges (> 90 deg) included");
    h.add(p + "beta_right", src([&](const SourceMeasure& s) { return s.cone[cone0].right.beta_deg; }), "deg", "as beta_left, the right edge");
    h.add(p + "wall_meet_y", src([&](const SourceMeasure& s) { return s.cone[cone0].wall_y(kVerticalEdgeDeg); }), "m", "y where the cone's edge reaches the wall column (mean of the sides that do, narrowing edges left out)");
    h.add(p + "wall_mobile_left", src([&](const SourceMeasure& s) { return s.wall_left[wall0]; }), "m", "height above the intruder's centre where the left wall band's v* >= cone.level (the fixed level)");
    h.add(p + "wall_mobile_right", src([&](const SourceMeasure& s) { return s.wall_right[wall0]; }), "m", "as wall_mobile_left, the right wall");
    h.add(p + "median_vstar", src([](const SourceMeasure& s) { return s.median_vstar; }), "-", "median v* over the bed nodes (the ringing)");
  }
}

// /profiles: one node column per snapshot [S, ny].
void add_profiles(H5Output& h, const StageRecord& r) {
  const std::vector<SnapshotMeasure>& ms = r.ms;
  const Grid& g = r.setup.grid;
  const auto S_ = static_cast<hsize_t>(ms.size()), NY = static_cast<hsize_t>(g.ny);
  const std::size_t S = ms.size();
  const auto rows = [&](auto get) {
    std::vector<float> v;
    v.reserve(S * g.ny);
    for (const SnapshotMeasure& x : ms) {
      const std::vector<float>& row = get(x);
      v.insert(v.end(), row.begin(), row.end());
    }
    return v;
  };
  h.add("profiles/centre_vy_instantaneous", rows([](const SnapshotMeasure& x) -> const auto& { return x.centre_vy[kInst]; }), "m/s", "vertical velocity (lab frame) along the node column through the intruder's centre (attribute centre_x)", {S_, NY});
  h.add("profiles/centre_vy_piv", rows([](const SnapshotMeasure& x) -> const auto& { return x.centre_vy[kPiv]; }), "m/s", "as centre_vy_instantaneous, PIV-like velocities", {S_, NY});
  h.add("profiles/centre_phi", rows([](const SnapshotMeasure& x) -> const auto& { return x.centre_phi; }), "-", "solid fraction along the node column through the intruder's centre", {S_, NY});
  h.add("profiles/wall_vstar_left", rows([](const SnapshotMeasure& x) -> const auto& { return x.wall_vstar[0]; }), "-", "mean v* of the nodes within wall.band_d of the left wall, per row (velocity_source)", {S_, NY});
  h.add("profiles/wall_vstar_right", rows([](const SnapshotMeasure& x) -> const auto& { return x.wall_vstar[1]; }), "-", "as wall_vstar_left, the right wall", {S_, NY});
  h.add("profiles/wall_local_left", rows([](const SnapshotMeasure& x) -> const auto& { return x.wall_local[0]; }), "-", "v* along the column wall.band_d / 2 from the left wall by local-linear regression of the grains' velocities "
      "(kernel wall.kernel_w x w; velocity_source): what the walls' mobility is judged on", {S_, NY});
  h.add("profiles/wall_local_right", rows([](const SnapshotMeasure& x) -> const auto& { return x.wall_local[1]; }), "-", "as wall_local_left, the right wall", {S_, NY});
}

// /tips: the velocity around the intruder, in its frame [S, tip_ny, tip_nx].
void add_tips(H5Output& h, const StageRecord& r) {
  const Setup& su = r.setup;
  const std::vector<SnapshotMeasure>& ms = r.ms;
  const double dx = su.grid.dx;
  const auto S_ = static_cast<hsize_t>(ms.size());
  std::vector<double> tx(su.tip_nx), ty(su.tip_ny);
  for (std::size_t a = 0; a < su.tip_nx; ++a) tx[a] = (static_cast<double>(a) - static_cast<double>(su.tip_nx / 2)) * dx;
  for (std::size_t b = 0; b < su.tip_ny; ++b) ty[b] = (static_cast<double>(b) - static_cast<double>(su.tip_ny / 2)) * dx;
  h.add("tips/dx", tx, "m", "node offsets from the intruder's centre (window snapped to the nearest node)");
  h.add("tips/dy", ty, "m", "node offsets from the intruder's centre, y");
  const hsize_t TY = su.tip_ny, TX = su.tip_nx;
  for (const std::size_t set : {kInst, kPiv})
    for (int comp = 0; comp < 2; ++comp) {
      std::vector<float> v;
      for (const SnapshotMeasure& x : ms) v.insert(v.end(), x.tip[set][comp].begin(), x.tip[set][comp].end());
      h.add(std::string("tips/") + (comp ? "vy_" : "vx_") + kSourceName[set], std::move(v), "m/s", "velocity in the intruder's frame (V - V_intruder) around the intruder", {S_, TY, TX});
    }
}

// /fields: the full fields of the chosen snapshots [F, ny, nx].
void add_fields(H5Output& h, const StageRecord& r) {
  const std::vector<SnapshotMeasure>& ms = r.ms;
  const auto NX = static_cast<hsize_t>(r.setup.grid.nx), NY = static_cast<hsize_t>(r.setup.grid.ny);
  const auto F = static_cast<hsize_t>(r.fields_at.size());
  std::vector<std::int64_t> idx(r.fields_at.begin(), r.fields_at.end());
  h.add("fields/snapshot", idx, "-", "snapshot index of each stored field");
  std::vector<float> phi;
  std::vector<float> v[2][2];
  for (const std::size_t k : r.fields_at) {
    phi.insert(phi.end(), ms[k].phi_field.begin(), ms[k].phi_field.end());
    for (int set = 0; set < 2; ++set)
      for (int comp = 0; comp < 2; ++comp) v[set][comp].insert(v[set][comp].end(), ms[k].v_field[set][comp].begin(), ms[k].v_field[set][comp].end());
  }
  h.add("fields/phi", std::move(phi), "-", "solid fraction; the mass density is rho = grain_density (root attribute) * phi", {F, NY, NX});
  for (const std::size_t set : {kInst, kPiv})
    for (int comp = 0; comp < 2; ++comp)
      h.add(std::string("fields/") + (comp ? "vy_" : "vx_") + kSourceName[set], std::move(v[set][comp]), "m/s", "lab-frame velocity V = p/rho, NaN where phi < mask_phi", {F, NY, NX});
}

}  // namespace

void add_grid(H5Output& h, const Grid& g, std::string y_about) {
  std::vector<double> gx(g.nx), gy(g.ny);
  for (std::size_t i = 0; i < g.nx; ++i) gx[i] = g.x(i);
  for (std::size_t j = 0; j < g.ny; ++j) gy[j] = g.y(j);
  h.add("grid/x", std::move(gx), "m", "node x (run-file frame)");
  h.add("grid/y", std::move(gy), "m", std::move(y_about));
}

H5Output cg_h5(const StageRecord& r, const json& metrics) {
  const Grid& g = r.setup.grid;
  H5Output h("cg", r.run_path);
  h.note("format", std::string("dem2d-cg-2"));
  h.note("velocity_source", std::string(kSourceName[r.primary]));
  h.note("metrics", metrics.dump());
  h.note("floor_y", r.setup.cell.floor);
  h.note("grain_density", r.setup.grain_density);
  h.note("centre_x", g.x(r.setup.centre_i));
  add_grid(h, g, "node y (run-file frame); the floor's face is at attribute floor_y");
  add_snapshot_series(h, r);
  add_profiles(h, r);
  add_tips(h, r);
  add_fields(h, r);
  if (r.have_events) {
    std::vector<double> peak;
    for (const RuptureEvent& e : r.events) peak.push_back(e.peak_time);
    h.add("events/peak_time", std::move(peak), "s", "time of each event's drag peak (the events file)");
    h.add("events/pre_rupture_snapshot", r.pre, "-", "the snapshot just before the rupture, -1 if none");
  }
  return h;
}

}  // namespace dem2d::analysis
