#include "frame/drag_profile.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dem2d::analysis {

DragProfile read_drag_profile(const RunReader& run) {
  const std::size_t b = run.body_with_role("intruder");
  const std::size_t nb = run.bodies();
  DragProfile p;
  p.time = run.series_times();
  if (p.time.empty()) throw std::runtime_error(run.path() + ": the run has no time series (output.series_interval = 0?)");
  const auto force = run.series("body_force_mean");  // [T, B, 2]
  const std::vector<Body> intruder = run.body_rows("series", b), floor = run.body_rows("series", run.body_with_role("floor"));
  for (std::size_t k = 0; k < p.time.size(); ++k) {
    p.height.push_back(intruder[k].centre().y - floor[k].ymax());
    p.drag.push_back(-force[(k * nb + b) * 2 + 1]);
  }
  const auto [low, high] = std::minmax_element(p.height.begin(), p.height.end());
  if (!(*high > *low))
    throw std::runtime_error(run.path() + ": the intruder '" + run.body_names()[b] + "' stays at " +
                             std::to_string(1e3 * *low) + " mm in all " + std::to_string(p.time.size()) +
                             " series rows: not a run that moves it (a fill?); give the pull-off's or the cyclic run's run.h5");
  return p;
}

}  // namespace dem2d::analysis
