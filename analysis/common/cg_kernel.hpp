// The coarse-graining kernel and grid the stages share (cg: velocity and
// solid fraction; stress: the stress tensor). A truncated Gaussian
// (docs/paper.md, "Coarse-graining"; paper section 2.3, eqs. 4-9):
//   G(r) = exp(-r^2 / (2 w^2)) / V_w  for r <= c w, 0 beyond,  V_w = 2 pi w^2 (1 - exp(-c^2 / 2)),
// so that G integrates to 1 over the disk r <= c w (c = 4 in the paper). SI units.
#pragma once

#include <cmath>
#include <cstddef>

#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// Nodes (x0 + i dx, y0 + j dx), i < nx, j < ny; node (i, j) is element j * nx + i of a field.
struct Grid {
  double x0 = 0.0, y0 = 0.0, dx = 0.0;  // m
  std::size_t nx = 0, ny = 0;
  double x(std::size_t i) const { return x0 + dx * static_cast<double>(i); }
  double y(std::size_t j) const { return y0 + dx * static_cast<double>(j); }
  std::size_t size() const { return nx * ny; }
  std::size_t at(std::size_t i, std::size_t j) const { return j * nx + i; }
  // the node range [first, last) whose coordinate lies in [lo, hi] (clipped to the grid)
  struct Range {
    std::size_t first = 0, last = 0;
  };
  Range columns(double lo, double hi) const { return range(lo, hi, x0, nx); }
  Range rows(double lo, double hi) const { return range(lo, hi, y0, ny); }

 private:
  Range range(double lo, double hi, double v0, std::size_t n) const;
};

// The nodes at the centres of the dx-wide squares tiling [xmin, xmax] x [ymin, ymax]
// (floor(width / dx) of them across, the tiling centred in the box). StageError if
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
  // The kernel integrated along the segment from a to b, int_0^1 G(r - a - s (b - a)) ds (1/m^2),
  // exactly (the truncation included): the weight of a contact's branch vector in the
  // coarse-grained stress (Weinhart et al. 2012), for which
  //   (b - a) . grad_r int_0^1 G(r - a - s (b - a)) ds = G(r - a) - G(r - b).
  // Given v_w = volume(). G(r - a) when a = b.
  double along(Vec2 r, Vec2 a, Vec2 b, double v_w) const;
};
// StageError if w <= 0 or cutoff <= 0.
Kernel make_kernel(double w, double cutoff_over_w);

}  // namespace dem2d::analysis
