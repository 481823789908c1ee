// stress: the coarse-grained stress of a dem2d run (definitions: analysis/stress/README.md).
//   stress RUN.h5 --out DIR [--config data/stress.toml] [--study data/study.toml] [--threads N]
// Writes DIR/metrics.json ({"stress": {...}}) and DIR/stress.h5, each under a
// temporary name and renamed. Exit codes (common/stage_main.hpp): 0 done; 1 an
// output could not be written; 2 bad input (run or config file, command line).
#include "common/output.hpp"
#include "common/stage_main.hpp"
#include "stress/stress_stage.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("stress",
                   "coarse-grained stress (contact + kinetic, Weinhart's branch-integrated kernel) of a dem2d run: "
                   "pressure and shear maps, the bed's stress at rest, and the force the stress carries onto a "
                   "body (the intruder by default) against the recorded one",
                   "Run file (HDF5) written by dem2d", "Output directory (metrics.json, stress.h5)");
  cmd.add_config("stress.toml");
  cmd.add_study();
  int threads = 0;
  cmd.add_threads(threads, "OpenMP threads across snapshots (0: OpenMP's default); results do not depend on it");
  return cmd.main(
      argc, argv,
      [&] { return run_stress(cmd.run, cmd.config, load_stress_config(cmd.config), load_study(cmd.study), threads); },
      [&](const StressResult& r) {
        r.h5.write(cmd.out + "/stress.h5");
        write_file_atomic(cmd.out + "/metrics.json", r.metrics.dump(2) + "\n");
        const auto& m = r.metrics["stress"];
        const auto& c = m["force_check"];
        return "force on the " + m["body_role"].get<std::string>() + " from the stress: " +
               c["verdict"].get<std::string>() + " (mean " + show_metric(c["mean_stress_n"]) + " against " +
               show_metric(c["mean_recorded_n"]) + " N/m recorded, inertia share " + show_metric(c["inertia_share"]) + ")";
      });
}
