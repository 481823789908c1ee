// network: the contact force network of a pull-off run (definitions:
// analysis/network/README.md).
//   network PULLOFF_RUN.h5 --out DIR [--config data/network.toml] [--events SPECTRUM.h5]
//           [--spectrum-metrics SPECTRUM_DIR/metrics.json] [--study data/study.toml]
// Writes DIR/metrics.json ({"network": {...}}) and DIR/network.h5, each under
// a temporary name and renamed. Exit codes (common/stage_main.hpp): 0 done; 1
// an output could not be written; 2 bad input (run, events, metrics or config
// file, command line).
#include "common/output.hpp"
#include "common/stage_main.hpp"
#include "network/network_stage.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("network",
                   "force-network percolation from the intruder to the walls, anisotropy and keystones of a dem2d "
                   "pull-off run (without an intruder: wall-to-wall spanning, fabric, loads on floor and walls)",
                   "Run file (HDF5) written by dem2d", "Output directory (metrics.json, network.h5)");
  cmd.add_config("network.toml");
  cmd.add_study();
  NetworkInputs in;
  cmd.add_option("--events", in.events, "Events of the spectrum stage (its spectrum.h5, /events)");
  cmd.add_option("--spectrum-metrics", in.spectrum_metrics, "metrics.json of the spectrum stage (top layer height)");
  return cmd.main(
      argc, argv,
      [&] {
        in.run = cmd.run;
        in.config = cmd.config;
        return run_network(in, load_network_config(cmd.config), load_study(cmd.study));
      },
      [&](const NetworkResult& r) {
        r.h5.write(cmd.out + "/network.h5");
        write_file_atomic(cmd.out + "/metrics.json", r.metrics.dump(2) + "\n");
        const auto& m = r.metrics["network"];
        if (!m.value("intruder", true))
          return "no intruder: strong network spans wall to wall in " + show_metric(m["spanning_fraction"]) +
                 " of the snapshots; at the end the side walls carry " + show_metric(m["final"]["wall_load_fraction"]) +
                 " of the load";
        const std::string loss = m["percolation_loss_height_mm"].is_null()
                                     ? "percolation loss " + m["percolation_loss_outcome"].get<std::string>()
                                     : "percolation lost above " + show_metric(m["percolation_loss_height_mm"]) + " mm";
        return loss + ", percolating below the top layer " + show_metric(m["percolating_fraction_below_top_layer"]) +
               ", top-layer anisotropy " + show_metric(m["top_layer_anisotropy"]) + ", keystone-explained fraction " +
               show_metric(m["keystone_explained_fraction"]);
      });
}
