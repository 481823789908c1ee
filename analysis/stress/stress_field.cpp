#include "stress/stress_field.hpp"

#include <cmath>

#include "core/hot_loop.hpp"
#include "frame/pulloff_frame.hpp"

namespace dem2d::analysis {

Vec2 contact_end(const Snapshot& s, std::size_t c) {
  const std::int32_t j = s.contacts.j[c];
  return j >= 0 ? s.position[static_cast<std::size_t>(j)] : contact_point(s, c);
}

Vec2 contact_force(const Contacts& k, std::size_t c) {
  return {k.fn[c] * k.nx[c] - k.ft[c] * k.ny[c], k.fn[c] * k.ny[c] + k.ft[c] * k.nx[c]};
}

namespace {

// adds weight(node) x values[q] into fields[q][node] for the nodes within the cut-off of the
// segment a-b (a point when a = b)
template <std::size_t Q, class Weight>
void spread(const Grid& g, double radius, Vec2 a, Vec2 b, std::array<std::vector<double>*, Q> fields,
            std::array<double, Q> values, Weight weight) {
  const Grid::Range cols = g.columns(std::min(a.x, b.x) - radius, std::max(a.x, b.x) + radius);
  const Grid::Range rows = g.rows(std::min(a.y, b.y) - radius, std::max(a.y, b.y) + radius);
  for (std::size_t j = rows.first; j < rows.last; ++j)
    for (std::size_t i = cols.first; i < cols.last; ++i) {
      const double w = weight(Vec2{g.x(i), g.y(j)});
      if (w == 0.0) continue;
      const std::size_t n = g.at(i, j);
      for (std::size_t q = 0; q < Q; ++q) (*fields[q])[n] += w * values[q];
    }
}

}  // namespace

DEM2D_HOT StressFields coarse_grain_stress(const Grid& g, const Kernel& kernel, const Snapshot& s) {
  const std::size_t nodes = g.size(), n = s.size();
  StressFields f;
  f.rho.assign(nodes, 0.0);
  for (auto* set : {&f.p, &f.body, &f.net})
    for (auto& v : *set) v.assign(nodes, 0.0);
  for (auto* set : {&f.contact, &f.kinetic})
    for (auto& v : *set) v.assign(nodes, 0.0);
  const double R = kernel.radius(), v_w = kernel.volume();
  const Contacts& k = s.contacts;

  // contacts: the branch-integrated stress; a body's push at its contact point
  std::vector<Vec2> net(n, Vec2{0.0, 0.0});
  for (std::size_t c = 0; c < k.size(); ++c) {
    const std::size_t i = static_cast<std::size_t>(k.i[c]);
    const Vec2 F = contact_force(k, c), xi = s.position[i], end = contact_end(s, c);
    const Vec2 l{xi.x - end.x, xi.y - end.y};
    net[i].x += F.x, net[i].y += F.y;
    if (k.j[c] >= 0) {
      const std::size_t j = static_cast<std::size_t>(k.j[c]);
      net[j].x -= F.x, net[j].y -= F.y;
    } else {
      spread<2>(g, R, end, end, {&f.body[0], &f.body[1]}, {F.x, F.y},
                [&](Vec2 r) { return kernel.along(r, end, end, v_w); });
    }
    spread<4>(g, R, xi, end, {&f.contact[kXX], &f.contact[kXY], &f.contact[kYX], &f.contact[kYY]},
              {F.x * l.x, F.x * l.y, F.y * l.x, F.y * l.y}, [&](Vec2 r) { return kernel.along(r, xi, end, v_w); });
  }
  // grains: mass, momentum, the second moment of velocity (the kinetic stress below), net force
  std::array<std::vector<double>, 3> vv;  // sum m v_a v_b G: xx, xy, yy
  for (auto& v : vv) v.assign(nodes, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.active[i]) continue;
    const Vec2 x = s.position[i], v = s.velocity[i];
    const double m = s.mass[i];
    spread<8>(g, R, x, x, {&f.rho, &f.p[0], &f.p[1], &vv[0], &vv[1], &vv[2], &f.net[0], &f.net[1]},
              {m, m * v.x, m * v.y, m * v.x * v.x, m * v.x * v.y, m * v.y * v.y, net[i].x, net[i].y},
              [&](Vec2 r) {
                const double d = std::hypot(r.x - x.x, r.y - x.y);
                return d <= R ? kernel.inside(d, v_w) : 0.0;
              });
  }
  // sigma_k = sum m v v G - p p / rho (sum m v' v' G with v' = v - p / rho)
  for (std::size_t q = 0; q < nodes; ++q) {
    if (!(f.rho[q] > 0.0)) continue;
    const double px = f.p[0][q], py = f.p[1][q], r = f.rho[q];
    f.kinetic[kXX][q] = vv[0][q] - px * px / r;
    f.kinetic[kXY][q] = f.kinetic[kYX][q] = vv[1][q] - px * py / r;
    f.kinetic[kYY][q] = vv[2][q] - py * py / r;
  }
  return f;
}

}  // namespace dem2d::analysis
