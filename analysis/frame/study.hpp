// The study's constants (data/study.toml): what the analysis stages need to
// compare with the experiment and no run holds (W, the paper's V, the unit d). The stages find the bodies by
// their roles in the run file (core/body_roles.hpp).
#pragma once

#include <limits>
#include <string>

#include "core/share_dir.hpp"

namespace dem2d::analysis {

// What no run holds (data/study.toml says why each): NaN until read.
struct Study {
  double intruder_depth = std::numeric_limits<double>::quiet_NaN();  // m, W
  double pull_speed = std::numeric_limits<double>::quiet_NaN();      // m/s, the paper's V
  double mean_diameter = std::numeric_limits<double>::quiet_NaN();   // m, d: the settings' length unit
};

// Reads the file (default: data/study.toml under share/dem2d, core/share_dir.hpp). Every key is
// required; a missing or unknown key and a bad value are errors naming the file, key and value
// (StageError).
Study load_study(const std::string& path = dem2d::data_file("study.toml"));

}  // namespace dem2d::analysis
