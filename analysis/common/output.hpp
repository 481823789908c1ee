// Writing the analysis stages' outputs: a file appears complete or not at all.
#pragma once

#include <string>

namespace dem2d::analysis {

// Writes `text` to path + ".tmp", then renames it to `path` (creating the
// parent directory if needed). Throws std::runtime_error naming the file.
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace dem2d::analysis
