// The drag on the intruder along the pull-off, from a run file's /series.
// Drag = -F_y: the vertical force of the grains on the intruder, per unit
// depth (N/m), positive when it resists the upward pull; the mean over each
// series interval (/series/body_force_mean: anti-aliased, not a sample).
// Height = the intruder's centre above the floor's top face (docs/paper.md: heights
// from the cell floor to the intruder's centre).
#pragma once

#include <vector>

#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

struct DragProfile {
  std::vector<double> time;    // s
  std::vector<double> height;  // m
  std::vector<double> drag;    // N/m
};

// Throws std::runtime_error naming the file if the run has no series or lacks the bodies.
DragProfile read_drag_profile(const RunReader& run);

}  // namespace dem2d::analysis
