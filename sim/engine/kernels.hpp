// The hot loop, templated on the effect set E. Every effect test below is
// `if constexpr`: an instantiation contains only the physics its scene names.
//
// One time step (velocity Verlet, as in LAMMPS: velocity-dependent forces use
// the half-step velocity):
//   v += dt/2 a(t);  x += dt v                      kick_drift   (parallel over grains)
//   move bodies; rebuild lists if the skin is used   serial
//   per-contact forces at x(t+dt)                   pair_forces, wall_forces (parallel over rows)
//   per-grain sums in a fixed order; v += dt/2 a    gather_kick  (parallel over grains)
//   body force sums                                  serial, fixed order
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

// v += dt/2 (F/m + g); x += dt v. Each thread leaves the largest speed squared
// it saw (m^2/s^2) in s.thread_v2max and whether a grain left the domain (or
// became non-finite) in s.thread_escaped; the caller reads them after a barrier.
template <EffectSet E>
inline void kick_drift(System& s) {
  Particles& p = s.p;
  const double h = 0.5 * s.dt, dt = s.dt;
  const double gx = s.gx, gy = s.gy;
  const Box box = s.domain;
  const auto n = static_cast<std::int64_t>(p.size());
  double v2max = 0.0;
  bool escaped = false;
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    if (!p.active[i]) continue;
    double ax = p.fx[i] * p.inv_mass[i], ay = p.fy[i] * p.inv_mass[i];
    if constexpr (has(E, effect::gravity)) {
      ax += gx;
      ay += gy;
    }
    const double vx = p.vx[i] + h * ax, vy = p.vy[i] + h * ay;
    const double w = p.omega[i] + h * p.torque[i] * p.inv_inertia[i];
    p.vx[i] = vx;
    p.vy[i] = vy;
    p.omega[i] = w;
    const double x = p.x[i] + dt * vx, y = p.y[i] + dt * vy;
    p.x[i] = x;
    p.y[i] = y;
    p.theta[i] += dt * w;
    v2max = std::max(v2max, vx * vx + vy * vy);
    escaped |= !box.contains(x, y) || !std::isfinite(w);  // contains() is false for NaN
  }
  const auto t = static_cast<size_t>(omp_get_thread_num());
  s.thread_v2max[t] = v2max;
  s.thread_escaped[t] = escaped;
}

// Particle-particle contacts: one evaluation per pair, results per slot.
template <EffectSet E>
inline void pair_forces(System& s, const LawCoefficients& c) {
  const Particles& p = s.p;
  PairList& L = s.lists.pairs;
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    const double xi = p.x[i], yi = p.y[i], ri = p.radius[i];
    const auto end = static_cast<size_t>(L.start[i + 1]);
    for (auto sl = static_cast<size_t>(L.start[i]); sl < end; ++sl) {
      const auto j = static_cast<size_t>(L.partner[sl]);
      const double dx = xi - p.x[j], dy = yi - p.y[j], rsum = ri + p.radius[j];
      const double d2 = dx * dx + dy * dy;
      if (d2 >= rsum * rsum) {  // open: forget the history
        L.fx[sl] = L.fy[sl] = L.fn[sl] = L.overlap[sl] = 0.0;
        if constexpr (has(E, effect::friction)) L.ft[sl] = L.q[sl] = 0.0;
        if constexpr (has(E, effect::rolling_resistance)) L.mr[sl] = 0.0;
        continue;
      }
      const double dist = std::sqrt(d2);
      double nx = 1.0, ny = 0.0;  // coincident centres: separate them along x
      if (dist > 0.0) {
        const double inv = 1.0 / dist;
        nx = dx * inv;
        ny = dy * inv;
      }
      const double delta = dist - rsum;
      const double rvx = p.vx[i] - p.vx[j], rvy = p.vy[i] - p.vy[j];
      double sqrt_meff = 0.0;
      if constexpr (has(E, effect::normal_damping))
        sqrt_meff = 1.0 / std::sqrt(p.inv_mass[i] + p.inv_mass[j]);
      const double fn = normal_force<E>(c, delta, rvx * nx + rvy * ny, sqrt_meff);
      double fx = fn * nx, fy = fn * ny;
      if constexpr (has(E, effect::friction)) {
        // branch vectors end at the middle of the overlap: a = r + delta/2
        const double tx = -ny, ty = nx;
        const double vt = rvx * tx + rvy * ty -
                          ((ri + 0.5 * delta) * p.omega[i] + (p.radius[j] + 0.5 * delta) * p.omega[j]);
        const double ft = capped_increment(L.ft[sl], -c.kt_dt * vt, c.mu * fn);
        L.ft[sl] = ft;
        L.q[sl] = -0.5 * delta * ft;
        fx += ft * tx;
        fy += ft * ty;
      }
      if constexpr (has(E, effect::rolling_resistance))
        L.mr[sl] = capped_increment(L.mr[sl], -c.kr_dt * (p.omega[i] - p.omega[j]), c.mu_r * fn);
      L.fx[sl] = fx;
      L.fy[sl] = fy;
      L.fn[sl] = fn;
      L.overlap[sl] = -delta;
    }
  }
}

// Grain-sphero-line contacts, one row per grain.
template <EffectSet E>
inline void wall_forces(System& s, const LawCoefficients& c) {
  const Particles& p = s.p;
  WallList& L = s.lists.walls;
  const Bodies& B = s.bodies;
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp for schedule(static) nowait
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    const auto end = static_cast<size_t>(L.start[i + 1]);
    for (auto sl = static_cast<size_t>(L.start[i]); sl < end; ++sl) {
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
}

// Per-grain resultant, summed in a fixed order (own row by ascending partner,
// then the reverse index by ascending i, then walls), then the closing
// half-kick v += dt/2 a(t+dt) if Kick.
template <EffectSet E, bool Kick>
inline void gather_kick(System& s) {
  Particles& p = s.p;
  const PairList& L = s.lists.pairs;
  const WallList& W = s.lists.walls;
  const double h = 0.5 * s.dt, gx = s.gx, gy = s.gy;
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp for schedule(static)
  for (std::int64_t k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    if (!p.active[i]) continue;
    double fx = 0.0, fy = 0.0, ft_sum = 0.0, tq = 0.0;
    const auto end = static_cast<size_t>(L.start[i + 1]);
    for (auto sl = static_cast<size_t>(L.start[i]); sl < end; ++sl) {
      fx += L.fx[sl];
      fy += L.fy[sl];
      if constexpr (has(E, effect::friction)) {
        ft_sum += L.ft[sl];
        tq += L.q[sl];
      }
      if constexpr (has(E, effect::rolling_resistance)) tq += L.mr[sl];
    }
    const auto rend = static_cast<size_t>(L.rev_start[i + 1]);
    for (auto r = static_cast<size_t>(L.rev_start[i]); r < rend; ++r) {
      const auto sl = static_cast<size_t>(L.rev_slot[r]);
      fx -= L.fx[sl];
      fy -= L.fy[sl];
      if constexpr (has(E, effect::friction)) {
        ft_sum += L.ft[sl];
        tq += L.q[sl];
      }
      if constexpr (has(E, effect::rolling_resistance)) tq -= L.mr[sl];
    }
    if constexpr (has(E, effect::friction)) tq -= p.radius[i] * ft_sum;
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
    if constexpr (Kick) {
      double ax = fx * p.inv_mass[i], ay = fy * p.inv_mass[i];
      if constexpr (has(E, effect::gravity)) {
        ax += gx;
        ay += gy;
      }
      p.vx[i] += h * ax;
      p.vy[i] += h * ay;
      p.omega[i] += h * tq * p.inv_inertia[i];
    }
  }
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
    gather_kick<E, false>(s);
  }
  if constexpr (has(E, effect::walls)) {
    body_sums(s);
    s.reset_body_sums();
  }
}

template <EffectSet E>
void advance(System& s, std::int64_t steps) {
  bool failed = false;
#pragma omp parallel num_threads(s.threads)
  for (std::int64_t k = 0; k < steps; ++k) {
    kick_drift<E>(s);
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
    gather_kick<E, true>(s);
    if constexpr (has(E, effect::walls)) {
#pragma omp single
      body_sums(s);
    }
  }
}

}  // namespace dem2d::kernels
