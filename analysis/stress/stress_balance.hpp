// The stress field's balance over a rectangle of nodes: the force the stress
// around it carries, the weight and the force densities inside. With
// stress_field.hpp's identity d_b sigma_c,ab = b_a - net_a, for a rectangle
// Omega that holds a body's contacts (and no other body's) with their kernels:
//   F_body = - oint sigma_c . n dl - int net dA                        (exact, to quadrature)
//          = - oint (sigma_c + sum m v v G) . n dl + int rho g dA - d/dt int p dA
// The stage reports the second without its last term (the quasi-static force
// the stress carries) against the force the run file records, and the first
// as a check of the fields. Trapezoid rules on the nodes; N/m, m, SI units.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "stress/stress_field.hpp"

namespace dem2d::analysis {

// The nodes [i0, i1] x [j0, j1] (inclusive) of a rectangle.
struct NodeBox {
  std::size_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
};
// The nodes within [xmin, xmax] x [ymin, ymax]; StageError if fewer than 2 x 2.
NodeBox node_box(const Grid& g, double xmin, double xmax, double ymin, double ymax);

// oint sigma . n dl over the box's edges (n the outward normal), component a:
// sum_b oint sigma_ab n_b; sigma = contact [+ kinetic + p p / rho: the whole momentum flux].
Vec2 stress_outflux(const Grid& g, const StressFields& f, const NodeBox& box, bool momentum_flux);
// int q dA over the box.
double box_integral(const Grid& g, const std::vector<double>& q, const NodeBox& box);

// The force on the body the box holds, from the fields (N/m).
struct BodyForce {
  Vec2 exact;         // - oint sigma_c . n - int net: the identity (to quadrature)
  Vec2 quasi_static;  // - oint (sigma_c + sum m v v G) . n + int rho g
  Vec2 inertia;       // int sum m a G dA = int (net + rho g): what quasi_static leaves out (its part of the change of momentum)
};
BodyForce body_force(const Grid& g, const StressFields& f, const NodeBox& box, Vec2 gravity);

// int_box G(r - c) dA for a point c (the trapezoid rule of box_integral), given v_w = k.volume().
double kernel_in_box(const Grid& g, const Kernel& k, double v_w, const NodeBox& box, Vec2 c);

// Body b of snapshot s: the force the run records on it (the sum of its contacts', as the engine's
// body_force) and the fields' account of it over the box around its outline, the kernel's cut-off plus
// `margin` out, with the other bodies' push on the grains inside (their contacts' forces times the part
// of their kernels the box holds) added back: -int b over the box is the body's force less that push.
struct BodyBalance {
  Vec2 recorded, exact, quasi_static, inertia;  // N/m
};
BodyBalance body_balance(const Grid& g, const Kernel& k, const StressFields& f, const Snapshot& s, int b,
                         double margin, Vec2 gravity);

}  // namespace dem2d::analysis
