// Scenes built in code for the tests: SPEC's glass beads and contact law,
// with the stiffness and effects each test needs.
#pragma once

#include <cmath>
#include <initializer_list>
#include <string>

#include "engine/system.hpp"
#include "scene/scene.hpp"

namespace dem2d::test {

inline constexpr double kDensity = 2500.0;  // kg/m^3, glass
inline constexpr double kMeanD = 3e-3;      // m

// SPEC's law with stiffness kn: k_t = k_n/2, e = 0.9, mu = 0.5,
// mu_r = mu d 1e-2, k_r = d^2 k_n 1e-4.
inline ContactLaw glass_law(double kn) {
  ContactLaw law;
  law.kn = kn;
  law.kt = 0.5 * kn;
  law.restitution = 0.9;
  law.friction = 0.5;
  law.rolling_friction = 0.5 * kMeanD * 1e-2;
  law.rolling_stiffness = kMeanD * kMeanD * kn * 1e-4;
  return law;
}

inline Scene glass_scene(EffectSet effects, double kn = 1.92e6) {
  Scene s;
  s.name = "test";
  s.effects = effects;
  s.density = kDensity;
  s.particle_particle = glass_law(kn);
  s.particle_wall = glass_law(kn);
  if (has(effects, effect::gravity)) s.gy = -9.81;
  s.domain = {-1.0, -1.0, 1.0, 1.0};
  s.skin = 0.5e-3;
  s.threads = 1;
  s.stop.duration = 1.0;
  return s;
}

inline void add_disk(Scene& s, double x, double y, double d, double vx = 0.0, double vy = 0.0,
                     double omega = 0.0) {
  s.particles.push_back({x, y, d, vx, vy, omega});
}

inline void add_wall(Scene& s, const std::string& name, double ax, double ay, double bx, double by,
                     double thickness = 2e-3, double vx = 0.0, double vy = 0.0) {
  s.bodies.push_back({name, ax, ay, bx, by, thickness, vx, vy});
}

// dt = dt_c / divisor with dt_c = sqrt(m_min / k_n)
inline void set_dt_fraction(Scene& s, double divisor) { s.dt = s.critical_dt() / divisor; }

inline double kinetic_energy(const System& sys) {
  double e = 0.0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    if (!sys.p.active[i]) continue;
    const double m = sys.p.mass[i], inertia = 1.0 / sys.p.inv_inertia[i];
    e += 0.5 * m * (sys.p.vx[i] * sys.p.vx[i] + sys.p.vy[i] * sys.p.vy[i]) +
         0.5 * inertia * sys.p.omega[i] * sys.p.omega[i];
  }
  return e;
}

}  // namespace dem2d::test
