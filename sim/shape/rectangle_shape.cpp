// shape = "rectangle": a rectangle of outer size [width, height] about
// `centre`, turned counter-clockwise by `angle`, its corners rounded by
// `thickness` / 2 (0: square corners, as the experiment's intruder).
#include <cmath>
#include <string>

#include "shape/shape_kinds.hpp"

namespace dem2d {

extern const ShapeKind kRectangleShape;
const ShapeKind kRectangleShape{
    "rectangle",
    {{"centre", ShapeKey::point, "centre", "m"},
     {"size", ShapeKey::point, "outer width and height", "m"},
     {"angle", ShapeKey::number, "rotation, counter-clockwise", "deg", false, 0.0}},
    [](const ShapeArgs& s) {
      const Point c = s.point.at("centre"), size = s.point.at("size");
      if (!(size.x > s.thickness && size.y > s.thickness))
        throw ShapeError("size", "width and height must exceed thickness = " + std::to_string(s.thickness) +
                                     " m (the rounding diameter): the core would have no area");
      const double hw = 0.5 * (size.x - s.thickness), hh = 0.5 * (size.y - s.thickness);
      const double a = s.number.at("angle") * M_PI / 180.0, ca = std::cos(a), sa = std::sin(a);
      std::vector<Point> v;
      for (const Point q : {Point{-hw, -hh}, Point{hw, -hh}, Point{hw, hh}, Point{-hw, hh}})
        v.push_back({c.x + ca * q.x - sa * q.y, c.y + sa * q.x + ca * q.y});
      return v;
    }};

}  // namespace dem2d
