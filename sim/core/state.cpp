#include "core/state.hpp"

namespace dem2d {

void Particles::resize(std::size_t n) {
  for (auto* v : {&x, &y, &vx, &vy, &theta, &omega, &fx, &fy, &torque, &radius, &mass, &inv_mass,
                  &inv_inertia})
    v->resize(n, 0.0);
  active.resize(n, 1);
}

void Bodies::resize(std::size_t n) {
  name.resize(n);
  role.resize(n);
  kind.resize(n);
  shape.resize(n);
  line.resize(n);
  for (auto* v : {&centre_x, &centre_y, &radius, &vx, &vy, &omega, &angle, &pivot_x, &pivot_y, &pivot0_x, &pivot0_y,
                  &anchor_x, &anchor_y, &origin_x, &origin_y, &fx, &fy, &torque})
    v->resize(n, 0.0);
  own_pivot.resize(n, 0);
  schedule.resize(n);
  anchor_step.resize(n, 0);
  active.resize(n, 1);
  removing.resize(n, 0);
}

namespace {
template <class Coordinate>
double vertex_mean(const Shape& s, Coordinate c) {
  double sum = 0.0;
  for (int k = 0; k < s.n; ++k) sum += c(s.vertex(k));
  return sum / s.n;
}
}  // namespace

void Bodies::shape_changed(std::size_t b) {
  line[b] = shape[b].edge[0];
  centre_x[b] = vertex_mean(shape[b], [](Point v) { return v.x; });
  centre_y[b] = vertex_mean(shape[b], [](Point v) { return v.y; });
  if (own_pivot[b]) {  // where vertex 0 carries it: R(angle) (pivot0 - origin) from vertex 0
    const double c = std::cos(angle[b]), s = std::sin(angle[b]);
    const double rx = pivot0_x[b] - origin_x[b], ry = pivot0_y[b] - origin_y[b];
    pivot_x[b] = shape[b].x0() + (c * rx - s * ry);
    pivot_y[b] = shape[b].y0() + (s * rx + c * ry);
  } else {
    pivot_x[b] = centre_x[b];
    pivot_y[b] = centre_y[b];
  }
}

void Bodies::set_shape(std::size_t b, const Shape& s) {
  shape[b] = s;
  shape_changed(b);
}

void Bodies::move_to(std::size_t b, double x, double y) {
  if (angle[b] == 0.0)
    dem2d::move_to(shape[b], x, y);
  else
    turn_to(shape[b], x, y, std::cos(angle[b]), std::sin(angle[b]));
  shape_changed(b);
}

}  // namespace dem2d
