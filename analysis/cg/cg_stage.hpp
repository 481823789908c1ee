// The stage `cg`: coarse-grained fields of a pull-off run, the
// mobility zones, the cone angle (R5), the wall-mobility length (R6) and the
// dilatancy at the onset (R11); on a run without an intruder (a box, a silo)
// the lab-frame fields and zones only (cg_lab.cpp). Definitions: analysis/cg/README.md.
//   compute_cg(...)  reads the run (and the events file), returns everything in memory
//   write_cg(...)    writes DIR/metrics.json and DIR/cg.h5 (each as .tmp, then renamed)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cg/cg_config.hpp"
#include "cg/cg_field.hpp"
#include "cg/cg_snapshot.hpp"
#include "common/events.hpp"
#include "common/snapshot_source.hpp"
#include "common/stage_output.hpp"
#include "frame/study.hpp"

namespace dem2d::analysis {


// For each event, the snapshot "just before the rupture": the last snapshot k
// with load_start <= t_k - window and t_k <= peak (the PIV window before t_k
// lies in the loading phase); -1 if there is none.
std::vector<std::int64_t> pre_rupture_snapshots(const std::vector<double>& times, const std::vector<RuptureEvent>& events,
                                                double window);

struct CgInput {
  std::string run_path;
  CgConfig config;
  std::string config_path;  // for the record
  Study study;              // the study's constants (read and checked; cg needs none of them)
  std::string events_path;  // "" : none
  int threads = 0;          // OpenMP threads (0: OpenMP's default); results do not depend on it
};

// cg.h5's grid/x and grid/y: the nodes' coordinates (m); y_about describes grid/y.
void add_grid(H5Output& h, const Grid& g, std::string y_about);

struct CgResult {
  nlohmann::ordered_json metrics;  // {"cg": {...}}
  H5Output h5;                     // cg.h5
};

// Everything, in memory. CgError (or std::runtime_error from the reader) on bad input.
CgResult compute_cg(const CgInput& in);
// The same on any source of snapshots with an intruder (in.run_path and
// in.events_path are only recorded): `events` the rupture events (nullptr: none,
// every snapshot is a loading snapshot).
CgResult compute_cg(const SnapshotSource& run, const std::vector<RuptureEvent>* events, const CgInput& in);

// ---- shared by the pull-off pass (cg_stage.cpp) and the lab-frame pass (cg_lab.cpp) ----

// The run without an intruder: lab-frame fields, solid fraction and zones.
CgResult compute_cg_lab(const SnapshotSource& run, const CgInput& in);

// The grains of snapshot s with their instantaneous velocities and, if given, a second set (PIV-like).
Grains grains_of(const Snapshot& s, const std::vector<Vec2>* piv);

// PIV-like velocities displacement / window (ok = false and zeros if an active grain has none).
struct PivVelocities {
  bool ok = true;
  std::vector<Vec2> v;
};
PivVelocities piv_velocities(const Snapshot& s, const std::vector<Vec2>& disp, double window);

// Snapshots k0 .. k1-1 and, if has_piv, their PIV-like velocities over `window` (s).
struct SnapshotBatch {
  std::vector<Snapshot> snaps;
  std::vector<PivVelocities> piv;  // {false, {}} without
};
SnapshotBatch read_batch(const SnapshotSource& run, std::size_t k0, std::size_t k1, bool has_piv, double window);

// su.kernel and su.grid from the config, su.cell and su.d: the grid spans the
// cell's width, from the floor to grid.height_mm or to the highest grain top
// at snapshot s0 plus the cut-off radius. CgError naming the config and run.
void kernel_and_grid(const CgInput& in, const std::string& path, const Snapshot& s0, Setup& su);

// The mean solid fraction of the nodes in the bulk of the bed at snapshot s
// (a cut-off radius from the walls, the floor and the free surface); the
// errors name the run (path) and the settings (config).
double bulk_solid_fraction(const Setup& su, const Snapshot& s, const std::string& path, const std::string& config);

// DIR/cg.h5 and DIR/metrics.json; std::runtime_error naming the file if one cannot be written.
void write_cg(const CgResult& r, const std::string& out_dir);

}  // namespace dem2d::analysis
