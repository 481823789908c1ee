// Snapshots whose stress is known (the stress stage's planted truth, and its
// unit tests): a strained triangular lattice with contact forces along its
// three directions (its stress exact), the same with each contact's force
// scattered, grains moving at +u and -u (kinetic stress rho u^2), random
// contacts around a body (its force the sum of theirs), a stack at rest on a
// floor (the floor carries its weight). SI units, per unit depth.
#pragma once

#include <array>

#include "runfile/run_reader.hpp"

namespace dem2d::planted {

inline constexpr double kGlassDensity = 2500.0;  // kg/m^3

// Appends an active disk of diameter d (mass kGlassDensity pi d^2 / 4 per unit depth).
void add_grain(Snapshot& s, Vec2 x, double d, Vec2 v = {});

struct StrainedLattice {
  Snapshot s;
  double area = 0.0;             // per grain (m^2)
  std::array<double, 4> sigma{};  // the exact stress xx, xy, yx, yy (Pa) of the unscattered forces
  Vec2 centre;                   // the lattice's middle (m)
};
// n x n grains of diameter d, neighbours along 0, 60, 120 deg at spacing d x stretch (the lattice
// stretched by stretch_x along x, stretch_y along y), contact forces fn[k], ft[k] along direction k,
// each times (1 + scatter x a standard normal) drawn with `seed` (scatter 0: none). The exact stress,
// sigma = (1/A) sum_k (fn_k n_k + ft_k t_k) (x) l_k, holds inside, a kernel's reach from the edges.
StrainedLattice strained_lattice(double d, double stretch_x, double stretch_y, std::array<double, 3> fn,
                                 std::array<double, 3> ft, int n = 40, double scatter = 0.0, unsigned seed = 1);

// A 40 x 40 lattice of diameter d whose grains move at +u or -u along x, alternating: V = 0 and
// sigma_k,xx = rho u^2 (rho = m / (d row)), sigma_k,yy = 0 inside.
Snapshot counter_moving_lattice(double d, double u);

// 60 grains within 12 mm of a 10 mm segment body at the origin, with 150 random grain-grain
// contacts and 12 on the body (random forces): *body_force is the grains' force on the body.
Snapshot random_contacts(unsigned seed, double d, Vec2* body_force);

// n grains of diameter d stacked on a floor segment (body 0, role floor) at y = 0, at rest:
// contact k carries the weight above it; *weight = n m g.
Snapshot stack_on_floor(int n, double d, double g, double* weight);

}  // namespace dem2d::planted
