// cg: coarse-grained velocity and solid-fraction fields of a pull-off run, the
// mobility zones, the cone angle, the wall-mobility length and the dilatancy
// at the onset (definitions: analysis/cg/README.md).
//   cg PULLOFF_RUN.h5 --out DIR [--config data/cg.toml] [--events SPECTRUM.h5] [--study data/study.toml] [--threads N]
// writes DIR/metrics.json ({"cg": {...}}) and DIR/cg.h5.
// Exit codes: 0 done; 1 an output could not be written; 2 bad input (run,
// events or config file, command line).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "cg/cg_stage.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;

std::string show(const nlohmann::ordered_json& v, const char* unit) {
  if (v.is_null()) return "n/a";
  char b[48];
  std::snprintf(b, sizeof b, "%.4g%s", v.get<double>(), unit);
  return b;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cg: coarse-grained fields of a pull-off run; mobility zones, cone angle, wall-mobility length, "
               "dilatancy"};
  dem2d::analysis::CgInput in;
  std::string out_dir, study_path = dem2d::data_file("study.toml");
  in.config_path = dem2d::data_file("cg.toml");
  app.add_option("run", in.run_path, "Pull-off run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_dir, "Output directory: metrics.json and cg.h5")->required();
  app.add_option("--config", in.config_path, "Settings (TOML)")->capture_default_str();
  app.add_option("--events", in.events_path, "Loading/rupture events of the spectrum stage (HDF5, /events/...)");
  app.add_option("--study", study_path, "The study's constants and body names (TOML)")->capture_default_str();
  app.add_option("--threads", in.threads, "OpenMP threads across snapshots (0: OpenMP's default); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  using namespace dem2d::analysis;
  CgResult result;
  try {
    in.study = load_study(study_path);
    in.config = load_cg_config(in.config_path);
    result = compute_cg(in);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cg: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    write_cg(result, out_dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cg: %s\n", e.what());
    return kExitFailed;
  }
  const auto& m = result.metrics["cg"];
  std::fprintf(stderr,
               "cg: %s: %zu snapshots, %s velocities, %s: cone angle %s (%zu of %zu edges narrow, left out; with "
               "them %s), wall-mobility length %s (from beta %s), dilatancy %s -> %s/{metrics.json,cg.h5}\n",
               in.run_path.c_str(), m["snapshots"].get<std::size_t>(), m["velocity_source"].get<std::string>().c_str(),
               m["loading_selection"].get<std::string>().c_str(), show(m["cone_angle_deg"], " deg").c_str(),
               m["cone_narrowing_edges"].get<std::size_t>(), m["cone_fitted_edges"].get<std::size_t>(),
               show(m["cone_angle_including_narrowing_deg"], " deg").c_str(),
               show(m["wall_mobility_length_mm"], " mm").c_str(),
               show(m["wall_mobility_length_from_beta_mm"], " mm").c_str(), show(m["dilatancy_delta_phi"], "").c_str(),
               out_dir.c_str());
  return 0;
}
