#include "stress/stress_balance.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/stage_error.hpp"
#include "frame/pulloff_frame.hpp"

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

double kernel_in_box(const Grid& g, const Kernel& k, double v_w, const NodeBox& b, Vec2 c) {
  const double R = k.radius();
  const Grid::Range cols = g.columns(c.x - R, c.x + R), rows = g.rows(c.y - R, c.y + R);
  double sum = 0.0;
  for (std::size_t j = std::max(rows.first, b.j0); j < std::min(rows.last, b.j1 + 1); ++j)
    for (std::size_t i = std::max(cols.first, b.i0); i < std::min(cols.last, b.i1 + 1); ++i) {
      const double r = std::hypot(g.x(i) - c.x, g.y(j) - c.y);
      if (r <= R) sum += weight(i, b.i0, b.i1) * weight(j, b.j0, b.j1) * k.inside(r, v_w);
    }
  return sum * g.dx * g.dx;
}

BodyBalance body_balance(const Grid& g, const Kernel& k, const StressFields& f, const Snapshot& s, int b,
                         double margin, Vec2 gravity) {
  const Body& body = s.bodies.at(static_cast<std::size_t>(b));
  const double reach = k.radius() + margin;
  const NodeBox box = node_box(g, body.xmin() - reach, body.xmax() + reach, body.ymin() - reach, body.ymax() + reach);
  const BodyForce F = body_force(g, f, box, gravity);
  Vec2 others{0.0, 0.0}, rec{0.0, 0.0};
  const double v_w = k.volume();
  for (std::size_t c = 0; c < s.contacts.size(); ++c) {
    if (s.contacts.j[c] >= 0) continue;
    const Vec2 Fc = contact_force(s.contacts, c);
    if (-1 - s.contacts.j[c] == b) {
      rec.x -= Fc.x, rec.y -= Fc.y;
      continue;
    }
    const double share = kernel_in_box(g, k, v_w, box, contact_point(s, c));
    others.x += share * Fc.x, others.y += share * Fc.y;
  }
  BodyBalance r;
  r.recorded = rec;
  r.exact = {F.exact.x + others.x, F.exact.y + others.y};
  r.quasi_static = {F.quasi_static.x + others.x, F.quasi_static.y + others.y};
  r.inertia = F.inertia;
  return r;
}

}  // namespace dem2d::analysis
