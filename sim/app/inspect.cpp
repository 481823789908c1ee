#include "app/inspect.hpp"

#include <cstdio>
#include <stdexcept>

#include "io/run_parameters.hpp"
#include "io/run_reader.hpp"

namespace dem2d {

int inspect_run_file(const std::string& path) {
  std::size_t contacts = 0;
  try {
    const RunReader run(path);
    const RunParameters parameters = run.parameters();
    run.check_rest();
    for (std::size_t k = 0; k < run.snapshots(); ++k) {
      contacts += run.snapshot(k).contacts.size();
      run.displacement(k);
    }
    std::printf("%s: a sound run file of scene %s\n  %zu grains, %zu bodies, %zu snapshots to t = %.6g s, "
                "%zu series rows, %zu contact rows\n",
                path.c_str(), parameters.name.c_str(), run.particles(), run.bodies(), run.snapshots(),
                run.snapshots() ? run.snapshot_times().back() : 0.0, run.series_rows(), contacts);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem2d: %s\n", e.what());
    return 2;
  }
}

}  // namespace dem2d
