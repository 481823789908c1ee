// network: the contact force network of a pull-off run (definitions:
// analysis/network/README.md).
//   network PULLOFF_RUN.h5 --out DIR [--config data/network.toml] [--events SPECTRUM.h5]
//           [--spectrum-metrics SPECTRUM_DIR/metrics.json] [--study data/study.toml]
// Writes DIR/metrics.json ({"network": {...}}) and DIR/network.h5, each under
// a temporary name and renamed. Exit codes: 0 done; 1 an output could not be
// written; 2 bad input (run, events, metrics or config file, command line).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "common/output.hpp"
#include "network/network_stage.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;
}

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  CLI::App app{"network: force-network percolation from the intruder to the walls, anisotropy and keystones "
               "of a dem2d pull-off run"};
  NetworkInputs in;
  std::string out_dir, study_path = dem2d::data_file("study.toml");
  in.config = dem2d::data_file("network.toml");
  app.add_option("run", in.run, "Pull-off run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_dir, "Output directory (metrics.json, network.h5)")->required();
  app.add_option("--config", in.config, "Settings (TOML)")->capture_default_str();
  app.add_option("--events", in.events, "Events of the spectrum stage (HDF5 with /events/...)");
  app.add_option("--spectrum-metrics", in.spectrum_metrics, "metrics.json of the spectrum stage (top layer height)");
  app.add_option("--study", study_path, "Study constants (TOML)")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  NetworkResult r;
  try {
    r = run_network(in, load_network_config(in.config), load_study(study_path));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "network: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    r.h5.write(out_dir + "/network.h5");
    write_file_atomic(out_dir + "/metrics.json", r.metrics.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "network: %s\n", e.what());
    return kExitFailed;
  }
  const auto& m = r.metrics["network"];
  const auto show = [](const nlohmann::ordered_json& v) { return v.is_null() ? std::string("n/a") : v.dump(); };
  std::fprintf(stderr,
               "network: %s: percolation lost above %s mm, percolating below the top layer %s, top-layer "
               "anisotropy %s, keystone-explained fraction %s -> %s\n",
               in.run.c_str(), show(m["percolation_loss_height_mm"]).c_str(),
               show(m["percolating_fraction_below_top_layer"]).c_str(), show(m["top_layer_anisotropy"]).c_str(),
               show(m["keystone_explained_fraction"]).c_str(), out_dir.c_str());
  return 0;
}
