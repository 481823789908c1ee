// cg_bench: the cost of coarse-graining one snapshot at the paper's resolution
// (250 x 420 nodes over 100 x 168 mm, dx = 0.4 mm; 1600 grains; two velocity
// sets, instantaneous and PIV-like, as the stage computes them) against w/dx,
// and how smooth the resulting v* field is (README.md, "Cost").
//   [CG_BENCH_RUN=RUN.h5] [CG_BENCH_SNAPSHOT=k] cg_bench [--benchmark_...]
// The snapshot is taken from CG_BENCH_RUN (default: results/default/pulloff/run.h5,
// its middle snapshot); without a run file, 1600 random grains fill a 140 mm bed.
// Counter `roughness` = d^2 * rms of the discrete Laplacian of v* over the
// nodes at least the cut-off radius from the walls and below the bed's top:
// the field's curvature on the grain scale (0 for a linear field).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "cg/cg_field.hpp"
#include "cg/cg_measure.hpp"
#include "runfile/run_reader.hpp"

namespace {

using namespace dem2d;
using namespace dem2d::analysis;

struct Input {
  Snapshot s;
  double v_ref = 1.2e-3, top = 0.14, d = 0.003;
};

Input& input() {
  static Input in = [] {
    Input r;
    const char* path = std::getenv("CG_BENCH_RUN");
    const std::string run = path ? path : DEM2D_SOURCE_DIR "/results/default/pulloff/run.h5";
    const char* snap = std::getenv("CG_BENCH_SNAPSHOT");
    if (std::filesystem::exists(run)) {
      const RunReader reader(run);
      r.s = reader.snapshot(snap ? std::stoul(snap) : reader.snapshots() / 2);
      r.top = 0.0;
      for (std::size_t i = 0; i < r.s.size(); ++i) r.top = std::max(r.top, r.s.position[i].y);
      std::fprintf(stderr, "cg_bench: %s, snapshot %zu (t = %.3f s, %zu grains)\n", run.c_str(), r.s.index, r.s.time,
                   r.s.size());
    } else {
      std::mt19937 rng(1);
      std::uniform_real_distribution<double> x(0.002, 0.098), y(0.002, 0.138), dd(0.002, 0.004), v(-2e-3, 2e-3);
      for (int i = 0; i < 1600; ++i) {
        const double di = dd(rng);
        r.s.position.push_back({x(rng), y(rng)});
        r.s.velocity.push_back({v(rng), v(rng)});
        r.s.diameter.push_back(di);
        r.s.mass.push_back(2500.0 * M_PI * di * di / 4);
        r.s.active.push_back(1);
      }
      std::fprintf(stderr, "cg_bench: no run file (%s): 1600 random grains\n", run.c_str());
    }
    return r;
  }();
  return in;
}

double roughness(const Grid& g, const std::vector<double>& vstar, double margin, double top, double d) {
  double sum = 0.0;
  long n = 0;
  for (std::size_t j = 1; j + 1 < g.ny; ++j)
    for (std::size_t i = 1; i + 1 < g.nx; ++i) {
      if (g.x(i) < margin || g.x(i) > 0.1 - margin || g.y(j) < margin || g.y(j) > top - margin) continue;
      const std::size_t c = g.at(i, j);
      const double lap = (vstar[c - 1] + vstar[c + 1] + vstar[c - g.nx] + vstar[c + g.nx] - 4 * vstar[c]) / (g.dx * g.dx);
      if (std::isfinite(lap)) sum += lap * lap, ++n;
    }
  return n ? d * d * std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

// Arg: w/dx x 100.
void BM_CoarseGrainSnapshot(benchmark::State& state) {
  const Input& in = input();
  const Grid g = make_grid(0.0, 0.1, 0.0, 0.168, 0.0004);
  const Kernel k = make_kernel(static_cast<double>(state.range(0)) / 100.0 * g.dx, 4.0);
  Grains grains{in.s.position, in.s.mass, in.s.diameter, in.s.active, {in.s.velocity, in.s.velocity}};
  Fields f;
  for (auto _ : state) {
    f = coarse_grain(g, k, grains);
    const Velocity a = velocity(f, 0, 0.2), b = velocity(f, 1, 0.2);
    benchmark::DoNotOptimize(a.vx.data());
    benchmark::DoNotOptimize(b.vx.data());
  }
  const std::vector<double> vstar = speed_ratio(velocity(f, 0, 0.2), 0.0, 0.0, in.v_ref);
  state.counters["w_over_dx"] = static_cast<double>(state.range(0)) / 100.0;
  state.counters["nodes"] = static_cast<double>(g.size());
  state.counters["grains"] = static_cast<double>(in.s.size());
  state.counters["roughness"] = roughness(g, vstar, k.radius(), in.top, in.d);
}
// w/dx = 2.5, 5, 7.5, 11.25 (the paper's w = 1.5 d at dx = 0.4 mm), 15, 20
BENCHMARK(BM_CoarseGrainSnapshot)->Arg(250)->Arg(500)->Arg(750)->Arg(1125)->Arg(1500)->Arg(2000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
