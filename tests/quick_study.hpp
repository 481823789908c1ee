// The quick study's run files (tests/scenes/quick_fill.toml, then
// quick_pulloff.toml from its bed: the runs `make reproduce PRESET=quick`
// makes), simulated once per ctest run by the fixture test `quick_study`
// (tests/quick_study.sh) into BUILD/tests/quick_study/{fill,pulloff}/run.h5
// ($DEM2D_QUICK_STUDY instead, if set: results/quick of `make reproduce
// PRESET=quick`, for example). A test that needs them fails when they are
// missing: it never skips.
#pragma once

#include <cstdlib>
#include <string>

namespace dem2d::test {

// "fill" or "pulloff": the path of that stage's run file.
inline std::string quick_study_run(const std::string& stage) {
  const char* dir = std::getenv("DEM2D_QUICK_STUDY");
  return (dir && *dir ? std::string(dir) : std::string(DEM2D_QUICK_STUDY_DIR)) + "/" + stage + "/run.h5";
}

// The message when it is missing.
inline std::string quick_study_missing(const std::string& path) {
  return path + " does not exist: run the tests through ctest (its fixture test quick_study makes it), or "
                "set DEM2D_QUICK_STUDY to a folder holding fill/run.h5 and pulloff/run.h5 (e.g. results/quick)";
}

}  // namespace dem2d::test
