#include "app/inspect.hpp"

#include <cstdint>
#include <cstdio>
#include <new>
#include <stdexcept>
#include <string>

#include "runfile/h5.hpp"
#include "runfile/run_parameters.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d {

namespace {

// What a run file claims to hold (its root attributes), for a message: "" if it cannot be read.
std::string claimed_size(const std::string& path) {
  try {
    const h5::File f = h5::File::open_read(path);
    if (!h5::has_attr(f, "/", "n_particles")) return "";
    const std::int64_t n = h5::read_attr_int(f, "/", "n_particles");
    return ": it claims " + std::to_string(n) + " grains (" + std::to_string(n * 16 / 1000000) +
           " MB for one snapshot's positions alone)";
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

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
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "dem2d: %s: out of memory reading it (std::bad_alloc)%s: a damaged file, or one larger "
                 "than this process may hold\n", path.c_str(), claimed_size(path).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem2d: %s\n", e.what());
    return 2;
  }
}

}  // namespace dem2d
