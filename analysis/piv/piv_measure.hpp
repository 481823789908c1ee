// One frame pair of the `piv` stage: rendered, masked, correlated, and
// measured beside the coarse-grained field on the same nodes
// (piv_stage.hpp; definitions: analysis/piv/README.md).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cg/cg_config.hpp"
#include "cg/cg_measure.hpp"
#include "common/cg_kernel.hpp"
#include "frame/cell.hpp"
#include "piv/piv_field.hpp"
#include "piv/render.hpp"

namespace dem2d::analysis {

inline constexpr std::size_t kPivSide = 0, kCgSide = 1;  // the two velocity sources
inline constexpr const char* kSideName[2] = {"piv", "cg"};

// What does not change along the run. Lengths in m, speeds in m/s.
struct PairSetup {
  Cell cell;
  double d = 0.0;          // mean grain diameter
  double interval = 0.0;   // the frames' nominal interval, s (the run's displacement_window, or `gap` snapshot intervals)
  std::size_t gap = 0;     // 0: frame A from the displacements over the run's window; else from the snapshot `gap` earlier
  double scale = 0.0;      // px per m
  Vec2 V;                  // the intruder's prescribed velocity: the camera's
  double v_ref = 0.0;      // v* = |v| / v_ref
  int intruder = -1;       // its body index
  Kernel kernel;           // the cg stage's
  CameraSettings camera;
  PivSettings piv;
  double wall_margin = 0.0, surface_margin = 0.0, mask_margin = 0.0;
  double rest_below = 0.0;  // nodes at rest: this far below the intruder's centre (the cg stage's noise.rest_margin_w x w)
  double tip_radius = 0.0;
  double min_swirl_share = 0.0;  // vortex.min_swirl_share
  CgConfig cg;             // zones and cone: the cg stage's definitions
};

// One velocity source on the nodes both sources have.
struct Side {
  ZoneAreas zones;
  ConeFit cone;
  double beta = kNaN;                // the cone's angle, edges narrowing upwards left out (deg)
  std::vector<float> rest_swirl;     // lambda_ci (x V / d) at the nodes at rest
  std::vector<float> tip_swirl[2];   // in the discs around the left and right tips
  std::vector<float> control_swirl[2];  // in discs of the same size at the region at rest's lower corners (empty: none there)
  std::vector<double> vstar_frame, swirl;  // the maps (kept snapshots only): |v - V| / v_ref, lambda_ci (x V / d)
};

struct PairMeasure {
  bool valid = false;
  std::string why;                      // when not valid
  double time = 0.0, height = kNaN, surface = kNaN;  // the intruder's centre and the free surface above the floor (m)
  Intruder in;
  Grid grid;                            // the PIV's vector grid in the lab frame at frame B (m)
  std::size_t vectors = 0, replaced = 0, common = 0;  // PIV vectors, of them replaced, nodes both sources have
  int passes = 0;
  double rms_vstar = kNaN, rms_vstar_frame = kNaN;   // rms(v*_PIV - v*_CG) over the common nodes, lab and intruder frame
  double median_vstar = kNaN;                        // median |v*_PIV - v*_CG| over them (lab frame)
  double render_s = 0.0, piv_s = 0.0, cg_s = 0.0;    // processor time of this pair's parts (s)
  Side side[2];
  std::optional<Image> a, b;            // the frames (kept ones only)
};

// The pair of snapshot s: frame A shows its grains less their displacements `disp` over `interval` (s),
// the camera that far back along V; seed draws the sensor noise.
PairMeasure measure_pair(const PairSetup& su, const Snapshot& s, const std::vector<Vec2>& disp, double interval,
                         unsigned seed, bool keep_maps, bool keep_frames);

// lambda_ci, the swirl strength (the imaginary part of the velocity gradient's complex eigenvalues; 0 where
// they are real), by central differences, NaN where a neighbour has no velocity; in 1/s. Counted only where
// the rotation dominates: lambda_ci >= min_share x the gradient's Frobenius norm (1/sqrt(2) in a rigid
// rotation; in a shear a with a small counter-shear e, lambda_ci = sqrt(a e), a share of sqrt(e / a): a
// shear layer's noise would otherwise read as swirl), else 0.
std::vector<double> swirl_strength(const Grid& g, const std::vector<double>& vx, const std::vector<double>& vy,
                                   double min_share);

}  // namespace dem2d::analysis
