#include "stress/stress_balance.hpp"

#include <string>

#include "common/stage_error.hpp"

namespace dem2d::analysis {

NodeBox node_box(const Grid& g, double xmin, double xmax, double ymin, double ymax) {
  const Grid::Range c = g.columns(xmin, xmax), r = g.rows(ymin, ymax);
  if (c.last < c.first + 2 || r.last < r.first + 2)
    throw StageError("a box of " + std::to_string(c.last - c.first) + " x " + std::to_string(r.last - r.first) +
                     " nodes: at least 2 x 2 needed");
  return {c.first, c.last - 1, r.first, r.last - 1};
}

namespace {

// trapezoid weight of node k of [k0, k1]
double weight(std::size_t k, std::size_t k0, std::size_t k1) { return k == k0 || k == k1 ? 0.5 : 1.0; }

}  // namespace

Vec2 stress_outflux(const Grid& g, const StressFields& f, const NodeBox& b, bool momentum_flux) {
  const auto sigma = [&](Component c, std::size_t n) {
    double s = f.contact[c][n];
    if (momentum_flux) {
      s += f.kinetic[c][n];
      if (f.rho[n] > 0.0) {
        const std::size_t a = c == kXX || c == kXY ? 0 : 1, bb = c == kXX || c == kYX ? 0 : 1;
        s += f.p[a][n] * f.p[bb][n] / f.rho[n];
      }
    }
    return s;
  };
  Vec2 out{0.0, 0.0};
  for (std::size_t j = b.j0; j <= b.j1; ++j) {  // right (n = +x) and left (n = -x) edges
    const double w = weight(j, b.j0, b.j1) * g.dx;
    const std::size_t r = g.at(b.i1, j), l = g.at(b.i0, j);
    out.x += w * (sigma(kXX, r) - sigma(kXX, l));
    out.y += w * (sigma(kYX, r) - sigma(kYX, l));
  }
  for (std::size_t i = b.i0; i <= b.i1; ++i) {  // top (n = +y) and bottom (n = -y)
    const double w = weight(i, b.i0, b.i1) * g.dx;
    const std::size_t t = g.at(i, b.j1), d = g.at(i, b.j0);
    out.x += w * (sigma(kXY, t) - sigma(kXY, d));
    out.y += w * (sigma(kYY, t) - sigma(kYY, d));
  }
  return out;
}

double box_integral(const Grid& g, const std::vector<double>& q, const NodeBox& b) {
  double sum = 0.0;
  for (std::size_t j = b.j0; j <= b.j1; ++j)
    for (std::size_t i = b.i0; i <= b.i1; ++i) sum += weight(i, b.i0, b.i1) * weight(j, b.j0, b.j1) * q[g.at(i, j)];
  return sum * g.dx * g.dx;
}

BodyForce body_force(const Grid& g, const StressFields& f, const NodeBox& box, Vec2 gravity) {
  const Vec2 contact = stress_outflux(g, f, box, false), flux = stress_outflux(g, f, box, true);
  const Vec2 net{box_integral(g, f.net[0], box), box_integral(g, f.net[1], box)};
  const double mass = box_integral(g, f.rho, box);
  BodyForce r;
  r.exact = {-contact.x - net.x, -contact.y - net.y};
  r.quasi_static = {-flux.x + mass * gravity.x, -flux.y + mass * gravity.y};
  r.inertia = {net.x + mass * gravity.x, net.y + mass * gravity.y};
  return r;
}

}  // namespace dem2d::analysis
