// Stage `stress`: the coarse-grained stress of a run (stress_field.hpp) on a
// grid over the cell, its maps at a few snapshots, the stress profile of the
// bed at rest, and the force the stress carries onto a body (the intruder,
// or the body of the config's role) against the force the run records
// (stress_balance.hpp). Definitions:
// analysis/stress/README.md. SI units (Pa: N/m per m of depth; N/m).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "common/stage_output.hpp"
#include "frame/study.hpp"
#include "stress/stress_config.hpp"

namespace dem2d::analysis {

struct StressResult {
  nlohmann::ordered_json metrics;  // {"stress": {...}}
  H5Output h5;                     // stress.h5
};
// StageError / std::runtime_error naming the file on bad input. threads: OpenMP
// threads across snapshots (0: OpenMP's default); the result does not depend on it.
StressResult run_stress(const std::string& run_path, const std::string& config_path, const StressConfig& cfg,
                        const Study& study, int threads);

}  // namespace dem2d::analysis
