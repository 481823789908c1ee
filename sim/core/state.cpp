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
  for (auto* v : {&centre_x, &centre_y, &radius, &vx, &vy, &anchor_x, &anchor_y, &origin_x, &origin_y, &fx, &fy, &torque})
    v->resize(n, 0.0);
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
}

void Bodies::set_shape(std::size_t b, const Shape& s) {
  shape[b] = s;
  shape_changed(b);
}

void Bodies::move_to(std::size_t b, double x, double y) {
  dem2d::move_to(shape[b], x, y);
  shape_changed(b);
}

}  // namespace dem2d
