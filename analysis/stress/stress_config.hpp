// Settings of the `stress` stage (data/stress.toml; analysis/stress/README.md).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace dem2d::analysis {

struct StressConfig {
  double w_over_d = 1.5;         // kernel width w / mean grain diameter (the cg stage's)
  double cutoff_over_w = 4.0;    // kernel cut-off radius / w
  double spacing_mm = 1.0;       // grid spacing (mm)
  std::string body_role = "intruder";  // the body whose force the stress is checked against (core/body_roles.hpp)
  double box_margin_mm = 1.0;    // the body's box: its outline + the kernel's cut-off + this (mm)
  std::int64_t every = 1;        // every k-th snapshot (and the last)
  std::int64_t maps = 6;         // snapshots whose maps stress.h5 keeps, spread over the measured ones
  double min_load_n = 0.05;      // the force check uses snapshots whose recorded |F_y| is at least this (N per m depth)
  double tolerance = 0.05;       // the check holds if the stress gives the mean force within this (relative)
};
// StageError "FILE:LINE:COL: key = value: ..." on a bad value or key.
StressConfig load_stress_config(const std::string& path);
nlohmann::ordered_json to_json(const StressConfig& c);

}  // namespace dem2d::analysis
