// The format names (root attribute `format`) of the run file (docs/run_file.md;
// written by writer/run_file.hpp, read by runfile/run_reader.hpp) and of the checkpoint
// (written and resumed from by run/checkpoint.hpp, read as a starting state
// by runfile/checkpoint_state.hpp).
#pragma once

namespace dem2d {

inline constexpr const char* kRunFileFormat = "dem2d-run-2";
inline constexpr const char* kCheckpointFormat = "dem2d-checkpoint-4";

}  // namespace dem2d
