#include "spectrum/spectrum_stage.hpp"


#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include "common/output.hpp"
#include "common/events.hpp"
#include "io/h5.hpp"
#include "io/run_parameters.hpp"
#include "io/run_reader.hpp"
#include "pulloff/drag_profile.hpp"

namespace dem2d::analysis {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw SpectrumError(path + ": " + what); }

// Height at which the intruder left the bed by the run's own stop criterion
// ([stop] body_free: no grain touching it connects to the walls, for
// free_time seconds): the height at end_time - free_time. NaN if the run
// did not stop that way.
double exit_height(const RunReader& run, const DragProfile& p) {
  const h5::File& f = run.file();
  if (run.stopped_by() != "body_free") return kNaN;
  const double free_time = run.parameters().stop.free_time;
  const double t = h5::read_attr_double(f, "/", "end_time") - free_time;
  if (!(t >= p.time.front() && t <= p.time.back())) return kNaN;
  const auto k = static_cast<std::size_t>(std::lower_bound(p.time.begin(), p.time.end(), t) - p.time.begin());
  if (k == 0) return p.height.front();
  const double a = (t - p.time[k - 1]) / (p.time[k] - p.time[k - 1]);
  return p.height[k - 1] + a * (p.height[k] - p.height[k - 1]);
}

double fill_bed_height(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "no such file (--fill-metrics)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("not a JSON file: ") + e.what());
  }
  const auto* v = j.contains("fill") ? &j["fill"] : nullptr;
  if (!v || !v->contains("bed_height_mm") || !(*v)["bed_height_mm"].is_number())
    fail(path, "no number fill.bed_height_mm (the fill stage's metrics, bed_metrics)");
  return 1e-3 * (*v)["bed_height_mm"].get<double>();
}

void put(const h5::File& f, const std::string& name, const std::vector<double>& v, const char* unit) {
  h5::write(f, name, v);
  h5::write_attr(f, name, "unit", std::string(unit));
}

// A spectrum's peak as attributes of its group (travel or time spectrum alike).
void write_peak(const h5::File& f, const std::string& group, const Psd& psd, const DominantPeak& k) {
  h5::write_attr(f, group, "dof", psd.dof);
  h5::write_attr(f, group, "peak_to_background", k.peak_to_background);
  h5::write_attr(f, group, "significance_threshold", k.threshold);
  h5::write_attr(f, group, "significant", static_cast<std::int64_t>(k.significant));
}

void write_psd(const h5::File& f, const std::string& group, const Band& b, const SpectrumScales& s, double speed) {
  std::vector<double> wavelength, f_paper, f_run;
  for (const double k : b.psd.frequency) {
    wavelength.push_back(1.0 / k);
    f_paper.push_back(k * s.paper_speed / s.d);
    f_run.push_back(k * speed / s.d);
  }
  put(f, group + "/wavenumber_per_d", b.psd.frequency, "cycles per d of travel");
  put(f, group + "/wavelength_d", wavelength, "d of travel");
  put(f, group + "/frequency_hz_at_paper_v", f_paper, "Hz");
  put(f, group + "/frequency_hz_at_run_v", f_run, "Hz");
  put(f, group + "/power", b.psd.power, "(N/m)^2 per (cycle per d)");
  h5::write_attr(f, group, "low_m", b.low);
  h5::write_attr(f, group, "high_m", b.high);
  h5::write_attr(f, group, "segments", static_cast<std::int64_t>(b.psd.segments));
  h5::write_attr(f, group, "dominant_period_d", b.peak.period);
  write_peak(f, group, b.psd, b.peak);
}

void write_h5(const h5::File& f, const SpectrumStage& st) {
  const SpectrumResult& r = st.result;
  const DragProfile& p = r.profile;
  h5::write_attr(f, "/", "format", std::string("dem2d-spectrum-1"));
  h5::write_attr(f, "/", "run_file", st.metrics["spectrum"]["run_file"].get<std::string>());
  h5::write_attr(f, "/", "bed_height_m", st.scales.bed_height);
  h5::write_attr(f, "/", "mean_diameter_m", st.scales.d);
  put(f, "profile/time", p.time, "s");
  put(f, "profile/height", p.height, "m");
  put(f, "profile/drag", p.drag, "N/m");
  put(f, "profile/trend", r.trend, "N/m");
  put(f, "profile/fluctuation", r.fluctuation, "N/m");
  put(f, "profile/envelope", r.envelope, "N/m");
  put(f, "profile/local_noise", r.local_noise, "N/m");
  write_psd(f, "psd", r.second_part, st.scales, r.speed);
  h5::write_attr(f, "psd", "search_min_period_d", r.min_period_d);  // the bands' search too
  for (const Band& b : r.bands) write_psd(f, "psd/bands/" + b.name, b, st.scales, r.speed);
  // /ringing: the second part's spectrum against time frequency and its peak
  put(f, "ringing/frequency_hz", r.ringing.psd.frequency, "Hz");
  put(f, "ringing/power", r.ringing.psd.power, "(N/m)^2 per Hz");
  h5::write_attr(f, "ringing", "nyquist_hz", r.ringing.nyquist);
  h5::write_attr(f, "ringing", "searched", static_cast<std::int64_t>(r.ringing.searched));
  h5::write_attr(f, "ringing", "frequency_hz", r.ringing.peak.frequency);
  write_peak(f, "ringing", r.ringing.psd, r.ringing.peak);
  h5::write_attr(f, "ringing", "line_rms_N_per_m", r.ringing.line_rms);
  h5::write_attr(f, "ringing", "geometric_cutoff_hz", r.geometric_cutoff);
  // /events: the events file's one schema (common/events.hpp), read by cg and network
  std::vector<RuptureEvent> events;
  for (const Event& e : r.events)
    events.push_back({p.time[e.load_start], p.height[e.load_start], p.time[e.peak], p.height[e.peak], p.drag[e.peak],
                      p.time[e.drop_end], p.height[e.drop_end], p.drag[e.peak] - p.drag[e.drop_end]});
  write_events(f, events);
  h5::write_attr(f, "events", "drop_delta_N_per_m", r.drop_delta);
  // the rupture catalogue's further columns (extras of the events schema)
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
  put(f, "events/drop_duration", drop_duration, "s");
  put(f, "events/loading_rise", rise, "N/m");
  put(f, "events/loading_stiffness", stiffness, "N/m per mm of travel");
  put(f, "events/load", r.event_load, "N/m");
  put(f, "events/relative_drop", relative, "1");
  put(f, "events/counted", counted, "1");
  h5::write_attr(f, "events", "rupture_rule", st.metrics["spectrum"]["rupture_rule"].get<std::string>());
  // /top_layer: drag against depth and its linear fit
  std::vector<double> depth, height, drag, fit;
  for (std::size_t k = r.top_begin; k < r.top_end; ++k) {
    height.push_back(p.height[k]);
    depth.push_back(st.scales.bed_height - p.height[k]);
    drag.push_back(p.drag[k]);
    fit.push_back(r.top_fit.intercept + r.top_fit.slope * 1e3 * depth.back());
  }
  put(f, "top_layer/depth", depth, "m");
  put(f, "top_layer/height", height, "m");
  put(f, "top_layer/drag", drag, "N/m");
  put(f, "top_layer/fit_drag", fit, "N/m");
  h5::write_attr(f, "top_layer", "top_layer_height_m", r.top_height);
  h5::write_attr(f, "top_layer", "outcome", r.top.outcome);
  h5::write_attr(f, "top_layer", "model", r.top.model);
  h5::write_attr(f, "top_layer", "change_point_m", r.top.best.height);
  h5::write_attr(f, "top_layer", "interval_low_m", r.top.low);
  h5::write_attr(f, "top_layer", "interval_high_m", r.top.high);
  h5::write_attr(f, "top_layer", "envelope_height_m", r.envelope_top_height);
  put(f, "top_layer/block_height", r.top.block_height, "m");
  put(f, "top_layer/block_variance", r.top.block_variance, "(N/m)^2");
  put(f, "top_layer/block_model", r.top.block_model, "(N/m)^2");
  put(f, "top_layer/block_load", r.top.block_load, "N/m");
  h5::write_attr(f, "top_layer", "slope_N_per_m_per_mm", r.top_fit.slope);
  h5::write_attr(f, "top_layer", "intercept_N_per_m", r.top_fit.intercept);
  h5::write_attr(f, "top_layer", "r2", r.top_fit.r2);
}

}  // namespace

SpectrumStage compute_spectrum_stage(const SpectrumInputs& in, const SpectrumConfig& config, const Study& study) {
  const RunReader run(in.run);
  const DragProfile profile = read_drag_profile(run);
  const auto& diameter = run.diameters();
  if (diameter.empty()) fail(in.run, "the run has no particles");
  const double body_speed = run.body_velocities()[run.body_with_role("intruder")].y;

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
  try {
    st.result = analyse(profile, st.scales, config, in.run);
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
  m["sensitivity"] = sensitivity_table(profile, st.scales, config, in.run);
  st.metrics = {{"spectrum", m}};
  return st;
}

void write_spectrum_outputs(const std::string& dir, const SpectrumStage& stage) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string h5_path = (fs::path(dir) / "spectrum.h5").string();
  try {
    h5::write_atomically(h5_path, [&](const h5::File& f) { write_h5(f, stage); });
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(e.what()) + " (cannot write " + h5_path + ")");
  }
  write_file_atomic((fs::path(dir) / "metrics.json").string(), stage.metrics.dump(2) + "\n");
}

}  // namespace dem2d::analysis
