// bed_metrics: the bed left by the filling stage, measured on the last
// snapshot of a dem2d run file (definitions: analysis/bed/README.md).
//   bed_metrics RUN.h5 --out DIR [--config FILE.toml]        writes DIR/metrics.json
// Exit codes (common/stage_main.hpp): 0 done; 1 the output could not be
// written; 2 bad input (missing, corrupt or unsuitable run file, bad config,
// bad command line).
#include <cstdio>

#include "bed/bed_metrics.hpp"
#include "common/output.hpp"
#include "common/stage_main.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("bed_metrics",
                   "free-surface height, bulk solid fraction, coordination number, largest overlap and kinetic "
                   "energy of the last snapshot of a dem2d run file",
                   "Run file (HDF5) written by dem2d", "Output directory: metrics.json");
  cmd.add_config("bed_metrics.toml");
  return cmd.main(
      argc, argv, [&] { return measure_run_file(cmd.run, load_bed_config(cmd.config), cmd.config); },
      [&](const nlohmann::ordered_json& metrics) {
        write_file_atomic(cmd.out + "/metrics.json", metrics.dump(2) + "\n");
        const auto& f = metrics["fill"];
        char line[200];
        std::snprintf(line, sizeof line, "solid fraction %.4f, bed height %.2f mm, coordination %.3f",
                      f["solid_fraction"].get<double>(), f["bed_height_mm"].get<double>(),
                      f["coordination_number"].get<double>());
        return std::string(line);
      });
}
