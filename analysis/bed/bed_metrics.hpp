// The bed after the filling stage: free-surface height, bulk solid fraction,
// coordination number, largest overlap, kinetic energy. Definitions and
// reasons: analysis/bed/README.md. Every function takes a Snapshot, so it can
// be tested on states built in code. SI units (lengths m) throughout; the JSON
// of fill_metrics is in mm.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "bed/bed_config.hpp"
#include "frame/cell.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// Fraction of `region` covered by the active grains, sampled on a square grid
// of the given spacing (points at the grid cells' centres; the grid is centred
// in region.box). A cell list of the disks keeps it O(points + N).
struct Coverage {
  double fraction = 0.0;
  double spacing = 0.0;         // (m)
  std::int64_t points = 0;      // sample points in the region (hole excluded)
  std::int64_t covered = 0;     // of which inside a disk
  std::int64_t excluded = 0;    // sample points of the box inside the hole
};
Coverage sample_coverage(const Snapshot& s, const Region& region, double spacing);

// Contacts per active grain, counting contacts with fn > 0: grain-grain for
// both grains, grain-body for the grain.
struct Coordination {
  double mean = 0.0;              // over all active grains
  double bulk = 0.0;              // over active grains centred in the bulk region (NaN if none)
  double without_rattlers = 0.0;  // over active grains with >= 2 contacts (NaN if none)
  std::int64_t grains = 0, bulk_grains = 0, rattlers = 0;  // rattler: < 2 contacts
  std::int64_t contacts = 0;      // contacts with fn > 0
};
Coordination coordination(const Snapshot& s, const Region& bulk);

// Largest overlap / d over the snapshot's contacts: d = min(d_i, d_j) for a
// grain pair, d_i against a body. i = j = -1 when there is no contact.
struct MaxOverlap {
  double over_d = 0.0, overlap = 0.0;  // -, m
  std::int32_t i = -1, j = -1;         // as in the run file: j < 0 is body -1 - j
};
MaxOverlap max_overlap(const Snapshot& s);

// Total area of the active grains' disks (m^2 per unit depth).
double active_grain_area(const Snapshot& s);

// Translational + rotational, active grains, I = m d^2 / 8 (J/m).
double kinetic_energy(const Snapshot& s);

// All of the above as the "fill" object of metrics.json (lengths in mm).
nlohmann::ordered_json fill_metrics(const Snapshot& s, const BedConfig& cfg);

// Reads the last snapshot of the run file and returns {"fill": fill_metrics}
// plus where it came from. Throws (message naming the file) on bad input.
nlohmann::ordered_json measure_run_file(const std::string& run_path, const BedConfig& cfg,
                                        const std::string& config_path = "");

}  // namespace dem2d::analysis
