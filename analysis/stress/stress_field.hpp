// The coarse-grained stress of one snapshot (Weinhart et al. 2012, "From
// discrete particles to continuum fields near a boundary"; Goldhirsch 2010),
// with the kernel G and grid of common/cg_kernel.hpp. Per unit depth, SI
// units, compression positive:
//   contact:  sigma_c(r) = sum_c F_c (x) l_c int_0^1 G(r - x_i + s l_c) ds
//             F_c the contact's force on grain i, l_c its branch vector:
//             x_i - x_j to a grain j, x_i - c to the contact point c on a body
//   kinetic:  sigma_k(r) = sum_i m_i v'_i (x) v'_i G(r - x_i),  v' = v_i - V(r),  V = p / rho
// Stress is sigma_c + sigma_k (Pa: forces per unit depth over a length).
// The branch integral makes the fields balance exactly: in the component
// sigma_ab (a the force's, b the branch's direction),
//   d_b sigma_c,ab = b_a + rho g_a - sum_i m_i a_i,a G(r - x_i)
// with b = sum over grain-body contacts of F G(r - c) (the bodies' push on
// the grains, at the contact points), so that the stress around a body plus
// the weight inside gives the force on it (stress_balance.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "common/cg_kernel.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// Component order of a tensor field: xx, xy, yx, yy (sigma_ab: a the force's direction).
enum Component : std::size_t { kXX = 0, kXY = 1, kYX = 2, kYY = 3 };

struct StressFields {
  std::vector<double> rho;                     // mass density (kg/m^3: masses per unit depth)  [nodes]
  std::array<std::vector<double>, 2> p;      // momentum density (kg/(m^2 s))                  [nodes]
  std::array<std::vector<double>, 4> contact;  // sigma_c (Pa)                                  [nodes]
  std::array<std::vector<double>, 4> kinetic;  // sigma_k (Pa), symmetric                       [nodes]
  std::array<std::vector<double>, 2> body;     // b: the bodies' force density on the grains (N/m^3) [nodes]
  std::array<std::vector<double>, 2> net;      // sum_i F_i G(r - x_i): the grains' net contact force density (N/m^3)
  double total(Component c, std::size_t n) const { return contact[c][n] + kinetic[c][n]; }
};

// The far end of contact row c's branch: the partner grain's centre, or the
// contact point on a body (frame/pulloff_frame.hpp's contact_point).
Vec2 contact_end(const Snapshot& s, std::size_t c);
// The contact's force on grain i: fn n + ft t, t = z x n = (-ny, nx).
Vec2 contact_force(const Contacts& k, std::size_t c);

// Every active grain and every contact of snapshot s on the grid. Cost:
// O((N + C) (c w / dx)^2) kernel evaluations (a branch: one exponential, two erf).
StressFields coarse_grain_stress(const Grid& grid, const Kernel& kernel, const Snapshot& s);

}  // namespace dem2d::analysis
