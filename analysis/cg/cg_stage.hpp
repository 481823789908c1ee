// The stage `cg` (issue 5): coarse-grained fields of a pull-off run, the
// mobility zones, the cone angle (R5), the wall-mobility length (R6) and the
// dilatancy at the onset (R11). Definitions: analysis/cg/README.md.
//   compute_cg(...)  reads the run (and the events file), returns everything in memory
//   write_cg(...)    writes DIR/metrics.json and DIR/cg.h5 (each as .tmp, then renamed)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cg/cg_config.hpp"
#include "cg/cg_field.hpp"
#include "common/events.hpp"
#include "common/study.hpp"

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
  Study study;              // body names
  std::string events_path;  // "" : none
  int threads = 0;          // OpenMP threads (0: OpenMP's default); results do not depend on it
};

// A named array for cg.h5: float32, float64 or int64 data (the one that is
// used), its shape (empty: 1-D) and unit.
struct Dataset {
  enum class Type { f32, f64, i64 } type = Type::f64;
  std::string name, unit, about;
  std::vector<hsize_t> dims;
  std::vector<float> f32;
  std::vector<double> f64;
  std::vector<std::int64_t> i64;
};

struct CgResult {
  nlohmann::ordered_json metrics;  // {"cg": {...}}
  std::vector<Dataset> datasets;   // the content of cg.h5
  std::vector<std::pair<std::string, std::string>> attributes;  // root attributes of cg.h5
};

// Everything, in memory. CgError (or std::runtime_error from the reader) on bad input.
CgResult compute_cg(const CgInput& in);

// DIR/cg.h5 and DIR/metrics.json; std::runtime_error naming the file if one cannot be written.
void write_cg(const CgResult& r, const std::string& out_dir);

}  // namespace dem2d::analysis
