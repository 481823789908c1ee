// Everything that evolves during a run, as plain data, plus the entry points
// that advance it. The kernels (engine/kernels.hpp) are instantiated once per
// declared effect set, plus a generic one; `advance` picks the one for the
// scene's effects when the System is built, and a specialised kernel never
// branches on an absent effect afterwards.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "contact/contact_law.hpp"
#include "core/aligned_vector.hpp"
#include "core/effects.hpp"
#include "core/state.hpp"
#include "engine/energy_ledger.hpp"
#include "engine/pass_clock.hpp"
#include "neighbour/contact_lists.hpp"
#include "scene/scene.hpp"
#include "shape/shape.hpp"

namespace dem2d {

struct LostParticle {
  std::int32_t id;
  std::int64_t step;
  double x, y;  // last position (m)
};

struct System;
using AdvanceFn = void (*)(System&, std::int64_t steps);
using ForceFn = void (*)(System&);

// What the scene fixes: read by every step, changed by none.
struct SystemConfig {
  EffectSet effects = 0;
  double dt = 0.0;  // time step (s)
  int threads = 1;  // the OpenMP team the run is set up for: the most its steps use (StepWork::threads)
  double gx = 0.0, gy = 0.0;  // gravity (m/s^2)
  ContactLaw law_pp, law_pw;  // grain-grain and grain-body laws
  LawCoefficients pp{}, pw{};  // their per-step coefficients
  Box domain;                  // grains leaving it are removed (m)
  bool polygon_bodies = false;  // a body's core has 3 or more vertices (kernels: wall_forces)
};

// What a step changes: everything a checkpoint saves, and nothing else.
struct SystemState {
  std::int64_t step = 0;
  Particles p;
  Bodies bodies;
  // The contacts: the lists' layout is derived (rebuilt from the positions on
  // restore); the history in their slots (tangential springs, rolling
  // moments, last evaluations) is state.
  NeighbourLists lists;
  // Sums of the body force and torque over steps, for interval means.
  std::vector<double> body_fx_sum, body_fy_sum, body_torque_sum;
  std::int64_t body_sum_steps = 0;
  std::vector<LostParticle> lost;
  EnergyLedger energy;  // where the energy goes (on if the scene asks: output.energy_balance)
  // A body was removed: the next step rebuilds the lists (after its drift,
  // so that the step's first half still sees the body's contacts).
  bool rebuild_pending = false;
};

// Derived from the state and never saved: when to rebuild the lists.
struct SystemCache {
  // Upper bound of how far particles / bodies moved since the last rebuild (m).
  double moved_particles = 0.0, moved_bodies = 0.0;
};

// What one step uses and no checkpoint keeps: the threads' shares of the
// work and their scratch. The results never depend on it.
struct StepWork {
  // The threads the steps use now, 1 to SystemConfig::threads (System::set_threads).
  int threads = 1;
  // What each thread's last drift found, one cache line per thread (written
  // by its thread every step, read by all after the next barrier).
  struct alignas(kCacheLine) DriftReport {
    double v2max = 0.0;    // largest speed^2 (m^2/s^2)
    bool escaped = false;  // a grain left the domain or became non-finite
  };
  std::vector<DriftReport> drift;
  // Thread t integrates and sums the grains [part[t], part[t+1]) and
  // evaluates their rows of the pair and wall lists; set at each rebuild so
  // that the threads' shares of work are even (threads + 1 entries). Inner
  // boundaries are multiples of System::kGrainsPerLine.
  std::vector<std::size_t> part;
  // Thread t's grains [part[t], shared_end[t]) are the ones whose kinematics
  // the pair rows of lower threads read (the half list has j > i): their
  // cache lines sit in another core when thread t integrates them. Set with
  // `part`.
  std::vector<std::size_t> shared_end;
  // Each thread's wall time per pass (engine/pass_clock.hpp), one entry per
  // thread of SystemConfig::threads while System::time_passes is on; empty
  // (not timed) otherwise.
  std::vector<PassTotals> pass_totals;
};

// A run's system: four parts, so that a reader can tell what a step changes
// (`state`, and `cache` and `work` as its by-products) from what it only
// reads (`config`).
struct System {
  explicit System(const Scene& scene);

  // Advance `steps` time steps with the scene's kernel. Throws std::runtime_error
  // if the state becomes non-finite.
  void advance(std::int64_t steps);

  double time() const { return static_cast<double>(state.step) * config.dt; }
  std::size_t size() const { return state.p.size(); }

  SystemConfig config;
  SystemState state;
  SystemCache cache;
  StepWork work;
  static constexpr std::size_t kGrainsPerLine = kCacheLine / sizeof(double);

  std::string failure;  // set by a kernel when the state became non-finite

  // The steps from now on on n threads (1 <= n <= config.threads): splits the
  // work anew; the lists and every result stay as they are.
  void set_threads(int n);
  // Times every pass of the steps from now on (on: the totals start at zero;
  // off: they are dropped). The results do not depend on it.
  void time_passes(bool on);
  // Rebuild the neighbour lists now, reset the displacement bounds and split
  // the work among the threads. When it happens never changes the results,
  // only the cost.
  void rebuild();
  // The rebuild inside a step (kernels' advance, after the drift): also
  // removes the grains a drift flagged (`escaped`) and hands the energy of
  // the contacts that disappear with them or with removed bodies to the
  // ledger. Sets `failure` on a non-finite state.
  void rebuild_in_step(bool escaped);
  // Removes (deactivates, records in `lost`) grains outside the domain; a
  // non-finite grain sets `failure` instead. Called whenever a drift flags one.
  void remove_escaped();
  // Gives the inactive grains zero inverse mass and inertia: the integrator
  // leaves them where they are. (Called by remove_escaped and on restore.)
  void freeze_lost();
  // Recompute body positions for the current step (moving bodies only).
  void place_bodies();
  // Prescribed motion from the current step on (needs the moving_bodies effect
  // unless the velocity is zero).
  void set_body_velocity(std::size_t b, double vx, double vy);
  // Takes body b out of the scene from the next step's force evaluation on
  // (its contacts still act in the current step).
  void remove_body(std::size_t b);
  std::size_t body_index(const std::string& name) const;  // throws if unknown
  // Evaluate forces for the current positions without advancing the springs
  // (used once at start-up: velocity Verlet needs F(t=0)).
  void evaluate_initial_forces();
  void reset_body_sums();

 private:
  void split_work();  // sets work.part and work.shared_end
  AdvanceFn advance_ = nullptr;
  ForceFn initial_forces_ = nullptr;
};

// `scene` with its grains replaced by the active grains of `sys` in their
// current state (position, velocity, spin): to continue from a settled state
// with other effects or parameters.
Scene with_state(Scene scene, const System& sys);

// The kernels that run a scene with `effects`: those specialised for it if
// the build has them and `generic` is false, else the generic ones
// (engine/kernel_table.hpp).
AdvanceFn advance_kernel(EffectSet effects, bool generic);
ForceFn initial_force_kernel(EffectSet effects, bool generic);

}  // namespace dem2d
