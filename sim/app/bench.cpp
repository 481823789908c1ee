#include "app/bench.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <nlohmann/json.hpp>

#include "engine/diagnostics.hpp"
#include "engine/kernel_sets.hpp"
#include "engine/system.hpp"
#include "scene/scene_toml.hpp"

namespace dem2d {

namespace {

using Clock = std::chrono::steady_clock;

// Each "zeroed" case has an effect compiled in with coefficients that make it
// do nothing (mu_r = k_r = 0, mu = k_t = 0, e = 1); the case after it has the
// effect compiled out. The two follow the same trajectory, so their difference
// is what the kernel selection saves.
// The first two cases measure the opt-in extras against the scene: the
// tangential and rolling dashpots compiled in with nu = 0 (the same
// trajectory), and the energy ledger.
struct Case {
  const char* name;
  EffectSet removed;   // effects taken out of the scene's set
  EffectSet zeroed;    // effects kept, with zero coefficients
  EffectSet added = 0; // effects added with zero coefficients (dashpots with nu = 0)
  bool ledger = false; // the energy ledger on (output.energy_balance)
  bool generic = false; // on the generic kernel (effects tested at run time)
};

constexpr EffectSet kRolling = effect::rolling_resistance, kFriction = effect::friction,
                    kDamping = effect::normal_damping, kDashpots = effect::tangential_damping | effect::rolling_damping;

constexpr Case kCases[] = {
    {"full contact law (scene)", 0, 0},
    {"full contact law, generic kernel", 0, 0, 0, false, true},
    {"+ tangential, rolling dashpots, nu = 0", 0, 0, kDashpots},
    {"+ energy ledger", 0, 0, 0, true},
    {"rolling compiled in, mu_r = k_r = 0", 0, kRolling},
    {"rolling compiled out", kRolling, 0},
    {"friction+rolling compiled in, all zero", 0, kRolling | kFriction},
    {"frictionless (compiled out)", kRolling | kFriction, 0},
    {"frictionless, damping in with e = 1", kRolling | kFriction, kDamping},
    {"frictionless, undamped (compiled out)", kRolling | kFriction | kDamping, 0},
};

// A case's effect set on a scene's, and whether it runs on the generic kernel (asked to, or because
// engine/kernel_sets.inc does not declare the set).
EffectSet effects_of(const Case& c, EffectSet scene) { return (scene & ~c.removed) | c.added; }
bool on_generic(const Case& c, EffectSet scene) { return c.generic || !kernels_specialised(effects_of(c, scene)); }

void zero(ContactLaw& law, EffectSet zeroed) {
  if (has(zeroed, kRolling)) law.rolling_friction = law.rolling_stiffness = 0.0;
  if (has(zeroed, kFriction)) law.friction = law.kt = 0.0;
  if (has(zeroed, kDamping)) law.restitution = 1.0;
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The settled state with its contact history (tangential springs, rolling
// moments), so that a copy starts as settled as the original.
Scene with_state_and_history(const Scene& scene, const System& bed) {
  Scene s = with_state(scene, bed);
  std::vector<std::int32_t> index(bed.size(), -1);  // grain of the System -> grain of the scene
  std::int32_t next = 0;
  for (std::size_t i = 0; i < bed.size(); ++i)
    if (bed.state.p.active[i]) index[i] = next++;
  const PairList& L = bed.state.lists.pairs;
  for (std::size_t i = 0; i < bed.size(); ++i)
    for (auto sl = static_cast<std::size_t>(L.start[i]); sl < static_cast<std::size_t>(L.start[i + 1]); ++sl)
      if (L.overlap[sl] > 0.0 && index[i] >= 0 && index[static_cast<std::size_t>(L.partner[sl])] >= 0)
        s.initial_contacts.push_back({index[i], index[static_cast<std::size_t>(L.partner[sl])], "", L.ft[sl], L.mr[sl]});
  const WallList& W = bed.state.lists.walls;
  for (std::size_t sl = 0; sl < W.slots(); ++sl)
    if (W.overlap[sl] > 0.0 && index[static_cast<std::size_t>(W.owner[sl])] >= 0)
      s.initial_contacts.push_back({index[static_cast<std::size_t>(W.owner[sl])], -1,
                                    bed.state.bodies.name[static_cast<std::size_t>(W.body[sl])], W.ft[sl], W.mr[sl]});
  return s;
}

// `tiles` copies of the settled cell side by side in one wider domain, each
// with its own bodies (walls) and contact history: the same physics per
// grain, N times the grains. The copies repeat every outer width of the
// bodies, so that neighbouring cells' walls touch and no grain sees the next
// cell.
Scene tiled(Scene s, int tiles, const std::string& scene_path) {
  if (s.bodies.empty()) throw std::invalid_argument(scene_path + ": bench --tiles needs a scene with walls (bodies)");
  double lo = 1e300, hi = -1e300;
  for (const BodySpec& b : s.bodies)
    for (const Point& v : b.vertices) {
      lo = std::min(lo, v.x - 0.5 * b.thickness);
      hi = std::max(hi, v.x + 0.5 * b.thickness);
    }
  const double period = hi - lo;  // (m)
  const Scene one = s;
  const auto n = static_cast<std::int32_t>(one.particles.size());
  s.particles.clear();
  s.bodies.clear();
  s.initial_contacts.clear();
  for (int k = 0; k < tiles; ++k) {
    const double dx = k * period;
    // (built with append: "_" + to_string trips GCC 12's false -Wrestrict warning)
    const std::string suffix = tiles > 1 ? std::string(1, '_').append(std::to_string(k)) : std::string();
    for (ParticleInit q : one.particles) {
      q.x += dx;
      s.particles.push_back(q);
    }
    for (BodySpec b : one.bodies) {
      b.name += suffix;
      for (Point& v : b.vertices) v.x += dx;
      s.bodies.push_back(b);
    }
    for (InitialContact c : one.initial_contacts) {
      c.i += k * n;
      if (c.j >= 0) c.j += k * n;
      if (!c.body.empty()) c.body += suffix;
      s.initial_contacts.push_back(c);
    }
  }
  s.domain.xmax += (tiles - 1) * period;
  return s;
}

System settle(const Scene& scene, const std::string& path) {
  const auto t0 = Clock::now();
  System bed(scene);
  const auto check = std::max<std::int64_t>(1, std::llround(scene.stop.check_interval / scene.dt));
  while (bed.time() < scene.stop.duration &&
         !(bed.time() >= scene.stop.min_time && kinetic_energy_criterion_met(bed, scene.stop)))
    bed.advance(check);
  std::printf("dem2d bench: %s\n  %zu disks, k_n = %.3g N/m, dt = %.4g s = dt_c/%.3g; settled for %.3g s "
              "(%.1f s wall), %zu contacts, kinetic energy %.3g J/m\n",
              path.c_str(), bed.size(), scene.particle_particle.kn, scene.dt, scene.critical_dt() / scene.dt,
              bed.time(), seconds_since(t0), contact_count(bed), kinetic_energy(bed));
  return bed;
}

struct Timing {
  double ns = 0.0;        // per particle-step
  double contacts = 0.0;  // per grain, at the end
  std::vector<PassTotals> passes;  // each thread's ns per pass (timed only), of the fastest repeat
  std::vector<std::string> shares;  // each thread's share of the work at the end (timed only)
};

// Thread t's share of the work: its grains, the ones lower threads' rows read, its pair rows' slots, the
// reverse slots it sums, its wall slots.
std::vector<std::string> work_shares(const System& sys) {
  const PairList& L = sys.state.lists.pairs;
  const WallList& W = sys.state.lists.walls;
  std::vector<std::string> out;
  for (std::size_t t = 0; t + 1 < sys.work.part.size(); ++t) {
    const std::size_t a = sys.work.part[t], b = sys.work.part[t + 1];
    char line[200];
    std::snprintf(line, sizeof line, "grains [%zu, %zu) (read by lower threads: %zu), pair slots %d, reverse %d, walls %d",
                  a, b, sys.work.shared_end[t] - a, L.start[b] - L.start[a], L.rev_start[b] - L.rev_start[a],
                  W.start[b] - W.start[a]);
    out.emplace_back(line);
  }
  return out;
}

// Best wall time of `repeat` runs of `steps` steps (after a warm-up of a tenth), with `passes` each
// thread's time per pass.
Timing time_steps(const Scene& s, int steps, int repeat, bool passes = false) {
  double best = 1e300;
  Timing out;
  for (int r = 0; r < repeat; ++r) {
    System sys(s);
    sys.advance(std::max(1, steps / 10));  // warm up caches and the neighbour lists
    sys.time_passes(passes);
    const auto t = Clock::now();
    sys.advance(steps);
    const double wall = seconds_since(t);
    out.contacts = static_cast<double>(contact_count(sys)) / static_cast<double>(sys.size());
    if (wall < best) {
      out.passes = sys.work.pass_totals;
      if (passes) out.shares = work_shares(sys);
    }
    best = std::min(best, wall);
  }
  const double particle_steps = static_cast<double>(steps) * static_cast<double>(s.particles.size());
  out.ns = best * 1e9 / particle_steps;
  for (PassTotals& t : out.passes)
    for (double& ns : t.ns) ns /= particle_steps;
  return out;
}

int run_passes(const BenchOptions& opt, const Scene& settled) {
  nlohmann::json out = nlohmann::json::array();
  for (const int threads : opt.threads) {
    Scene s = settled;
    s.threads = threads;
    const Timing t = time_steps(s, opt.steps, opt.repeat, true);
    std::printf("\n  full contact law, %d thread%s: %.2f ns/particle-step (%.2f contacts/grain); "
                "each thread's time per pass, ns/particle-step\n  %-28s", threads, threads > 1 ? "s" : "",
                t.ns, t.contacts, "pass");
    for (int k = 0; k < threads; ++k) std::printf(" %9s%d", "thread ", k);
    std::printf("\n");
    std::vector<double> sum(t.passes.size(), 0.0);
    for (std::size_t p = 0; p < kPasses; ++p) {
      std::printf("  %-28s", kPassNames[p]);
      nlohmann::json row = {{"threads", threads}, {"pass", kPassNames[p]}, {"ns_per_particle_step", {}}};
      for (std::size_t k = 0; k < t.passes.size(); ++k) {
        std::printf(" %10.2f", t.passes[k].ns[p]);
        sum[k] += t.passes[k].ns[p];
        row["ns_per_particle_step"].push_back(t.passes[k].ns[p]);
      }
      std::printf("\n");
      out.push_back(row);
    }
    std::printf("  %-28s", "sum (the step, timed)");
    for (const double x : sum) std::printf(" %10.2f", x);
    std::printf("\n");
    for (std::size_t k = 0; k < t.shares.size(); ++k) std::printf("  thread %zu: %s\n", k, t.shares[k].c_str());
  }
  if (!opt.json.empty()) std::ofstream(opt.json) << out.dump(2) << "\n";
  return 0;
}

int run_scaling(const BenchOptions& opt, const Scene& settled) {
  nlohmann::json out = nlohmann::json::array();
  std::printf("\n  %10s %8s %7s %17s %12s\n", "disks", "steps", "threads", "ns/particle-step", "contacts/N");
  for (const int k : opt.tiles) {
    Scene s = tiled(settled, k, opt.scene);
    const double n = static_cast<double>(s.particles.size());
    const int steps = std::max(10, static_cast<int>(std::llround(opt.particle_steps / n)));
    for (const int threads : opt.threads) {
      s.threads = threads;
      const Timing t = time_steps(s, steps, opt.repeat);
      std::printf("  %10zu %8d %7d %17.2f %12.2f\n", s.particles.size(), steps, threads, t.ns, t.contacts);
      std::fflush(stdout);
      out.push_back({{"tiles", k}, {"particles", s.particles.size()}, {"steps", steps}, {"threads", threads},
                     {"ns_per_particle_step", t.ns}, {"contacts_per_particle", t.contacts}});
    }
  }
  if (!opt.json.empty()) std::ofstream(opt.json) << out.dump(2) << "\n";
  return 0;
}

}  // namespace

int run_bench(const BenchOptions& opt) {
  Scene scene = load_scene(opt.scene);
  scene.threads = *std::max_element(opt.threads.begin(), opt.threads.end());
  if (opt.list) {  // the cases and the kernel each runs on, without settling
    for (const Case& c : kCases)
      std::printf("%-42s  %-9s {%s}\n", c.name, on_generic(c, scene.effects) ? "generic" : "specialised",
                  effect_names(effects_of(c, scene.effects)).c_str());
    return 0;
  }

  // settle with the scene's own stop criterion
  const Scene settled = with_state_and_history(scene, settle(scene, opt.scene));
  if (!opt.tiles.empty()) return run_scaling(opt, settled);
  if (opt.passes) return run_passes(opt, settled);

  nlohmann::json out = nlohmann::json::array();
  std::printf("\n  %-42s %7s %17s %12s\n", "case", "threads", "ns/particle-step", "contacts/N");
  for (const Case& c : kCases) {
    const EffectSet effects = effects_of(c, settled.effects);
    const bool generic = on_generic(c, settled.effects);
    for (const int threads : opt.threads) {
      Scene s = settled;
      s.effects = effects;
      s.generic_kernel = generic;
      s.output.energy_balance = c.ledger;
      s.threads = threads;
      zero(s.particle_particle, c.zeroed);
      zero(s.particle_wall, c.zeroed);
      const Timing t = time_steps(s, opt.steps, opt.repeat);
      std::printf("  %-42s %7d %17.2f %12.2f%s\n", c.name, threads, t.ns, t.contacts,
                  generic && !c.generic ? "  (generic kernel: set not declared)" : "");
      out.push_back({{"case", c.name}, {"effects", effect_names(s.effects)}, {"generic_kernel", generic},
                     {"threads", threads},
                     {"ns_per_particle_step", t.ns}, {"contacts_per_particle", t.contacts},
                     {"particles", s.particles.size()}, {"steps", opt.steps}});
    }
  }
  if (!opt.json.empty()) std::ofstream(opt.json) << out.dump(2) << "\n";
  return 0;
}

}  // namespace dem2d
