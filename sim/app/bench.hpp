// `dem2d bench`: settles the standard bed (a scene file under data/bench/)
// and measures ns per particle-step for several effect sets and thread counts
// on that same packing, so the cost of each effect is visible; or, with
// tiles, how the cost per particle-step scales with N.
#pragma once

#include <string>
#include <vector>

#include "core/share_dir.hpp"

namespace dem2d {

struct BenchOptions {
  std::string scene = dem2d::data_file("bench/settled_bed.toml");
  int steps = 4000;   // timed steps per measurement
  int repeat = 5;     // measurements per case; the fastest is reported
  std::vector<int> threads{1, 2};
  std::string json;   // optional output file
  // Scaling mode: instead of the effect cases, time the full contact law on
  // `tiles` copies of the settled bed side by side in one wider cell (same
  // physics per grain, N = tiles x the bed's grains), with about
  // `particle_steps` particle-steps per measurement.
  std::vector<int> tiles;
  double particle_steps = 2e8;
  // Passes mode: each thread's time per pass of the step (engine/pass_clock.hpp)
  // on the full contact law, for each thread count, from the fastest repeat.
  bool passes = false;
  bool list = false;  // list the cases and the kernel each runs on, and stop
};

int run_bench(const BenchOptions& options);

}  // namespace dem2d
