// The contact law (SPEC "Contact model"), shared by particle-particle and
// particle-sphero-line contacts.
//
// Sign conventions: delta <= 0 is the overlap (negative when touching), n points
// from the partner to the grain, t = z x n so that (n, t) is right-handed.
// vn = (v_i - v_j).n, vt = tangential velocity of i's contact point relative to
// the partner's, spin = omega_i - omega_j.
//
//   F_n = max(0, -k_n delta - c_n vn),  c_n = 2 nu sqrt(m_eff k_n)  (never attractive)
//   S_t <- clamp(S_t - k_t vt dt, +-mu F_n)                           (incremental spring, Coulomb cap)
//   F_t = clamp(S_t - c_t vt, +-mu F_n)
//   S_r <- clamp(S_r - k_r spin dt, +-mu_r F_n),   M_r = clamp(S_r - c_r spin, +-mu_r F_n)
//
// c_t = 2 nu_t sqrt(m_eff k_t) and c_r = 2 nu_r sqrt(I_eff k_r) are the opt-in
// tangential and rolling dashpots (effects tangential_damping and
// rolling_damping). Without them c_t = c_r = 0 and F_t = S_t, M_r = S_r: the
// paper's law. With them the spring is still the paper's (capped on its
// own), the dashpot acts beside it and the sum is capped again. This differs
// from LAMMPS's granular models and MercuryDPM, which while sliding reset
// the spring to S = F_cap + c v: that can load the spring beyond the cap
// (c v > mu F_n) and hand the energy back to the grains later (the energy
// ledger measured negative slip dissipation on a single oblique collision).
// Here each part is passive: the spring-slider and the dashpot each
// dissipate >= 0 at every step (docs/contact_law.md).
//
// In 2D the tangent direction is unique, so the stored tangential spring is a
// scalar along the current t: it turns with the contact, keeping its magnitude,
// which is exactly "kept in the current tangent direction".
#pragma once

#include <algorithm>
#include <cmath>

#include "core/effects.hpp"

namespace dem2d {

// Material constants of one contact law as the scene gives them (SI).
struct ContactLaw {
  double kn = 0.0;                 // normal stiffness (N/m)
  double kt = 0.0;                 // tangential stiffness (N/m)
  double restitution = 1.0;        // normal coefficient of restitution e, in (0, 1]
  double friction = 0.0;           // Coulomb coefficient mu
  double rolling_friction = 0.0;   // mu_r (m): |M_r| <= mu_r F_n
  double rolling_stiffness = 0.0;  // k_r (N m / rad)
  double tangential_damping_ratio = 0.0;  // nu_t: c_t = 2 nu_t sqrt(m_eff k_t)
  double rolling_damping_ratio = 0.0;     // nu_r: c_r = 2 nu_r sqrt(I_eff k_r)
  double cohesion_force = 0.0;            // f_c (N/m): the pull-off force (contact/cohesion.hpp)
  double cohesion_range = 0.0;            // delta_c (m): the gap at which the attraction ends
};

// Restitution of a head-on collision under the normal law above,
// F_n = max(0, k x + c x') with x the overlap: the force vanishes before the
// overlap does (when x'' = 0), the grains then part at constant speed, so
//   e(nu) = exp(-2 nu arccos(nu) / sqrt(1 - nu^2))     nu < 1
//         = exp(-2)                                     nu = 1
//         = exp(-2 nu arccosh(nu) / sqrt(nu^2 - 1))     nu > 1
// (Schwager & Poeschel, Granular Matter 9, 465 (2007); derivation in
// docs/contact_law.md). The familiar exp(-pi nu / sqrt(1 - nu^2)) holds only
// for a law that may pull: with it, e = 0.5 would give 0.551 here.
double restitution_of_damping_ratio(double nu);

// The damping ratio nu >= 0 that gives restitution e in (0, 1] under this
// law: the inverse of restitution_of_damping_ratio (monotone), solved to
// round-off. nu(1) = 0; nu -> 1/(2 sqrt(e)) as e -> 0.
double damping_ratio(double restitution);

// The law with the per-step products folded in, as the kernel uses it.
struct LawCoefficients {
  double kn;         // N/m
  double damp;       // 2 nu sqrt(k_n): c_n = damp * sqrt(m_eff)  (sqrt(N/m))
  double kt_dt;      // k_t * dt   (N s/m)
  double kr_dt;      // k_r * dt   (N m s/rad)
  double mu;         // -
  double mu_r;       // m
  double damp_t;     // 2 nu_t sqrt(k_t): c_t = damp_t * sqrt(m_eff)
  double damp_r;     // 2 nu_r sqrt(k_r): c_r = damp_r * sqrt(I_eff)
  double coh_f;      // f_c (N/m)
  double coh_k;      // f_c / delta_c (N/m per m of gap)
  double coh_range;  // delta_c (m)
};

LawCoefficients coefficients(const ContactLaw& law, double dt);

template <EffectSet E>
inline double normal_force(const LawCoefficients& c, double delta, double vn, double sqrt_meff) {
  double fn = -c.kn * delta;
  if constexpr (has(E, effect::normal_damping)) fn -= c.damp * sqrt_meff * vn;
  return fn > 0.0 ? fn : 0.0;
}

// An incremental spring capped at +-cap, with (Damped) a dashpot beside it
// and their sum capped again: the tangential force and the rolling moment.
// `increment` is the spring's change this step (-k v dt), `dashpot` the
// dashpot's force c v.
struct CappedSpring {
  double force;   // what acts on the grain
  double spring;  // the spring stored for the next step
};

template <bool Damped>
inline CappedSpring capped_spring(double stored, double increment, double dashpot, double cap) {
  const double spring = std::clamp(stored + increment, -cap, cap);
  if constexpr (!Damped)
    return {spring, spring};
  else
    return {std::clamp(spring - dashpot, -cap, cap), spring};
}

// Energy stored in one contact's springs (J/m): 1/2 k_n overlap^2, 1/2 S_t^2/k_t
// and 1/2 S_r^2/k_r, the last two only with the effects that add the springs.
struct SpringEnergy {
  double normal = 0.0, tangential = 0.0, rolling = 0.0;
  double total() const { return normal + tangential + rolling; }
};

inline SpringEnergy spring_energy(const ContactLaw& law, EffectSet effects, double overlap, double ft, double mr) {
  SpringEnergy u;
  u.normal = 0.5 * law.kn * overlap * overlap;
  if (has(effects, effect::friction) && law.kt > 0.0) u.tangential = 0.5 * ft * ft / law.kt;
  if (has(effects, effect::rolling_resistance) && law.rolling_stiffness > 0.0)
    u.rolling = 0.5 * mr * mr / law.rolling_stiffness;
  return u;
}

// The slip state as the run file reports it: the tangential force sits on the cone.
inline bool is_sliding(double fn, double ft, double mu) { return fn > 0.0 && std::abs(ft) >= mu * fn; }

}  // namespace dem2d
