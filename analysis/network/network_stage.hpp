// Stage `network` over a pull-off run file: settings (data/network.toml), the
// pass over every snapshot, metrics ({"network": {...}}) and network.h5.
// Definitions: analysis/network/README.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/snapshot_source.hpp"
#include "frame/study.hpp"
#include "network/network.hpp"
#include "common/stage_output.hpp"

namespace dem2d::analysis {

struct NetworkConfig {
  double strong_threshold = 1.0;            // strong: fn > this x the snapshot's mean fn
  std::string floor_rule = "vertex_removed";  // or "bottom_layer_removed"
  std::string walls = "both";               // percolating: intruder reaches "both" side walls, or "either"
  double bin_width_d = 1.0;                 // height bins (mean diameters)
  double loss_level = 0.5;                  // loss height: percolating fraction stays below this above it
  double loss_false_alarm = 0.01;           // a loss: the step test's p-value below this
  std::int64_t loss_permutations = 200;     // of the step test
  double power_depth_end_to_wall = 1.0;     // a none's power: loss planted this x (L_c - L)/2 below the surface
  double power_tolerance_d = 3.0;           // ... found within this x d
  std::int64_t power_replicas = 20;         // ... in this many planted series
  double min_power = 0.8;                   // a none with less power is undetermined
  double anisotropy_region_height = 1.0;    // region above the intruder, x end-to-wall distance
  std::int64_t anisotropy_min_contacts = 10;  // fewer strong contacts in the region: anisotropy undefined
  double keystone_end_zone_d = 0.5;         // intruder end: grain centre within this x d of a segment end, or beyond
  double keystone_share = 0.5;              // keystone: carries >= this share of the max flow to a wall
  double ejection_distance_d = 1.0;         // explained: a keystone moved more than this x its diameter
  double event_max_gap_s = 0.3;             // snapshots further than this from peak / drop end: unresolved
  std::int64_t figure_every = 20;           // force-network segments for every k-th snapshot
  std::vector<double> sensitivity_strong_threshold = {0.8, 1.0, 1.2};
  std::vector<double> sensitivity_bin_width_d = {0.5, 1.0, 2.0};
  std::vector<double> sensitivity_anisotropy_region_height = {0.5, 1.0, 2.0};
  std::vector<double> sensitivity_anisotropy_min_contacts = {10, 30, 100};
  std::vector<double> sensitivity_keystone_share = {0.25, 0.5, 0.75};
  std::vector<double> sensitivity_ejection_distance_d = {0.5, 1.0, 1.5};
};

// Keys not given keep the defaults above; StageError "FILE:LINE:COL: ..." on
// unknown keys, wrong types or values out of range.
NetworkConfig load_network_config(const std::string& path);
nlohmann::ordered_json to_json(const NetworkConfig& c);

struct NetworkInputs {
  std::string run, config;
  std::string events;            // "" : no events (keystone check skipped)
  std::string spectrum_metrics;  // "" : top layer from our own percolation-loss height
};

struct NetworkResult {
  nlohmann::ordered_json metrics;  // {"network": {...}}
  H5Output h5;                     // network.h5
};

// Reads everything and computes; StageError / std::runtime_error (naming the
// file) on bad input.
// A run without an intruder goes to run_bed_network.
NetworkResult run_network(const NetworkInputs& in, const NetworkConfig& cfg, const Study& study);
// The same on any source of snapshots with an intruder (the files named in
// `in` are only recorded): the rupture events and the spectrum's top-layer
// height (mm; NaN: none) given.
NetworkResult run_network(const SnapshotSource& run, const std::vector<RuptureEvent>& events, double spectrum_top_mm,
                          const NetworkInputs& in, const NetworkConfig& cfg, const Study& study);

// What needs no intruder (a box, a silo, a fill), per snapshot: the
// compressive network, whether its strong part spans the cell from wall to
// wall, the fabric of the strong grain-grain contacts above the floor, and
// the load on the floor and the side walls (bed_network.cpp).
NetworkResult run_bed_network(const SnapshotSource& run, const NetworkInputs& in, const NetworkConfig& cfg,
                              const Study& study);

// spectrum.top_layer_height_mm of a spectrum metrics file, or NaN when the key
// is absent or null; StageError naming the file if it is missing or not JSON.
double read_top_layer_height_mm(const std::string& path);

}  // namespace dem2d::analysis
