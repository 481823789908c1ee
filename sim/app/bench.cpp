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

// Each "zeroed" case has an effect compiled in with coefficients that make it
// do nothing (mu_r = k_r = 0, mu = k_t = 0, e = 1); the case after it has the
// effect compiled out. The two follow the same trajectory, so their difference
// is what the kernel selection saves.
struct Case {
  const char* name;
  EffectSet removed;   // effects taken out of the scene's set
  EffectSet zeroed;    // effects kept, with zero coefficients
};

constexpr EffectSet kRolling = effect::rolling_resistance, kFriction = effect::friction,
                    kDamping = effect::normal_damping;

constexpr Case kCases[] = {
    {"full contact law (scene)", 0, 0},
    {"rolling compiled in, mu_r = k_r = 0", 0, kRolling},
    {"rolling compiled out", kRolling, 0},
    {"friction+rolling compiled in, all zero", 0, kRolling | kFriction},
    {"frictionless (compiled out)", kRolling | kFriction, 0},
    {"frictionless, damping in with e = 1", kRolling | kFriction, kDamping},
    {"frictionless, undamped (compiled out)", kRolling | kFriction | kDamping, 0},
};

void zero(ContactLaw& law, EffectSet zeroed) {
  if (has(zeroed, kRolling)) law.rolling_friction = law.rolling_stiffness = 0.0;
  if (has(zeroed, kFriction)) law.friction = law.kt = 0.0;
  if (has(zeroed, kDamping)) law.restitution = 1.0;
}

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
  std::printf("\n  %-42s %7s %17s %12s\n", "case", "threads", "ns/particle-step", "contacts/N");
  for (const Case& c : kCases) {
    for (const int threads : opt.threads) {
      Scene s = settled;
      s.effects &= ~c.removed;
      s.threads = threads;
      zero(s.particle_particle, c.zeroed);
      zero(s.particle_wall, c.zeroed);
      double best = 1e300, contacts = 0.0;
      for (int r = 0; r < opt.repeat; ++r) {
        System sys(s);
        sys.advance(opt.steps / 10);  // warm up caches and the neighbour lists
        const auto t = Clock::now();
        sys.advance(opt.steps);
        best = std::min(best, seconds_since(t));
        contacts = static_cast<double>(contact_count(sys)) / static_cast<double>(sys.size());
      }
      const double ns = best * 1e9 / (static_cast<double>(opt.steps) * static_cast<double>(s.particles.size()));
      std::printf("  %-42s %7d %17.2f %12.2f\n", c.name, threads, ns, contacts);
      out.push_back({{"case", c.name}, {"effects", effect_names(s.effects)}, {"threads", threads},
                     {"ns_per_particle_step", ns}, {"contacts_per_particle", contacts},
                     {"particles", s.particles.size()}, {"steps", opt.steps}});
    }
  }
  if (!opt.json.empty()) std::ofstream(opt.json) << out.dump(2) << "\n";
  return 0;
}

}  // namespace dem2d
