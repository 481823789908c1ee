// A checkpoint read as a starting state (`dem2d run --initial CHECKPOINT`,
// LAMMPS's read_restart followed by new settings): the grains' positions,
// velocities, spins, diameters and whether they are still in the domain, the
// bodies' names, and the history (tangential spring, rolling moment) of every
// acting contact, in the shape of a run file's snapshot. The checkpoint's
// format is run/checkpoint.hpp's (runfile/run_format.hpp: kCheckpointFormat).
#pragma once

#include <string>

#include "runfile/run_reader.hpp"

namespace dem2d {

// The file's root attribute `format` names a dem2d checkpoint (of any version).
bool is_checkpoint(const std::string& path);

// The checkpoint's state (time NaN: a checkpoint stores its step, not dt; the
// bodies carry their names only). Throws std::runtime_error starting with the
// path if it is not a checkpoint of this version, or is damaged.
Snapshot checkpoint_state(const std::string& path);

}  // namespace dem2d
