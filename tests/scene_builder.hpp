// Scenes built in code for the tests: the paper's glass beads and contact law,
// with the stiffness and effects each test needs.
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <string>

#include "core/body_roles.hpp"
#include "engine/system.hpp"
#include "scene/scene.hpp"

namespace dem2d::test {

inline constexpr double kDensity = 2500.0;  // kg/m^3, glass
inline constexpr double kMeanD = 3e-3;      // m
// the study's effects: a poured bed with friction and rolling resistance in a walled cell
inline constexpr EffectSet kFull =
    effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance | effect::walls;
// ... with moving bodies and both dashpots: every effect the run-file, ledger and scene tests exercise together
// (named, not "all but ...": an effect added to the engine does not change what they test; cohesion:
// test_cohesion.cpp, turning bodies: test_motion.cpp)
inline constexpr EffectSet kFullMoving =
    kFull | effect::moving_bodies | effect::tangential_damping | effect::rolling_damping;

// The paper's law (docs/paper.md) with stiffness kn: k_t = k_n/2, e = 0.9, mu = 0.5,
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
  BodySpec b = BodySpec::segment(name, ax, ay, bx, by, thickness);
  b.role = legacy_body_role(name);  // the tests name the study's bodies after their roles
  b.vx = vx;
  b.vy = vy;
  s.bodies.push_back(b);
}

// dt = dt_c / divisor with dt_c = sqrt(m_min / k_n)
inline void set_dt_fraction(Scene& s, double divisor) { s.dt = s.critical_dt() / divisor; }

// A box open at the top (inner faces x = 0, x = width, y = 0; walls 2 mm
// thick) with n disks of diameter uniform in [d_min, d_max] on a square grid
// of pitch 1.05 d_max above the floor. dt = dt_c / 20.
inline Scene boxed_bed(EffectSet effects, int n, double width, double kn = 1.92e6, std::uint64_t seed = 1,
                       double d_min = 2e-3, double d_max = 4e-3) {
  Scene s = glass_scene(effects | effect::walls, kn);
  const double pitch = 1.05 * d_max;
  const int per_row = static_cast<int>(width / pitch);
  const double height = pitch * (n / per_row + 2);
  std::mt19937_64 rng(seed);
  for (int k = 0; k < n; ++k) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    add_disk(s, pitch * (0.5 + k % per_row), pitch * (0.5 + k / per_row), d_min + u * (d_max - d_min));
  }
  add_wall(s, "floor", -1e-3, -1e-3, width + 1e-3, -1e-3);
  add_wall(s, "left", -1e-3, -1e-3, -1e-3, height + 0.05);
  add_wall(s, "right", width + 1e-3, -1e-3, width + 1e-3, height + 0.05);
  s.domain = {-0.02, -0.02, width + 0.02, height + 0.1};
  set_dt_fraction(s, 20.0);
  return s;
}

// A hexagonal crystal of nx x ny disks (odd rows one shorter) at pitch p
// (p < d: compressed) in a closed box whose walls' faces touch the outer
// grains: diameters uniform in [d_lo, d_hi], velocity components uniform in
// [-v, v] (m/s), drawn from `seed`. Walls 2 mm thick; the domain 1 cm larger.
inline void crystal_in_box(Scene& s, int nx, int ny, double p, double d_lo, double d_hi, double v,
                           std::uint64_t seed = 3) {
  const double row = p * std::sqrt(3.0) / 2.0;
  std::mt19937_64 rng(seed);
  auto uniform = [&rng](double a, double b) { return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  for (int r = 0; r < ny; ++r)
    for (int c = 0; c < nx - (r % 2); ++c) {
      const double d = uniform(d_lo, d_hi), vx = uniform(-v, v), vy = uniform(-v, v);
      add_disk(s, (0.5 + c + 0.5 * (r % 2)) * p, 0.5 * p + r * row, d, vx, vy);
    }
  const double width = nx * p, height = p + (ny - 1) * row;
  add_wall(s, "floor", -1e-3, -1e-3, width + 1e-3, -1e-3);
  add_wall(s, "lid", -1e-3, height + 1e-3, width + 1e-3, height + 1e-3);
  add_wall(s, "left", -1e-3, -1e-3, -1e-3, height + 1e-3);
  add_wall(s, "right", width + 1e-3, -1e-3, width + 1e-3, height + 1e-3);
  s.domain = {-0.01, -0.01, width + 0.01, height + 0.01};
}

// Advances until `seconds` of simulated time have passed.
inline void run_for(System& sys, double seconds) {
  sys.advance(std::llround(seconds / sys.config.dt));
}

}  // namespace dem2d::test
