// The hot loop, templated on the effect set E. Every effect test below is a
// constant in an instantiation for a scene's set (applies<E>, compiles<E>:
// core/effects.hpp), so it contains only the physics its scene names; the
// generic instantiation (E == effect::generic) has all of it and tests the
// scene's set (s.config.effects) at run time, doing the same arithmetic for
// the effects it applies and none for the others.
//
// One time step (velocity Verlet, as in LAMMPS: velocity-dependent forces use
// the half-step velocity). Thread t owns the grains [part[t], part[t+1]) and
// their rows of the contact lists (System::split_work):
//   v += dt/2 a(t);  x += dt v                    integrate (own grains, vectorised)
//   barrier; the rebuild test                     every thread decides alike from the
//                                                 same data; a rebuild is serial
//   [energy ledger: open_step; a barrier before a rebuild]
//   per-contact forces at x(t+dt)                 pair_forces, wall_forces (own rows;
//                                                 pair slots vectorised)
//   barrier
//   [energy ledger: close_step, barrier]
//   per-grain sums in a fixed order               gather (own grains)
//   v += dt/2 a(t+dt)                             integrate, in one pass with the next step's
//                                                 opening kick + drift within a call
//   body force sums; move the bodies              thread 0, before the next barrier
// Two barriers a step; all loops run inside one OpenMP parallel region per
// call; none allocates.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <utility>

#include <omp.h>

#include "contact/contact_model.hpp"
#include "core/hot_loop.hpp"
#include "engine/pass_clock.hpp"
#include "engine/step_barrier.hpp"
#include "engine/system.hpp"

// The hot loops below: DEM2D_HOT (core/hot_loop.hpp), in versions for the CPU.

namespace dem2d::kernels {

using std::size_t;

// This thread's grains [first, second).
inline std::pair<size_t, size_t> my_grains(const System& s) {
  const auto t = static_cast<size_t>(omp_get_thread_num());
  return {s.work.part[t], s.work.part[t + 1]};
}

// This thread's slots [first, last) of a list whose row i is [start[i], start[i+1]).
inline std::pair<std::int64_t, std::int64_t> my_slots(const System& s, const AlignedVector<std::int32_t>& start) {
  const std::pair<size_t, size_t> grains = my_grains(s);
  return {start[grains.first], start[grains.second]};
}

// Velocity Verlet's per-grain updates, h = dt/2, a = F/m + g, as one vectorised pass:
//   Close: v += h a, omega += h T/I            (end of a step)
//   Open:  the same kick, then x += dt v,      (start of the next step)
//          theta += dt omega
// Lost grains stay frozen: they have zero inverse mass (System::freeze_lost),
// so their kick is scaled by 0 (by exactly 1 for the others); the mask comes
// from inv_mass, not from `active`, so that the loop is all doubles and
// vectorises. With Open, each thread leaves the largest speed^2 and whether a
// grain left the domain or became non-finite in the System (the box test is
// false for NaN); the caller reads them after a barrier.
template <EffectSet E, bool Close, bool Open>
DEM2D_HOT inline void integrate(System& s) {
  Particles& p = s.state.p;
  // plain locals, not a structured binding: GCC does not see a binding's
  // members as loop-invariant bounds and would not vectorise the loop
  const std::pair<size_t, size_t> range = my_grains(s);
  const size_t begin = range.first, end = range.second;
  const double h = 0.5 * s.config.dt, dt = s.config.dt, gx = s.config.gx, gy = s.config.gy;
  const Box box = s.config.domain;
  double *x = p.x.data(), *y = p.y.data(), *vx = p.vx.data(), *vy = p.vy.data();
  double *w = p.omega.data(), *th = p.theta.data();
  const double *fx = p.fx.data(), *fy = p.fy.data(), *tq = p.torque.data();
  const double *im = p.inv_mass.data(), *ii = p.inv_inertia.data();
  // Reductions on 64-bit integers, so that every lane is 8 bytes and no
  // floating-point max is needed: a speed^2 is never negative, and
  // non-negative doubles order like their bit patterns (NaN above all).
  std::int64_t v2max_bits = 0, escaped = 0;
  const bool gravity = applies<E>(s.config.effects, effect::gravity);
#pragma omp simd reduction(max : v2max_bits) reduction(| : escaped)
  for (size_t i = begin; i < end; ++i) {
    const double live = im[i] > 0.0 ? 1.0 : 0.0;
    const double k = h * live;
    double ax = fx[i] * im[i], ay = fy[i] * im[i];
    if (gravity) {
      ax += gx;
      ay += gy;
    }
    const double aw = tq[i] * ii[i];
    double u = vx[i], v = vy[i], o = w[i];
    if constexpr (Close) {
      u += k * ax;
      v += k * ay;
      o += k * aw;
    }
    if constexpr (Open) {
      u += k * ax;
      v += k * ay;
      o += k * aw;
      const double xn = x[i] + dt * u, yn = y[i] + dt * v;
      x[i] = xn;
      y[i] = yn;
      th[i] += dt * o;
      v2max_bits = std::max(v2max_bits, std::bit_cast<std::int64_t>(u * u + v * v));
      const bool inside = (xn >= box.xmin) & (xn <= box.xmax) & (yn >= box.ymin) & (yn <= box.ymax);
      escaped |= static_cast<std::int64_t>(live != 0.0) & static_cast<std::int64_t>(!inside || !std::isfinite(o));
    }
    vx[i] = u;
    vy[i] = v;
    w[i] = o;
  }
  if constexpr (Open) {
    const auto t = static_cast<size_t>(omp_get_thread_num());
    s.work.drift[t] = {std::bit_cast<double>(v2max_bits), escaped != 0};
  }
}

// Particle-particle contacts: one evaluation per pair, results per slot.
// A flat loop over slots without branches (open contacts are masked to zero
// by selects), so that the compiler vectorises it; the law is the model's
// (contact/contact_model.hpp), the geometry the loop's.
template <EffectSet E>
DEM2D_HOT inline void pair_forces(System& s, const ContactModel<E> model) {  // by value: cannot alias the outputs
  const Particles& p = s.state.p;
  PairList& L = s.state.lists.pairs;
  const std::int32_t *own = L.owner.data(), *par = L.partner.data();
  const double *x = p.x.data(), *y = p.y.data(), *vx = p.vx.data(), *vy = p.vy.data(), *w = p.omega.data();
  const double *rad_i = L.ri.data(), *rad_j = L.rj.data(), *sqm = L.sqrt_meff.data(), *sqi = L.sqrt_ieff.data();
  double *ft = L.ft.data(), *mr = L.mr.data(), *ti = L.ti.data(), *tj = L.tj.data();
  double *fx = L.fx.data(), *fy = L.fy.data(), *fn = L.fn.data(), *ov = L.overlap.data();
  const std::pair<std::int64_t, std::int64_t> slots = my_slots(s, L.start);
  const std::int64_t first = slots.first, last = slots.second;
  const bool friction = applies<E>(model.scene, effect::friction);
  const bool rolling = applies<E>(model.scene, effect::rolling_resistance);
  // simd: slots are independent (each reads grain data, writes only its own slot)
#pragma omp simd
  for (std::int64_t sl = first; sl < last; ++sl) {
    const std::int32_t i = own[sl], j = par[sl];
    const double dx = x[i] - x[j], dy = y[i] - y[j], ri = rad_i[sl], rj = rad_j[sl], rsum = ri + rj;
    const double d2 = dx * dx + dy * dy, reach = model.reach(rsum);
    const bool acts = d2 < reach * reach;
    const double dist = std::sqrt(d2);
    const bool apart = dist > 0.0;  // coincident centres: separate them along x
    const double inv = 1.0 / (apart ? dist : 1.0);
    const double nx = apart ? dx * inv : 1.0, ny = apart ? dy * inv : 0.0;
    const double delta = dist - rsum;
    const double rvx = vx[i] - vx[j], rvy = vy[i] - vy[j];
    // branch vectors end at the middle of the overlap: a = r + delta/2
    const double ai = ri + 0.5 * delta, aj = rj + 0.5 * delta;
    const double tx = -ny, ty = nx;
    const ContactMotion m = grain_pair_motion(rvx, rvy, nx, ny, ai, w[i], aj, w[j]);
    double vt = 0.0, spin = 0.0, sqrt_i = 0.0;
    if (friction) vt = m.vt;
    if (rolling) {
      spin = m.spin;
      sqrt_i = sqi[sl];
    }
    const ContactForce f = model.eval({delta, m.vn, vt, spin, sqm[sl], sqrt_i}, acts, ft[sl], mr[sl]);
    double fxs = f.fn * nx, fys = f.fn * ny, tqi = 0.0, tqj = 0.0;
    if (friction) {
      fxs += f.ft * tx;
      fys += f.ft * ty;
      tqi = -ai * f.ft;
      tqj = -aj * f.ft;
    }
    if (rolling) {
      tqi += f.mr;
      tqj -= f.mr;
    }
    fx[sl] = acts ? fxs : 0.0;
    fy[sl] = acts ? fys : 0.0;
    if (friction || rolling) {
      ti[sl] = acts ? tqi : 0.0;
      tj[sl] = acts ? tqj : 0.0;
    }
    fn[sl] = f.fn;
    ov[sl] = acts ? -delta : 0.0;
  }
}

// Grain-body contacts: a flat loop over the wall slots, vectorised like
// pair_forces (open contacts masked by selects), with the same model. An
// open slot is zeroed and keeps its last contact point. The geometry is the
// shape's closest point (shape/shape.hpp): inline for sphero-lines; with
// polygon bodies (Polygons, a run-time property of the scene) a scalar
// narrow phase over the slots first, whose loop over a polygon's edges would
// not vectorise.
template <EffectSet E, bool Polygons>
DEM2D_HOT inline void wall_forces(System& s, const ContactModel<E> model) {  // by value: cannot alias the outputs
  const Particles& p = s.state.p;
  WallList& L = s.state.lists.walls;
  const Bodies& B = s.state.bodies;
  const Shape* shape = B.shape.data();
  const Segment* line = B.line.data();
  const std::int32_t *own = L.owner.data(), *body = L.body.data();
  const double *x = p.x.data(), *y = p.y.data(), *vx = p.vx.data(), *vy = p.vy.data(), *w = p.omega.data();
  const double *rad = p.radius.data(), *sqm = L.sqrt_m.data(), *sqi = L.sqrt_i.data();
  const double *brad = B.radius.data(), *bvx = B.vx.data(), *bvy = B.vy.data();
  const double *bw = B.omega.data(), *bpx = B.pivot_x.data(), *bpy = B.pivot_y.data();
  double *ft = L.ft.data(), *mr = L.mr.data(), *fxo = L.fx.data(), *fyo = L.fy.data(), *tqo = L.tq.data();
  double *cx = L.cx.data(), *cy = L.cy.data(), *fno = L.fn.data(), *ov = L.overlap.data();
  double *gd = L.dist.data(), *gnx = L.nx.data(), *gny = L.ny.data();
  const std::pair<std::int64_t, std::int64_t> slots = my_slots(s, L.start);
  const std::int64_t first = slots.first, last = slots.second;
  const EffectSet scene = model.scene;
  const bool moving = applies<E>(scene, effect::moving_bodies), rotating = applies<E>(scene, effect::rotating_bodies);
  const bool friction = applies<E>(scene, effect::friction), rolling = applies<E>(scene, effect::rolling_resistance);
  if constexpr (Polygons)
    for (std::int64_t sl = first; sl < last; ++sl) {
      const std::int32_t i = own[sl];
      const Proximity g = closest_point(shape[body[sl]], x[i], y[i]);
      gd[sl] = g.dist;
      gnx[sl] = g.nx;
      gny[sl] = g.ny;
    }
#pragma omp simd
  for (std::int64_t sl = first; sl < last; ++sl) {
    const std::int32_t i = own[sl], b = body[sl];
    Proximity g;
    if constexpr (Polygons)
      g = {gd[sl], gnx[sl], gny[sl]};
    else
      g = closest_point(line[b], x[i], y[i]);
    const double ri = rad[i];
    const double delta = g.dist - (ri + brad[b]);
    const bool acts = delta < model.range();
    const double a = ri + 0.5 * delta;  // centre to contact point (m)
    const double px = rotating ? x[i] - a * g.nx : 0.0, py = rotating ? y[i] - a * g.ny : 0.0;  // contact point (turning)
    const auto [rvx, rvy] = relative_to_surface(vx[i], vy[i], moving, rotating, bvx[b], bvy[b], bw[b], bpx[b], bpy[b], px, py);
    const double tx = -g.ny, ty = g.nx;
    const ContactMotion m = grain_body_motion(rvx, rvy, g.nx, g.ny, a, w[i]);
    double vt = 0.0, spin = 0.0, sqrt_i = 0.0;
    if (friction) vt = m.vt;
    if (rolling) {
      spin = m.spin;
      sqrt_i = sqi[sl];
    }
    const ContactForce f = model.eval({delta, m.vn, vt, spin, sqm[sl], sqrt_i}, acts, ft[sl], mr[sl]);
    double fx = f.fn * g.nx, fy = f.fn * g.ny, tq = 0.0;
    if (friction) {
      fx += f.ft * tx;
      fy += f.ft * ty;
      tq = -a * f.ft;
    }
    if (rolling) tq += f.mr;
    fxo[sl] = acts ? fx : 0.0;
    fyo[sl] = acts ? fy : 0.0;
    tqo[sl] = acts ? tq : 0.0;
    cx[sl] = acts ? x[i] - a * g.nx : cx[sl];
    cy[sl] = acts ? y[i] - a * g.ny : cy[sl];
    fno[sl] = f.fn;
    ov[sl] = acts ? -delta : 0.0;
  }
}

template <EffectSet E>
inline void body_forces(System& s, const ContactModel<E> model) {
  if (s.config.polygon_bodies)
    wall_forces<E, true>(s, model);
  else
    wall_forces<E, false>(s, model);
}

// Asks, with write intent, for the lines of this thread's grains that lower
// threads' pair rows read this step (System::StepWork::shared_end). Called after the
// barrier that ends the pair loops, before the sums: the other cores give the
// lines up while the sums run, and the integration that follows writes lines
// it already owns (measured: thread 1's integration 5.8-6.6k -> 4.5k cycles
// a step on the 1600-grain bed).
inline void claim_shared_grains(System& s) {
  const auto t = static_cast<size_t>(omp_get_thread_num());
  Particles& p = s.state.p;
  for (double* a : {p.x.data(), p.y.data(), p.vx.data(), p.vy.data(), p.omega.data()})
    for (size_t i = s.work.part[t]; i < s.work.shared_end[t]; i += System::kGrainsPerLine) __builtin_prefetch(a + i, 1, 3);
}

// Per-grain resultant force and torque, summed in a fixed order (own row by
// ascending partner, then the reverse index by ascending i, then walls).
// Each thread sums its own grains, the ones it then integrates, so no
// barrier is needed in between.
template <EffectSet E>
DEM2D_HOT inline void gather(System& s) {
  Particles& p = s.state.p;
  const PairList& L = s.state.lists.pairs;
  const WallList& W = s.state.lists.walls;
  const std::pair<size_t, size_t> range = my_grains(s);
  const EffectSet scene = s.config.effects;
  const bool torque = applies<E>(scene, effect::friction) || applies<E>(scene, effect::rolling_resistance);
  const bool walls = applies<E>(scene, effect::walls);
  for (size_t i = range.first; i < range.second; ++i) {
    if (!p.active[i]) continue;
    double fx = 0.0, fy = 0.0, tq = 0.0;
    const auto end = static_cast<size_t>(L.start[i + 1]);
    for (auto sl = static_cast<size_t>(L.start[i]); sl < end; ++sl) {
      fx += L.fx[sl];
      fy += L.fy[sl];
      if (torque) tq += L.ti[sl];
    }
    const auto rend = static_cast<size_t>(L.rev_start[i + 1]);
    for (auto r = static_cast<size_t>(L.rev_start[i]); r < rend; ++r) {
      const auto sl = static_cast<size_t>(L.rev_slot[r]);
      fx -= L.fx[sl];
      fy -= L.fy[sl];
      if (torque) tq += L.tj[sl];
    }
    if (walls) {
      const auto wend = static_cast<size_t>(W.start[i + 1]);
      for (auto sl = static_cast<size_t>(W.start[i]); sl < wend; ++sl) {
        fx += W.fx[sl];
        fy += W.fy[sl];
        tq += W.tq[sl];
      }
    }
    p.fx[i] = fx;
    p.fy[i] = fy;
    p.torque[i] = tq;
  }
}

// Force and torque the grains exert on each body, summed in slot order.
inline void body_sums(System& s) {
  Bodies& B = s.state.bodies;
  const WallList& W = s.state.lists.walls;
  std::fill(B.fx.begin(), B.fx.end(), 0.0);
  std::fill(B.fy.begin(), B.fy.end(), 0.0);
  std::fill(B.torque.begin(), B.torque.end(), 0.0);
  for (size_t sl = 0; sl < W.slots(); ++sl) {
    const auto b = static_cast<size_t>(W.body[sl]);
    B.fx[b] -= W.fx[sl];
    B.fy[b] -= W.fy[sl];
    // lever arm from the body's pivot to the contact point, force -F,
    // plus the reaction of the rolling moment
    const double lx = W.cx[sl] - B.pivot_x[b], ly = W.cy[sl] - B.pivot_y[b];
    B.torque[b] -= lx * W.fy[sl] - ly * W.fx[sl];
    B.torque[b] -= W.mr[sl];
  }
  for (size_t b = 0; b < B.size(); ++b) {
    s.state.body_fx_sum[b] += B.fx[b];
    s.state.body_fy_sum[b] += B.fy[b];
    s.state.body_torque_sum[b] += B.torque[b];
  }
  ++s.state.body_sum_steps;
}

template <EffectSet E>
void initial_forces(System& s) {
  const EffectSet scene = s.config.effects;
  ContactModel<E> pp{s.config.pp, scene}, pw{s.config.pw, scene};  // no spring increments: there is no previous step
  pp.c.kt_dt = pp.c.kr_dt = pw.c.kt_dt = pw.c.kr_dt = 0.0;
  const bool walls = applies<E>(scene, effect::walls);
#pragma omp parallel num_threads(s.work.threads)
  {
    pair_forces<E>(s, pp);
    if constexpr (compiles<E>(effect::walls))
      if (walls) body_forces<E>(s, pw);
#pragma omp barrier
    gather<E>(s);
  }  // (the region's end is a barrier)
  if (walls) {
    body_sums(s);
    s.reset_body_sums();
  }
}

// Thread 0's serial work after a drift has opened a step: the step count and
// the bodies' positions for it. No other thread reads either before the next
// barrier.
template <EffectSet E>
inline void open_step_serial(System& s) {
  ++s.state.step;
  if (applies<E>(s.config.effects, effect::moving_bodies)) s.place_bodies();
}

template <EffectSet E>
void advance(System& s, std::int64_t steps) {
  if (steps <= 0) return;
  bool failed = false;
  StepBarrier barrier;  // the step's phases (step_barrier.hpp: its waiters sleep when the cores are taken)
  barrier.reset(s.work.threads);
  const EffectSet scene = s.config.effects;
  const bool walls = applies<E>(scene, effect::walls);
#pragma omp parallel num_threads(s.work.threads)
  {
    // every thread keeps the same displacement bound, from the same numbers
    double moved = s.cache.moved_particles;
    const auto thread = static_cast<size_t>(omp_get_thread_num());
    PassClock clock(s.work.pass_totals.empty() ? nullptr : &s.work.pass_totals[thread]);
    integrate<E, false, true>(s);
    clock.end(Pass::integrate);
#pragma omp master
    open_step_serial<E>(s);
    clock.end(Pass::bodies);
    const bool ledger = s.state.energy.on;  // the same for every thread: the extra barriers below match
    for (std::int64_t k = 0; k < steps; ++k) {
      barrier.wait();
      if (ledger) energy::open_step(s);
      double v2max = 0.0;
      bool escaped = false;
      for (const auto& r : s.work.drift) {
        v2max = std::max(v2max, r.v2max);
        escaped |= r.escaped;
      }
      moved += std::sqrt(v2max) * s.config.dt;
      clock.end(Pass::wait_drift);
      if (escaped || s.state.rebuild_pending || moved > 0.5 * s.state.lists.skin() || moved + s.cache.moved_bodies > s.state.lists.skin()) {
        // Every thread has taken this decision (and its open_step is done
        // with the old lists) before the rebuild resets what it was taken
        // from (rebuild_pending, moved_bodies, the drift reports): without
        // this barrier a thread that runs late decides otherwise, skips the
        // rebuild, and the threads' barriers no longer match (a hang, seen
        // with 2 threads sharing one core).
        barrier.wait();
#pragma omp master
        {
          s.rebuild_in_step(escaped);
          failed = !s.failure.empty();
        }
        barrier.wait();
        moved = 0.0;
        clock.end(Pass::rebuild);
        if (failed) break;
      }
      pair_forces<E>(s, ContactModel<E>{s.config.pp, scene});
      clock.end(Pass::pairs);
      if constexpr (compiles<E>(effect::walls))
        if (walls) body_forces<E>(s, ContactModel<E>{s.config.pw, scene});
      clock.end(Pass::walls);
      barrier.wait();
      clock.end(Pass::wait_forces);
      if (ledger) {
        energy::close_step(s);
        barrier.wait();
        clock.end(Pass::ledger);
      }  // no grain moves before every thread's close_step has read it
      claim_shared_grains(s);
      gather<E>(s);
      clock.end(Pass::gather);
      const bool open = k + 1 < steps;
      if (open)
        integrate<E, true, true>(s);  // close this step, open the next
      else
        integrate<E, true, false>(s);
      clock.end(Pass::integrate);
#pragma omp master
      {
        // this step's body force sums (all wall slots were done before the
        // barrier above) need the bodies where they were: sum, then move them
        if (walls) body_sums(s);
        if (open) open_step_serial<E>(s);
      }
      clock.end(Pass::bodies);
    }
#pragma omp master
    s.cache.moved_particles = moved;
  }
}

}  // namespace dem2d::kernels
