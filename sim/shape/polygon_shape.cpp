// shape = "polygon": any convex polygon, its vertices [[x0, y0], ...] in
// order (either way round), its corners rounded by `thickness` / 2.
#include "shape/shape_kinds.hpp"

namespace dem2d {

extern const ShapeKind kPolygonShape;
const ShapeKind kPolygonShape{"polygon",
                              {{"vertices", ShapeKey::points, "vertices of the core", "m"}},
                              [](const ShapeArgs& s) { return convex_polygon(s.points.at("vertices"), "vertices"); }};

}  // namespace dem2d
