// The drag of a cyclic run (an intruder driven up and down through the bed,
// pipeline/cyclic.toml) cut into legs: each leg a stretch of rows over which
// the intruder keeps moving the same way (up: +1, down: -1; rows where it
// holds still belong to no leg), each cycle an upward leg and the downward
// leg after it. Drag as in drag_profile.hpp: -F_y, > 0 when the grains push
// the intruder down (resisting an upward pull; helping a downward push).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "frame/drag_profile.hpp"

namespace dem2d::analysis {

struct DragLeg {
  int cycle;            // 0, 1, ...: a cycle starts with each upward leg
  int direction;        // +1 up, -1 down
  std::size_t begin;    // first row
  std::size_t end;      // one past the last row
};

// Legs of the profile: row k belongs to the leg of the way the intruder
// moved since row k-1; rows after a hold (a height change below `still` m)
// belong to no leg.
std::vector<DragLeg> drag_legs(const DragProfile& p, double still = 1e-12);

// cycles.* metrics: the number of cycles and, per leg, its height range (mm)
// and the drag's largest, smallest and mean value over it (N/m).
nlohmann::ordered_json cycle_metrics(const DragProfile& p, const std::vector<DragLeg>& legs);

// cycle,direction,time_s,height_mm,drag_N_per_m: the rows of every leg.
std::string cycles_csv(const DragProfile& p, const std::vector<DragLeg>& legs);

}  // namespace dem2d::analysis
