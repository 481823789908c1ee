// One snapshot in the stage `cg`: its coarse-grained fields measured (zones,
// cone fits for every sensitivity value, wall mobility, the dilatancy region's
// solid fraction) and what cg.h5 keeps of it (profiles, the intruder-frame
// window, full fields). Definitions: analysis/cg/README.md.
#pragma once

#include <cstddef>
#include <vector>

#include "cg/cg_config.hpp"
#include "cg/cg_field.hpp"
#include "cg/cg_measure.hpp"
#include "frame/cell.hpp"

namespace dem2d::analysis {

// The velocity sets: instantaneous (/snapshots/velocity) and PIV-like (displacement / window).
inline constexpr std::size_t kInst = 0, kPiv = 1;
inline constexpr const char* kSourceName[2] = {"instantaneous", "piv"};

// Everything the measurement of a snapshot needs that does not change along the run.
struct Setup {
  Grid grid;
  Kernel kernel;
  Cell cell;
  double d = 0.0;             // mean grain diameter (m)
  double grain_density = 0.0; // kg/m^3: rho = grain_density * phi
  double v_ref = 0.0;         // V_ref of v* = |V| / V_ref (m/s): zones.reference_speed_mm_s, or the intruder's speed
  Pull pull;                  // the intruder's velocity V (m/s): the frame of the profiles
  double phi_ref = 0.0;       // bulk solid fraction at snapshot 0 (the last one without an intruder)
  double min_phi = 0.0;       // nodes below have no velocity
  double window = 0.0;        // PIV window (s)
  Intruder start;             // the intruder at snapshot 0
  std::size_t centre_i = 0;   // node column through the intruder's centre
  std::size_t tip_nx = 0, tip_ny = 0;
  std::vector<double> levels, starts, bands, heights;  // sensitivity values (v*, m, m, m)
  // v* of single nodes at rest (noise pre-pass), sorted; the cone's level is
  // raised to its (1 - noise.cone_false_alarm) quantile
  std::vector<double> rest_nodes;
  std::size_t level0 = 0, start0 = 0, band0 = 0, height0 = 0;  // indices of the primary values
  std::size_t level_fixed = 0;  // index of cone.level itself (the definitions before the noise calibration)
  // SourceMeasure::cone is [level][start], wall_left/right [level][band]: the primary entries
  // the cone is measured on the paper's level (cone.level) and kept where the
  // zone at the noise-calibrated level (level0) has that edge too
  std::size_t cone0() const { return level_fixed * starts.size() + start0; }
  std::size_t cone_gate() const { return level0 * starts.size() + start0; }
  std::size_t wall0() const { return level0 * bands.size() + band0; }
  std::size_t wall_fixed() const { return level_fixed * bands.size() + band0; }
};

// One velocity source of one snapshot.
struct SourceMeasure {
  bool valid = false;
  ZoneAreas zones;
  ZoneExtent red, mobile;                 // zones grown from the intruder (dragged; v* >= primary level)
  std::vector<ConeFit> cone;              // [level][start]
  std::vector<double> wall_left, wall_right;  // mobile length (m) [level][band]
  double median_vstar = kNaN;
};

struct SnapshotMeasure {
  double time = 0.0, height = 0.0, surface = 0.0;  // intruder centre and free surface above the floor (m)
  Intruder intruder;
  SourceMeasure src[2];                       // [kInst, kPiv]
  std::vector<double> phi_follow, phi_fixed;  // [region height]
  // the PIV noise at rest: sum of (vx^2 + vy^2) / V_ref^2 over the grains of
  // the wall bands below the intruder (cg_report.cpp, wall_noise), and their number
  double rest_grain_ss = 0.0;
  std::size_t rest_grains = 0;
  // per-snapshot profiles and the intruder-frame window (float32 for cg.h5)
  std::vector<float> centre_vy[2], centre_phi, wall_vstar[2], tip[2][2];
  // v* along the column band_d / 2 from each wall by local-linear regression
  // (local_linear_profile; the primary velocities): the walls' mobility
  std::vector<float> wall_local[2];
  // its velocity components (x V_ref) and its noise gain along the same
  // columns (local_linear_profile): the walls' mobility is judged on them
  std::vector<float> wall_vx[2], wall_vy[2], wall_gain[2];
  // full fields (only for the selected snapshots)
  std::vector<float> phi_field, v_field[2][2];
};

// Measures snapshot s (intruder `in`) on its (averaged) fields f, the zones,
// the cone and the walls' v* on `moving` (f averaged over cone.frame_snapshots
// in the intruder's frame; f itself when that is 1); `piv`, `moving_piv`: the
// PIV set of f, of `moving` is valid; `full_fields`: keep the 2D fields;
// `primary`: the set whose wall profiles are kept.
SnapshotMeasure measure_snapshot(const Setup& su, const CgConfig& c, const Fields& f, bool piv, const Fields& moving,
                                 bool moving_piv, const Snapshot& s, const Intruder& in, bool full_fields,
                                 std::size_t primary);

// The rows of the wall bands at rest in a snapshot: above floor + margin and
// below the intruder's centre - margin (margin = noise.rest_margin_w x w).
struct RestRows {
  double low = 0.0, high = 0.0;  // y (m)
  bool any() const { return high > low; }
};
RestRows rest_rows(const Setup& su, const CgConfig& c, const Intruder& in);
// The q-quantile of sorted values (the smallest value at or above a fraction q
// of them: conservative in the tail; the largest when there are too few); NaN if none.
double upper_quantile(const std::vector<double>& sorted, double q);
// The cone's level: max(cone.level, the (1 - false_alarm) quantile of su.rest_nodes).
double cone_level(const Setup& su, const CgConfig& c, double false_alarm);

// Fills m.wall_local from the grains and velocity set `set` of the snapshot
// (rows where the fields f have no velocity are NaN).
void add_wall_profiles(const Setup& su, const CgConfig& c, const Fields& f, const Grains& grains, std::size_t set,
                       SnapshotMeasure& m);

// Adds to m the per-grain PIV noise of the grains within wall.band_d of a
// wall in those rows (v: the grains' PIV-like velocities, m/s).
void add_rest_grain_noise(const Setup& su, const CgConfig& c, const Snapshot& s, const std::vector<Vec2>& v,
                          SnapshotMeasure& m);

}  // namespace dem2d::analysis
