// pulloff_metrics: the drag on the intruder along a pull-off run and the
// run's summary (pulloff_metrics.hpp; drag and height: analysis/frame/drag_profile.hpp).
//   pulloff_metrics RUN.h5 --out DIR [--bed FILL_RUN.h5] [--study data/study.toml] [--cycles]
// writes DIR/metrics.json and DIR/drag.csv, and with --cycles (a cyclic run:
// analysis/pulloff/drag_cycles.hpp) DIR/cycles.csv.
// Exit codes (common/stage_main.hpp): 0 done; 1 an output could not be written; 2 bad input.
#include <cstdio>

#include "common/output.hpp"
#include "common/stage_main.hpp"
#include "pulloff/drag_cycles.hpp"
#include "pulloff/pulloff_metrics.hpp"

namespace {
struct Result {
  nlohmann::ordered_json metrics;
  std::string csv, cycles_csv;
};
}  // namespace

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("pulloff_metrics", "drag force against intruder height, and the pull-off's summary",
                   "Pull-off run file (HDF5) written by dem2d",
                   "Output directory: metrics.json, drag.csv (time_s,height_mm,drag_N_per_m,drag_N)");
  cmd.add_study();
  std::string bed_path;
  bool cycles = false;
  cmd.add_option("--bed", bed_path, "The run the pull-off started from (the fill): the intruder's load at rest");
  cmd.add_flag("--cycles", cycles,
               "A cyclic run: cut the drag into up and down legs, write them to DIR/cycles.csv (cycle,"
               "direction,time_s,height_mm,drag_N_per_m) and add pulloff.cycles to the metrics");
  return cmd.main(
      argc, argv,
      [&] {
        Result r;
        const Study study = load_study(cmd.study);
        const dem2d::RunReader run(cmd.run);
        const DragProfile profile = read_drag_profile(run);
        if (bed_path.empty()) {
          r.metrics = pulloff_metrics(run, profile, study);
        } else {
          const dem2d::RunReader bed(bed_path);
          r.metrics = pulloff_metrics(run, profile, study, &bed);
        }
        r.csv = drag_csv(profile, study);
        if (cycles) {
          const std::vector<DragLeg> legs = drag_legs(profile);
          r.metrics["pulloff"]["cycles"] = cycle_metrics(profile, legs);
          r.cycles_csv = cycles_csv(profile, legs);
        }
        return r;
      },
      [&](const Result& r) {
        write_file_atomic(cmd.out + "/drag.csv", r.csv);
        if (cycles) write_file_atomic(cmd.out + "/cycles.csv", r.cycles_csv);
        write_file_atomic(cmd.out + "/metrics.json", r.metrics.dump(2) + "\n");
        const auto& m = r.metrics["pulloff"];
        char line[200];
        std::snprintf(line, sizeof line, "travel %.1f mm, max drag %.3g N/m (%.3g N) at %.1f mm",
                      m["travel_mm"].get<double>(), m["drag_max_N_per_m"].get<double>(), m["drag_max_N"].get<double>(),
                      m["height_at_drag_max_mm"].get<double>());
        return std::string(line);
      });
}
