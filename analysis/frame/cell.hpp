// The cell the grains are in, found by the bodies' roles in a run file
// (left_wall, right_wall, floor, and an optional intruder): the walls' and
// floor's inner faces, the intruder's outline, the bed's free surface and its
// bulk. Every analysis stage measures in this frame. SI units (m) throughout.
#pragma once

#include <cstdint>
#include <optional>

#include "common/stage_error.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

struct Rect {
  double xmin = 0.0, xmax = 0.0, ymin = 0.0, ymax = 0.0;
  double width() const { return xmax - xmin; }
  double height() const { return ymax - ymin; }
  bool contains(double x, double y) const { return x >= xmin && x <= xmax && y >= ymin && y <= ymax; }
};

// The points closer than `radius` to a convex core (sim/shape/shape.hpp): a
// body (its outline rounded by its radius), or one with a margin added.
struct Rounded {
  Shape core;
  double radius = 0.0;  // (m)
  bool contains(double x, double y) const { return closest_point(core, x, y).dist < radius; }
};

// A rectangle with an optional hole.
struct Region {
  Rect box;
  std::optional<Rounded> hole;
  bool contains(double x, double y) const { return box.contains(x, y) && !(hole && hole->contains(x, y)); }
};

// The cell's inner faces (the sides facing the grains) and the intruder: the
// bodies with the roles left_wall, right_wall, floor and intruder (optional).
struct Cell {
  double left = 0.0, right = 0.0, floor = 0.0;  // x, x, y (m)
  std::optional<Rounded> intruder;              // its outline
};
// Throws StageError if a wall is missing or the faces enclose nothing.
Cell find_cell(const Snapshot& s);

// Mean diameter of the active grains (m); StageError if there are none.
double mean_active_diameter(const Snapshot& s);

// Free surface: per column, the highest grain top (y + d/2) of the active
// grains centred in it; heights above the floor's inner face (m). A column
// without grains has height 0.
struct Surface {
  double height = 0.0, min = 0.0, max = 0.0;  // mean, lowest, highest column
  double column_width = 0.0;
  int columns = 0, empty_columns = 0;
  std::int64_t grains_above = 0;  // active grains entirely above the mean surface (y - d/2 > height)
};
Surface bed_surface(const Snapshot& s, const Cell& cell, double column_width);

// The bulk region: the cell shrunk by `margin` from the walls, floor and free
// surface (height above the floor), minus the points within `margin` of the
// intruder's surface. StageError if it is empty.
Region bulk_region(const Cell& cell, double surface_height, double margin);

}  // namespace dem2d::analysis
