// cg: coarse-grained velocity and solid-fraction fields of a pull-off run, the
// mobility zones, the cone angle, the wall-mobility length and the dilatancy
// at the onset (definitions: analysis/cg/README.md).
//   cg PULLOFF_RUN.h5 --out DIR [--config data/cg.toml] [--events SPECTRUM.h5] [--study data/study.toml] [--threads N]
// writes DIR/metrics.json ({"cg": {...}}) and DIR/cg.h5. Exit codes
// (common/stage_main.hpp): 0 done; 1 an output could not be written; 2 bad
// input (run, events or config file, command line).
#include "cg/cg_stage.hpp"
#include "common/stage_main.hpp"
#include "common/stage_output.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("cg",
                   "coarse-grained fields of a pull-off run; mobility zones, cone angle, wall-mobility length, "
                   "dilatancy (without an intruder: lab-frame fields, solid fraction, speeds, zones)",
                   "Run file (HDF5) written by dem2d", "Output directory: metrics.json and cg.h5");
  cmd.add_config("cg.toml");
  cmd.add_study();
  CgInput in;
  cmd.add_option("--events", in.events_path, "Loading/rupture events of the spectrum stage (its spectrum.h5, /events)");
  cmd.add_threads(in.threads,
                  "OpenMP threads across snapshots (0: OpenMP's default); results do not depend on it");
  return cmd.main(
      argc, argv,
      [&] {
        in.run_path = cmd.run;
        in.config_path = cmd.config;
        in.study = load_study(cmd.study);
        in.config = load_cg_config(cmd.config);
        return compute_cg(in);
      },
      [&](const CgResult& result) {
        write_cg(result, cmd.out);
        const auto& m = result.metrics["cg"];
        if (!m.value("intruder", true)) {
          const auto& f = m["final"];
          return std::to_string(m["snapshots"].get<std::size_t>()) + " snapshots, no intruder (lab frame): final CG solid fraction over the bed's nodes " +
                 show_metric(f["bed_solid_fraction"], "") + " (walls and surface included; bed_metrics' Φ is the bulk's), mean speed " + show_metric(f["mean_speed_mm_s"], " mm/s") +
                 ", mobile fraction " + show_metric(f["mobile_fraction"], "");
        }
        return std::to_string(m["snapshots"].get<std::size_t>()) + " snapshots, " +
               m["velocity_source"].get<std::string>() + " velocities, " + m["loading_selection"].get<std::string>() +
               ": cone angle " +
               (m["cone_angle_deg"].is_number() ? show_metric(m["cone_angle_deg"], " deg")
                                                : m["cone_angle_outcome"].get<std::string>()) + " (" +
               std::to_string(m["cone_narrowing_edges"].get<std::size_t>()) + " of " +
               std::to_string(m["cone_fitted_edges"].get<std::size_t>()) + " edges narrow, left out; with them " +
               show_metric(m["cone_angle_including_narrowing_deg"], " deg") + "), wall-mobility length " +
               show_metric(m["wall_mobility_length_mm"], " mm") + " (from beta " +
               show_metric(m["wall_mobility_length_from_beta_mm"], " mm") + "), dilatancy " + show_metric(m["dilatancy_delta_phi"], "");
      });
}
