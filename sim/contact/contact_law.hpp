// The contact law (SPEC "Contact model"), shared by particle-particle and
// particle-sphero-line contacts.
//
// Sign conventions: delta <= 0 is the overlap (negative when touching), n points
// from the partner to the grain, t = z x n so that (n, t) is right-handed.
// vn = (v_i - v_j).n, vt = tangential velocity of i's contact point relative to
// the partner's, spin = omega_i - omega_j.
//
//   F_n = max(0, -k_n delta - c vn),  c = 2 nu sqrt(m_eff k_n)   (never attractive)
//   F_t <- clamp(F_t - k_t vt dt, -mu F_n, mu F_n)                (incremental, Coulomb cap)
//   M_r <- clamp(M_r - k_r spin dt, -mu_r F_n, mu_r F_n)          (incremental rolling spring)
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
};

// nu = -ln e / sqrt(pi^2 + ln^2 e): the damping ratio that gives restitution e
// for a linear spring-dashpot.
inline double damping_ratio(double restitution) {
  const double l = std::log(restitution);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

// The law with the per-step products folded in, as the kernel uses it.
struct LawCoefficients {
  double kn;         // N/m
  double damp;       // 2 nu sqrt(k_n): c = damp * sqrt(m_eff)  (sqrt(N/m))
  double kt_dt;      // k_t * dt   (N s/m)
  double kr_dt;      // k_r * dt   (N m s/rad)
  double mu;         // -
  double mu_r;       // m
};

inline LawCoefficients coefficients(const ContactLaw& law, double dt) {
  return {law.kn, 2.0 * damping_ratio(law.restitution) * std::sqrt(law.kn), law.kt * dt,
          law.rolling_stiffness * dt, law.friction, law.rolling_friction};
}

template <EffectSet E>
inline double normal_force(const LawCoefficients& c, double delta, double vn, double sqrt_meff) {
  double fn = -c.kn * delta;
  if constexpr (has(E, effect::normal_damping)) fn -= c.damp * sqrt_meff * vn;
  return fn > 0.0 ? fn : 0.0;
}

// Incremental spring with a symmetric cap: the tangential force and the rolling moment.
inline double capped_increment(double stored, double increment, double cap) {
  return std::clamp(stored + increment, -cap, cap);
}

// The slip state as the run file reports it: the tangential force sits on the cone.
inline bool is_sliding(double fn, double ft, double mu) { return fn > 0.0 && std::abs(ft) >= mu * fn; }

}  // namespace dem2d
