// friction: friction mobilisation mu* = |F_t| / (mu F_n) in a pull-off run
// (definitions: analysis/friction/README.md).
//   friction PULLOFF_RUN.h5 --out DIR [--config data/friction.toml] [--study data/study.toml]
// Writes DIR/metrics.json ({"friction": {...}}) and DIR/friction.h5, each under
// a temporary name and renamed. Exit codes (common/stage_main.hpp): 0 done; 1
// an output could not be written; 2 bad input (run or config file, command line).
#include "common/output.hpp"
#include "common/stage_main.hpp"
#include "friction/friction.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("friction",
                   "friction mobilisation mu* = |F_t|/(mu F_n) of a dem2d pull-off run: slip fraction, mean mu* of "
                   "bulk and wall contacts against the intruder's height (without an intruder: over the run and "
                   "against depth)",
                   "Run file (HDF5) written by dem2d", "Output directory (metrics.json, friction.h5)");
  cmd.add_config("friction.toml");
  cmd.add_study();
  return cmd.main(
      argc, argv,
      [&] { return run_friction(cmd.run, cmd.config, load_friction_config(cmd.config), load_study(cmd.study)); },
      [&](const FrictionResult& r) {
        r.h5.write(cmd.out + "/friction.h5");
        write_file_atomic(cmd.out + "/metrics.json", r.metrics.dump(2) + "\n");
        const auto& m = r.metrics["friction"];
        if (!m.value("intruder", true))
          return "no intruder: slip fraction " + show_metric(m["slip_fraction"]) + ", mean mu* bulk " +
                 show_metric(m["mean_mu_star_bulk"]) + ", walls " + show_metric(m["mean_mu_star_wall"]);
        return "slip fraction " + show_metric(m["slip_fraction"]) + ", mean mu* lower " + show_metric(m["mean_mu_star_lower"]) +
               ", upper " + show_metric(m["mean_mu_star_upper"]);
      });
}
