#include "app/bench.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/diagnostics.hpp"
#include "engine/system.hpp"
#include "scene/scene_toml.hpp"

namespace dem2d {

namespace {

using Clock = std::chrono::steady_clock;

struct Case {
  const char* name;
  EffectSet removed;       // effects taken out of the scene's set
  bool zero_rolling_law;   // rolling compiled in, but with mu_r = k_r = 0
};

constexpr Case kCases[] = {
    {"scene effects (full contact law)", 0, false},
    {"rolling compiled in, mu_r = k_r = 0", 0, true},
    {"no rolling resistance", effect::rolling_resistance, false},
    {"frictionless", effect::rolling_resistance | effect::friction, false},
    {"frictionless, undamped", effect::rolling_resistance | effect::friction | effect::normal_damping, false},
};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int run_bench(const BenchOptions& opt) {
  Scene scene = load_scene(opt.scene);
  scene.threads = *std::max_element(opt.threads.begin(), opt.threads.end());

  // settle with the scene's own stop criterion
  const auto t0 = Clock::now();
  System bed(scene);
  const auto check = std::max<std::int64_t>(1, std::llround(scene.stop.check_interval / scene.dt));
  while (bed.time() < scene.stop.duration &&
         !(bed.time() >= scene.stop.min_time && kinetic_energy(bed) < scene.stop.kinetic_energy_below))
    bed.advance(check);
  std::printf("dem2d bench: %s\n  %zu disks, k_n = %.3g N/m, dt = %.4g s = dt_c/%.3g; settled for %.3g s "
              "(%.1f s wall), %zu contacts, kinetic energy %.3g J/m\n",
              opt.scene.c_str(), bed.size(), scene.particle_particle.kn, scene.dt, scene.critical_dt() / scene.dt,
              bed.time(), seconds_since(t0), contact_count(bed), kinetic_energy(bed));
  const Scene settled = with_state(scene, bed);

  nlohmann::json out = nlohmann::json::array();
  std::printf("\n  %-40s %8s %18s\n", "case", "threads", "ns/particle-step");
  for (const Case& c : kCases) {
    for (const int threads : opt.threads) {
      Scene s = settled;
      s.effects &= ~c.removed;
      s.threads = threads;
      if (c.zero_rolling_law) {
        s.particle_particle.rolling_friction = s.particle_particle.rolling_stiffness = 0.0;
        s.particle_wall.rolling_friction = s.particle_wall.rolling_stiffness = 0.0;
      }
      double best = 1e300;
      for (int r = 0; r < opt.repeat; ++r) {
        System sys(s);
        sys.advance(opt.steps / 10);  // warm up caches and the neighbour lists
        const auto t = Clock::now();
        sys.advance(opt.steps);
        best = std::min(best, seconds_since(t));
      }
      const double ns = best * 1e9 / (static_cast<double>(opt.steps) * static_cast<double>(s.particles.size()));
      std::printf("  %-40s %8d %18.2f\n", c.name, threads, ns);
      out.push_back({{"case", c.name}, {"threads", threads}, {"ns_per_particle_step", ns},
                     {"particles", s.particles.size()}, {"steps", opt.steps}});
    }
  }
  if (!opt.json.empty()) std::ofstream(opt.json) << out.dump(2) << "\n";
  return 0;
}

}  // namespace dem2d
