// The drag on the intruder along the pull-off, from a run file's /series.
// Drag = -F_y: the vertical force of the grains on the intruder, per unit
// depth (N/m), positive when it resists the upward pull; the mean over each
// series interval (/series/body_force_mean: anti-aliased, not a sample).
// Height = the intruder's centre above the floor's top face (docs/paper.md: heights
// from the cell floor to the intruder's centre).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "frame/study.hpp"
#include "io/run_reader.hpp"

namespace dem2d::analysis {

struct DragProfile {
  std::vector<double> time;    // s
  std::vector<double> height;  // m
  std::vector<double> drag;    // N/m
};

// Throws std::runtime_error naming the file if the run has no series or lacks the bodies.
DragProfile read_drag_profile(const RunReader& run);

// The bed's load on the intruder at rest, before the pull (N/m): -F_y of the
// intruder in the last series row of the run the pull-off started from (the
// fill, which ends at rest), as a mean over that row's interval. The pull-off's
// own first row is not it: the intruder moves from t = 0 and the dashpots
// add c V (+1 % on the study's bed).
double static_load(const RunReader& bed);

// Summary of the pull-off (pulloff.* metrics, lengths in mm, forces in N/m
// and, x W, in N) and the run's cost. `bed`: the run the pull-off started
// from, for the static load (none: drag_static_N_per_m is null).
nlohmann::ordered_json pulloff_metrics(const RunReader& run, const DragProfile& profile, const Study& study,
                                       const RunReader* bed = nullptr);

// time_s,height_mm,drag_N_per_m,drag_N
std::string drag_csv(const DragProfile& profile, const Study& study);

}  // namespace dem2d::analysis
