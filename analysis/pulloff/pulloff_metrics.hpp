// The stage `pulloff_metrics`: the pull-off's summary and cost (pulloff.*
// metrics) and its drag against height as CSV, from the drag series
// (frame/drag_profile.hpp: the definitions of drag and height). Lengths in mm,
// forces in N/m and, x W (the intruder's depth, data/study.toml), in N.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "frame/drag_profile.hpp"
#include "frame/study.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

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
