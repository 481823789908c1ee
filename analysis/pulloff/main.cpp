// pulloff_metrics: the drag on the intruder along a pull-off run and the
// run's summary (analysis/pulloff/drag_profile.hpp for the definitions).
//   pulloff_metrics RUN.h5 --out METRICS.json [--csv DRAG.csv] [--bed FILL_RUN.h5] [--study data/study.toml]
//                   [--cycles CYCLES.csv]   (a cyclic run: analysis/pulloff/drag_cycles.hpp)
// Exit codes: 0 done; 1 an output could not be written; 2 bad input.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "common/output.hpp"
#include "pulloff/drag_cycles.hpp"
#include "pulloff/drag_profile.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;
}

int main(int argc, char** argv) {
  CLI::App app{"pulloff_metrics: drag force against intruder height, and the pull-off's summary"};
  std::string run_path, out_path, csv_path, bed_path, cycles_path, study_path = dem2d::data_file("study.toml");
  app.add_option("run", run_path, "Pull-off run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_path, "Metrics file to write (JSON)")->required();
  app.add_option("--csv", csv_path, "Also write the drag profile: time_s,height_mm,drag_N_per_m,drag_N");
  app.add_option("--bed", bed_path, "The run the pull-off started from (the fill): the intruder's load at rest");
  app.add_option("--study", study_path, "The study's constants (TOML)")->capture_default_str();
  app.add_option("--cycles", cycles_path,
                 "A cyclic run: cut the drag into up and down legs, write them (cycle,direction,time_s,height_mm,"
                 "drag_N_per_m) and add pulloff.cycles to the metrics");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  using namespace dem2d::analysis;
  nlohmann::ordered_json metrics;
  std::string csv, cycles_csv_text;
  try {
    const Study study = load_study(study_path);
    const dem2d::RunReader run(run_path);
    const DragProfile profile = read_drag_profile(run);
    if (bed_path.empty()) {
      metrics = pulloff_metrics(run, profile, study);
    } else {
      const dem2d::RunReader bed(bed_path);
      metrics = pulloff_metrics(run, profile, study, &bed);
    }
    csv = drag_csv(profile, study);
    if (!cycles_path.empty()) {
      const std::vector<DragLeg> legs = drag_legs(profile);
      metrics["pulloff"]["cycles"] = cycle_metrics(profile, legs);
      cycles_csv_text = cycles_csv(profile, legs);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pulloff_metrics: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    if (!csv_path.empty()) write_file_atomic(csv_path, csv);
    if (!cycles_path.empty()) write_file_atomic(cycles_path, cycles_csv_text);
    write_file_atomic(out_path, metrics.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pulloff_metrics: %s\n", e.what());
    return kExitFailed;
  }
  const auto& m = metrics["pulloff"];
  std::fprintf(stderr, "pulloff_metrics: %s: travel %.1f mm, max drag %.3g N/m (%.3g N) at %.1f mm -> %s\n",
               run_path.c_str(), m["travel_mm"].get<double>(), m["drag_max_N_per_m"].get<double>(),
               m["drag_max_N"].get<double>(), m["height_at_drag_max_mm"].get<double>(), out_path.c_str());
  return 0;
}
