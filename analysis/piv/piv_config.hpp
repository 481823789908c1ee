// Settings of the `piv` stage (data/piv.toml; analysis/piv/README.md): the
// camera, the PIV passes, the region of interest and the mask, the snapshots,
// the vortex measure. The comparison with coarse-graining takes the kernel,
// the zones' and the cone's definitions from the cg stage's settings, named
// by compare.cg_config: one source for both stages.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "piv/piv_field.hpp"
#include "piv/render.hpp"

namespace dem2d::analysis {

struct PivConfig {
  CameraSettings camera;          // [camera]
  PivSettings piv;                // [piv]
  // [roi]: what PIV leaves out, as the paper's region of interest and mask
  double wall_margin_d = 0.5;     // the walls' and the floor's faces, and this many d inside them
  double surface_margin_d = 1.0;  // above the free surface less this many d
  double mask_margin_d = 0.25;    // the intruder's outline widened by this many d
  // [snapshots]
  std::int64_t every = 1;         // every k-th snapshot (and the last)
  double frame_interval_s = 0.0;  // the frames' interval, s: 0 the run's displacement_window, else that or a whole
                                  // number of the run's snapshot intervals
  std::int64_t maps = 6;          // snapshots whose maps piv.h5 keeps, spread over the measured ones
  std::int64_t png_frames = 1;    // of those, the first this many written as PNG frame pairs (0: none)
  // [compare]
  std::string cg_config = "cg.toml";  // the cg stage's settings (relative to this file's folder)
  // [vortex]: swirl strength lambda_ci of the velocity gradient (x V / d)
  double tip_radius_d = 3.0;      // a tip's disc: nodes within this many d of the intruder's tip
  double min_swirl_share = 0.5;   // lambda_ci counted where it is at least this share of the gradient's norm
  double rest_quantile = 0.999;   // the threshold: this quantile of lambda_ci over the nodes at rest
  std::int64_t min_nodes = 3;     // a vortex: at least this many nodes of a tip's disc above it
};
// StageError "FILE:LINE:COL: key = value: ..." on a bad value or key.
PivConfig load_piv_config(const std::string& path);
nlohmann::ordered_json to_json(const PivConfig& c);
// compare.cg_config resolved against the folder of the file at `path`; StageError naming that file and
// the key when nothing is there (a settings file copied elsewhere without the cg stage's beside it).
std::string cg_config_path(const std::string& path, const PivConfig& c);

}  // namespace dem2d::analysis
