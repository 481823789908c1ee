// Stage `friction`: friction mobilisation mu* = |F_t| / (mu F_n) at every
// contact of a pull-off run, the slip fraction and the mean mu* of bulk and
// wall contacts against the intruder's height (R7, R8 in docs/paper.md; paper Fig. 12, 13).
// Definitions and reasons: analysis/friction/README.md. SI units (m, N/m).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/stage_output.hpp"
#include "contact/contact_law.hpp"
#include "frame/height_bins.hpp"
#include "frame/pulloff_frame.hpp"
#include "frame/study.hpp"
#include "runfile/run_parameters.hpp"

namespace dem2d::analysis {

// The run's contact laws as far as mu* needs them: the Coulomb coefficient mu
// (coefficient `mu`) and what sets the load that caps friction
// (contact/contact_law.hpp: friction_load), for grain-grain and grain-body
// (walls, floor, intruder) contacts, under the run's effects.
struct FrictionLaws {
  EffectSet effects = effect::friction;
  LawCoefficients grain, wall;
};

// From the run's /parameters (runfile/run_parameters.hpp); mu_grain, mu_wall (if
// given) replace the laws' Coulomb coefficients. StageError "<where>: ..." if
// the run has no friction and none is given.
FrictionLaws friction_laws(const RunParameters& run, std::optional<double> mu_grain, std::optional<double> mu_wall,
                           const std::string& where);

// mu* per contact: |ft| / (mu F_load), the engine's own ratio (the run file's
// mu_star), with mu and F_load of the contact's law: F_load = fn plus what
// the law's terms pull with (cohesion's f_c) for a touching contact; NaN
// where F_load <= 0 (no load) or the contact acts across a gap (no friction):
// excluded.
std::vector<double> mu_star(const Contacts& c, const std::vector<Partner>& partners, const FrictionLaws& laws);

// The contacts of one snapshot summarised. Groups: bulk = grain-grain, wall =
// grain-side wall (left, right); floor and intruder separately; all = every
// contact with fn > 0 (including any other body).
struct MuStarMean {
  double sum = 0.0;
  std::int64_t count = 0;
  void add(double v) { sum += v, ++count; }
  double mean() const { return count > 0 ? sum / static_cast<double>(count) : std::numeric_limits<double>::quiet_NaN(); }
};
struct SnapshotFriction {
  std::int64_t rows = 0;     // contacts in the run file (overlap > 0)
  std::int64_t zero_fn = 0;  // of which fn <= 0: excluded from everything below
  std::vector<std::int64_t> slipping;  // per threshold: contacts with mu* >= threshold
  std::int64_t sliding_flag = 0;       // contacts with fn > 0 flagged `sliding` by the engine
  MuStarMean bulk, wall, floor, intruder, all;
  double slip_fraction(std::size_t t) const {
    return all.count > 0 ? static_cast<double>(slipping[t]) / static_cast<double>(all.count)
                         : std::numeric_limits<double>::quiet_NaN();
  }
};
SnapshotFriction summarise_friction(const Contacts& c, const std::vector<Partner>& partners,
                                    const std::vector<double>& mu_star, const std::vector<double>& thresholds);

struct FrictionConfig {
  double slip_threshold = 0.99;        // slipping: mu* >= this
  double cone_angle_deg = 60.0;        // H_c = (L_c - L) / 2 tan(beta), from the run's cell and intruder
  std::optional<double> critical_height_mm;  // H_c given directly (overrides the cone angle)
  double lower_band_top = 0.5;         // lower part: intruder height < this x H_c
  double bin_width_d = 1.0;            // height bins of the mu* curves (mean diameters)
  std::int64_t histogram_bins = 50;    // mu* histogram over [0, 1]
  std::int64_t figure_every = 20;      // per-contact data every k-th snapshot
  std::optional<double> mu_grain, mu_wall;  // override the scene's coefficients
  std::vector<double> sensitivity_slip_threshold = {0.95, 0.99, 0.999};
  std::vector<double> sensitivity_lower_band_top = {0.25, 0.5, 0.75};
};
FrictionConfig load_friction_config(const std::string& path);
nlohmann::ordered_json to_json(const FrictionConfig& c);

struct FrictionResult {
  nlohmann::ordered_json metrics;  // {"friction": {...}}
  H5Output h5;                     // friction.h5
};
// StageError / std::runtime_error naming the file on bad input.
FrictionResult run_friction(const std::string& run_path, const std::string& config_path, const FrictionConfig& cfg,
                            const Study& study);

}  // namespace dem2d::analysis
