// Settings of `bed_metrics` (data/bed_metrics.toml; keys in analysis/bed/README.md).
#pragma once

#include <stdexcept>
#include <string>

#include "common/stage_error.hpp"

namespace dem2d::analysis {

// A problem with the input: the run file's contents or the configuration.
struct BedError : StageError {
  using StageError::StageError;
};

struct BedConfig {
  double margin_d = 2.0;         // bulk region: this many mean diameters from walls, surface and intruder
  double sampling_per_d = 50.0;  // solid fraction: sample points per mean diameter
  double column_width_d = 1.0;   // free surface: column width in mean diameters
  bool operator==(const BedConfig&) const = default;
};

// Reads a config file; keys not given keep their defaults. Unknown keys, wrong
// types and values out of range are errors (BedError "FILE:LINE:COL: ...").
BedConfig load_bed_config(const std::string& path);

}  // namespace dem2d::analysis
