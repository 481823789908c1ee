// Settings of the stage `cg` (data/cg.toml; every key is documented there and
// in analysis/cg/README.md). Lengths in the file are in mm or in multiples of
// the mean grain diameter d or of the kernel width w, as each key's name says.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace dem2d::analysis {

// A problem with the stage's input: the run file's contents, the events file
// or the configuration. The message names the file.
struct CgError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CgConfig {
  // [kernel]
  double w_over_d = 1.5;       // kernel width w / mean grain diameter
  double cutoff_over_w = 4.0;  // cut-off radius / w
  // [grid]
  double spacing_mm = 0.4;     // node spacing
  double height_mm = 0.0;      // grid height above the floor; 0: the bed's top at snapshot 0 + cut-off
  double mask_fraction = 0.25; // nodes with phi < mask_fraction * phi_ref have no velocity (outside the bed)
  int average_snapshots = 1;   // trailing average of rho, p over this many snapshots (1: none)
  // [velocity]
  std::string velocity = "piv";  // which velocity the metrics use: "piv" (displacement / window) or "instantaneous"
  // [zones]
  double immobile_below = 0.25;  // v* below: immobile (blue)
  double dragged_above = 0.75;   // v* above: dragged (red); between: cone (green)
  double reference_speed_mm_s = 0.0;  // V_ref of v* = |V| / V_ref; 0: the intruder's speed (none without an intruder)
  // [cone]
  double level = 0.25;           // v* of the mobilised zone's edge
  double fit_start_w = 0.0;      // first fitted row: the intruder's top face + fit_start_w * w
  double fit_min_span_d = 2.0;   // an edge spanning less than this (in d) gives no angle
  double seed_depth_d = 1.0;     // the mobilised zone grows from the nodes this deep above the intruder's top
  int min_snapshots = 5;         // beta is reported from at least this many snapshots with an angle ...
  double max_interval_deg = 5.0; // ... whose mean's 95 % t-interval is at most +- this (deg); else undetermined
  int frame_snapshots = 1;       // zones and cone on rho, p averaged over this many snapshots in the intruder's frame; at most 100 (each held in memory)
  // [wall]
  double wall_band_d = 1.0;          // nodes closer than this to a wall's face form its band
  double wall_min_mobile_d = 1.0;    // a wall is mobile if its band's v*, averaged over this length, reaches the level
  double wall_kernel_w = 2.0;        // the walls' local-linear profiles use a kernel this many w wide
  double wall_pool_d = 2.0;          // ... averaged over the snapshots within this much intruder travel (d, full width)
  double wall_loss_false_alarm = 0.01;  // the loss height is reported when its permutation p-value is below this
  int wall_permutations = 200;       // of the mobile flags, for that p-value
  // the test's power to find a loss at the paper's H_c (below); it decides a miss
  double wall_power_cone_angle_deg = 60.0;  // the planted loss: (L_c - L)/2 tan(this) below the surface
  int wall_power_replicas = 20;      // planted flag series
  double wall_power_tolerance_d = 3.0;  // a planted loss counts as found within this many d of its depth
  double wall_min_power = 0.8;       // a miss is "none" at this power or more, else "undetermined"
  // [noise]: the PIV noise measured where the bed is at rest, and the levels it sets
  double rest_margin_w = 4.0;        // at rest: rows this many w below the intruder's centre and above the floor
  double cone_false_alarm = 0.001;   // the cone level is at least the (1 - this) quantile of single nodes' v* at rest
  double wall_false_alarm = 0.05;    // per snapshot, the chance that noise alone makes the walls mobile
  int noise_snapshots = 50;          // snapshots of the pre-pass that measures the nodes' noise
  // [dilatancy]
  double region_width_L = 1.0;       // region width / intruder length L, centred on the intruder
  double region_offset_w = 2.0;      // region bottom: the intruder's top face + this * w
  double region_height_d = 10.0;     // region height in d
  double after_travel_d = 1.0;       // "just after the onset": first snapshot with this much travel (in d)
  // [output]
  std::vector<double> bands_mm = {0, 30, 60, 90, 120, 150};  // intruder-height bands for beta per band
  double field_every_mm = 10.0;      // full fields every this much travel (0: none), plus the pre-rupture ones
  int field_max_snapshots = 60;      // at most this many snapshots with full fields (events evenly thinned)
  int field_follow_snapshots = 2;    // with each pre-rupture snapshot, the fields of this many after it
  double tip_window_width_mm = 32.0;   // intruder-frame window around the intruder, stored for every snapshot
  double tip_window_height_mm = 16.0;
  // [sensitivity]: each list is varied one at a time around the values above
  std::vector<double> levels = {0.2, 0.25, 0.3};
  std::vector<double> fit_starts_w = {0.0, 1.0};
  std::vector<double> max_edge_angles_deg = {180.0, 90.0, 85.0, 80.0};  // beta cut-off for the cone's edges (180: all)
  std::vector<double> wall_bands_d = {1.0, 2.0};
  std::vector<double> cone_false_alarms = {1e-4, 1e-3, 1e-2};
  std::vector<double> wall_false_alarms = {0.01, 0.05, 0.2};
  std::vector<double> after_travels_d = {0.5, 1.0, 2.0};
  std::vector<double> region_heights_d = {5.0, 10.0, 20.0};

  bool operator==(const CgConfig&) const = default;
};

// Reads a config file; keys not given keep the defaults above. Unknown keys,
// wrong types and values out of range are errors
// (CgError "FILE:LINE:COL: key = value: must be ...").
CgConfig load_cg_config(const std::string& path);

// Checks the values' ranges (also for configs built in code); CgError naming `where`.
void validate(const CgConfig& c, const std::string& where);

}  // namespace dem2d::analysis
