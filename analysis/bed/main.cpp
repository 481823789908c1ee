// bed_metrics: the bed left by the filling stage, measured on the last
// snapshot of a dem2d run file (definitions: analysis/bed/README.md).
//   bed_metrics RUN.h5 --out METRICS.json [--config FILE.toml]
// Exit codes: 0 done; 1 the output could not be written; 2 bad input (missing,
// corrupt or unsuitable run file, bad config, bad command line).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "bed/bed_metrics.hpp"
#include "common/output.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;
}

int main(int argc, char** argv) {
  CLI::App app{"bed_metrics: free-surface height, bulk solid fraction, coordination number, largest overlap "
               "and kinetic energy of the last snapshot of a dem2d run file"};
  std::string run_path, out_path, config_path = dem2d::data_file("bed_metrics.toml");
  app.add_option("run", run_path, "Run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_path, "Metrics file to write (JSON)")->required();
  app.add_option("--config", config_path, "Settings (TOML)")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  nlohmann::ordered_json metrics;
  try {
    metrics = dem2d::analysis::measure_run_file(run_path, dem2d::analysis::load_bed_config(config_path), config_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bed_metrics: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    dem2d::analysis::write_file_atomic(out_path, metrics.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bed_metrics: %s\n", e.what());
    return kExitFailed;
  }
  const auto& f = metrics["fill"];
  std::fprintf(stderr, "bed_metrics: %s: solid fraction %.4f, bed height %.2f mm, coordination %.3f -> %s\n",
               run_path.c_str(), f["solid_fraction"].get<double>(), f["bed_height_mm"].get<double>(),
               f["coordination_number"].get<double>(), out_path.c_str());
  return 0;
}
