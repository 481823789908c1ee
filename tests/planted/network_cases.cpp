// Planted truth for the network stage: the percolation-loss height (R4, R10)
// of planted arches to the walls, with random strong contacts as noise; the
// arches never lost or never there (a none, with its power); the power against
// the found rate where the arches lapse at random; keystones ejected at a
// planted fraction of the ruptures (R9).
#include <cmath>
#include <cstdio>

#include "network/network_stage.hpp"
#include "planted/bed_snapshots.hpp"
#include "planted/planted.hpp"

namespace dem2d::planted {

std::vector<Row> network_cases(const Settings& set, const std::string& data_dir) {
  const analysis::NetworkConfig cfg = analysis::load_network_config(data_dir + "/network.toml");
  const analysis::Study study = analysis::load_study(data_dir + "/study.toml");
  const analysis::NetworkInputs names{"planted", data_dir + "/network.toml", "", ""};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto metrics = [&](double loss, double spurious, unsigned seed, double from, double to, double lapse = 0.0) {
    BedGeometry g;
    g.seed = seed, g.start = from;
    NetworkScenario n;
    n.loss = loss, n.spurious = spurious, n.end = to, n.seed = seed, n.lapse = lapse;
    const analysis::MemorySource src = network_run(make_bed(g), n);
    return analysis::run_network(src, {}, nan, names, cfg, study).metrics["network"];
  };
  auto loss_height = [&](double loss, double spurious, unsigned seed, double from, double to) {
    return metric(metrics(loss, spurious, seed, from, to), "percolation_loss_height_mm");
  };
  // where the stage plants the loss whose power it reports: power_depth_end_to_wall x (L_c - L)/2 below the bed
  const nlohmann::ordered_json probe = metrics(1.0, 0.0, 1, 0.080, 0.081);
  const double claim_mm = probe["initial_bed_height_mm"].get<double>() -
                          cfg.power_depth_end_to_wall * probe["end_to_wall_distance_mm"].get<double>();
  std::vector<Row> rows;
  for (const double spurious : set.spurious_strong) {
    for (const double loss_mm : set.percolation_loss_mm) {
      Row r{"percolation loss (R4, R10)", "arches to both walls below " + fmt("%g", loss_mm) + " mm",
            "percolation-loss height", "mm", loss_mm, spurious, "of the contacts strong at random"};
      r.tolerance = 3.0;  // one height bin (1 d)
      r.note = "the intruder from 30 mm below the loss to 20 mm above it";
      summarise(r, set.replicas, [&](unsigned seed) {
        return loss_height(1e-3 * loss_mm, spurious, seed, 1e-3 * (loss_mm - 30.0), 1e-3 * (loss_mm + 20.0));
      });
      rows.push_back(r);
    }
    Row never{"percolation loss (R4, R10)", "arches to both walls at every height: never lost", "percolation-loss height",
              "mm", nan, spurious, "of the contacts strong at random"};
    const Replicas nevers(set.replicas, [&](unsigned seed) { return metrics(1.0, spurious, seed, 0.080, 0.130); });
    nevers.fill(never, [](const auto& m) { return metric(m, "percolation_loss_height_mm"); });
    rows.push_back(never);
    Row sure{"percolation loss (R4, R10)", "never lost: the none's power to see a loss at " + fmt("%.0f", claim_mm) + " mm",
             "power", "-", 1.0, spurious, "of the contacts strong at random"};
    sure.tolerance = 1.0 - cfg.min_power;  // a none here is evidence of absence
    nevers.fill(sure, [](const auto& m) { return metric(m, "percolation_loss_power"); });
    rows.push_back(sure);
    Row none{"percolation loss (R4, R10)", "no arches: never percolating, no loss within the heights seen (80-130 mm)",
             "percolation-loss height", "mm", nan, spurious, "of the contacts strong at random"};
    summarise(none, set.replicas, [&](unsigned seed) { return loss_height(0.0, spurious, seed, 0.080, 0.130); });
    rows.push_back(none);
    // the power against the found rate: arches below the loss at the paper's
    // depth missing in a fraction of the snapshots at random
    for (const double lapse : set.percolation_lapse) {
      const Replicas runs(set.replicas, [&](unsigned seed) {
        return metrics(1e-3 * claim_mm, spurious, seed, 1e-3 * (claim_mm - 30.0), 1e-3 * (claim_mm + 20.0), lapse);
      });
      const std::string name = "lost at " + fmt("%.0f", claim_mm) + " mm, the arches below missing in " +
                               fmt("%g", 100.0 * lapse) + " % of the snapshots";
      const auto [found, power] = power_rows(runs, "percolation-loss power", name, spurious,
                                             "of the contacts strong at random", "percolation_loss_height_mm", claim_mm,
                                             cfg.power_tolerance_d * study.mean_diameter * 1e3, "mm",
                                             "percolation_loss_power");
      rows.push_back(found);
      rows.push_back(power);
    }
    for (const double fraction : set.keystone_fractions) {
      Row k{"keystone ejections (R9)", "20 ruptures, a keystone ejected 1.5 d below the intruder in " + fmt("%g", 100 * fraction) + " %",
            "fraction of ruptures explained", "-", fraction, spurious, "of the contacts strong at random"};
      k.tolerance = 0.1;
      summarise(k, set.replicas, [&](unsigned seed) {
        BedGeometry g;
        g.seed = seed;
        KeystoneScenario ks;
        ks.ejected = fraction, ks.spurious = spurious, ks.seed = seed;
        const KeystoneRun run = keystone_run(make_bed(g), ks);
        return metric(analysis::run_network(run.source, run.events, nan, names, cfg, study).metrics["network"],
                      "keystone_explained_fraction");
      });
      rows.push_back(k);
    }
  }
  return rows;
}

}  // namespace dem2d::planted
