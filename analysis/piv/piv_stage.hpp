// The stage `piv`: synthetic PIV of the simulated front face, as the paper
// measures it (analysis/piv/README.md). For each snapshot with displacements,
// the grains rendered twice by a camera that follows the intruder (frame A:
// the positions one displacement_window earlier, frame B: the snapshot's),
// the intruder masked and the region of interest cut to the granular sample,
// then PIV of the pair (piv_field.hpp). On the PIV's own vector grid, the
// same detectors as the cg stage's (zones, the cone's edges and angle) run on
// the PIV field and on the coarse-grained field of the grains' displacements
// (the cg stage's kernel), on the nodes both have: the maps' rms difference,
// the paired differences of beta and the zones (what the measurement method
// moves), and the vortex measure near the intruder's tips (R12).
//   run_piv(...)    everything in memory
//   write_piv(...)  DIR/metrics.json, DIR/piv.h5 and the PNG frames (each as .tmp, then renamed)
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cg/cg_config.hpp"
#include "common/snapshot_source.hpp"
#include "common/stage_output.hpp"
#include "frame/study.hpp"
#include "piv/piv_config.hpp"

namespace dem2d::analysis {

struct PivInput {
  std::string run_path, config_path, cg_config_path;
  std::string cg_metrics_path;  // the cg stage's metrics.json, quoted beside the comparison ("": none)
  PivConfig config;
  CgConfig cg;
  Study study;
  int threads = 0;  // OpenMP threads across snapshots (0: OpenMP's default); results do not depend on it
};

struct PivResult {
  nlohmann::ordered_json metrics;  // {"piv": {...}}
  H5Output h5;                     // piv.h5
  std::vector<std::pair<std::string, Image>> frames;  // PNG frames: file name, image
};

// StageError naming the run or the setting on bad input.
PivResult run_piv(const SnapshotSource& run, const PivInput& in);
PivResult run_piv(const PivInput& in);
// An image as an 8-bit grey PNG (Cairo), written as path.tmp and renamed.
void write_png(const Image& im, const std::string& path);
void write_piv(const PivResult& r, const std::string& out_dir);

}  // namespace dem2d::analysis
