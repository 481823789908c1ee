// The one body shape the engine knows: a convex sphero-polygon, i.e. every
// point within `radius` of a convex core polygon (Alonso-Marroquin 2008). One
// vertex is a disk, two a sphero-line (the paper's walls and intruder, docs/paper.md), three or
// more a polygon with rounded corners (sharp ones for radius 0). Scene shape
// kinds (shape/shape_kinds.hpp) only produce the core's vertices.
//
// The hot loop asks a shape one question, closest_point: the signed distance
// from a grain centre O to the core and the unit normal pointing from the core
// to O. Outside the core it is the distance to the nearest edge (to a vertex
// beyond an edge's ends); inside it (an overlap deeper than the rounding) it
// is minus the depth below the least-penetrated face, along that face's
// normal, so that the overlap and the normal stay continuous across the
// boundary. A body that translates keeps its edges' directions and lengths,
// so a move sets the vertices and nothing else; a body that turns
// (turn_to) gets its vertices and edges anew from its outline at the start.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "shape/spheroline.hpp"

namespace dem2d {

struct Point {
  double x = 0.0, y = 0.0;  // (m)
};

struct Shape {
  static constexpr int kMaxVertices = 16;
  int n = 0;  // vertices of the core (1: a disk, 2: a sphero-line, >= 3: a polygon, counter-clockwise)
  std::array<Segment, kMaxVertices> edge{};  // edge k: vertex k to vertex k + 1 (world); n <= 2: edge 0 only
  std::array<double, kMaxVertices> px{}, py{};  // vertex k (world, m): as given until the body moves
  std::array<double, kMaxVertices> ox{}, oy{};  // vertex k - vertex 0 (m), fixed
  std::array<double, kMaxVertices> ux{}, uy{};  // outward unit normal of edge k (n >= 3)

  double x0() const { return px[0]; }  // vertex 0, the body's reference point (m)
  double y0() const { return py[0]; }
  Point vertex(int k) const { return {px[k], py[k]}; }
};

// The edges and outward normals from the vertices.
inline void set_edges(Shape& s) {
  if (s.n <= 2) {
    s.edge[0] = make_segment(s.px[0], s.py[0], s.px[s.n - 1], s.py[s.n - 1]);
    return;
  }
  for (int k = 0; k < s.n; ++k) {
    const int j = (k + 1) % s.n;
    s.edge[k] = make_segment(s.px[k], s.py[k], s.px[j], s.py[j]);
    s.ux[k] = -s.edge[k].nx0;  // make_segment's normal is the left one: inward for counter-clockwise
    s.uy[k] = -s.edge[k].ny0;
  }
}

// A shape from its core vertices in world coordinates: 1 or 2 vertices, or a
// convex polygon in counter-clockwise order (shape/shape_kinds.hpp checks).
inline Shape make_shape(const std::vector<Point>& v) {
  Shape s;
  s.n = static_cast<int>(v.size());
  for (int k = 0; k < s.n; ++k) {
    s.px[k] = v[k].x;
    s.py[k] = v[k].y;
    s.ox[k] = v[k].x - v[0].x;
    s.oy[k] = v[k].y - v[0].y;
  }
  set_edges(s);
  return s;
}

// Moves the shape so that vertex 0 is at (x, y) (m); the others keep their
// offsets from it exactly (no round-off accumulates over moves).
inline void move_to(Shape& s, double x, double y) {
  for (int k = 0; k < s.n; ++k) {
    s.px[k] = x + s.ox[k];
    s.py[k] = y + s.oy[k];
  }
  const int edges = s.n <= 2 ? 1 : s.n;
  for (int k = 0; k < edges; ++k) {
    s.edge[k].ax = s.px[k];
    s.edge[k].ay = s.py[k];
  }
}

// Turns the shape by the angle whose cosine and sine are (c, sn) from its
// orientation at the start and puts vertex 0 at (x, y) (m): vertex k is at
// (x, y) + R (ox_k, oy_k), from the fixed offsets (no round-off accumulates).
inline void turn_to(Shape& s, double x, double y, double c, double sn) {
  for (int k = 0; k < s.n; ++k) {
    s.px[k] = x + (c * s.ox[k] - sn * s.oy[k]);
    s.py[k] = y + (sn * s.ox[k] + c * s.oy[k]);
  }
  set_edges(s);
}

// Signed distance from O = (px, py) to the core and the unit normal from the core to O.
// Always inlined: the kernels' narrow phase calls it per contact slot, and
// GCC 12 left it out of line there once the contact law's terms were folded
// in (polygon pull-off 2 % slower).
[[gnu::always_inline]] inline Proximity closest_point(const Shape& s, double px, double py) {
  if (s.n <= 2) return closest_point(s.edge[0], px, py);
  Proximity best{std::numeric_limits<double>::infinity(), 0.0, 0.0};
  double depth = -std::numeric_limits<double>::infinity();
  int face = 0;
  for (int k = 0; k < s.n; ++k) {
    const Proximity g = closest_point(s.edge[k], px, py);
    if (g.dist < best.dist) best = g;
    const double h = (px - s.edge[k].ax) * s.ux[k] + (py - s.edge[k].ay) * s.uy[k];
    if (h > depth) {
      depth = h;
      face = k;
    }
  }
  if (depth > 0.0) return best;         // outside: the nearest point of the boundary
  return {depth, s.ux[face], s.uy[face]};  // inside: below the least-penetrated face
}

// Bounding box of the core (m); add the rounding radius for the body's.
struct Bounds {
  double xmin, ymin, xmax, ymax;
};
inline Bounds core_bounds(const Shape& s) {
  Bounds b{s.x0(), s.y0(), s.x0(), s.y0()};
  for (int k = 1; k < s.n; ++k) {
    const Point v = s.vertex(k);
    b.xmin = std::min(b.xmin, v.x);
    b.xmax = std::max(b.xmax, v.x);
    b.ymin = std::min(b.ymin, v.y);
    b.ymax = std::max(b.ymax, v.y);
  }
  return b;
}

}  // namespace dem2d
