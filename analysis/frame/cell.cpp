#include "frame/cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/stage_output.hpp"  // format_mm

namespace dem2d::analysis {

Cell find_cell(const Snapshot& s) {
  const auto body = [&](const char* role) -> const Body& {
    const int b = s.find_role(role);
    if (b < 0) throw StageError(s.no_body_with_role(role));
    return s.bodies[static_cast<std::size_t>(b)];
  };
  const Body& l = body("left_wall");
  const Body& r = body("right_wall");
  const Body& f = body("floor");
  Cell c;
  c.left = l.xmax();
  c.right = r.xmin();
  c.floor = f.ymax();
  if (c.right <= c.left)
    throw StageError("the walls' inner faces x = " + format_mm(c.left) + " ('" + l.name + "') and " +
                     format_mm(c.right) + " ('" + r.name + "') enclose no cell");
  if (const int b = s.find_role("intruder"); b >= 0) {
    const Body& in = s.bodies[static_cast<std::size_t>(b)];
    c.intruder = Rounded{in.core(), in.radius()};
  }
  return c;
}

double mean_active_diameter(const Snapshot& s) {
  double sum = 0.0;
  std::int64_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.active[i]) sum += s.diameter[i], ++n;
  if (n == 0) throw StageError("snapshot " + std::to_string(s.index) + " has no active grains");
  return sum / static_cast<double>(n);
}

Surface bed_surface(const Snapshot& s, const Cell& cell, double column_width) {
  const double width = cell.right - cell.left;
  Surface out;
  out.columns = std::max(1, static_cast<int>(std::lround(width / column_width)));
  out.column_width = width / out.columns;
  std::vector<double> top(static_cast<std::size_t>(out.columns), -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec2 p = s.position[i];
    if (!s.active[i] || p.x < cell.left || p.x > cell.right) continue;
    const int k = std::min(out.columns - 1, static_cast<int>((p.x - cell.left) / out.column_width));
    double& t = top[static_cast<std::size_t>(k)];
    t = std::max(t, p.y + 0.5 * s.diameter[i] - cell.floor);
  }
  out.min = std::numeric_limits<double>::infinity();
  out.max = -out.min;
  double sum = 0.0;
  for (double& t : top) {
    if (std::isinf(t)) t = 0.0, ++out.empty_columns;
    sum += t;
    out.min = std::min(out.min, t);
    out.max = std::max(out.max, t);
  }
  out.height = sum / out.columns;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.active[i] && s.position[i].y - 0.5 * s.diameter[i] - cell.floor > out.height) ++out.grains_above;
  return out;
}

Region bulk_region(const Cell& cell, double surface_height, double margin) {
  Region r;
  r.box = {cell.left + margin, cell.right - margin, cell.floor + margin, cell.floor + surface_height - margin};
  if (r.box.width() <= 0.0 || r.box.height() <= 0.0)
    throw StageError("the bulk region is empty: the cell is " + format_mm(cell.right - cell.left) + " wide and the bed " +
                     format_mm(surface_height) + " high, less than twice the margin of " + format_mm(margin));
  if (cell.intruder) {
    r.hole = *cell.intruder;
    r.hole->radius += margin;
  }
  return r;
}

}  // namespace dem2d::analysis
