#include "pulloff/pulloff_metrics.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "runfile/h5.hpp"

namespace dem2d::analysis {

double static_load(const RunReader& bed) {
  const std::size_t b = bed.body_with_role("intruder");
  const std::size_t nb = bed.bodies();
  if (bed.series_rows() == 0 || nb == 0)
    throw std::runtime_error(bed.path() + ": the run has no time series to take the intruder's load at rest from");
  const auto force = bed.series("body_force_mean");  // [T, B, 2]
  return -force[force.size() - 2 * nb + 2 * b + 1];
}

nlohmann::ordered_json pulloff_metrics(const RunReader& run, const DragProfile& p, const Study& study,
                                       const RunReader* bed) {
  const h5::File& f = run.file();
  const auto max_it = std::max_element(p.drag.begin(), p.drag.end());
  const auto k_max = static_cast<std::size_t>(max_it - p.drag.begin());
  const auto overlap = run.series("max_overlap");
  const auto& diameter = run.diameters();
  if (diameter.empty()) throw std::runtime_error(run.path() + ": the run has no grains");
  double d_mean = 0.0;
  for (const double d : diameter) d_mean += d / static_cast<double>(diameter.size());
  // (run files written before wall_seconds existed report no cost)
  const double wall = h5::has_attr(f, "/", "wall_seconds") ? h5::read_attr_double(f, "/", "wall_seconds") : 0.0;
  const auto steps = h5::read_attr_int(f, "/", "steps");
  const double particle_steps = static_cast<double>(steps) * static_cast<double>(run.particles());
  return {{"pulloff",
           {{"run_file", run.path()},
            {"stop_reason", h5::read_attr_string(f, "/", "stop_reason")},
            {"start_height_mm", 1e3 * p.height.front()},
            {"end_height_mm", 1e3 * p.height.back()},
            {"travel_mm", 1e3 * (p.height.back() - p.height.front())},
            {"duration_s", p.time.back() - p.time.front()},
            {"series_rows", p.time.size()},
            {"drag_max_N_per_m", *max_it},
            {"drag_max_N", *max_it * study.intruder_depth},
            {"height_at_drag_max_mm", 1e3 * p.height[k_max]},
            {"drag_static_N_per_m", bed ? nlohmann::ordered_json(static_load(*bed)) : nullptr},
            {"drag_static_from", bed ? bed->path() : ""},
            {"drag_start_N_per_m", p.drag.front()},  // the first row: the intruder already moving
            {"drag_final_N_per_m", p.drag.back()},
            {"max_overlap_over_d", *std::max_element(overlap.begin(), overlap.end()) / d_mean},
            {"particles", run.particles()},
            {"lost_particles", h5::read_attr_int(f, "/", "lost_particles")},
            {"steps", steps},
            {"wall_seconds", wall},
            {"ns_per_particle_step", particle_steps > 0 && wall > 0 ? wall * 1e9 / particle_steps : 0.0},
            {"intruder_depth_W_m", study.intruder_depth}}}};
}

std::string drag_csv(const DragProfile& p, const Study& study) {
  std::string out = "time_s,height_mm,drag_N_per_m,drag_N\n";
  char line[160];
  for (std::size_t k = 0; k < p.time.size(); ++k) {
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g\n", p.time[k], 1e3 * p.height[k], p.drag[k],
                  p.drag[k] * study.intruder_depth);
    out += line;
  }
  return out;
}

}  // namespace dem2d::analysis
