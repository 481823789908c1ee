// Checkpoint / restart. A checkpoint holds everything the next step reads:
// positions, velocities, spins, orientations, the force and torque of the last
// evaluation (velocity Verlet's first half-kick uses them), the contact history
// of every touching contact, lost grains and the body-force sums. The
// neighbour lists are rebuilt on restore; since each grain sums its contacts
// in a fixed order (partner index), a restored run continues bitwise
// identically to an uninterrupted one.
#pragma once

#include <cstdint>
#include <string>

#include "engine/system.hpp"
#include "run/jam_control.hpp"

namespace dem2d {

// Where the driver was when the checkpoint was taken.
struct RunProgress {
  std::int64_t next_series = 0, next_snapshot = 0, next_check = 0;  // steps of the next events
  std::int64_t last_contact = 0;  // last step the stop.body_free body touched a grain
  double wall_seconds = 0.0;       // wall-clock time spent on the run so far (s)
  int segments = 0;               // run-file segments written
  std::int64_t series_rows = 0, snapshots = 0;
  JamController::State jam;
  // positions taken for the displacement of the snapshot at step ref_for (-1: none pending)
  std::int64_t ref_for = -1;
  std::vector<double> ref_position;  // x0, y0, x1, y1, ... (m)
};

// Written to path + ".tmp", then renamed: a checkpoint on disk is always complete.
void write_checkpoint(const std::string& path, const System& sys, const RunProgress& progress,
                      const std::string& scene_text);

// The scene text a checkpoint was made from ("" if the file is not a checkpoint).
std::string checkpoint_scene_text(const std::string& path);

// Overwrites the evolving state of `sys` (built from the same scene) with the
// checkpoint's and returns the driver's progress.
RunProgress read_checkpoint(const std::string& path, System& sys);

}  // namespace dem2d
