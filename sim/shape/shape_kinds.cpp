#include "shape/shape_kinds.hpp"

#include <algorithm>
#include <string>

namespace dem2d {

#define DEM2D_SHAPE(kind) extern const ShapeKind kind;
#include "shape/shape_list.inc"
#undef DEM2D_SHAPE

const std::vector<ShapeKind>& shape_kinds() {
#define DEM2D_SHAPE(kind) kind,
  static const std::vector<ShapeKind> kinds{
#include "shape/shape_list.inc"
  };
#undef DEM2D_SHAPE
  return kinds;
}

const ShapeKind* find_shape_kind(std::string_view name) {
  for (const ShapeKind& k : shape_kinds())
    if (name == k.name) return &k;
  return nullptr;
}

std::vector<Point> convex_polygon(std::vector<Point> v, const char* key) {
  const auto n = v.size();
  if (n < 3 || n > static_cast<std::size_t>(Shape::kMaxVertices))
    throw ShapeError(key, "a polygon needs 3 to " + std::to_string(Shape::kMaxVertices) + " vertices, not " +
                              std::to_string(n));
  const auto cross = [&](std::size_t k) {  // turn at vertex k+1
    const Point a = v[k], b = v[(k + 1) % n], c = v[(k + 2) % n];
    return (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
  };
  double area2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) area2 += v[k].x * v[(k + 1) % n].y - v[(k + 1) % n].x * v[k].y;
  if (area2 < 0.0) std::reverse(v.begin(), v.end());
  for (std::size_t k = 0; k < n; ++k)
    if (!(cross(k) > 0.0))
      throw ShapeError(key, "not a strictly convex polygon: the turn at vertex " + std::to_string((k + 1) % n) +
                                " is straight, reversed or the vertex repeats (give the vertices in order "
                                "around a convex outline)");
  // every turn the same way is not enough: a star winds more than once
  double turn = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Point a = v[k], b = v[(k + 1) % n], c = v[(k + 2) % n];
    turn += std::atan2(cross(k), (b.x - a.x) * (c.x - b.x) + (b.y - a.y) * (c.y - b.y));
  }
  if (turn > 2.0 * M_PI + 1e-9) throw ShapeError(key, "the outline winds more than once (a star, not convex)");
  return v;
}

}  // namespace dem2d
