// Distance from a disk centre O to a sphero-line (segment C1C2 with round caps
// of radius r_s), the paper's eq. 1-3 (docs/paper.md). With C the middle of C1C2, u its unit direction
// and v the unit normal:
//   CO.u <= -|C1C2|/2 : contact with cap C1, delta = |O C1| - (d + d_s)/2
//   CO.u >=  |C1C2|/2 : contact with cap C2, delta = |O C2| - (d + d_s)/2
//   otherwise          : flat side,          delta = |CO.v| - (d + d_s)/2
// All three are the distance from O to the closest point P of the segment, so
// they are evaluated as one clamped projection: the overlap and the normal are
// continuous across the flat/cap boundary by construction.
#pragma once

#include <algorithm>
#include <cmath>

namespace dem2d {

// Segment geometry cached per body (changes only if the body is redefined).
struct Segment {
  double ax, ay;     // C1 (m)
  double ex, ey;     // C2 - C1 (m)
  double inv_len2;   // 1/|C1C2|^2, 0 for a zero-length segment (a point obstacle)
  double nx0, ny0;   // fallback normal for a centre lying exactly on the segment
};

inline Segment make_segment(double ax, double ay, double bx, double by) {
  Segment s{ax, ay, bx - ax, by - ay, 0.0, 0.0, 1.0};
  const double len2 = s.ex * s.ex + s.ey * s.ey;
  if (len2 > 0.0) {
    s.inv_len2 = 1.0 / len2;
    const double inv_len = 1.0 / std::sqrt(len2);
    s.nx0 = -s.ey * inv_len;  // left normal v, so that (u, v) is right-handed
    s.ny0 = s.ex * inv_len;
  }
  return s;
}

struct Proximity {
  double dist;    // |O P| (m)
  double nx, ny;  // unit normal from P to O
};

[[gnu::always_inline]] inline Proximity closest_point(const Segment& s, double ox, double oy) {  // per contact slot
  const double rx = ox - s.ax, ry = oy - s.ay;
  const double t = std::clamp((rx * s.ex + ry * s.ey) * s.inv_len2, 0.0, 1.0);
  const double dx = rx - t * s.ex, dy = ry - t * s.ey;
  const double dist = std::sqrt(dx * dx + dy * dy);
  // selects rather than a branch, so that a loop over wall slots vectorises;
  // a centre on the segment is pushed out along the segment's normal
  const bool apart = dist > 0.0;
  const double div = apart ? dist : 1.0;
  return {dist, apart ? dx / div : s.nx0, apart ? dy / div : s.ny0};
}

}  // namespace dem2d
