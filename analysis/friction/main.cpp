// friction: friction mobilisation mu* = |F_t| / (mu F_n) in a pull-off run
// (definitions: analysis/friction/README.md).
//   friction PULLOFF_RUN.h5 --out DIR [--config data/friction.toml] [--study data/study.toml]
// Writes DIR/metrics.json ({"friction": {...}}) and DIR/friction.h5, each under
// a temporary name and renamed. Exit codes: 0 done; 1 an output could not be
// written; 2 bad input (run or config file, command line).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "common/output.hpp"
#include "friction/friction.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;
}

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  CLI::App app{"friction: friction mobilisation mu* = |F_t|/(mu F_n) of a dem2d pull-off run: slip fraction, "
               "mean mu* of bulk and wall contacts against the intruder's height"};
  std::string run_path, out_dir, config_path = dem2d::data_file("friction.toml"),
                                 study_path = dem2d::data_file("study.toml");
  app.add_option("run", run_path, "Pull-off run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_dir, "Output directory (metrics.json, friction.h5)")->required();
  app.add_option("--config", config_path, "Settings (TOML)")->capture_default_str();
  app.add_option("--study", study_path, "Study constants (TOML)")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  FrictionResult r;
  try {
    r = run_friction(run_path, config_path, load_friction_config(config_path), load_study(study_path));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "friction: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    r.h5.write(out_dir + "/friction.h5");
    write_file_atomic(out_dir + "/metrics.json", r.metrics.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "friction: %s\n", e.what());
    return kExitFailed;
  }
  const auto& m = r.metrics["friction"];
  const auto show = [](const nlohmann::ordered_json& v) { return v.is_null() ? std::string("n/a") : v.dump(); };
  std::fprintf(stderr, "friction: %s: slip fraction %s, mean mu* lower %s, upper %s -> %s\n", run_path.c_str(),
               show(m["slip_fraction"]).c_str(), show(m["mean_mu_star_lower"]).c_str(),
               show(m["mean_mu_star_upper"]).c_str(), out_dir.c_str());
  return 0;
}
