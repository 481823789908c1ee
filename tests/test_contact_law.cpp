// Normal contact law: the restitution of head-on collisions is the one the
// scene asks for, over the whole range of e, for equal and unequal disks and
// against walls; and the damping ratio that gives it is the non-attractive
// law's (contact_law.hpp), not the textbook formula for a law that may pull.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/contact_law.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

constexpr EffectSet kHeadOn = effect::normal_damping | effect::friction | effect::rolling_resistance;
constexpr double kRestitutions[] = {0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.95, 1.0};

// e(nu) of the non-attractive law, its inverse, and the two values that tell
// it from the law that may pull.
TEST(DampingRatio, InvertsTheNonAttractiveLaw) {
  for (const double e : kRestitutions) EXPECT_NEAR(restitution_of_damping_ratio(damping_ratio(e)), e, 1e-13 * e);
  EXPECT_EQ(damping_ratio(1.0), 0.0);
  EXPECT_NEAR(restitution_of_damping_ratio(1.0), std::exp(-2.0), 1e-15);  // critically damped: e = e^-2
  // continuous through nu = 1 (the series there against the closed forms either side)
  EXPECT_NEAR(restitution_of_damping_ratio(1.0 - 1e-7), std::exp(-2.0), 1e-7);
  EXPECT_NEAR(restitution_of_damping_ratio(1.0 + 1e-7), std::exp(-2.0), 1e-7);
  EXPECT_NEAR(restitution_of_damping_ratio(1.0 - 1e-3), restitution_of_damping_ratio(1.0 - 1e-3 + 1e-9), 1e-8);
  // nu = -ln e / sqrt(pi^2 + ln^2 e), exact only if the force may pull, gives
  // e' = 0.550 for e = 0.5 and 0.902 for 0.9 under this law (an independent check measured 0.551, 0.902)
  auto textbook = [](double e) { return -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e)); };
  EXPECT_NEAR(restitution_of_damping_ratio(textbook(0.5)), 0.550, 1e-3);
  EXPECT_NEAR(restitution_of_damping_ratio(textbook(0.9)), 0.902, 1e-3);
  EXPECT_GT(damping_ratio(0.9), textbook(0.9));
  // overdamped for e < e^-2; e -> 1/(4 nu^2) as nu grows
  EXPECT_GT(damping_ratio(0.1), 1.0);
  EXPECT_NEAR(restitution_of_damping_ratio(1e3) * 4e6, 1.0, 1e-4);
}

// Relative velocity of two disks after a head-on collision at `v` (m/s), over `v`.
double pair_restitution(double e, double d0, double d1, double v, double kn) {
  Scene s = glass_scene(kHeadOn, kn);
  s.particle_particle.restitution = e;
  const double gap = 0.5 * (d0 + d1) + 0.5e-3;
  add_disk(s, -0.5 * gap, 0.0, d0, v, 0.0);
  add_disk(s, 0.5 * gap, 0.0, d1, 0.0, 0.0);
  set_dt_fraction(s, 800.0);  // the dashpot's half-step velocity errs by O(dt): 0.6 % at e = 0.05 with dt_c/400
  System sys(s);
  while (!(sys.state.p.vx[1] > sys.state.p.vx[0] && sys.state.p.x[1] - sys.state.p.x[0] > 0.5 * (d0 + d1))) sys.advance(10);
  EXPECT_NEAR(sys.state.p.mass[0] * sys.state.p.vx[0] + sys.state.p.mass[1] * sys.state.p.vx[1], sys.state.p.mass[0] * v, 1e-12 * sys.state.p.mass[0] * v);
  EXPECT_EQ(sys.state.p.vy[0], 0.0);
  EXPECT_EQ(sys.state.p.omega[0], 0.0);
  return (sys.state.p.vx[1] - sys.state.p.vx[0]) / v;
}

TEST(Restitution, EqualDisksHeadOnIsE) {
  for (const double kn : {1.92e6, 1.92e8})
    for (const double e : kRestitutions) EXPECT_NEAR(pair_restitution(e, 3e-3, 3e-3, 0.2, kn), e, 0.005 * e) << "kn " << kn;
}

TEST(Restitution, UnequalDisksHeadOnIsE) {
  for (const double e : kRestitutions) EXPECT_NEAR(pair_restitution(e, 2e-3, 4e-3, 0.2, 1.92e6), e, 0.005 * e);
}

TEST(Restitution, DiskOnWallIsE) {
  for (const double e : kRestitutions) {
    Scene s = glass_scene(kHeadOn | effect::walls);
    s.particle_wall.restitution = e;
    add_wall(s, "floor", -0.01, -1e-3, 0.01, -1e-3, 2e-3);  // flat face at y = 0
    add_disk(s, 0.0, 2e-3, 3e-3, 0.0, -0.1);
    set_dt_fraction(s, 400.0);
    System sys(s);
    while (!(sys.state.p.vy[0] > 0.0 && sys.state.p.y[0] > 1.5e-3)) sys.advance(10);
    EXPECT_NEAR(sys.state.p.vy[0] / 0.1, e, 0.005 * e);
    EXPECT_EQ(sys.state.p.vx[0], 0.0);
  }
}

// The force vanishes before the overlap does: the contact's force phase
// lasts t* = 2 arccos(nu) / w_d, w_d = w0 sqrt(1 - nu^2), shorter than the
// pi / w_d of a law that may pull (14 % shorter at e = 0.5).
TEST(Restitution, ForcePhaseEndsWhenTheAccelerationVanishes) {
  const double e = 0.5, nu = damping_ratio(e), kn = 1.92e6;
  Scene s = glass_scene(effect::normal_damping, kn);
  s.particle_particle.restitution = e;
  add_disk(s, -1.6e-3, 0.0, 3e-3, 0.1, 0.0);
  add_disk(s, 1.6e-3, 0.0, 3e-3, -0.1, 0.0);
  set_dt_fraction(s, 1000.0);
  System sys(s);
  double first = -1.0, last = -1.0;
  while (!(sys.state.p.vx[1] > sys.state.p.vx[0] && sys.state.p.x[1] - sys.state.p.x[0] > 3.01e-3)) {
    sys.advance(1);
    if (sys.state.p.fx[1] > 0.0) {
      if (first < 0.0) first = sys.time();
      last = sys.time();
    }
  }
  const double w0 = std::sqrt(kn / (0.5 * sys.state.p.mass[0])), wd = w0 * std::sqrt(1.0 - nu * nu);
  EXPECT_NEAR(last - first, 2.0 * std::acos(nu) / wd, 3.0 * sys.config.dt);
  EXPECT_LT(last - first, 0.9 * M_PI / wd);
}

}  // namespace
}  // namespace dem2d::test
