#include "common/cg_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/stage_error.hpp"
#include "core/number_text.hpp"

namespace dem2d::analysis {

namespace {

std::string mm(double metres) {
  std::ostringstream s;
  s << metres * 1e3 << " mm";
  return s.str();
}

}  // namespace

Grid::Range Grid::range(double lo, double hi, double v0, std::size_t n) const {
  const double top = static_cast<double>(n);
  const double first = std::clamp(std::ceil((lo - v0) / dx), 0.0, top);
  const double last = std::clamp(std::floor((hi - v0) / dx) + 1.0, 0.0, top);
  return {static_cast<std::size_t>(first), static_cast<std::size_t>(std::max(first, last))};
}

Grid make_grid(double xmin, double xmax, double ymin, double ymax, double dx) {
  if (!(dx > 0.0)) throw StageError("grid spacing " + mm(dx) + ": must be > 0");
  const double width = xmax - xmin, height = ymax - ymin;
  // (a whole number of spacings within rounding counts as whole)
  const double nx = std::floor(width / dx * (1.0 + 1e-12)), ny = std::floor(height / dx * (1.0 + 1e-12));
  if (nx < 1.0 || ny < 1.0)
    throw StageError("grid spacing " + mm(dx) + " is larger than the domain (" + mm(width) + " x " + mm(height) +
                     "): no node");
  if (nx * ny > 1e8) throw StageError("grid of " + sig3(nx * ny) + " nodes: more than 1e8 (spacing " + mm(dx) + ")");
  Grid g;
  g.dx = dx;
  g.nx = static_cast<std::size_t>(nx);
  g.ny = static_cast<std::size_t>(ny);
  g.x0 = xmin + 0.5 * (width - (nx - 1.0) * dx);
  g.y0 = ymin + 0.5 * (height - (ny - 1.0) * dx);
  return g;
}

double Kernel::volume() const {
  return 2.0 * std::numbers::pi * w * w * (1.0 - std::exp(-0.5 * cutoff * cutoff));
}

double Kernel::operator()(double r) const {
  return r <= radius() ? inside(r, volume()) : 0.0;
}

double Kernel::along(Vec2 r, Vec2 a, Vec2 b, double v_w) const {
  const double ux = b.x - a.x, uy = b.y - a.y, l2 = ux * ux + uy * uy;
  const double px = r.x - a.x, py = r.y - a.y, p2 = px * px + py * py;
  const double R2 = radius() * radius();
  if (!(l2 > 1e-24 * R2)) return p2 <= R2 ? inside(std::sqrt(p2), v_w) : 0.0;
  // |r - a - s u|^2 = l2 (s - s0)^2 + q2: q the distance from the segment's line
  const double s0 = (px * ux + py * uy) / l2;
  const double q2 = std::max(0.0, p2 - s0 * s0 * l2);
  if (q2 > R2) return 0.0;
  // the part of the segment within the cut-off, s in [s1, s2]
  const double h = std::sqrt((R2 - q2) / l2);
  const double s1 = std::max(0.0, s0 - h), s2 = std::min(1.0, s0 + h);
  if (!(s1 < s2)) return 0.0;
  const double k = std::sqrt(l2 / (2.0 * w * w));
  const double line = 0.5 * std::sqrt(std::numbers::pi) / k * (std::erf(k * (s2 - s0)) - std::erf(k * (s1 - s0)));
  return std::exp(-q2 / (2.0 * w * w)) * line / v_w;
}

Kernel make_kernel(double w, double cutoff_over_w) {
  if (!(w > 0.0)) throw StageError("kernel width w = " + mm(w) + ": must be > 0");
  if (!(cutoff_over_w > 0.0)) throw StageError("kernel cut-off " + shortest(cutoff_over_w) + " w: must be > 0");
  return {w, cutoff_over_w};
}

}  // namespace dem2d::analysis
