// piv: synthetic PIV of a dem2d pull-off's front face, compared with coarse-graining
// (definitions: analysis/piv/README.md).
//   piv RUN.h5 --out DIR [--config data/piv.toml] [--cg-metrics CG/metrics.json] [--study data/study.toml] [--threads N]
// Writes DIR/metrics.json ({"piv": {...}}), DIR/piv.h5 and DIR/frames/*.png
// (snapshots.png_frames pairs), each under a temporary name and renamed. Exit
// codes (common/stage_main.hpp): 0 done; 1 an output could not be written; 2
// bad input (run, config or cg metrics file, command line).
#include <cstdlib>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cg/cg_config.hpp"
#include "common/stage_main.hpp"
#include "piv/piv_stage.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
#ifdef __GLIBC__
  // every frame pair allocates a dozen 5.7 MB images: kept by the allocator, not returned to the kernel and
  // faulted in again each time (a quarter of the stage's time went to page faults and zeroing)
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
  StageCommand cmd("piv",
                   "synthetic PIV of a pull-off's front face (frames rendered as the paper's camera sees the beads, "
                   "FFT cross-correlation with deforming windows), its fields beside the coarse-grained ones on the "
                   "same nodes: zones, cone angle, the maps' difference, vortices at the intruder's tips",
                   "Run file (HDF5) written by dem2d", "Output directory (metrics.json, piv.h5, frames/)");
  cmd.add_config("piv.toml");
  cmd.add_study();
  PivInput in;
  cmd.add_option("--cg-metrics", in.cg_metrics_path, "The cg stage's metrics.json, quoted beside the comparison");
  cmd.add_threads(in.threads, "OpenMP threads across frame pairs (0: OpenMP's default); results do not depend on it");
  return cmd.main(
      argc, argv,
      [&] {
        in.run_path = cmd.run;
        in.config_path = cmd.config;
        in.config = load_piv_config(cmd.config);
        in.cg_config_path = cg_config_path(cmd.config, in.config);
        in.cg = load_cg_config(in.cg_config_path);
        in.study = load_study(cmd.study);
        return run_piv(in);
      },
      [&](const PivResult& r) {
        write_piv(r, cmd.out);
        const auto& m = r.metrics["piv"];
        const auto& b = m["cone_angle_deg"];
        return std::to_string(m["pairs"].get<std::size_t>()) + " frame pairs, rms v* difference PIV - CG " +
               show_metric(m["rms_vstar_difference"]) + ", cone angle PIV " + show_metric(b["piv"]["mean"], " deg") +
               " CG " + show_metric(b["cg"]["mean"], " deg") + " (paired difference " +
               show_metric(b["difference"]["mean"], " deg") + "), tip vortices: PIV " +
               m["vortices"]["piv"]["verdict"].get<std::string>() + ", CG " + m["vortices"]["cg"]["verdict"].get<std::string>();
      });
}
