#include "planted/planted.hpp"

#include <cstdio>
#include <numeric>

#include "common/stage_config.hpp"

namespace dem2d::planted {

std::string fmt(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

void summarise(Row& row, int replicas, const std::function<Outcome(unsigned)>& replica) {
  row.replicas = replicas;
  // replicas side by side; each depends on its seed only
  std::vector<Outcome> outcomes(static_cast<std::size_t>(replicas));
#pragma omp parallel for schedule(dynamic, 1)
  for (int r = 1; r <= replicas; ++r) outcomes[static_cast<std::size_t>(r - 1)] = replica(static_cast<unsigned>(r));
  std::vector<double> values;
  for (const Outcome& o : outcomes)
    if (o.found && std::isfinite(o.value)) values.push_back(o.value);
  row.found = static_cast<int>(values.size());
  for (const Outcome& o : outcomes)
    if (o.found && std::isfinite(o.value) && std::isfinite(o.low) && std::isfinite(o.high)) {
      ++row.intervals;
      row.covered += o.low <= row.planted && row.planted <= o.high;
    }
  if (!values.empty()) {
    const double n = static_cast<double>(values.size());
    row.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
    double ss = 0.0;
    for (const double v : values) ss += (v - row.mean) * (v - row.mean);
    row.sd = values.size() > 1 ? std::sqrt(ss / (n - 1.0)) : 0.0;
  }
  const double found_fraction = static_cast<double>(row.found) / static_cast<double>(replicas);
  if (!row.judged) {
    row.pass = true;
    if (!row.expects_none()) row.bias = row.mean - row.planted;
  } else if (row.expects_none()) {
    row.pass = found_fraction <= row.max_false;
  } else {
    row.bias = row.mean - row.planted;
    // where found, it must be right; found often enough (a case may require nothing)
    row.pass = found_fraction >= row.min_found && (row.found == 0 || std::abs(row.bias) <= row.tolerance);
    if (row.min_coverage > 0.0 && row.intervals > 0)
      row.pass = row.pass && static_cast<double>(row.covered) >= row.min_coverage * static_cast<double>(row.intervals);
  }
}

Outcome metric(const nlohmann::ordered_json& m, const char* key) {
  const auto& v = m[key];
  return v.is_number() ? Outcome{true, v.get<double>()} : Outcome{};
}

Replicas::Replicas(int n, const std::function<nlohmann::ordered_json(unsigned)>& run, bool side_by_side)
    : metrics(static_cast<std::size_t>(n)) {
#pragma omp parallel for schedule(dynamic, 1) if (side_by_side)
  for (int r = 1; r <= n; ++r) metrics[static_cast<std::size_t>(r - 1)] = run(static_cast<unsigned>(r));
}

void Replicas::fill(Row& row, const std::function<Outcome(const nlohmann::ordered_json&)>& read) const {
  summarise(row, static_cast<int>(metrics.size()), [&](unsigned seed) { return read(metrics[seed - 1]); });
}

std::pair<Row, Row> power_rows(const Replicas& reps, const std::string& detector, const std::string& name, double noise,
                               const std::string& noise_unit, const char* value_key, double planted, double tolerance,
                               const std::string& unit, const char* power_key, const std::string& limit) {
  Row found{detector, name + ": how often it is found", "found fraction", "-", 1.0, noise, noise_unit};
  found.judged = false;
  found.note = "the found fraction is the mean (1: within " + fmt("%g", tolerance) + " " + unit + " of " +
               fmt("%.1f", planted) + " " + unit + ", 0: not)";
  reps.fill(found, [&](const auto& m) {
    const Outcome h = metric(m, value_key);
    return Outcome{true, h.found && std::abs(h.value - planted) <= tolerance ? 1.0 : 0.0};
  });
  Row power{detector, name + ": the power the stage reports", "estimated power", "-", found.mean, noise, noise_unit};
  power.tolerance = 0.25;
  power.judged = reps.metrics.size() >= 10 && limit.empty();
  power.limit = limit;
  power.note = "planted: the found fraction of the row above; the power is the stage's, on every replica (it reads a "
               "miss by it)";
  reps.fill(power, [&](const auto& m) { return metric(m, power_key); });
  return {found, power};
}

nlohmann::ordered_json to_json(const Row& r) {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  return {{"detector", r.detector},   {"case", r.name},           {"quantity", r.quantity},
          {"unit", r.unit},           {"planted", num(r.planted)}, {"noise", r.noise},
          {"noise_unit", r.noise_unit}, {"replicas", r.replicas},   {"found", r.found},
          {"mean", num(r.mean)},      {"sd", num(r.sd)},           {"bias", num(r.bias)},
          {"tolerance", r.tolerance}, {"max_false", r.max_false},  {"min_found", r.min_found},
          {"intervals", r.intervals}, {"covered", r.covered},     {"min_coverage", r.min_coverage},
          {"judged", r.judged},       {"pass", r.pass},            {"note", r.note},
          {"limit", r.limit}};
}

Settings load_settings(const std::string& path, bool quick) {
  Settings s;
  analysis::StageConfig file(path);
  auto read = [&](analysis::StageConfig t) {
    t.integer("replicas", s.replicas, 1, 10000, "replicas per case");
    t.numbers("drag_noise", s.drag_noise, 0.0, 10.0, "rms, x the load");
    t.numbers("top_depths_mm", s.top_depths_mm, 0.0, 1e4, "mm");
    t.numbers("spacings_d", s.spacings_d, 0.0, 100.0, "d", analysis::StageConfig::Ends::open_low);
    t.numbers("piv_noise", s.piv_noise, 0.0, 100.0, "x V per component");
    t.numbers("piv_noise_beyond", s.piv_noise_beyond, 0.0, 100.0, "x V per component");
    t.numbers("correlated_piv_noise", s.correlated_piv_noise, 0.0, 100.0, "x V per component");
    t.numbers("piv_correlation_d", s.piv_correlation_d, 0.0, 100.0, "x mean diameter", analysis::StageConfig::Ends::open_low);
    t.numbers("intermittent_at_rest", s.intermittent_at_rest, 0.0, 1.0, "fraction of snapshots", analysis::StageConfig::Ends::open_high);
    t.number("cone_travel_mm", s.cone_travel_mm, 0.0, 1e3, "mm", analysis::StageConfig::Ends::open_low);
    t.number("intermittent_travel_mm", s.intermittent_travel_mm, 0.0, 1e3, "mm", analysis::StageConfig::Ends::open_low);
    t.numbers("cone_angles_deg", s.cone_angles_deg, 0.0, 90.0, "degrees", analysis::StageConfig::Ends::open);
    t.numbers("wall_lengths_mm", s.wall_lengths_mm, 0.0, 1e4, "mm", analysis::StageConfig::Ends::open_low);
    t.numbers("asymmetric_cone_deg", s.asymmetric_cone_deg, 0.0, 90.0, "degrees", analysis::StageConfig::Ends::open);
    t.numbers("edge_bends", s.edge_bends, -1.0, 1.0, "bend");
    t.numbers("shape_piv_noise", s.shape_piv_noise, 0.0, 100.0, "x V per component");
    t.numbers("dilatancy", s.dilatancy, -0.5, 0.5, "solid fraction change");
    t.numbers("position_noise_d", s.position_noise_d, 0.0, 10.0, "x mean diameter");
    t.numbers("percolation_loss_mm", s.percolation_loss_mm, 0.0, 1e4, "mm", analysis::StageConfig::Ends::open_low);
    t.numbers("percolation_lapse", s.percolation_lapse, 0.0, 1.0, "fraction of snapshots", analysis::StageConfig::Ends::open_high);
    t.numbers("spurious_strong", s.spurious_strong, 0.0, 1.0, "fraction of contacts");
    t.numbers("keystone_fractions", s.keystone_fractions, 0.0, 1.0, "fraction of ruptures");
    t.numbers("stress_force_scatter", s.stress_force_scatter, 0.0, 10.0, "rms, x each contact's force");
    t.number("piv_travel_mm", s.piv_travel_mm, 0.0, 1e3, "mm", analysis::StageConfig::Ends::open_low);
    t.numbers("piv_swirl", s.piv_swirl, 0.0, 100.0, "x V / d", analysis::StageConfig::Ends::open_low);
    t.reject_unknown();
  };
  read(file.table("full"));
  if (quick) read(file.table("quick"));
  else file.table("quick");
  file.reject_unknown();
  if (s.asymmetric_cone_deg.size() != 2)
    throw analysis::StageError(path + ": asymmetric_cone_deg has " + std::to_string(s.asymmetric_cone_deg.size()) +
                               " values: must be two angles, the left edge's and the right edge's");
  return s;
}

}  // namespace dem2d::planted
