#include "frame/pulloff_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/stage_output.hpp"  // format_number

namespace dem2d::analysis {

const char* partner_name(Partner p) {
  switch (p) {
    case Partner::grain: return "grain";
    case Partner::left: return "left";
    case Partner::right: return "right";
    case Partner::floor: return "floor";
    case Partner::intruder: return "intruder";
    case Partner::other: return "other";
  }
  return "?";
}

double PulloffGeometry::axial(Vec2 p) const { return (p.x - centre.x) * axis.x + (p.y - centre.y) * axis.y; }

namespace {
// The axis and length of a body's core: along its longest edge (a
// sphero-line's only one), pointing to +x (to +y if vertical).
void intruder_axis(const Body& in, PulloffGeometry& g) {
  const std::vector<Vec2>& v = in.vertices;
  const std::size_t n = v.size();
  const std::size_t edges = n > 2 ? n : n - 1;  // a point has none, a segment one
  double longest = 0.0;
  for (std::size_t k = 0; k < edges; ++k) {
    const Vec2 a = v[k], b = v[(k + 1) % n];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len <= longest) continue;
    longest = len;
    const double sign = (b.x - a.x > 0.0 || (b.x == a.x && b.y > a.y)) ? 1.0 : -1.0;
    g.axis = {sign * (b.x - a.x) / len, sign * (b.y - a.y) / len};
  }
  if (n <= 2) {
    g.core_length = longest;
    return;
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec2& q : v) {
    const double along = q.x * g.axis.x + q.y * g.axis.y;
    lo = std::min(lo, along);
    hi = std::max(hi, along);
  }
  g.core_length = hi - lo;
}
}  // namespace

PulloffGeometry pulloff_geometry(const Snapshot& s) {
  PulloffGeometry g;
  g.cell = find_cell(s);
  g.left = s.find_role("left_wall");
  g.right = s.find_role("right_wall");
  g.floor = s.find_role("floor");
  g.intruder = s.find_role("intruder");
  if (g.intruder < 0) return g;
  const Body& in = s.bodies[static_cast<std::size_t>(g.intruder)];
  g.centre = in.centre();
  intruder_axis(in, g);
  g.cap_radius = in.radius();
  return g;
}

std::vector<Partner> classify_contacts(const Snapshot& s, const PulloffGeometry& g) {
  std::vector<Partner> out(s.contacts.size(), Partner::grain);
  for (std::size_t c = 0; c < out.size(); ++c) {
    const std::int32_t j = s.contacts.j[c];
    if (j >= 0) continue;
    const int b = -1 - j;
    out[c] = b == g.left       ? Partner::left
             : b == g.right    ? Partner::right
             : b == g.floor    ? Partner::floor
             : b == g.intruder ? Partner::intruder
                               : Partner::other;
  }
  return out;
}

Vec2 contact_point(const Snapshot& s, std::size_t c) {
  const auto i = static_cast<std::size_t>(s.contacts.i[c]);
  const double reach = 0.5 * s.diameter[i] - 0.5 * s.contacts.overlap[c];
  return {s.position[i].x - s.contacts.nx[c] * reach, s.position[i].y - s.contacts.ny[c] * reach};
}

double bed_height(const Snapshot& s, const PulloffGeometry& g) {
  return bed_surface(s, g.cell, mean_active_diameter(s)).height;
}

}  // namespace dem2d::analysis
