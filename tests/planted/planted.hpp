// The planted-truth suite: each detector of the analysis stages is run,
// unchanged, on synthetic input whose answer is known (a planted rupture
// spacing, size distribution, top layer, cone angle, wall-mobility length,
// dilatancy, percolation loss, keystone ejections, stress, the synthetic PIV's), over replicas and noise
// levels; every case states its tolerance here, next to what it checks, and
// cases with nothing planted must come back "none". What is swept (noise
// levels, planted values, replicas): data/planted.toml.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace dem2d::planted {

// What one replica of a case gave: a value, or none (the detector found nothing).
struct Outcome {
  bool found = false;
  double value = std::numeric_limits<double>::quiet_NaN();
  // the detector's interval for the value, where it gives one (NaN: none)
  double low = std::numeric_limits<double>::quiet_NaN(), high = std::numeric_limits<double>::quiet_NaN();
};

// One case, summarised over its replicas.
struct Row {
  Row(std::string detector_, std::string name_, std::string quantity_, std::string unit_, double planted_,
      double noise_, std::string noise_unit_)
      : detector(std::move(detector_)), name(std::move(name_)), quantity(std::move(quantity_)), unit(std::move(unit_)),
        planted(planted_), noise(noise_), noise_unit(std::move(noise_unit_)) {}
  std::string detector;  // e.g. "top layer"
  std::string name;      // e.g. "abrupt, 45 mm deep"
  std::string quantity;  // what is compared, e.g. "depth below the surface"
  std::string unit;
  double planted = std::numeric_limits<double>::quiet_NaN();  // NaN: nothing planted, "none" expected
  double noise = 0.0;
  std::string noise_unit;
  double tolerance = 0.0;  // |mean - planted| allowed (value cases)
  int replicas = 0, found = 0;
  double mean = std::numeric_limits<double>::quiet_NaN(), sd = std::numeric_limits<double>::quiet_NaN();
  double bias = std::numeric_limits<double>::quiet_NaN();  // mean - planted
  double max_false = 0.1;   // "none" cases: largest fraction of replicas allowed to find something
  double min_found = 0.9;   // value cases: smallest fraction of replicas that must find it
  // intervals: of the replicas that found it and gave one, how many contain
  // the planted value (intervals = 0: the detector gives none)
  int intervals = 0, covered = 0;
  double min_coverage = 0.0;  // judged when > 0: covered / intervals must reach it
  bool judged = true;       // false: shown for comparison (an old definition), or a known limit, not a check
  std::string limit;        // a known limit of the detector (judged = false): what it cannot do here, and why
  bool pass = false;
  std::string note;
  bool expects_none() const { return std::isnan(planted); }
};

// Runs `replica(seed)` for seeds 1..replicas and fills the row's statistics and verdict.
void summarise(Row& row, int replicas, const std::function<Outcome(unsigned)>& replica);

// A stage's metric as an outcome: its value, or none where it is null or absent.
Outcome metric(const nlohmann::ordered_json& m, const char* key);

// A scenario's replicas run once (seeds 1..n); each row then reads what it
// needs of their metrics. Side by side, one thread each; or one after the
// other when `run` uses every thread itself (side_by_side false).
struct Replicas {
  std::vector<nlohmann::ordered_json> metrics;
  Replicas(int n, const std::function<nlohmann::ordered_json(unsigned)>& run, bool side_by_side = true);
  void fill(Row& row, const std::function<Outcome(const nlohmann::ordered_json&)>& read) const;
};

// A stage's power against its found rate, two rows: how often the replicas
// find the planted value (metric `value_key` within `tolerance` of `planted`,
// in `unit`; shown, not judged), and the mean of the power the stage reports
// on every replica (metric `power_key`), judged against that rate within 0.25
// from 10 replicas on (a run's power is near 0 or 1: a mean over a few runs
// scatters by ~0.3), unless `limit` says why it cannot be (then shown only).
std::pair<Row, Row> power_rows(const Replicas& reps, const std::string& detector, const std::string& name, double noise,
                               const std::string& noise_unit, const char* value_key, double planted, double tolerance,
                               const std::string& unit, const char* power_key, const std::string& limit = "");

// A number printed with a printf format, for the cases' names.
std::string fmt(const char* format, double v);

nlohmann::ordered_json to_json(const Row& r);

// What data/planted.toml sweeps (the quick set for make test: fewer replicas and levels).
struct Settings {
  int replicas = 10;
  std::vector<double> drag_noise{0.0125, 0.025, 0.05};  // white noise on the drag, x the load (+ 0.25 N/m)
  std::vector<double> top_depths_mm{20.0, 45.0, 70.0};
  std::vector<double> spacings_d{0.25, 0.5, 1.0};
  std::vector<double> piv_noise{0.0, 0.1, 0.3, 0.5};  // per-grain PIV velocity noise, x V per component
  std::vector<double> piv_noise_beyond{1.0};  // the same, beyond what a run resolves (beta may be undetermined)
  std::vector<double> correlated_piv_noise{0.15, 0.5};  // the same, correlated in space over ...
  std::vector<double> piv_correlation_d{2.0, 5.0};      // ... these lengths, x mean diameter
  std::vector<double> cone_angles_deg{50.0, 60.0, 70.0};
  std::vector<double> intermittent_at_rest{0.3, 0.5, 0.7};  // H_c's power: fraction of snapshots in which nothing moves
  double cone_travel_mm = 0.5;                        // the cg family's cones: a snapshot every this much travel
  double intermittent_travel_mm = 5.0;                // ... in snapshots this far apart
  std::vector<double> wall_lengths_mm{54.0, 78.0, 124.0};
  std::vector<double> asymmetric_cone_deg{50.0, 70.0};  // a cone's left and right edges (degrees)
  std::vector<double> edge_bends{-0.1, 0.3};            // edges that bend (ConeScenario::bend)
  std::vector<double> shape_piv_noise{0.0, 0.3};        // per-grain noise on those two families, x V
  std::vector<double> dilatancy{0.0, -0.01, -0.026, -0.05};
  std::vector<double> position_noise_d{0.0, 0.05, 0.1};  // grain-position noise, x mean diameter
  std::vector<double> percolation_loss_mm{70.0, 100.0};
  std::vector<double> percolation_lapse{0.3, 0.5};  // percolation loss's power: fraction of snapshots without arches
  std::vector<double> spurious_strong{0.0, 0.05, 0.1};  // fraction of contacts made strong at random
  std::vector<double> keystone_fractions{0.0, 0.5, 1.0};
  std::vector<double> stress_force_scatter{0.0, 0.2, 0.5};  // each contact's force scattered, rms x its value
  double piv_travel_mm = 5.0;                // the piv family's frame pairs, one every this much travel
  std::vector<double> piv_swirl{0.25, 1.0};  // planted vortices beside the tips, angular velocity x V / d
};
Settings load_settings(const std::string& path, bool quick);

// Each family of cases runs the stage's own code with its settings file
// (data/<stage>.toml in `data_dir`).
std::vector<Row> drag_cases(const Settings& s, const std::string& data_dir);
std::vector<Row> cg_cases(const Settings& s, const std::string& data_dir);
std::vector<Row> network_cases(const Settings& s, const std::string& data_dir);
std::vector<Row> stress_cases(const Settings& s, const std::string& data_dir);
std::vector<Row> piv_cases(const Settings& s, const std::string& data_dir);

}  // namespace dem2d::planted
