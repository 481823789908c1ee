// Checkpoint / restart. A checkpoint holds everything the next step reads:
// positions, velocities, spins, orientations, the force and torque of the last
// evaluation (velocity Verlet's first half-kick uses them), the contact history
// of every touching contact, lost grains and the body-force sums. The
// neighbour lists are rebuilt on restore; since each grain sums its contacts
// in a fixed order (partner index), a restored run continues bitwise
// identically to an uninterrupted one. The run loop's controllers
// (run/controller.hpp) save and restore their own state in it.
#pragma once

#include <span>
#include <string>

#include "engine/system.hpp"
#include "run/controller.hpp"

namespace dem2d {

// Written to path + ".tmp", then renamed: a checkpoint on disk is always
// complete. Holds the System's evolving state, each controller's state (in
// the group controllers/<name>) and the wall time spent so far (s).
void write_checkpoint(const std::string& path, const System& sys, std::span<Controller* const> controllers,
                      double wall_seconds, const std::string& scene_text);

// The scene text a checkpoint was made from ("" if the file is not a
// checkpoint of this format).
std::string checkpoint_scene_text(const std::string& path);

// Overwrites the evolving state of `sys` (built from the same scene) and of
// the controllers (built for it, in the same list) with the checkpoint's;
// returns the wall time spent before it (s).
double read_checkpoint(const std::string& path, System& sys, std::span<Controller* const> controllers);

}  // namespace dem2d
