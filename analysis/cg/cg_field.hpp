// Coarse-grained velocity and solid fraction, with the kernel G and grid of
// common/cg_kernel.hpp (docs/paper.md, "Coarse-graining"; paper section 2.3, eqs. 4-9):
//   rho(r) = sum m_i G(r - r_i)          mass density (kg/m^3: masses are per unit depth)
//   phi(r) = sum a_i G(r - r_i)          solid fraction (a_i = pi d_i^2 / 4, the disk's area)
//   p(r)   = sum m_i v_i G(r - r_i)      momentum density, one field per velocity set
//   V(r)   = p / rho                     velocity
// on a regular grid of nodes. SI units throughout.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cg/cg_config.hpp"
#include "common/cg_kernel.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// The grains of one snapshot (per unit depth). Inactive grains are skipped.
// Each velocity set gives one momentum field.
struct Grains {
  std::span<const Vec2> position;         // m
  std::span<const double> mass;           // kg/m
  std::span<const double> diameter;       // m
  std::span<const std::uint8_t> active;
  std::vector<std::span<const Vec2>> velocities;  // m/s, each [N]
};

struct Fields {
  std::vector<double> rho, phi;            // [nodes]
  std::vector<std::vector<double>> px, py; // [sets][nodes]: momentum density (kg/(m^2 s))
};

// Sums every active grain's kernel onto the nodes within the cut-off. Cost:
// O(N (c w / dx)^2). The Gaussian factorises, exp(-(X^2 + Y^2)/2w^2) =
// exp(-X^2/2w^2) exp(-Y^2/2w^2), so each grain needs one exponential per node
// column and row it reaches; each row is then a scaled add.
Fields coarse_grain(const Grid& grid, const Kernel& kernel, const Grains& grains);

// Adds `add` into `sum` (same grid and sets); scales all fields by `factor`.
void accumulate(Fields& sum, const Fields& add);
void scale(Fields& f, double factor);

// The average of fields[0 .. n) in the frame of a point at at[k] in field k
// (m; e.g. the intruder's centre), on the nodes of the last: field k is moved
// by at[n-1] - at[k], i.e. its value at a node is taken at node - that shift,
// bilinear between nodes, 0 beyond the grid. What moves with the point stays;
// noise independent between the fields averages out as 1/sqrt(n).
Fields frame_average(const Grid& g, const std::vector<const Fields*>& fields, const std::vector<Vec2>& at);

// The velocity field of set s: V = p / rho where phi >= min_phi, NaN elsewhere.
struct Velocity {
  std::vector<double> vx, vy;  // m/s [nodes]
};
Velocity velocity(const Fields& f, std::size_t set, double min_phi);

}  // namespace dem2d::analysis
