// The study's constants (data/study.toml): what the analysis stages need to
// compare with the experiment (W, V, L_c, L, d). The stages find the bodies by
// their roles in the run file (core/body_roles.hpp).
#pragma once

#include <string>

#include "core/share_dir.hpp"

namespace dem2d::analysis {

struct Study {
  double intruder_depth = 0.049;   // m, W
  double cell_width = 0.100;       // m, L_c
  double intruder_length = 0.010;  // m, L
  double pull_speed = 0.0012;      // m/s, V
  double mean_diameter = 0.003;    // m, d
};

// Reads the file (default: data/study.toml under share/dem2d, core/share_dir.hpp). Unknown keys and bad
// values are errors naming the file, key and value (std::runtime_error).
Study load_study(const std::string& path = dem2d::data_file("study.toml"));

}  // namespace dem2d::analysis
