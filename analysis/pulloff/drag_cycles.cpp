#include "pulloff/drag_cycles.hpp"

#include <algorithm>
#include <cstdio>

namespace dem2d::analysis {

std::vector<DragLeg> drag_legs(const DragProfile& p, double still) {
  std::vector<DragLeg> legs;
  int cycle = -1;
  for (std::size_t k = 1; k < p.height.size(); ++k) {
    const double dh = p.height[k] - p.height[k - 1];
    const int dir = dh > still ? 1 : dh < -still ? -1 : 0;
    if (dir == 0) continue;
    // row k closes the interval over which the intruder moved `dir`
    if (legs.empty() || legs.back().direction != dir || legs.back().end != k) {
      if (dir == 1 || cycle < 0) ++cycle;  // a cycle starts going up (or with whatever comes first)
      legs.push_back({cycle, dir, k, k + 1});
    } else {
      legs.back().end = k + 1;
    }
  }
  return legs;
}

nlohmann::ordered_json cycle_metrics(const DragProfile& p, const std::vector<DragLeg>& legs) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const DragLeg& l : legs) {
    const auto first = p.drag.begin() + static_cast<std::ptrdiff_t>(l.begin);
    const auto last = p.drag.begin() + static_cast<std::ptrdiff_t>(l.end);
    double mean = 0.0;
    for (auto it = first; it != last; ++it) mean += *it / static_cast<double>(l.end - l.begin);
    const auto [lo, hi] = std::minmax_element(first, last);
    rows.push_back({{"cycle", l.cycle},
                    {"direction", l.direction > 0 ? "up" : "down"},
                    {"rows", l.end - l.begin},
                    {"height_from_mm", 1e3 * p.height[l.begin - 1]},
                    {"height_to_mm", 1e3 * p.height[l.end - 1]},
                    {"drag_max_N_per_m", *hi},
                    {"drag_min_N_per_m", *lo},
                    {"drag_mean_N_per_m", mean}});
  }
  return {{"cycles", legs.empty() ? 0 : legs.back().cycle + 1}, {"legs", rows}};
}

std::string cycles_csv(const DragProfile& p, const std::vector<DragLeg>& legs) {
  std::string out = "cycle,direction,time_s,height_mm,drag_N_per_m\n";
  char line[160];
  for (const DragLeg& l : legs)
    for (std::size_t k = l.begin; k < l.end; ++k) {
      std::snprintf(line, sizeof line, "%d,%s,%.9g,%.9g,%.9g\n", l.cycle, l.direction > 0 ? "up" : "down",
                    p.time[k], 1e3 * p.height[k], p.drag[k]);
      out += line;
    }
  return out;
}

}  // namespace dem2d::analysis
