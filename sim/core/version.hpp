// The code version recorded in run files and checkpoints:
// "<project version>+<git describe of the source tree at the last build>".
#pragma once

#include <string>

namespace dem2d {

// The git part is read at run time from share/dem2d/code_version.txt of the
// build tree or the installation (core/share_dir.hpp; refreshed at every
// build, see cmake/write_version.cmake), so committing does not change the
// binaries; "+unknown" when that file is not there.
const std::string& code_version();

}  // namespace dem2d
