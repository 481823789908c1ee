// An axis-aligned rectangle (m): a scene's domain, where grains may be.
#pragma once

namespace dem2d {

struct Box {
  double xmin = 0.0, ymin = 0.0, xmax = 0.0, ymax = 0.0;  // (m)
  bool contains(double x, double y) const { return x >= xmin && x <= xmax && y >= ymin && y <= ymax; }
};

}  // namespace dem2d
