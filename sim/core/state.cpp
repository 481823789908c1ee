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
  for (auto* v : {&ax, &ay, &bx, &by, &radius, &vx, &vy, &anchor_x, &anchor_y, &origin_x, &origin_y, &fx, &fy, &torque})
    v->resize(n, 0.0);
  schedule.resize(n);
  anchor_step.resize(n, 0);
  active.resize(n, 1);
  removing.resize(n, 0);
}

}  // namespace dem2d
