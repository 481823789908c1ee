// Runs a scene with the installed engine library, then reads the run file
// back with its reader: what another project's program would do.
//   consumer SCENE.toml OUT_DIR
#include <cstdio>
#include <exception>

#include "run/run.hpp"
#include "runfile/run_reader.hpp"
#include "scene/scene_toml.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer SCENE.toml OUT_DIR\n");
    return 2;
  }
  try {
    dem2d::Scene scene = dem2d::load_scene(argv[1]);
    scene.threads = 1;
    dem2d::RunOptions options;
    options.out_dir = argv[2];
    const dem2d::RunReport report = dem2d::run_scene(scene, options);
    const dem2d::RunReader run(report.run_file);
    const dem2d::Snapshot last = run.snapshot(run.snapshots() - 1);
    std::printf("consumer: %zu particles, %zu snapshots, last at t = %g s, first grain at y = %g m\n",
                run.particles(), run.snapshots(), run.snapshot_times().back(), last.position[0].y);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
