#include "engine/system.hpp"

#include "engine/diagnostics.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace dem2d {

namespace {

SystemConfig config_of(const Scene& scene) {
  SystemConfig c;
  c.effects = scene.effects;
  c.dt = scene.dt;
  omp_set_dynamic(0);
  c.threads = scene.threads > 0 ? scene.threads : omp_get_max_threads();
  if (c.threads > omp_get_thread_limit())  // the kernels need every thread they split the work for
    throw std::invalid_argument("threads = " + std::to_string(c.threads) + " exceeds OpenMP's thread limit " +
                                std::to_string(omp_get_thread_limit()) + " (OMP_THREAD_LIMIT)");
  // The team OpenMP really gives: fewer threads where parallel regions are inactive (OMP_MAX_ACTIVE_LEVELS=0,
  // or a System made inside a parallel region). The step's barriers wait for config.threads threads, so
  // the work is split for the team there is (the results do not depend on it); else a deadlock.
  int team = 1;
#pragma omp parallel num_threads(c.threads)
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  c.threads = std::min(c.threads, team);
  c.gx = scene.gx;
  c.gy = scene.gy;
  c.law_pp = scene.particle_particle;
  c.law_pw = scene.particle_wall;
  c.pp = coefficients(scene.particle_particle, scene.dt);
  c.pw = coefficients(scene.particle_wall, scene.dt);
  c.domain = scene.domain;
  return c;
}

}  // namespace

System::System(const Scene& scene) : config(config_of(scene)) {
  const EffectSet effects = config.effects;
  Particles& p = state.p;
  Bodies& bodies = state.bodies;
  work.threads = config.threads;
  work.drift.assign(static_cast<std::size_t>(work.threads), StepWork::DriftReport{});

  const std::size_t n = scene.particles.size();
  p.resize(n);
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleInit& q = scene.particles[i];
    const double r = 0.5 * q.d;
    const double m = scene.density * M_PI * q.d * q.d / 4.0;  // per unit depth (kg/m)
    const double inertia = m * q.d * q.d / 8.0;                // disk: I = m d^2 / 8 (kg m)
    p.x[i] = q.x;
    p.y[i] = q.y;
    p.vx[i] = q.vx;
    p.vy[i] = q.vy;
    p.omega[i] = q.omega;
    p.radius[i] = r;
    p.mass[i] = m;
    p.inv_mass[i] = 1.0 / m;
    p.inv_inertia[i] = 1.0 / inertia;
    r_max = std::max(r_max, r);
  }

  const std::size_t nb = scene.bodies.size();
  if (nb > 0 && !has(effects, effect::walls))
    throw std::invalid_argument("the scene has bodies but not the walls effect");
  for (const BodySpec& q : scene.bodies)
    if ((q.vx != 0.0 || q.vy != 0.0 || !q.motion.empty()) && !has(effects, effect::moving_bodies))
      throw std::invalid_argument("body " + q.name + " has a velocity but the scene lacks the moving_bodies effect");
  bodies.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    const BodySpec& q = scene.bodies[b];
    bodies.name[b] = q.name;
    bodies.role[b] = q.role;
    bodies.kind[b] = q.shape;
    bodies.set_shape(b, make_shape(q.vertices));
    config.polygon_bodies = config.polygon_bodies || bodies.shape[b].n > 2;
    bodies.anchor_x[b] = bodies.origin_x[b] = q.vertices[0].x;
    bodies.anchor_y[b] = bodies.origin_y[b] = q.vertices[0].y;
    bodies.radius[b] = 0.5 * q.thickness;
    bodies.vx[b] = q.vx;
    bodies.vy[b] = q.vy;
  }
  for (std::size_t b = 0; b < nb; ++b) {
    const BodySpec& q = scene.bodies[b];
    if (q.motion.empty()) continue;
    bodies.schedule[b] = MotionSchedule(q.motion, q.motion_repeat);
    bodies.anchor_step[b] = -1;
    if (bodies.schedule[b].turns() && !has(effects, effect::rotating_bodies))
      throw std::invalid_argument("body " + q.name + " turns but the scene lacks the rotating_bodies effect");
    if (q.pivot || bodies.schedule[b].turns()) {  // the scene's pivot, else the centre at the start
      bodies.own_pivot[b] = 1;
      bodies.pivot0_x[b] = q.pivot ? q.pivot->x : bodies.centre_x[b];
      bodies.pivot0_y[b] = q.pivot ? q.pivot->y : bodies.centre_y[b];
    }
    const MotionSchedule::State s = bodies.schedule[b].at(0.0);
    bodies.vx[b] = s.vx;
    bodies.vy[b] = s.vy;
    bodies.omega[b] = s.omega;
    bodies.move_to(b, bodies.shape[b].x0(), bodies.shape[b].y0());  // its pivot
  }
  state.body_fx_sum.assign(nb, 0.0);
  state.body_fy_sum.assign(nb, 0.0);
  state.body_torque_sum.assign(nb, 0.0);

  // how far beyond touching contacts act (m)
  const double range = scene.interaction_range();
  const Box& domain = config.domain;
  state.lists.configure(domain.xmin, domain.ymin, domain.xmax, domain.ymax, std::max(r_max, 1e-300), scene.skin,
                        range);
  advance_ = advance_kernel(effects, scene.generic_kernel);
  initial_forces_ = initial_force_kernel(effects, scene.generic_kernel);
  remove_escaped();
  if (!failure.empty()) throw std::runtime_error(failure);
  rebuild();
  for (const InitialContact& c : scene.initial_contacts) {  // history carried over from a run
    if (c.j >= 0) {
      state.lists.set_pair_history(c.i, c.j, c.ft, c.mr);
    } else if (has(effects, effect::walls)) {
      for (std::size_t b = 0; b < nb; ++b)  // a body of the earlier run may be gone: then no history
        if (bodies.name[b] == c.body) state.lists.set_wall_history(c.i, static_cast<std::int32_t>(b), c.ft, c.mr);
    }
  }
  evaluate_initial_forces();
  state.energy.on = scene.output.energy_balance;
  if (state.energy.on) energy::start(*this);
}

void System::advance(std::int64_t steps) {
  if (!failure.empty()) throw std::runtime_error(failure);
  advance_(*this, steps);
  if (!failure.empty()) throw std::runtime_error(failure);
}

void System::evaluate_initial_forces() { initial_forces_(*this); }

void System::place_bodies() {
  Bodies& bodies = state.bodies;
  const std::int64_t step = state.step;
  const double dt = config.dt;
  double moved = 0.0;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (!bodies.active[b]) continue;
    double x, y;  // C1 at this step
    if (bodies.anchor_step[b] < 0) {
      // on its schedule: positions at t = step dt; the velocity the contacts
      // see is the one over the step that led here (at t - dt/2), as the
      // grains' half-step velocity
      const double t = static_cast<double>(step) * dt;
      const MotionSchedule::State s = bodies.schedule[b].at(t), mid = bodies.schedule[b].at(t - 0.5 * dt);
      bodies.vx[b] = mid.vx;
      bodies.vy[b] = mid.vy;
      if (bodies.schedule[b].turns()) {
        // the pivot displaced, vertex 0 turned about it from where it was at the start
        bodies.angle[b] = s.angle;
        bodies.omega[b] = mid.omega;
        const double c = std::cos(s.angle), sn = std::sin(s.angle);
        const double rx = bodies.origin_x[b] - bodies.pivot0_x[b], ry = bodies.origin_y[b] - bodies.pivot0_y[b];
        x = bodies.pivot0_x[b] + s.x + (c * rx - sn * ry);
        y = bodies.pivot0_y[b] + s.y + (sn * rx + c * ry);
        const Shape& shape = bodies.shape[b];
        const auto px = shape.px, py = shape.py;  // where the vertices were
        bodies.move_to(b, x, y);
        for (int k = 0; k < shape.n; ++k)  // (a rigid motion moves no point of a convex outline further than its vertices)
          moved = std::max(moved, std::hypot(shape.px[k] - px[k], shape.py[k] - py[k]));
        continue;
      }
      x = bodies.origin_x[b] + s.x;
      y = bodies.origin_y[b] + s.y;
      moved = std::max(moved, std::hypot(x - bodies.shape[b].x0(), y - bodies.shape[b].y0()));
    } else {
      const double vx = bodies.vx[b], vy = bodies.vy[b];
      const double t = static_cast<double>(step - bodies.anchor_step[b]) * dt;
      x = bodies.anchor_x[b] + vx * t;
      y = bodies.anchor_y[b] + vy * t;
      moved = std::max(moved, std::hypot(vx, vy) * dt);
    }
    bodies.move_to(b, x, y);
  }
  cache.moved_bodies += moved;
}

void System::set_body_velocity(std::size_t b, double vx, double vy) {
  Bodies& bodies = state.bodies;
  if ((vx != 0.0 || vy != 0.0) && !has(config.effects, effect::moving_bodies))
    throw std::invalid_argument("body " + bodies.name[b] + " cannot move: the scene lacks the moving_bodies effect");
  place_bodies();  // positions up to date for this step
  bodies.anchor_x[b] = bodies.shape[b].x0();
  bodies.anchor_y[b] = bodies.shape[b].y0();
  bodies.anchor_step[b] = state.step;
  bodies.vx[b] = vx;
  bodies.vy[b] = vy;
  bodies.omega[b] = 0.0;  // it keeps the angle it has
}

void System::remove_body(std::size_t b) {
  state.bodies.removing[b] = 1;
  state.rebuild_pending = true;
}

std::size_t System::body_index(const std::string& name) const {
  for (std::size_t b = 0; b < state.bodies.size(); ++b)
    if (state.bodies.name[b] == name) return b;
  throw std::invalid_argument("no body named '" + name + "'");
}

void System::remove_escaped() {
  Particles& p = state.p;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.active[i]) continue;
    const bool finite = std::isfinite(p.x[i]) && std::isfinite(p.y[i]) && std::isfinite(p.vx[i]) &&
                        std::isfinite(p.vy[i]) && std::isfinite(p.omega[i]);
    if (!finite) {
      std::ostringstream msg;
      msg << "particle " << i << " has a non-finite state at step " << state.step << " (t = " << time()
          << " s): the time step is too large for the stiffness, or the scene is unstable";
      failure = msg.str();
      return;
    }
    if (!config.domain.contains(p.x[i], p.y[i])) {
      if (state.energy.on) energy::remove_grain(*this, i);
      state.lost.push_back({static_cast<std::int32_t>(i), state.step, p.x[i], p.y[i]});
      p.active[i] = 0;
      p.vx[i] = p.vy[i] = p.omega[i] = 0.0;
      p.fx[i] = p.fy[i] = p.torque[i] = 0.0;
    }
  }
  freeze_lost();
}

void System::freeze_lost() {
  Particles& p = state.p;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.active[i]) p.inv_mass[i] = p.inv_inertia[i] = 0.0;  // frozen where it left
}

void System::rebuild() {
  Bodies& bodies = state.bodies;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies.removing[b]) {
      bodies.active[b] = bodies.removing[b] = 0;
      bodies.fx[b] = bodies.fy[b] = bodies.torque[b] = 0.0;
    }
  state.lists.rebuild_pairs(state.p);
  if (has(config.effects, effect::walls)) state.lists.rebuild_walls(state.p, bodies.shape, bodies.radius, bodies.active);
  cache.moved_particles = 0.0;
  cache.moved_bodies = 0.0;
  state.rebuild_pending = false;
  split_work();
}

void System::rebuild_in_step(bool escaped) {
  // Only removed grains and bodies lose touching contacts at a rebuild (a
  // touching pair is always within the skin), so the stored energy the
  // lists lose is theirs.
  EnergyLedger& energy = state.energy;
  const double before = energy.on ? elastic_energy(*this) : 0.0;
  if (escaped) remove_escaped();
  if (!failure.empty()) return;
  rebuild();
  if (energy.on) {
    const double gone = before - elastic_energy(*this);
    energy.removed += gone;
    energy.error_offset -= gone;
  }
}

void System::set_threads(int n) {
  if (n < 1 || n > config.threads)
    throw std::invalid_argument("set_threads(" + std::to_string(n) + "): from 1 to " + std::to_string(config.threads));
  if (n == work.threads) return;
  work.threads = n;
  work.drift.assign(static_cast<std::size_t>(n), StepWork::DriftReport{});
  split_work();
}

void System::time_passes(bool on) {
  work.pass_totals.assign(on ? static_cast<std::size_t>(config.threads) : 0, PassTotals{});
}

void System::split_work() {
  // Cost of grain i in units of one gathered contact: its pair rows are
  // evaluated (~2 units a slot), its own and reverse slots summed (1 unit
  // each), its wall slots evaluated and summed, and it is integrated (~2).
  const std::size_t n = state.p.size();
  const PairList& L = state.lists.pairs;
  const WallList& W = state.lists.walls;
  auto cost = [&](std::size_t i) {
    const double own = L.start[i + 1] - L.start[i], rev = L.rev_start[i + 1] - L.rev_start[i];
    const double wall = W.start.size() == n + 1 ? W.start[i + 1] - W.start[i] : 0.0;
    return 2.0 + 3.0 * own + rev + 4.0 * wall;
  };
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) total += cost(i);
  const auto nt = static_cast<std::size_t>(work.threads);
  work.part.assign(nt + 1, n);
  work.part[0] = 0;
  double acc = 0.0;
  std::size_t t = 1;
  for (std::size_t i = 0; i < n && t < nt; ++i) {
    acc += cost(i);
    // boundaries on whole cache lines of the per-grain arrays, so that no line
    // is written by two threads (measured: 5 % at 1600 grains, 2 threads)
    while (t < nt && acc >= total * static_cast<double>(t) / static_cast<double>(nt))
      work.part[t++] = std::min(n, (i + 1 + kGrainsPerLine - 1) / kGrainsPerLine * kGrainsPerLine);
  }
  work.shared_end.assign(work.part.begin(), work.part.end() - 1);
  for (std::size_t t_i = 0; t_i + 1 < nt; ++t_i) {
    const auto first = static_cast<std::size_t>(L.start[work.part[t_i]]), last = static_cast<std::size_t>(L.start[work.part[t_i + 1]]);
    for (std::size_t sl = first; sl < last; ++sl) {
      const auto j = static_cast<std::size_t>(L.partner[sl]);
      if (j < work.part[t_i + 1]) continue;
      const auto t_j = static_cast<std::size_t>(std::upper_bound(work.part.begin(), work.part.end(), j) - work.part.begin()) - 1;
      work.shared_end[t_j] = std::max(work.shared_end[t_j], j + 1);
    }
  }
}

Scene with_state(Scene scene, const System& sys) {
  scene.particles.clear();
  for (std::size_t i = 0; i < sys.size(); ++i)
    if (sys.state.p.active[i])
      scene.particles.push_back(
          {sys.state.p.x[i], sys.state.p.y[i], 2.0 * sys.state.p.radius[i], sys.state.p.vx[i], sys.state.p.vy[i], sys.state.p.omega[i]});
  return scene;
}

void System::reset_body_sums() {
  std::fill(state.body_fx_sum.begin(), state.body_fx_sum.end(), 0.0);
  std::fill(state.body_fy_sum.begin(), state.body_fy_sum.end(), 0.0);
  std::fill(state.body_torque_sum.begin(), state.body_torque_sum.end(), 0.0);
  state.body_sum_steps = 0;
}

}  // namespace dem2d
