// The stability limit of the time step: the largest dt for which the
// engine's integrator stays bounded on the stiffest packing a scene can form.
//
// The integrator is velocity Verlet whose dashpots are fed the half-step
// velocity (engine/kernels.hpp). Linearised about a packing at rest, one step
// of it is, with M the masses and inertias, K and C the stiffness and
// damping matrices of the contact springs and dashpots,
//   x_{n+2} - 2 x_{n+1} + x_n = -dt^2 M^-1 K x_{n+1} - dt M^-1 C (x_{n+1} - x_n),
// stable when every root z of its characteristic equation has |z| <= 1. For
// one mode of frequency w and damping ratio zeta this is
//   w dt <= 2 (sqrt(1 + zeta^2) - zeta)
// (undamped: w dt <= 2). The stiffest packing is the hexagonal crystal of the
// smallest grains, every grain touching six: its fastest modes are found by
// Bloch analysis (each wave vector q of the Brillouin zone gives a 3x3 problem
// in u_x, u_y and the spin angle), along the path Gamma-M-K-Gamma, where the
// extremes lie (checked against a full 24x24 grid of the zone in the tests).
// The normal springs alone give w_max = sqrt(6 k_n/m) (dt <= 0.816 dt_c
// undamped, dt_c = sqrt(m/k_n)); the tangential springs add a faster mode, all
// grains spinning alike against them, w = sqrt(24 k_t/m) (k_t = k_n/2: dt <=
// 0.577 dt_c). Derivation and measurements: docs/contact_law.md.
#pragma once

#include <string>

#include "contact/contact_law.hpp"
#include "core/effects.hpp"

namespace dem2d {

struct StabilityLimit {
  double dt = 0.0;                 // largest stable time step (s)
  double dt_over_critical = 0.0;   // dt / dt_c, dt_c = sqrt(m/k_n) of the grain size given
  std::string mode;                // the fastest mode: where in the zone, and what moves
};

// For grains of diameter d (m) and density rho (kg/m^3) per unit depth
// (m = rho pi d^2/4, I = m d^2/8), under `law` with the springs and dashpots
// of `effects` (normal_damping, friction, tangential_damping,
// rolling_resistance, rolling_damping; the others do not change it).
StabilityLimit stability_limit(const ContactLaw& law, EffectSet effects, double density, double d);

// The same on an n x n grid of the whole Brillouin zone instead of the path
// (for tests: it must agree with the path).
StabilityLimit stability_limit_on_grid(const ContactLaw& law, EffectSet effects, double density, double d, int n);

}  // namespace dem2d
