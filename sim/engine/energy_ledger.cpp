#include "engine/energy_ledger.hpp"

#include <cmath>
#include <utility>

#include "engine/diagnostics.hpp"
#include "engine/kernels.hpp"

namespace dem2d::energy {

namespace {

// Half the work of a force (fx, fy) and torque t on grain i over this step:
// 1/2 (F.dx + t dtheta), the displacements being dt times the half-step
// velocities.
double half_work(const System& s, std::size_t i, double fx, double fy, double t) {
  return 0.5 * s.config.dt * (fx * s.state.p.vx[i] + fy * s.state.p.vy[i] + t * s.state.p.omega[i]);
}

// The gravity vector the grains feel (m/s^2): zero without the effect.
std::pair<double, double> gravity_of(const System& s) {
  return has(s.config.effects, effect::gravity) ? std::pair{s.config.gx, s.config.gy} : std::pair{0.0, 0.0};
}

// Kinematics of a touching contact at the step's end, as the kernel sees it
// (the same functions: contact/law_terms.hpp): normal velocity, tangential
// velocity of the contact points, relative spin.
struct Motion : ContactMotion {
  double tx, ty;  // t = z x n
  double a;       // the grain's branch length to the contact point (m)
};

Motion pair_motion(const Particles& p, std::size_t i, std::size_t j, double overlap) {
  const double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dist = std::sqrt(dx * dx + dy * dy);
  const double nx = dist > 0.0 ? dx / dist : 1.0, ny = dist > 0.0 ? dy / dist : 0.0;
  const double rvx = p.vx[i] - p.vx[j], rvy = p.vy[i] - p.vy[j];
  const double ai = p.radius[i] - 0.5 * overlap, aj = p.radius[j] - 0.5 * overlap;
  return {grain_pair_motion(rvx, rvy, nx, ny, ai, p.omega[i], aj, p.omega[j]), -ny, nx, ai};
}

Motion wall_motion(const System& s, std::size_t i, std::size_t b, double overlap) {
  const Particles& p = s.state.p;
  const Proximity g = closest_point(s.state.bodies.shape[b], p.x[i], p.y[i]);
  const double a = p.radius[i] - 0.5 * overlap;
  const Bodies& B = s.state.bodies;
  const EffectSet e = s.config.effects;
  const auto [rvx, rvy] =  // (the kernel's flags: turning bodies need moving ones, core/effects.hpp)
      relative_to_surface(p.vx[i], p.vy[i], has(e, effect::moving_bodies), has(e, effect::rotating_bodies), B.vx[b],
                          B.vy[b], B.omega[b], B.pivot_x[b], B.pivot_y[b], p.x[i] - a * g.nx, p.y[i] - a * g.ny);
  return {grain_body_motion(rvx, rvy, g.nx, g.ny, a, p.omega[i]), -g.ny, g.nx, a};
}

// What a touching contact's terms dissipated this step (contact/contact_law.hpp: dissipated): `fn`, `ft`,
// `moment` act on the grain at the step's end (from the slot's force and torques); `elastic_fn` is what
// the springs push with (Stored::fn); sqrt_m, sqrt_i the slot's effective mass and inertia roots.
Dissipation dissipated_at(const System& s, const ContactLaw& law, const LawCoefficients& c, const Motion& m,
                          double overlap, double sqrt_m, double sqrt_i, double elastic_fn, double fn, double ft,
                          double moment, double spring_t, double spring_t_prev, double spring_r, double spring_r_prev) {
  const double dt = s.config.dt;
  const ContactStep step{{-overlap, m.vn, m.vt, m.spin, sqrt_m, sqrt_i}, dt, 0.0, ft, spring_t, spring_t_prev,
                         moment, spring_r, spring_r_prev};
  return dissipated(law, c, s.config.effects, step, (elastic_fn - fn) * m.vn * dt);
}

double sum(const Dissipation& d) {
  double total = 0.0;
  for (const double v : d) total += v;
  return total;
}

// A contact that opened this step: the kernel zeroed its springs, whose
// energy the terms' sliders take (the cap fell to 0 with F_n).
void release(EnergyLedger& e, std::size_t i, const ContactLaw& law, EffectSet effects, double ft_prev, double mr_prev) {
  const Dissipation d = released(law, effects, {0.0, ft_prev, mr_prev});
  for (std::size_t k = 0; k < d.size(); ++k) e.dissipated[k][i] += d[k];
  e.error[i] -= sum(d);
}

void add(EnergyLedger& e, std::size_t i, const Dissipation& d) {
  for (std::size_t k = 0; k < d.size(); ++k) e.dissipated[k][i] += d[k];
}

// Visits this thread's rows of the pair and wall lists, in order.
template <class PairFn, class WallFn>
void my_contacts(System& s, PairFn&& pair, WallFn&& wall) {
  const auto [first, last] = kernels::my_grains(s);
  for (std::size_t i = first; i < last; ++i) {
    const PairList& L = s.state.lists.pairs;
    for (auto sl = static_cast<std::size_t>(L.start[i]); sl < static_cast<std::size_t>(L.start[i + 1]); ++sl)
      pair(i, sl);
    if (!has(s.config.effects, effect::walls)) continue;
    const WallList& W = s.state.lists.walls;
    for (auto sl = static_cast<std::size_t>(W.start[i]); sl < static_cast<std::size_t>(W.start[i + 1]); ++sl)
      wall(i, sl);
  }
}

// 1/2 of the work a contact did on its grains over this step with the force
// it holds now (the start's or the end's), split into the relative part and
// the part the body's displacement did.
struct Work {
  double relative, body;
};

Work pair_work(const System& s, std::size_t sl, std::size_t i) {
  const PairList& L = s.state.lists.pairs;
  const auto j = static_cast<std::size_t>(L.partner[sl]);
  return {half_work(s, i, L.fx[sl], L.fy[sl], L.ti[sl]) + half_work(s, j, -L.fx[sl], -L.fy[sl], L.tj[sl]), 0.0};
}

Work wall_work(const System& s, std::size_t sl, std::size_t i) {
  const WallList& W = s.state.lists.walls;
  const auto b = static_cast<std::size_t>(W.body[sl]);
  double body = 0.0;
  if (has(s.config.effects, effect::moving_bodies)) {  // the body's surface at the contact point
    const std::array<double, 2> v = s.state.bodies.velocity_at(b, W.cx[sl], W.cy[sl]);
    body = 0.5 * s.config.dt * (W.fx[sl] * v[0] + W.fy[sl] * v[1]);
  }
  return {half_work(s, i, W.fx[sl], W.fy[sl], W.tq[sl]) - body, body};
}

}  // namespace

void start(System& s) {
  EnergyLedger& e = s.state.energy;
  for (const auto& [name, a] : accumulators(e)) a->assign(s.size(), 0.0);
  e.removed = 0.0;
  e.error_offset = 0.0;
  e.error_offset = -balance(s).integration_error;
}

void open_step(System& s) {
  EnergyLedger& e = s.state.energy;
  PairList& L = s.state.lists.pairs;
  WallList& W = s.state.lists.walls;
  my_contacts(
      s,
      [&](std::size_t i, std::size_t sl) {
        L.ft_prev[sl] = L.ft[sl];
        L.mr_prev[sl] = L.mr[sl];
        if (!(L.overlap[sl] > 0.0)) return;
        const Work w = pair_work(s, sl, i);
        e.error[i] += spring_energy(s.config.law_pp, s.config.effects, L.overlap[sl], L.ft[sl], L.mr[sl]).total() - w.relative;
      },
      [&](std::size_t i, std::size_t sl) {
        W.ft_prev[sl] = W.ft[sl];
        W.mr_prev[sl] = W.mr[sl];
        if (!(W.overlap[sl] > 0.0)) return;
        const Work w = wall_work(s, sl, i);
        e.body_work[i] += w.body;
        e.error[i] += spring_energy(s.config.law_pw, s.config.effects, W.overlap[sl], W.ft[sl], W.mr[sl]).total() - w.relative;
      });
}

void close_step(System& s) {
  EnergyLedger& e = s.state.energy;
  const PairList& L = s.state.lists.pairs;
  const WallList& W = s.state.lists.walls;
  my_contacts(
      s,
      [&](std::size_t i, std::size_t sl) {
        if (!(L.overlap[sl] > 0.0)) return release(e, i, s.config.law_pp, s.config.effects, L.ft_prev[sl], L.mr_prev[sl]);
        const Work w = pair_work(s, sl, i);
        const Motion m = pair_motion(s.state.p, i, static_cast<std::size_t>(L.partner[sl]), L.overlap[sl]);
        const double ft = L.fx[sl] * m.tx + L.fy[sl] * m.ty;  // T_i = -a_i F_t + M_r
        const Stored u = spring_energy(s.config.law_pp, s.config.effects, L.overlap[sl], L.ft[sl], L.mr[sl]);
        const Dissipation d = dissipated_at(s, s.config.law_pp, s.config.pp, m, L.overlap[sl], L.sqrt_meff[sl],
                                            L.sqrt_ieff[sl], u.fn, L.fn[sl], ft, L.ti[sl] + m.a * ft, L.ft[sl],
                                            L.ft_prev[sl], L.mr[sl], L.mr_prev[sl]);
        add(e, i, d);
        e.error[i] -= u.total() + w.relative + sum(d);
      },
      [&](std::size_t i, std::size_t sl) {
        if (!(W.overlap[sl] > 0.0)) return release(e, i, s.config.law_pw, s.config.effects, W.ft_prev[sl], W.mr_prev[sl]);
        const Work w = wall_work(s, sl, i);
        const Motion m = wall_motion(s, i, static_cast<std::size_t>(W.body[sl]), W.overlap[sl]);
        const double ft = W.fx[sl] * m.tx + W.fy[sl] * m.ty;
        const Stored u = spring_energy(s.config.law_pw, s.config.effects, W.overlap[sl], W.ft[sl], W.mr[sl]);
        const Dissipation d = dissipated_at(s, s.config.law_pw, s.config.pw, m, W.overlap[sl], W.sqrt_m[sl], W.sqrt_i[sl],
                                            u.fn, W.fn[sl], ft, W.tq[sl] + m.a * ft, W.ft[sl], W.ft_prev[sl],
                                            W.mr[sl], W.mr_prev[sl]);
        add(e, i, d);
        e.body_work[i] += w.body;
        e.error[i] -= u.total() + w.relative + sum(d);
      });
}

void remove_grain(System& s, std::size_t i) {
  // What the grain carries out: its shadow kinetic energy at the step's start,
  // its potential energy there, and the first half of this step's work on it
  // (its contacts' first halves went into the ledger already; their second
  // halves never come). Velocities are the half-step ones, forces the start's.
  const Particles& p = s.state.p;
  const auto [gx, gy] = gravity_of(s);
  const double ax = p.fx[i] * p.inv_mass[i] + gx, ay = p.fy[i] * p.inv_mass[i] + gy, aw = p.torque[i] * p.inv_inertia[i];
  const double m = p.mass[i], inertia = 1.0 / p.inv_inertia[i];
  const double ux = p.vx[i] - s.config.dt * ax, uy = p.vy[i] - s.config.dt * ay, uw = p.omega[i] - s.config.dt * aw;  // v^(n-1/2)
  const double shadow = 0.5 * m * (ux * p.vx[i] + uy * p.vy[i]) + 0.5 * inertia * uw * p.omega[i];
  const double x0 = p.x[i] - s.config.dt * p.vx[i], y0 = p.y[i] - s.config.dt * p.vy[i];
  const double potential = -m * (gx * x0 + gy * y0);
  s.state.energy.removed += shadow + potential + half_work(s, i, p.fx[i], p.fy[i], p.torque[i]);
}

EnergyBalance balance(const System& s) {
  const EnergyLedger& e = s.state.energy;
  const Particles& p = s.state.p;
  EnergyBalance out;
  const Stored u = spring_energy(s);
  out.elastic_normal = u.normal;
  out.elastic_tangential = u.tangential;
  out.elastic_rolling = u.rolling;
  out.kinetic = kinetic_energy(s);
  out.gravity = has(s.config.effects, effect::gravity) ? gravity_energy(s) : 0.0;
  // physical minus shadow kinetic energy: sum 1/2 (dt/2)^2 (m a^2 + I alpha^2)
  const double h = 0.5 * s.config.dt;
  const auto [gx, gy] = gravity_of(s);
  double shadow_gap = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.active[i]) continue;
    const double ax = p.fx[i] * p.inv_mass[i] + gx, ay = p.fy[i] * p.inv_mass[i] + gy;
    const double aw = p.torque[i] * p.inv_inertia[i];
    shadow_gap += 0.5 * h * h * (p.mass[i] * (ax * ax + ay * ay) + aw * aw / p.inv_inertia[i]);
  }
  if (e.error.size() == p.size())
    for (std::size_t i = 0; i < p.size(); ++i) {
      out.body_work += e.body_work[i];
      for (std::size_t k = 0; k < out.dissipated.size(); ++k) out.dissipated[k] += e.dissipated[k][i];
      out.integration_error += e.error[i];
    }
  out.removed = e.removed;
  out.integration_error += e.error_offset - shadow_gap;
  return out;
}

}  // namespace dem2d::energy
