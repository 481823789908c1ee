// Coarse-graining with a truncated Gaussian kernel (docs/paper.md, "Coarse-graining";
// paper section 2.3, eqs. 4-9):
//   G(r) = exp(-r^2 / (2 w^2)) / V_w  for r <= c w, 0 beyond,  V_w = 2 pi w^2 (1 - exp(-c^2 / 2)),
// so that G integrates to 1 over the disk r <= c w (c = 4 in the paper).
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
#include "io/run_reader.hpp"

namespace dem2d::analysis {

// Nodes (x0 + i dx, y0 + j dx), i < nx, j < ny; node (i, j) is element j * nx + i of a field.
struct Grid {
  double x0 = 0.0, y0 = 0.0, dx = 0.0;  // m
  std::size_t nx = 0, ny = 0;
  double x(std::size_t i) const { return x0 + dx * static_cast<double>(i); }
  double y(std::size_t j) const { return y0 + dx * static_cast<double>(j); }
  std::size_t size() const { return nx * ny; }
  std::size_t at(std::size_t i, std::size_t j) const { return j * nx + i; }
};

// The nodes at the centres of the dx-wide squares tiling [xmin, xmax] x [ymin, ymax]
// (floor(width / dx) of them across, the tiling centred in the box). CgError if
// dx <= 0 or the box is narrower or lower than dx (no node).
Grid make_grid(double xmin, double xmax, double ymin, double ymax, double dx);

struct Kernel {
  double w = 0.0;       // width (m)
  double cutoff = 4.0;  // cut-off radius in units of w
  double radius() const { return cutoff * w; }
  double volume() const;             // V_w (m^2)
  double operator()(double r) const;  // G(r) (1/m^2)
  // G(r) for r <= radius(), given v_w = volume(): for loops that compute V_w once
  double inside(double r, double v_w) const { return std::exp(-r * r / (2.0 * w * w)) / v_w; }
};
// CgError if w <= 0 or cutoff <= 0.
Kernel make_kernel(double w, double cutoff_over_w);

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

// The velocity field of set s: V = p / rho where phi >= min_phi, NaN elsewhere.
struct Velocity {
  std::vector<double> vx, vy;  // m/s [nodes]
};
Velocity velocity(const Fields& f, std::size_t set, double min_phi);

}  // namespace dem2d::analysis
