// pulloff_metrics: the drag on the intruder along a pull-off run and the
// run's summary (analysis/pulloff/drag_profile.hpp for the definitions).
//   pulloff_metrics RUN.h5 --out METRICS.json [--csv DRAG.csv] [--bed FILL_RUN.h5] [--study data/study.toml]
//                   [--cycles CYCLES.csv]   (a cyclic run: analysis/pulloff/drag_cycles.hpp)
// Exit codes (common/stage_main.hpp): 0 done; 1 an output could not be written; 2 bad input.
#include <cstdio>

#include "common/output.hpp"
#include "common/stage_main.hpp"
#include "pulloff/drag_cycles.hpp"
#include "pulloff/drag_profile.hpp"

namespace {
struct Result {
  nlohmann::ordered_json metrics;
  std::string csv, cycles_csv;
};
}  // namespace

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("pulloff_metrics", "drag force against intruder height, and the pull-off's summary",
                   "Pull-off run file (HDF5) written by dem2d", "Metrics file to write (JSON)");
  cmd.add_study();
  std::string csv_path, bed_path, cycles_path;
  cmd.app().add_option("--csv", csv_path, "Also write the drag profile: time_s,height_mm,drag_N_per_m,drag_N");
  cmd.app().add_option("--bed", bed_path, "The run the pull-off started from (the fill): the intruder's load at rest");
  cmd.app().add_option("--cycles", cycles_path,
                       "A cyclic run: cut the drag into up and down legs, write them (cycle,direction,time_s,"
                       "height_mm,drag_N_per_m) and add pulloff.cycles to the metrics");
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
        if (!cycles_path.empty()) {
          const std::vector<DragLeg> legs = drag_legs(profile);
          r.metrics["pulloff"]["cycles"] = cycle_metrics(profile, legs);
          r.cycles_csv = cycles_csv(profile, legs);
        }
        return r;
      },
      [&](const Result& r) {
        if (!csv_path.empty()) write_file_atomic(csv_path, r.csv);
        if (!cycles_path.empty()) write_file_atomic(cycles_path, r.cycles_csv);
        write_file_atomic(cmd.out, r.metrics.dump(2) + "\n");
        const auto& m = r.metrics["pulloff"];
        char line[200];
        std::snprintf(line, sizeof line, "travel %.1f mm, max drag %.3g N/m (%.3g N) at %.1f mm",
                      m["travel_mm"].get<double>(), m["drag_max_N_per_m"].get<double>(), m["drag_max_N"].get<double>(),
                      m["height_at_drag_max_mm"].get<double>());
        return std::string(line);
      });
}
