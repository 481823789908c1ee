// The run file's format names (root attribute `format`, docs/run_file.md),
// shared by the writer (io/run_file.hpp) and the reader (io/run_reader.hpp).
#pragma once

namespace dem2d {

inline constexpr const char* kRunFileFormat = "dem2d-run-2";

}  // namespace dem2d
