// Planted truth for the network stage: the percolation-loss height (R4, R10)
// of planted arches to the walls, with random strong contacts as noise; the
// arches never lost or never there; keystones ejected at a planted fraction
// of the ruptures (R9).
#include <cstdio>

#include "network/network_stage.hpp"
#include "planted/bed_snapshots.hpp"
#include "planted/planted.hpp"

namespace dem2d::planted {

namespace {

Outcome number(const nlohmann::ordered_json& m, const char* key) {
  const auto& v = m[key];
  return v.is_number() ? Outcome{true, v.get<double>()} : Outcome{};
}

}  // namespace

std::vector<Row> network_cases(const Settings& set, const std::string& data_dir) {
  const analysis::NetworkConfig cfg = analysis::load_network_config(data_dir + "/network.toml");
  const analysis::Study study = analysis::load_study(data_dir + "/study.toml");
  const analysis::NetworkInputs names{"planted", data_dir + "/network.toml", "", ""};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto loss_height = [&](double loss, double spurious, unsigned seed, double from, double to) {
    BedGeometry g;
    g.seed = seed, g.start = from;
    NetworkScenario n;
    n.loss = loss, n.spurious = spurious, n.end = to, n.seed = seed;
    const analysis::MemorySource src = network_run(make_bed(g), n);
    return number(analysis::run_network(src, {}, nan, names, cfg, study).metrics["network"], "percolation_loss_height_mm");
  };
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
    summarise(never, set.replicas, [&](unsigned seed) { return loss_height(1.0, spurious, seed, 0.080, 0.130); });
    rows.push_back(never);
    Row none{"percolation loss (R4, R10)", "no arches: lost from the start (80 mm)", "percolation-loss height", "mm",
             80.0, spurious, "of the contacts strong at random"};
    none.tolerance = 3.0;
    summarise(none, set.replicas, [&](unsigned seed) { return loss_height(0.0, spurious, seed, 0.080, 0.130); });
    rows.push_back(none);
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
        return number(analysis::run_network(run.source, run.events, nan, names, cfg, study).metrics["network"],
                      "keystone_explained_fraction");
      });
      rows.push_back(k);
    }
  }
  return rows;
}

}  // namespace dem2d::planted
