// Where the project's shared files are: share/dem2d/ (data/: the study's
// constants, the stages' settings, the benchmark scene; code_version.txt).
// Found only where this project puts it, from the running executable: in a
// build tree (build/release/share/dem2d, made by CMake; its data/ links to
// the source's) and in an installed tree (PREFIX/bin/dem2d,
// PREFIX/libexec/dem2d/<stage> -> PREFIX/share/dem2d); never in a parent
// folder or the current one, which may hold another installation's. The
// environment variable DEM2D_SHARE names another. No source-tree path is
// compiled in.
#pragma once

#include <string>

namespace dem2d {

// The share/dem2d folder, or "" if it is not where it belongs.
const std::string& share_dir();

// "" if share_dir() was found, else the error a program stops with: the
// program, where its data belong and DEM2D_SHARE.
std::string share_problem();

// <share>/data/<relative>, the share where it belongs even if missing (the
// error of whoever opens it names that place).
std::string data_file(const std::string& relative);

}  // namespace dem2d
