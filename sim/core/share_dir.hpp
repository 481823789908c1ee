// Where the project's shared files are: share/dem2d/ (data/: the study's
// constants, the stages' settings, the benchmark scene; code_version.txt).
// Found from the running executable, searching its folder and each parent
// for share/dem2d, as laid out in an installed tree (PREFIX/bin/dem2d,
// PREFIX/libexec/dem2d/<stage> -> PREFIX/share/dem2d) and in a build tree
// (build/release/share/dem2d, made by CMake; its data/ links to the
// source's). The environment variable DEM2D_SHARE overrides the search. No
// source-tree path is compiled in.
#pragma once

#include <string>

namespace dem2d {

// The share/dem2d folder, or "" if none was found.
const std::string& share_dir();

// share_dir()/data/<relative>; "share/dem2d/data/<relative>" (a path that
// does not exist, named in the error of whoever opens it) if none was found.
std::string data_file(const std::string& relative);

}  // namespace dem2d
