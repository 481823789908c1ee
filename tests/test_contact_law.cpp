// Normal contact law: restitution of a head-on collision.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

constexpr EffectSet kHeadOn = effect::normal_damping | effect::friction | effect::rolling_resistance;

TEST(Restitution, ParticleParticleHeadOnIsE) {
  for (const double kn : {1.92e6, 1.92e8}) {
    Scene s = glass_scene(kHeadOn, kn);
    const double v = 0.1;  // m/s each, towards each other
    add_disk(s, -2e-3, 0.0, 3e-3, v, 0.0);
    add_disk(s, 2e-3, 0.0, 3e-3, -v, 0.0);
    set_dt_fraction(s, 50.0);
    System sys(s);
    while (!(sys.p.vx[1] > sys.p.vx[0] && sys.p.x[1] - sys.p.x[0] > 3.1e-3)) sys.advance(10);
    const double e = (sys.p.vx[1] - sys.p.vx[0]) / (2.0 * v);
    EXPECT_NEAR(e, 0.9, 0.009) << "kn = " << kn;
    EXPECT_NEAR(sys.p.vx[0] + sys.p.vx[1], 0.0, 1e-15);  // momentum
    EXPECT_EQ(sys.p.vy[0], 0.0);
    EXPECT_EQ(sys.p.omega[0], 0.0);
  }
}

TEST(Restitution, ParticleUnequalMassesIsE) {
  Scene s = glass_scene(kHeadOn);
  add_disk(s, -3e-3, 0.0, 2e-3, 0.2, 0.0);
  add_disk(s, 2e-3, 0.0, 4e-3, 0.0, 0.0);
  set_dt_fraction(s, 50.0);
  System sys(s);
  const double p0 = sys.p.mass[0] * 0.2;
  while (!(sys.p.vx[1] > sys.p.vx[0] && sys.p.x[1] - sys.p.x[0] > 3.1e-3)) sys.advance(10);
  EXPECT_NEAR((sys.p.vx[1] - sys.p.vx[0]) / 0.2, 0.9, 0.009);
  EXPECT_NEAR(sys.p.mass[0] * sys.p.vx[0] + sys.p.mass[1] * sys.p.vx[1], p0, 1e-12 * p0);
}

TEST(Restitution, ParticleWallHeadOnIsE) {
  Scene s = glass_scene(kHeadOn | effect::walls);
  add_wall(s, "floor", -0.01, -1e-3, 0.01, -1e-3, 2e-3);  // flat face at y = 0
  add_disk(s, 0.0, 2e-3, 3e-3, 0.0, -0.1);
  set_dt_fraction(s, 50.0);
  System sys(s);
  while (!(sys.p.vy[0] > 0.0 && sys.p.y[0] > 2e-3)) sys.advance(10);
  EXPECT_NEAR(sys.p.vy[0] / 0.1, 0.9, 0.009);
  EXPECT_EQ(sys.p.vx[0], 0.0);
}


}  // namespace
}  // namespace dem2d::test
