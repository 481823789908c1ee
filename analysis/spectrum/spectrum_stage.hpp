// Stage `spectrum` on a pull-off run file: reads the drag profile and the
// run's scales, analyses them (spectrum.hpp) and writes DIR/metrics.json and
// DIR/spectrum.h5 (layout: analysis/spectrum/README.md). Reads only the run
// file (and optionally the fill's metrics): it never runs a simulation.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "frame/study.hpp"
#include "spectrum/spectrum.hpp"

namespace dem2d::analysis {

struct SpectrumInputs {
  std::string run, config, study, fill_metrics;  // paths; fill_metrics may be empty
};

struct SpectrumStage {
  SpectrumResult result;
  SpectrumScales scales;
  double intruder_depth = 0.0;     // m, W
  nlohmann::ordered_json metrics;  // {"spectrum": {...}}, sensitivity table included
};

// Every problem with the inputs is a std::runtime_error naming the file (exit 2).
SpectrumStage compute_spectrum_stage(const SpectrumInputs& in, const SpectrumConfig& config, const Study& study);

// DIR/metrics.json and DIR/spectrum.h5, each written under a temporary name
// and renamed (creating DIR). Throws std::runtime_error naming the file.
void write_spectrum_outputs(const std::string& dir, const SpectrumStage& stage);

}  // namespace dem2d::analysis
