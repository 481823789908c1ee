// The hot loop, templated on the effect set E. Every effect test below is
// `if constexpr`: an instantiation contains only the physics its scene names.
//
// One time step (velocity Verlet, as in LAMMPS: velocity-dependent forces use
// the half-step velocity):
//   v += dt/2 a(t);  x += dt v                    kick + drift (parallel over grains)
//   move bodies; rebuild lists if the skin is used serial
//   per-contact forces at x(t+dt)                 pair_forces (parallel over slots, vectorised),
//                                                 wall_forces
//   per-grain sums in a fixed order; v += dt/2 a  gather (parallel over grains), fused with
//                                                 the next step's kick + drift within a call
//   body force sums                                serial, fixed order
// All loops run inside one OpenMP parallel region per call; none allocates.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <omp.h>

#include "engine/system.hpp"

namespace dem2d::kernels {

using std::size_t;

// The two halves of velocity Verlet for one grain.
// kick:  v += h (F/m + g), omega += h T/I      (h = dt/2)
// drift: x += dt v, theta += dt omega; records the largest speed^2 and whether
//        the grain left the domain or became non-finite (contains() is false for NaN).
struct DriftStats {
  double v2max = 0.0;  // m^2/s^2
  bool escaped = false;
};

template <EffectSet E>
inline void kick(Particles& p, size_t i, double h, double gx, double gy) {
  double ax = p.fx[i] * p.inv_mass[i], ay = p.fy[i] * p.inv_mass[i];
  if constexpr (has(E, effect::gravity)) {
    ax += gx;
    ay += gy;
  }
  p.vx[i] += h * ax;
  p.vy[i] += h * ay;
  p.omega[i] += h * p.torque[i] * p.inv_inertia[i];
}

inline void drift(Particles& p, size_t i, double dt, const Box& box, DriftStats& st) {
  const double vx = p.vx[i], vy = p.vy[i], w = p.omega[i];
  const double x = p.x[i] + dt * vx, y = p.y[i] + dt * vy;
  p.x[i] = x;
  p.y[i] = y;
  p.theta[i] += dt * w;
  st.v2max = std::max(st.v2max, vx * vx + vy * vy);
  st.escaped |= !box.contains(x, y) || !std::isfinite(w);
}

// Each thread leaves its drift statistics in the System; the caller reads
// them after a barrier.
inline void publish(System& s, const DriftStats& st) {
  const auto t = static_cast<size_t>(omp_get_thread_num());
  s.thread_v2max[t] = st.v2max;
  s.thread_escaped[t] = st.escaped;
}

// The opening kick and drift of a step, for the first step of a call.
template <EffectSet E>
inline void kick_drift(System& s) {
  Particles& p = s.p;
  const double h = 0.5 * s.dt;
  const auto n = static_cast<std::int64_t>(p.size());
  DriftStats st;
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    if (!p.active[i]) continue;
    kick<E>(p, i, h, s.gx, s.gy);
    drift(p, i, s.dt, s.domain, st);
  }
  publish(s, st);
}

// Particle-particle contacts: one evaluation per pair, results per slot.
// A flat loop over slots without branches (open contacts are masked to zero
// by selects), so that the compiler vectorises it; a touching slot goes
// through exactly the arithmetic of the scalar law in contact_law.hpp.
template <EffectSet E>
inline void pair_forces(System& s, const LawCoefficients c) {  // by value: cannot alias the outputs
  const Particles& p = s.p;
  PairList& L = s.lists.pairs;
  const std::int32_t *own = L.owner.data(), *par = L.partner.data();
  const double *x = p.x.data(), *y = p.y.data(), *vx = p.vx.data(), *vy = p.vy.data(), *w = p.omega.data();
  const double *rad_i = L.ri.data(), *rad_j = L.rj.data(), *sqm = L.sqrt_meff.data();
  double *ft = L.ft.data(), *mr = L.mr.data(), *ti = L.ti.data(), *tj = L.tj.data();
  double *fx = L.fx.data(), *fy = L.fy.data(), *fn = L.fn.data(), *ov = L.overlap.data();
  const auto slots = static_cast<std::int64_t>(L.slots());
  // simd: slots are independent (each reads grain data, writes only its own slot)
#pragma omp for simd schedule(static) nowait
  for (std::int64_t sl = 0; sl < slots; ++sl) {
    const std::int32_t i = own[sl], j = par[sl];
    const double dx = x[i] - x[j], dy = y[i] - y[j], ri = rad_i[sl], rj = rad_j[sl], rsum = ri + rj;
    const double d2 = dx * dx + dy * dy;
    const bool touch = d2 < rsum * rsum;
    const double dist = std::sqrt(d2);
    const bool apart = dist > 0.0;  // coincident centres: separate them along x
    const double inv = 1.0 / (apart ? dist : 1.0);
    const double nx = apart ? dx * inv : 1.0, ny = apart ? dy * inv : 0.0;
    const double delta = dist - rsum;
    const double rvx = vx[i] - vx[j], rvy = vy[i] - vy[j];
    const double f_n = touch ? normal_force<E>(c, delta, rvx * nx + rvy * ny, sqm[sl]) : 0.0;
    double fxs = f_n * nx, fys = f_n * ny, tqi = 0.0, tqj = 0.0;
    if constexpr (has(E, effect::friction)) {
      // branch vectors end at the middle of the overlap: a = r + delta/2
      const double ai = ri + 0.5 * delta, aj = rj + 0.5 * delta;
      const double tx = -ny, ty = nx;
      const double vt = rvx * tx + rvy * ty - (ai * w[i] + aj * w[j]);
      const double f_t = touch ? capped_increment(ft[sl], -c.kt_dt * vt, c.mu * f_n) : 0.0;
      ft[sl] = f_t;
      fxs += f_t * tx;
      fys += f_t * ty;
      tqi = -ai * f_t;
      tqj = -aj * f_t;
    }
    if constexpr (has(E, effect::rolling_resistance)) {
      const double m = touch ? capped_increment(mr[sl], -c.kr_dt * (w[i] - w[j]), c.mu_r * f_n) : 0.0;
      mr[sl] = m;
      tqi += m;
      tqj -= m;
    }
    fx[sl] = touch ? fxs : 0.0;
    fy[sl] = touch ? fys : 0.0;
    if constexpr (has(E, effect::friction) || has(E, effect::rolling_resistance)) {
      ti[sl] = touch ? tqi : 0.0;
      tj[sl] = touch ? tqj : 0.0;
    }
    fn[sl] = f_n;
    ov[sl] = touch ? -delta : 0.0;
  }
}

// Grain-sphero-line contacts: a flat loop over the (few) wall slots.
template <EffectSet E>
inline void wall_forces(System& s, const LawCoefficients& c) {
  const Particles& p = s.p;
  WallList& L = s.lists.walls;
  const Bodies& B = s.bodies;
  const auto slots = static_cast<std::int64_t>(L.slots());
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < slots; ++k) {
    const auto sl = static_cast<size_t>(k);
    const auto i = static_cast<size_t>(L.owner[sl]);
    const auto b = static_cast<size_t>(L.body[sl]);
    const SegmentProximity g = closest_point(s.seg[b], p.x[i], p.y[i]);
    const double ri = p.radius[i];
    const double delta = g.dist - (ri + B.radius[b]);
    if (delta >= 0.0) {
      L.fx[sl] = L.fy[sl] = L.tq[sl] = L.fn[sl] = L.overlap[sl] = 0.0;
      if constexpr (has(E, effect::friction)) L.ft[sl] = 0.0;
      if constexpr (has(E, effect::rolling_resistance)) L.mr[sl] = 0.0;
      continue;
    }
    double rvx = p.vx[i], rvy = p.vy[i];
    if constexpr (has(E, effect::moving_bodies)) {
      rvx -= B.vx[b];
      rvy -= B.vy[b];
    }
    double sqrt_m = 0.0;
    if constexpr (has(E, effect::normal_damping)) sqrt_m = std::sqrt(p.mass[i]);
    const double fn = normal_force<E>(c, delta, rvx * g.nx + rvy * g.ny, sqrt_m);
    const double a = ri + 0.5 * delta;  // centre to contact point (m)
    double fx = fn * g.nx, fy = fn * g.ny, tq = 0.0;
    if constexpr (has(E, effect::friction)) {
      const double tx = -g.ny, ty = g.nx;
      const double vt = rvx * tx + rvy * ty - a * p.omega[i];
      const double ft = capped_increment(L.ft[sl], -c.kt_dt * vt, c.mu * fn);
      L.ft[sl] = ft;
      fx += ft * tx;
      fy += ft * ty;
      tq = -a * ft;
    }
    if constexpr (has(E, effect::rolling_resistance)) {
      const double mr = capped_increment(L.mr[sl], -c.kr_dt * p.omega[i], c.mu_r * fn);
      L.mr[sl] = mr;
      tq += mr;
    }
    L.fx[sl] = fx;
    L.fy[sl] = fy;
    L.tq[sl] = tq;
    L.cx[sl] = p.x[i] - a * g.nx;
    L.cy[sl] = p.y[i] - a * g.ny;
    L.fn[sl] = fn;
    L.overlap[sl] = -delta;
  }
}

// What follows the force sum of a grain in gather():
enum class Then {
  nothing,     // forces only (start-up)
  kick,        // closing half-kick: v(t+dt) (the last step of a call)
  kick_drift,  // closing half-kick, then the next step's kick and drift
};

// Per-grain resultant, summed in a fixed order (own row by ascending partner,
// then the reverse index by ascending i, then walls), then `next`. Fusing the
// next step's kick and drift into this pass saves a sweep over the grains and
// does the same operations in the same order as separate passes would.
template <EffectSet E, Then next>
inline void gather(System& s) {
  Particles& p = s.p;
  const PairList& L = s.lists.pairs;
  const WallList& W = s.lists.walls;
  const double h = 0.5 * s.dt;
  const auto n = static_cast<std::int64_t>(p.size());
  DriftStats st;
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    if (!p.active[i]) continue;
    constexpr bool kTorque = has(E, effect::friction) || has(E, effect::rolling_resistance);
    double fx = 0.0, fy = 0.0, tq = 0.0;
    const auto end = static_cast<size_t>(L.start[i + 1]);
    for (auto sl = static_cast<size_t>(L.start[i]); sl < end; ++sl) {
      fx += L.fx[sl];
      fy += L.fy[sl];
      if constexpr (kTorque) tq += L.ti[sl];
    }
    const auto rend = static_cast<size_t>(L.rev_start[i + 1]);
    for (auto r = static_cast<size_t>(L.rev_start[i]); r < rend; ++r) {
      const auto sl = static_cast<size_t>(L.rev_slot[r]);
      fx -= L.fx[sl];
      fy -= L.fy[sl];
      if constexpr (kTorque) tq += L.tj[sl];
    }
    if constexpr (has(E, effect::walls)) {
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
    if constexpr (next != Then::nothing) kick<E>(p, i, h, s.gx, s.gy);
    if constexpr (next == Then::kick_drift) {
      kick<E>(p, i, h, s.gx, s.gy);
      drift(p, i, s.dt, s.domain, st);
    }
  }
  if constexpr (next == Then::kick_drift) publish(s, st);
}

// Force and torque the grains exert on each body, summed in slot order.
inline void body_sums(System& s) {
  Bodies& B = s.bodies;
  const WallList& W = s.lists.walls;
  std::fill(B.fx.begin(), B.fx.end(), 0.0);
  std::fill(B.fy.begin(), B.fy.end(), 0.0);
  std::fill(B.torque.begin(), B.torque.end(), 0.0);
  for (size_t sl = 0; sl < W.slots(); ++sl) {
    const auto b = static_cast<size_t>(W.body[sl]);
    B.fx[b] -= W.fx[sl];
    B.fy[b] -= W.fy[sl];
    // lever arm from the body's middle to the contact point, force -F,
    // plus the reaction of the rolling moment
    const double lx = W.cx[sl] - B.centre_x(b), ly = W.cy[sl] - B.centre_y(b);
    B.torque[b] -= lx * W.fy[sl] - ly * W.fx[sl];
    B.torque[b] -= W.mr[sl];
  }
  for (size_t b = 0; b < B.size(); ++b) {
    s.body_fx_sum[b] += B.fx[b];
    s.body_fy_sum[b] += B.fy[b];
    s.body_torque_sum[b] += B.torque[b];
  }
  ++s.body_sum_steps;
}

template <EffectSet E>
void initial_forces(System& s) {
  LawCoefficients pp = s.pp, pw = s.pw;  // no spring increments: there is no previous step
  pp.kt_dt = pp.kr_dt = pw.kt_dt = pw.kr_dt = 0.0;
#pragma omp parallel num_threads(s.threads)
  {
    pair_forces<E>(s, pp);
    if constexpr (has(E, effect::walls)) wall_forces<E>(s, pw);
#pragma omp barrier
    gather<E, Then::nothing>(s);
  }
  if constexpr (has(E, effect::walls)) {
    body_sums(s);
    s.reset_body_sums();
  }
}

template <EffectSet E>
void advance(System& s, std::int64_t steps) {
  if (steps <= 0) return;
  bool failed = false;
#pragma omp parallel num_threads(s.threads)
  {
    kick_drift<E>(s);
    for (std::int64_t k = 0; k < steps; ++k) {
#pragma omp barrier
#pragma omp single
      {
        const double v2max = *std::max_element(s.thread_v2max.begin(), s.thread_v2max.end());
        const bool escaped =
            std::find(s.thread_escaped.begin(), s.thread_escaped.end(), 1) != s.thread_escaped.end();
        std::fill(s.thread_v2max.begin(), s.thread_v2max.end(), 0.0);
        std::fill(s.thread_escaped.begin(), s.thread_escaped.end(), 0);
        ++s.step;
        s.moved_particles += std::sqrt(v2max) * s.dt;
        if constexpr (has(E, effect::moving_bodies)) s.place_bodies();
        if (escaped) s.remove_escaped();
        const double half_skin = 0.5 * s.lists.skin();
        if (escaped || s.moved_particles > half_skin || s.moved_particles + s.moved_bodies > s.lists.skin())
          s.rebuild();
        failed = !s.failure.empty();
      }
      if (failed) break;
      pair_forces<E>(s, s.pp);
      if constexpr (has(E, effect::walls)) wall_forces<E>(s, s.pw);
#pragma omp barrier
      if (k + 1 < steps)
        gather<E, Then::kick_drift>(s);
      else
        gather<E, Then::kick>(s);
      if constexpr (has(E, effect::walls)) {
#pragma omp single
        body_sums(s);
      }
    }
  }
}

}  // namespace dem2d::kernels
