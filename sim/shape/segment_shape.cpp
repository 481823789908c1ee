// shape = "segment" (the default): the paper's sphero-line (docs/paper.md), a segment C1C2 with
// round caps of diameter `thickness`.
#include "shape/shape_kinds.hpp"

namespace dem2d {

extern const ShapeKind kSegmentShape;
const ShapeKind kSegmentShape{
    "segment",
    {{"a", ShapeKey::point, "end point C1", "m"}, {"b", ShapeKey::point, "end point C2", "m"}},
    [](const ShapeArgs& s) { return std::vector<Point>{s.point.at("a"), s.point.at("b")}; }};

}  // namespace dem2d
