#include "piv/piv_stage.hpp"

#include <cairo.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include "common/json_input.hpp"
#include "common/normal.hpp"
#include "common/output.hpp"
#include "common/snapshot_loop.hpp"
#include "common/stage_output.hpp"
#include "common/units.hpp"
#include "frame/cell.hpp"
#include "frame/intruder.hpp"
#include "piv/piv_measure.hpp"

namespace dem2d::analysis {

namespace {

using json = nlohmann::ordered_json;

struct Stats {
  std::size_t n = 0;
  double mean = kNaN, sd = kNaN, half = kNaN;  // half: the 95 % t-interval's half width
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  double sum = 0.0;
  for (double x : v)
    if (std::isfinite(x)) sum += x, ++s.n;
  if (s.n == 0) return s;
  s.mean = sum / static_cast<double>(s.n);
  if (s.n < 2) return s;
  double ss = 0.0;
  for (double x : v)
    if (std::isfinite(x)) ss += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(ss / static_cast<double>(s.n - 1));
  s.half = student_t975(static_cast<int>(s.n - 1)) * s.sd / std::sqrt(static_cast<double>(s.n));
  return s;
}
json to_json(const Stats& s, double scale = 1.0) {
  return {{"mean", number_or_null(s.mean * scale)},
          {"interval", {number_or_null((s.mean - s.half) * scale), number_or_null((s.mean + s.half) * scale)}},
          {"sd", number_or_null(s.sd * scale)},
          {"snapshots", s.n}};
}

// Wilson's 95 % interval of a proportion k / n
std::pair<double, double> wilson(std::size_t k, std::size_t n) {
  if (n == 0) return {kNaN, kNaN};
  const double z = 1.959964, p = static_cast<double>(k) / static_cast<double>(n), nn = static_cast<double>(n);
  const double c = (p + z * z / (2 * nn)) / (1 + z * z / nn);
  const double h = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn)) / (1 + z * z / nn);
  return {std::max(0.0, c - h), std::min(1.0, c + h)};
}

// the q-quantile of the values (the smallest at or above a fraction q of them); NaN if none
double quantile(std::vector<float> v, double q) {
  if (v.empty()) return kNaN;
  const auto at = std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(at), v.end());
  return v[at];
}

bool vortex(const std::vector<float>& disc, double threshold, std::int64_t min_nodes) {
  std::int64_t n = 0;
  for (float x : disc) n += x > threshold;
  return n >= min_nodes;
}

// The frames' interval: the run's displacement_window (frame_interval_s = 0 or equal to it), or a whole
// number of its snapshot intervals (frame A from the snapshot that many earlier); else a refusal.
void frame_interval(const SnapshotSource& run, const PivInput& in, PairSetup& su) {
  const double asked = in.config.frame_interval_s, window = run.displacement_window();
  const bool has_window = run.has_displacements() && window > 0.0;
  if (asked == 0.0 || (has_window && std::abs(asked - window) <= 1e-9 * window)) {
    if (!has_window)
      throw StageError(run.path() + ": the run has no displacements over a window (the scene's [output] "
                       "displacement_window, s, > 0 and at most the snapshot interval) and " + in.config_path +
                       " asks for them (snapshots.frame_interval_s = 0): PIV needs frame pairs; give a whole number of "
                       "the run's snapshot intervals instead");
    su.interval = window, su.gap = 0;
    return;
  }
  const std::vector<double>& t = run.snapshot_times();
  std::vector<double> steps;
  for (std::size_t k = 1; k < t.size(); ++k) steps.push_back(t[k] - t[k - 1]);
  double spacing = kNaN;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
    spacing = steps[steps.size() / 2];
  }
  const double gap = std::round(asked / spacing);
  if (!(gap >= 1.0) || std::abs(gap * spacing - asked) > 0.01 * asked || gap >= static_cast<double>(t.size()))
    throw StageError(in.config_path + ": snapshots.frame_interval_s = " + format_number(asked) + ": " + run.path() +
                     " cannot give it: its frame pairs are its displacement_window (" +
                     (has_window ? format_number(window) + " s" : std::string("none")) +
                     ") or a whole number of its snapshot intervals (" + format_number(spacing) + " s, " +
                     std::to_string(t.size()) + " snapshots)");
  su.interval = gap * spacing, su.gap = static_cast<std::size_t>(gap);
}

PairSetup setup(const SnapshotSource& run, const Snapshot& s0, const PivInput& in) {
  const PivConfig& c = in.config;
  PairSetup su;
  su.cell = find_cell(s0);
  su.d = mean_active_diameter(s0);
  su.intruder = s0.find_role("intruder");
  if (su.intruder < 0)
    throw StageError(run.path() + ": " + s0.no_body_with_role("intruder") + ": the camera follows the intruder");
  frame_interval(run, in, su);
  const Pull pull = pull_of(run);
  su.V = pull.velocity;
  su.v_ref = in.cg.reference_speed_mm_s > 0.0 ? in.cg.reference_speed_mm_s / kMm : pull.speed();
  if (!(su.v_ref > 0.0))
    throw StageError(in.cg_config_path + ": zones.reference_speed_mm_s = 0 and the intruder does not move: v* = |v| / V "
                     "needs a speed");
  su.scale = c.camera.px_per_diameter / su.d;
  su.kernel = make_kernel(in.cg.w_over_d * su.d, in.cg.cutoff_over_w);
  su.camera = c.camera;
  su.piv = c.piv;
  const auto first = static_cast<std::size_t>(c.piv.windows.front());
  if (first > c.camera.width || first > c.camera.height)
    throw StageError(in.config_path + ": piv.windows_px = " + std::to_string(first) + " does not fit in the " +
                     std::to_string(c.camera.width) + " x " + std::to_string(c.camera.height) +
                     " px image (camera.width_px, camera.height_px): no window");
  su.wall_margin = c.wall_margin_d * su.d;
  su.surface_margin = c.surface_margin_d * su.d;
  su.mask_margin = c.mask_margin_d * su.d;
  su.rest_below = in.cg.rest_margin_w * su.kernel.w;
  su.tip_radius = c.tip_radius_d * su.d;
  su.min_swirl_share = c.min_swirl_share;
  su.cg = in.cg;
  return su;
}

// the pairs' paired differences (PIV - CG) of a per-side value
template <class Get>
json compare(const std::vector<PairMeasure>& ms, Get get, double scale, const char* unit) {
  std::vector<double> v[2], diff;
  for (const PairMeasure& m : ms) {
    const double a = get(m.side[kPivSide]), b = get(m.side[kCgSide]);
    v[0].push_back(a), v[1].push_back(b);
    if (std::isfinite(a) && std::isfinite(b)) diff.push_back(a - b);
  }
  return {{"piv", to_json(stats(v[0]), scale)}, {"cg", to_json(stats(v[1]), scale)},
          {"difference", to_json(stats(diff), scale)}, {"unit", unit}};
}

// R12: vortices near the tips, against discs of the same size in the bed at rest
json vortices(const std::vector<PairMeasure>& ms, const PivConfig& c, std::size_t k) {
  std::vector<float> rest;
  for (const PairMeasure& m : ms) rest.insert(rest.end(), m.side[k].rest_swirl.begin(), m.side[k].rest_swirl.end());
  const double th = quantile(rest, c.rest_quantile);
  json j;
  j["threshold_v_over_d"] = number_or_null(th);
  j["rest_nodes"] = rest.size();
  if (std::isnan(th)) {
    j["verdict"] = "undetermined";
    j["why"] = "no node at rest (rows below the intruder's centre by the cg stage's noise.rest_margin_w x w) to set the threshold";
    return j;
  }
  std::size_t pairs = 0, left = 0, right = 0, either = 0, controls = 0, control_hits = 0;
  for (const PairMeasure& m : ms) {
    const Side& s = m.side[k];
    const bool l = vortex(s.tip_swirl[0], th, c.min_nodes), r = vortex(s.tip_swirl[1], th, c.min_nodes);
    ++pairs, left += l, right += r, either += l || r;
    if (!s.control_swirl[0].empty() || !s.control_swirl[1].empty()) {
      ++controls;
      control_hits += vortex(s.control_swirl[0], th, c.min_nodes) || vortex(s.control_swirl[1], th, c.min_nodes);
    }
  }
  // the threshold's sensitivity: the rates at other quantiles and cluster sizes
  json sens = json::array();
  for (const double q : {0.99, 0.999, 0.9999})
    for (const std::int64_t n : {c.min_nodes, 3 * c.min_nodes, 10 * c.min_nodes}) {
      const double t = quantile(rest, q);
      std::size_t hits = 0, ctrl = 0;
      for (const PairMeasure& m : ms) {
        const Side& s = m.side[k];
        hits += vortex(s.tip_swirl[0], t, n) || vortex(s.tip_swirl[1], t, n);
        ctrl += vortex(s.control_swirl[0], t, n) || vortex(s.control_swirl[1], t, n);
      }
      sens.push_back({{"rest_quantile", q}, {"min_nodes", n}, {"threshold_v_over_d", number_or_null(t)},
                      {"tip_rate", fraction_or_null(static_cast<std::int64_t>(hits), static_cast<std::int64_t>(ms.size()))},
                      {"control_rate", fraction_or_null(static_cast<std::int64_t>(ctrl), static_cast<std::int64_t>(controls))}});
    }
  const auto tip = wilson(either, pairs), rest_rate = wilson(control_hits, controls);
  j["pairs"] = pairs;
  j["tip_rate"] = fraction_or_null(static_cast<std::int64_t>(either), static_cast<std::int64_t>(pairs));
  j["tip_rate_interval"] = {number_or_null(tip.first), number_or_null(tip.second)};
  j["left_tip_rate"] = fraction_or_null(static_cast<std::int64_t>(left), static_cast<std::int64_t>(pairs));
  j["right_tip_rate"] = fraction_or_null(static_cast<std::int64_t>(right), static_cast<std::int64_t>(pairs));
  j["control_pairs"] = controls;
  j["control_rate"] = fraction_or_null(static_cast<std::int64_t>(control_hits), static_cast<std::int64_t>(controls));
  j["control_rate_interval"] = {number_or_null(rest_rate.first), number_or_null(rest_rate.second)};
  std::string verdict = "undetermined", why;
  if (controls == 0) {
    why = "no pair shows the region at rest's lower corners (the control discs): nothing to compare the tips with";
  } else if (tip.first > rest_rate.second) {
    verdict = "holds";
    why = "vortices at the tips more often than in the bed at rest (the tips' 95 % interval above the control's)";
  } else if (tip.second <= rest_rate.second) {
    verdict = "fails";
    why = "the tips show vortices no more often than the bed at rest allows";
  } else {
    why = "the tips' and the control's intervals overlap: more pairs";
  }
  j["verdict"] = verdict;
  j["why"] = why;
  j["sensitivity"] = sens;
  return j;
}

// The valid pairs of the run's snapshots (every c.every-th), measured on `threads`, in snapshot order.
struct Pairs {
  std::vector<PairMeasure> ms;
  std::vector<std::size_t> ks;  // their snapshots (frame B)
  std::size_t skipped = 0;
  std::string skipped_why;      // the first skipped pair's reason
  std::map<std::string, std::size_t> why_count;  // every reason a pair was skipped for, how often
};
Pairs measure_pairs(const SnapshotSource& run, const PairSetup& su, const PivConfig& c, int threads,
                    const std::string& settings) {
  const std::vector<std::size_t> ks = every_kth(run.snapshots(), static_cast<std::size_t>(c.every));
  // the maps (and frames) among the snapshots whose frame A lies within the run
  std::vector<std::size_t> later;
  const std::vector<double>& times = run.snapshot_times();
  for (std::size_t k : ks)
    if (su.gap > 0 ? k >= su.gap : times[k] >= times.front() + su.interval) later.push_back(k);
  const std::vector<std::size_t> map_ks = spread_over(later, static_cast<std::size_t>(c.maps));
  // frames A from earlier snapshots: their grains' positions (NaN where not active), read first
  std::vector<std::vector<Vec2>> earlier(su.gap > 0 ? ks.size() : 0);
  for (std::size_t q = 0; q < earlier.size(); ++q) {
    if (ks[q] < su.gap) continue;
    const Snapshot e = run.snapshot(ks[q] - su.gap);
    earlier[q].assign(e.size(), {kNaN, kNaN});
    for (std::size_t g = 0; g < e.size(); ++g)
      if (e.active[g]) earlier[q][g] = e.position[g];
  }

  Pairs p;
  for_each_snapshot(
      run, ks, threads,
      [&](std::size_t k, const Snapshot& s, const std::vector<Vec2>& window_disp) {
        const auto at = std::lower_bound(map_ks.begin(), map_ks.end(), k);
        const bool keep = at != map_ks.end() && *at == k;
        const bool frames = keep && static_cast<std::int64_t>(at - map_ks.begin()) < c.png_frames;
        if (su.gap == 0) return measure_pair(su, s, window_disp, su.interval, static_cast<unsigned>(k), keep, frames);
        const std::vector<Vec2>& e = earlier[static_cast<std::size_t>(std::lower_bound(ks.begin(), ks.end(), k) - ks.begin())];
        std::vector<Vec2> disp;  // empty: frame A before the run's start
        if (!e.empty()) {
          disp.resize(s.size());
          for (std::size_t g = 0; g < s.size(); ++g) disp[g] = {s.position[g].x - e[g].x, s.position[g].y - e[g].y};
        }
        const double interval = k >= su.gap ? times[k] - times[k - su.gap] : su.interval;
        if (std::abs(interval - su.interval) > 0.01 * su.interval) {  // a snapshot off the run's spacing (the last one)
          PairMeasure off;
          off.why = "frame A, " + std::to_string(su.gap) + " snapshot(s) earlier, is " + format_number(interval) +
                    " s earlier, not the frame interval " + format_number(su.interval) + " s";
          return off;
        }
        return measure_pair(su, s, disp, interval, static_cast<unsigned>(k), keep, frames);
      },
      [&](std::size_t k, PairMeasure&& m) {
        if (!m.valid) {
          if (p.skipped++ == 0) p.skipped_why = "snapshot " + std::to_string(k) + ": " + m.why;
          ++p.why_count[m.why];
          return;
        }
        p.ks.push_back(k);
        p.ms.push_back(std::move(m));
      });
  if (p.ms.empty()) {  // (the settings decide as much as the run: both named, and every reason with its count)
    std::string why;
    for (const auto& [reason, n] : p.why_count) why += (why.empty() ? "" : "; ") + std::to_string(n) + " x " + reason;
    throw StageError(settings + " with " + run.path() + ": no snapshot gives a frame pair with PIV vectors (" +
                     (why.empty() ? std::string("none measured") : std::to_string(p.skipped) + " skipped: " + why) + ")");
  }
  return p;

}

// H_c: why PIV cannot give it here (the view above the intruder against where a cone at the PIV's beta
// meets the walls)
json wall_mobility(const PivConfig& c, const PairSetup& su, const std::vector<PairMeasure>& ms) {
  const double view = 0.5 * static_cast<double>(c.camera.height) / su.scale;  // the view above the intruder's centre (m)
  const double beta = stats(column_of(ms, [](const PairMeasure& m) { return m.side[kPivSide].beta; })).mean;
  const double half_gap = 0.5 * (su.cell.right - su.cell.left - ms.front().in.length());
  const double meet = half_gap * std::tan(beta * std::numbers::pi / 180.0);  // the cone at beta meets the walls this far above
  return {
      {"measured", false},
      {"view_above_intruder_mm", view * kMm},
      {"cone_meets_walls_above_intruder_mm", number_or_null(meet * kMm)},
      {"why", "not from PIV: the region of interest leaves the walls' faces and " + format_number(c.wall_margin_d) +
                  " d inside them out (as the paper's), and the camera follows the intruder: it sees " +
                  format_number(std::round(view * kMm)) + " mm above the intruder's centre, while a cone at the PIV's "
                  "beta meets the walls " + (std::isfinite(meet) ? format_number(std::round(meet * kMm)) : std::string("?")) +
                  " mm above it (1/2 (L_c - L) tan beta); the cg stage's H_c is quoted under cg_stage"}};
}

// metrics.json's "piv" object
json metrics(const SnapshotSource& run, const PivInput& in, const PairSetup& su, const Pairs& p, int threads,
             std::chrono::steady_clock::time_point t_start) {
  const PivConfig& c = in.config;
  const std::vector<PairMeasure>& ms = p.ms;
  double render_s = 0.0, piv_s = 0.0, cg_s = 0.0, rms = 0.0, rms_frame = 0.0, vectors = 0.0, replaced = 0.0, passes = 0.0;
  for (const PairMeasure& m : ms) {
    render_s += m.render_s, piv_s += m.piv_s, cg_s += m.cg_s;
    rms += m.rms_vstar * m.rms_vstar, rms_frame += m.rms_vstar_frame * m.rms_vstar_frame;
    vectors += static_cast<double>(m.vectors), replaced += static_cast<double>(m.replaced), passes += m.passes;
  }
  const double P = static_cast<double>(ms.size());
  json j;
  j["run_file"] = run.path();
  j["config_file"] = in.config_path;
  j["cg_config_file"] = in.cg_config_path;
  j["pairs"] = ms.size();
  j["pairs_skipped"] = p.skipped;
  if (p.skipped > 0) j["pairs_skipped_first"] = p.skipped_why;
  j["frame_interval_s"] = su.interval;
  j["frame_interval_from"] = su.gap == 0 ? std::string("the run's displacement_window")
                                         : std::to_string(su.gap) + " snapshot interval" + (su.gap > 1 ? "s" : "");
  j["px_per_m"] = su.scale;
  j["px_per_diameter"] = c.camera.px_per_diameter;
  j["vector_spacing_mm"] = ms.front().grid.dx * kMm;
  j["vector_spacing_d"] = ms.front().grid.dx / su.d;
  j["kernel_w_mm"] = su.kernel.w * kMm;
  j["vectors_per_pair"] = vectors / P;
  j["replaced_fraction"] = vectors > 0.0 ? replaced / vectors : kNaN;
  j["passes_per_pair"] = passes / P;
  j["rms_vstar_difference"] = std::sqrt(rms / P);
  j["rms_vstar_difference_intruder_frame"] = std::sqrt(rms_frame / P);
  std::vector<double> medians;
  for (const PairMeasure& m : ms) medians.push_back(m.median_vstar);
  std::nth_element(medians.begin(), medians.begin() + static_cast<long>(medians.size() / 2), medians.end());
  j["median_abs_vstar_difference"] = medians[medians.size() / 2];
  j["rms_note"] = "rms over the pairs of each pair's rms of v*_PIV - v*_CG over the nodes both have; v* = |v| / V "
                  "(lab frame) and |v - V| / V (intruder frame, the paper's Fig. 10); median_abs: the median over the pairs of each "
                  "pair's median |v*_PIV - v*_CG| (lab frame): the typical node, where the rms is led by the few fast ones";
  j["cone_angle_deg"] = compare(ms, [](const Side& s) { return s.beta; }, 1.0, "deg");
  j["zone_area_immobile_mm2"] = compare(ms, [](const Side& s) { return s.zones.immobile; }, kMm * kMm, "mm^2");
  j["zone_area_cone_mm2"] = compare(ms, [](const Side& s) { return s.zones.cone; }, kMm * kMm, "mm^2");
  j["zone_area_dragged_mm2"] = compare(ms, [](const Side& s) { return s.zones.dragged; }, kMm * kMm, "mm^2");
  j["compare_note"] = "every pair's PIV field and the coarse-grained field of the grains' displacements over the same "
                      "window (the cg stage's kernel), on the PIV's vector grid and the nodes both have; the cone at the "
                      "cg stage's cone.level (not its noise-calibrated level), edges narrowing upwards left out; "
                      "difference: PIV - CG paired by pair; intervals: 95 % t over pairs (pairs of one run are not "
                      "independent: a lower bound on the uncertainty)";
  j["wall_mobility"] = wall_mobility(c, su, ms);
  j["vortices"] = {{"piv", vortices(ms, c, kPivSide)}, {"cg", vortices(ms, c, kCgSide)}};
  if (!in.cg_metrics_path.empty()) {
    const nlohmann::json all = read_json(in.cg_metrics_path, "--cg-metrics");
    if (!all.contains("cg") || !all["cg"].is_object())
      throw StageError(in.cg_metrics_path + ": not the cg stage's metrics.json (no object \"cg\")");
    const nlohmann::json& cg = all["cg"];
    j["cg_stage"] = {{"cone_angle_deg", cg.value("cone_angle_deg", json())},
                     {"cone_angle_all_snapshots_deg", cg.value("cone_angle_all_snapshots_deg", json())},
                     {"wall_mobility_length_mm", cg.value("wall_mobility_length_mm", json())},
                     {"metrics_file", in.cg_metrics_path}};
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  j["cost"] = {{"seconds", wall}, {"threads", threads}, {"render_seconds_per_pair", render_s / P},
               {"piv_seconds_per_pair", piv_s / P}, {"cg_seconds_per_pair", cg_s / P}};
  j["config"] = to_json(c);

  return j;
}

// metrics.json, piv.h5 and the kept frames
PivResult outputs(const SnapshotSource& run, const PairSetup& su, const Pairs& pairs, json j) {
  const std::vector<PairMeasure>& ms = pairs.ms;
  const std::vector<std::size_t>& valid_ks = pairs.ks;
  PivResult r;
  r.metrics = {{"piv", std::move(j)}};
  H5Output& h = r.h5;
  h = H5Output("piv", run.path());
  h.note("cell_left", su.cell.left), h.note("cell_right", su.cell.right), h.note("cell_floor", su.cell.floor);
  h.note("mean_diameter", su.d), h.note("v_ref", su.v_ref);
  std::vector<std::int64_t> snap(valid_ks.begin(), valid_ks.end());
  h.add("pairs/snapshot", snap, "-", "snapshot index in the run file (frame B)");
  const auto col = [&](auto get) { return column_of(ms, get); };
  h.add("pairs/time", col([](const PairMeasure& m) { return m.time; }), "s", "frame B's time");
  h.add("pairs/intruder_height", col([](const PairMeasure& m) { return m.height; }), "m", "the intruder's centre above the floor");
  h.add("pairs/surface_height", col([](const PairMeasure& m) { return m.surface; }), "m", "the highest grain top above the floor");
  h.add("pairs/vectors", col([](const PairMeasure& m) { return static_cast<double>(m.vectors); }), "-", "PIV vectors in the region of interest");
  h.add("pairs/replaced", col([](const PairMeasure& m) { return static_cast<double>(m.replaced); }), "-", "of them replaced by the median test");
  h.add("pairs/rms_vstar_difference", col([](const PairMeasure& m) { return m.rms_vstar; }), "-", "rms of v*_PIV - v*_CG (lab frame)");
  h.add("pairs/median_abs_vstar_difference", col([](const PairMeasure& m) { return m.median_vstar; }), "-",
        "median |v*_PIV - v*_CG| (lab frame)");
  h.add("pairs/rms_vstar_difference_intruder_frame", col([](const PairMeasure& m) { return m.rms_vstar_frame; }), "-",
        "rms of |v - V|/V, PIV - CG");
  for (std::size_t k = 0; k < 2; ++k) {
    const std::string p = std::string("pairs/") + kSideName[k] + "/";
    h.add(p + "beta", col([k](const PairMeasure& m) { return m.side[k].beta; }), "deg", "the cone's angle (NaN: none)");
    h.add(p + "beta_left", col([k](const PairMeasure& m) { return m.side[k].cone.left.beta_deg; }), "deg", "its left edge");
    h.add(p + "beta_right", col([k](const PairMeasure& m) { return m.side[k].cone.right.beta_deg; }), "deg", "its right edge");
    h.add(p + "area_immobile", col([k](const PairMeasure& m) { return m.side[k].zones.immobile; }), "m^2", "v* < zones.immobile_below");
    h.add(p + "area_cone", col([k](const PairMeasure& m) { return m.side[k].zones.cone; }), "m^2", "between");
    h.add(p + "area_dragged", col([k](const PairMeasure& m) { return m.side[k].zones.dragged; }), "m^2", "v* > zones.dragged_above");
    h.add(p + "tip_swirl_max", col([k](const PairMeasure& m) {
            float x = 0.0f;
            for (const auto& d : m.side[k].tip_swirl) for (float v : d) x = std::max(x, v);
            return static_cast<double>(x);
          }), "V/d", "the largest lambda_ci in the tips' discs");
  }
  // the maps of the kept pairs: every pair has the same vector grid in the camera's frame
  std::vector<std::int64_t> mk;
  std::vector<double> x0, y0, in_l, in_r, in_t, in_c;
  std::vector<float> maps[2][2];  // [side][vstar, swirl]
  const Grid& g0 = ms.front().grid;
  for (std::size_t q = 0; q < ms.size(); ++q) {
    const PairMeasure& m = ms[q];
    if (m.side[0].vstar_frame.empty()) continue;
    mk.push_back(static_cast<std::int64_t>(valid_ks[q]));
    x0.push_back(m.grid.x0), y0.push_back(m.grid.y0);
    in_l.push_back(m.in.left), in_r.push_back(m.in.right), in_t.push_back(m.in.top), in_c.push_back(m.in.yc);
    for (std::size_t k = 0; k < 2; ++k) {
      maps[k][0].insert(maps[k][0].end(), m.side[k].vstar_frame.begin(), m.side[k].vstar_frame.end());
      maps[k][1].insert(maps[k][1].end(), m.side[k].swirl.begin(), m.side[k].swirl.end());
    }
    if (m.a) {
      const std::string name = "frame_" + std::to_string(valid_ks[q]);
      r.frames.emplace_back(name + "_a.png", *m.a);
      r.frames.emplace_back(name + "_b.png", *m.b);
    }
  }
  const std::size_t M = mk.size();
  h.add("maps/snapshot", mk, "-", "snapshots of the maps");
  h.add("maps/x0", x0, "m", "the vector grid's first column (lab frame)");
  h.add("maps/y0", y0, "m", "its first (lowest) row");
  h.note("maps_dx", g0.dx), h.note("maps_nx", static_cast<std::int64_t>(g0.nx)), h.note("maps_ny", static_cast<std::int64_t>(g0.ny));
  h.add("maps/intruder_left", in_l, "m", "the intruder's left tip x");
  h.add("maps/intruder_right", in_r, "m", "its right tip x");
  h.add("maps/intruder_top", in_t, "m", "its top face y");
  h.add("maps/intruder_centre", in_c, "m", "its centre y");
  for (std::size_t k = 0; k < 2; ++k) {
    h.add(std::string("maps/vstar_") + kSideName[k], maps[k][0], "-",
          std::string("|v - V| / V in the intruder's frame, ") + (k == 0 ? "PIV" : "coarse-grained") + " (NaN: not both)",
          {M, g0.ny, g0.nx});
    h.add(std::string("maps/swirl_") + kSideName[k], maps[k][1], "V/d", "lambda_ci, the swirl strength", {M, g0.ny, g0.nx});
  }
  return r;
}

}  // namespace

PivResult run_piv(const SnapshotSource& run, const PivInput& in) {
  const auto t_start = std::chrono::steady_clock::now();
  const PivConfig& c = in.config;
  const std::size_t S = run.snapshots();
  if (S == 0) throw StageError(run.path() + ": the run file has no snapshots");
  const Snapshot s0 = run.snapshot(0);
  PairSetup su;
  try {
    su = setup(run, s0, in);
  } catch (const StageError& e) {
    const std::string msg = e.what();
    if (msg.rfind(run.path(), 0) == 0 || msg.rfind(in.config_path, 0) == 0 || msg.rfind(in.cg_config_path, 0) == 0) throw;
    throw StageError(in.config_path + " with " + run.path() + ": " + msg);
  }
  const int threads = in.threads > 0 ? in.threads : omp_get_max_threads();
  const Pairs p = measure_pairs(run, su, c, threads, in.config_path);
  return outputs(run, su, p, metrics(run, in, su, p, threads, t_start));
}

PivResult run_piv(const PivInput& in) {
  const RunFileSource source(in.run_path);
  return run_piv(source, in);
}

void write_png(const Image& im, const std::string& path) {
  const int W = static_cast<int>(im.width), H = static_cast<int>(im.height);
  cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
  unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  cairo_surface_flush(s);
  for (int j = 0; j < H; ++j) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::size_t>(j) * stride);
    for (int i = 0; i < W; ++i) {
      const auto v = static_cast<std::uint32_t>(std::lround(std::clamp(im.at(i, j), 0.0f, 1.0f) * 255.0f));
      row[i] = (v << 16) | (v << 8) | v;
    }
  }
  cairo_surface_mark_dirty(s);
  const std::string tmp = path + ".tmp";
  const cairo_status_t st = cairo_surface_write_to_png(s, tmp.c_str());
  cairo_surface_destroy(s);
  if (st != CAIRO_STATUS_SUCCESS) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot write the PNG (" + cairo_status_to_string(st) + ")");
  }
  std::filesystem::rename(tmp, path);
}

void write_piv(const PivResult& r, const std::string& out_dir) {
  if (!r.frames.empty()) {
    std::filesystem::create_directories(out_dir + "/frames");
    for (const auto& [name, im] : r.frames) write_png(im, out_dir + "/frames/" + name);
  }
  r.h5.write(out_dir + "/piv.h5");
  write_file_atomic(out_dir + "/metrics.json", r.metrics.dump(2) + "\n");
}

}  // namespace dem2d::analysis
