// The stage `cg`'s results from its measured snapshots: the metrics
// ({"cg": {...}}: cone angle, wall-mobility length, dilatancy, zones, per-band
// values, sensitivity tables) and the datasets of cg.h5. Definitions:
// analysis/cg/README.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cg/cg_snapshot.hpp"
#include "cg/cg_stage.hpp"

namespace dem2d::analysis {

// What the stage measured, and how.
struct StageRecord {
  Setup setup;
  CgConfig config;
  std::vector<SnapshotMeasure> ms;      // [S]
  std::vector<double> times, heights;   // [S] s; intruder centre above the floor (m)
  std::vector<std::uint8_t> piv_ok;     // [S] the snapshot has PIV-like velocities
  bool has_piv = false;                 // the run has displacements
  std::size_t primary = kInst;          // velocity set of the metrics
  bool have_events = false;
  std::vector<RuptureEvent> events;
  std::vector<std::int64_t> pre;        // [E] pre-rupture snapshot of each event, -1 if none
  std::int64_t after = -1;              // dilatancy: the snapshot "just after the onset"
  std::vector<std::size_t> fields_at;   // snapshots with full fields
  double seconds = 0.0, cg_seconds = 0.0;
  int threads = 1;
  std::string run_path, events_path, config_path;
};

// The first snapshot at which the intruder has travelled `travel` (m) from snapshot 0, -1 if none.
std::int64_t first_after_travel(const std::vector<double>& heights, double travel);

nlohmann::ordered_json cg_metrics(const StageRecord& r);   // the object under "cg"
// cg.h5: the per-snapshot series, profiles, intruder-frame windows and fields; `metrics` goes in as an attribute.
H5Output cg_h5(const StageRecord& r, const nlohmann::ordered_json& metrics);

}  // namespace dem2d::analysis
