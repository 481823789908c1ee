#include "spectrum/spectrum_stage.hpp"


#include <algorithm>
#include <filesystem>
#include <numeric>
#include <stdexcept>

#include "common/events.hpp"
#include "common/json_input.hpp"
#include "common/output.hpp"
#include "common/stage_output.hpp"
#include "frame/drag_profile.hpp"
#include "frame/intruder.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_parameters.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw SpectrumError(path + ": " + what); }

// Height at which the intruder left the bed by the run's own stop criterion
// ([stop] body_free: no grain touching it connects to the walls, for
// free_time seconds): the height at end_time - free_time. NaN if the run
// did not stop that way.
double exit_height(const RunReader& run, const DragProfile& p) {
  if (run.stopped_by() != "body_free") return kNaN;
  const double free_time = run.parameters().stop.free_time;
  const double t = run.end_time() - free_time;
  if (!(t >= p.time.front() && t <= p.time.back())) return kNaN;
  const auto k = static_cast<std::size_t>(std::lower_bound(p.time.begin(), p.time.end(), t) - p.time.begin());
  if (k == 0) return p.height.front();
  const double a = (t - p.time[k - 1]) / (p.time[k] - p.time[k - 1]);
  return p.height[k - 1] + a * (p.height[k] - p.height[k - 1]);
}

double fill_bed_height(const std::string& path) {
  const nlohmann::json j = read_json(path, "--fill-metrics");
  const auto* v = j.contains("fill") ? &j["fill"] : nullptr;
  if (!v || !v->contains("bed_height_mm") || !(*v)["bed_height_mm"].is_number())
    fail(path, "no number fill.bed_height_mm (the fill stage's metrics, bed_metrics)");
  return 1e-3 * (*v)["bed_height_mm"].get<double>();
}

using I64 = std::int64_t;

// A spectrum's peak as attributes of its group (travel or time spectrum alike).
void add_peak(H5Output& h, const std::string& group, const Psd& psd, const DominantPeak& k) {
  h.attr(group, "dof", psd.dof);
  h.attr(group, "peak_to_background", k.peak_to_background);
  h.attr(group, "significance_threshold", k.threshold);
  h.attr(group, "significant", static_cast<I64>(k.significant));
}

void add_psd(H5Output& h, const std::string& group, const Band& b, const SpectrumScales& s, double speed) {
  std::vector<double> wavelength, f_paper, f_run;
  for (const double k : b.psd.frequency) {
    wavelength.push_back(1.0 / k);
    f_paper.push_back(k * s.paper_speed / s.d);
    f_run.push_back(k * speed / s.d);
  }
  h.add(group + "/wavenumber_per_d", b.psd.frequency, "cycles per d of travel", "travel wavenumber of each bin");
  h.add(group + "/wavelength_d", std::move(wavelength), "d of travel", "1 / wavenumber");
  h.add(group + "/frequency_hz_at_paper_v", std::move(f_paper), "Hz", "the wavenumber at the paper's pull speed");
  h.add(group + "/frequency_hz_at_run_v", std::move(f_run), "Hz", "the wavenumber at the run's pull speed");
  h.add(group + "/power", b.psd.power, "(N/m)^2 per (cycle per d)", "Welch power spectral density of the fluctuation");
  h.attr(group, "low_m", b.low);
  h.attr(group, "high_m", b.high);
  h.attr(group, "segments", static_cast<I64>(b.psd.segments));
  h.attr(group, "dominant_period_d", b.peak.period);
  add_peak(h, group, b.psd, b.peak);
}

void add_profile(H5Output& h, const SpectrumResult& r) {
  const DragProfile& p = r.profile;
  h.add("profile/time", p.time, "s", "time of each drag sample");
  h.add("profile/height", p.height, "m", "intruder centre above the floor's face");
  h.add("profile/drag", p.drag, "N/m", "drag on the intruder (the pulling force less its weight)");
  h.add("profile/trend", r.trend, "N/m", "the drag's slow trend (removed before the spectra)");
  h.add("profile/fluctuation", r.fluctuation, "N/m", "drag - trend");
  h.add("profile/envelope", r.envelope, "N/m", "running rms of the fluctuation");
  h.add("profile/local_noise", r.local_noise, "N/m", "local noise of the fluctuation from first differences");
}

void add_ringing(H5Output& h, const SpectrumResult& r) {
  h.add("ringing/frequency_hz", r.ringing.psd.frequency, "Hz", "time frequency of each bin");
  h.add("ringing/power", r.ringing.psd.power, "(N/m)^2 per Hz", "power spectral density of the second part's drag");
  h.attr("ringing", "nyquist_hz", r.ringing.nyquist);
  h.attr("ringing", "searched", static_cast<I64>(r.ringing.searched));
  h.attr("ringing", "frequency_hz", r.ringing.peak.frequency);
  add_peak(h, "ringing", r.ringing.psd, r.ringing.peak);
  h.attr("ringing", "line_rms_N_per_m", r.ringing.line_rms);
  h.attr("ringing", "geometric_cutoff_hz", r.geometric_cutoff);
}

// /events: the events file's one schema (common/events.hpp), read by cg and
// network, and the rupture catalogue's further columns.
void add_events(H5Output& h, const SpectrumStage& st) {
  const SpectrumResult& r = st.result;
  const DragProfile& p = r.profile;
  std::vector<RuptureEvent> events;
  for (const Event& e : r.events)
    events.push_back({p.time[e.load_start], p.height[e.load_start], p.time[e.peak], p.height[e.peak], p.drag[e.peak],
                      p.time[e.drop_end], p.height[e.drop_end], p.drag[e.peak] - p.drag[e.drop_end]});
  analysis::add_events(h, events);
  h.attr("events", "drop_delta_N_per_m", r.drop_delta);
  std::vector<double> drop_duration, rise, stiffness, relative, counted;
  for (std::size_t i = 0; i < r.events.size(); ++i) {
    const Event& e = r.events[i];
    drop_duration.push_back(p.time[e.drop_end] - p.time[e.peak]);
    rise.push_back(p.drag[e.peak] - p.drag[e.load_start]);
    const double travel = p.height[e.peak] - p.height[e.load_start];
    stiffness.push_back(travel > 0.0 ? 1e-3 * rise.back() / travel : kNaN);
    relative.push_back(r.event_load[i] > 0.0 ? (p.drag[e.peak] - p.drag[e.drop_end]) / r.event_load[i] : kNaN);
    counted.push_back(r.counted[i]);
  }
  h.add("events/drop_duration", std::move(drop_duration), "s", "drop_end_time - peak_time");
  h.add("events/loading_rise", std::move(rise), "N/m", "peak drag - drag at load_start");
  h.add("events/loading_stiffness", std::move(stiffness), "N/m per mm of travel", "loading_rise over the travel from load_start to the peak");
  h.add("events/load", r.event_load, "N/m", "the drag's trend at the peak");
  h.add("events/relative_drop", std::move(relative), "1", "drop / load");
  h.add("events/counted", std::move(counted), "1", "1 if the rupture rule counts the event (attribute rupture_rule)");
  h.attr("events", "rupture_rule", st.metrics["spectrum"]["rupture_rule"].get<std::string>());
}

// /top_layer: drag against depth and its linear fit, the change-point model's blocks.
void add_top_layer(H5Output& h, const SpectrumStage& st) {
  const SpectrumResult& r = st.result;
  const DragProfile& p = r.profile;
  std::vector<double> depth, height, drag, fit;
  for (std::size_t k = r.top_begin; k < r.top_end; ++k) {
    height.push_back(p.height[k]);
    depth.push_back(st.scales.bed_height - p.height[k]);
    drag.push_back(p.drag[k]);
    fit.push_back(r.top_fit.intercept + r.top_fit.slope * 1e3 * depth.back());
  }
  h.add("top_layer/depth", std::move(depth), "m", "intruder depth below the bed surface");
  h.add("top_layer/height", std::move(height), "m", "intruder centre above the floor's face");
  h.add("top_layer/drag", std::move(drag), "N/m", "drag in the top layer");
  h.add("top_layer/fit_drag", std::move(fit), "N/m", "the linear fit of drag against depth");
  h.add("top_layer/block_height", r.top.block_height, "m", "intruder height at each block's middle");
  h.add("top_layer/block_variance", r.top.block_variance, "(N/m)^2", "fluctuation variance in each block");
  h.add("top_layer/block_model", r.top.block_model, "(N/m)^2", "the change-point model's variance in each block");
  h.add("top_layer/block_load", r.top.block_load, "N/m", "mean drag trend in each block");
  h.attr("top_layer", "top_layer_height_m", r.top_height);
  h.attr("top_layer", "outcome", r.top.outcome);
  h.attr("top_layer", "model", r.top.model);
  h.attr("top_layer", "change_point_m", r.top.best.height);
  h.attr("top_layer", "interval_low_m", r.top.low);
  h.attr("top_layer", "interval_high_m", r.top.high);
  h.attr("top_layer", "envelope_height_m", r.envelope_top_height);
  h.attr("top_layer", "slope_N_per_m_per_mm", r.top_fit.slope);
  h.attr("top_layer", "intercept_N_per_m", r.top_fit.intercept);
  h.attr("top_layer", "r2", r.top_fit.r2);
}

H5Output spectrum_h5(const SpectrumStage& st) {
  const SpectrumResult& r = st.result;
  H5Output h("spectrum", st.metrics["spectrum"]["run_file"].get<std::string>());
  h.note("format", std::string("dem2d-spectrum-2"));
  h.note("bed_height_m", st.scales.bed_height);
  h.note("mean_diameter_m", st.scales.d);
  add_profile(h, r);
  add_psd(h, "psd", r.second_part, st.scales, r.speed);
  h.attr("psd", "search_min_period_d", r.min_period_d);  // the bands' search too
  for (const Band& b : r.bands) add_psd(h, "psd/bands/" + b.name, b, st.scales, r.speed);
  add_ringing(h, r);
  add_events(h, st);
  add_top_layer(h, st);
  return h;
}

}  // namespace

SpectrumStage compute_spectrum_stage(const SpectrumInputs& in, const SpectrumConfig& config, const Study& study) {
  const RunReader run(in.run);
  const DragProfile profile = read_drag_profile(run);
  const auto& diameter = run.diameters();
  if (diameter.empty()) fail(in.run, "the run has no particles");
  const double body_speed = pull_of(run).speed();

  SpectrumStage st;
  st.intruder_depth = study.intruder_depth;
  st.scales.d = std::accumulate(diameter.begin(), diameter.end(), 0.0) / static_cast<double>(diameter.size());
  st.scales.paper_speed = study.pull_speed;
  const double exit = exit_height(run, profile);
  const bool from_fill = !in.fill_metrics.empty();
  st.scales.bed_height = from_fill ? fill_bed_height(in.fill_metrics) : exit;
  if (!(st.scales.bed_height > 0.0))
    fail(in.run, "cannot tell the bed height: the run did not stop on the intruder leaving the bed "
                 "([stop] body_free); give --fill-metrics");
  TopLayerMemo searched;  // the run's analysis and its sensitivity rows share their top-layer searches
  try {
    st.result = analyse(profile, st.scales, config, in.run, &searched);
  } catch (const SpectrumError& e) {  // the run's drag profile against the settings: name both
    throw SpectrumError(std::string(e.what()) + " (settings: " + (in.config.empty() ? "defaults" : in.config) + ")");
  }

  nlohmann::ordered_json m;
  m["run_file"] = in.run;
  m["config_file"] = in.config;
  m["study_file"] = in.study;
  m["fill_metrics_file"] = from_fill ? nlohmann::ordered_json(in.fill_metrics) : nlohmann::ordered_json(nullptr);
  m["bed_height_source"] = from_fill ? "fill metrics: fill.bed_height_mm" : "exit of the intruder (run's stop criterion)";
  m["exit_height_mm"] = 1e3 * exit;
  m["body_speed_mm_s"] = 1e3 * body_speed;
  m.update(spectrum_metrics(st.result, st.scales, config, study.intruder_depth));
  m["sensitivity"] = sensitivity_table(profile, st.scales, config, in.run, &searched);
  st.metrics = {{"spectrum", m}};
  return st;
}

void write_spectrum_outputs(const std::string& dir, const SpectrumStage& stage) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  spectrum_h5(stage).write((fs::path(dir) / "spectrum.h5").string());
  write_file_atomic((fs::path(dir) / "metrics.json").string(), stage.metrics.dump(2) + "\n");
}

}  // namespace dem2d::analysis
