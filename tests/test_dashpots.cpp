// The opt-in tangential and rolling dashpots (contact_law.hpp): without them
// the paper's law (docs/paper.md) leaves the tangential and rolling springs undamped, so a disk
// stopped by rolling resistance rocks on for ever and a rolling disk's speed
// keeps ringing; with them both die out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

constexpr EffectSet kRolling =
    effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance | effect::walls;

// A 3 mm disk launched rolling at 5 mm/s on a flat floor, the paper's law
// (rolling friction mu_r = 1.5e-5 m): it stops within ~0.08 s, then rocks on
// its rolling spring. Returns the largest |v| over the 20 ms before t (s).
double rocking_speed(EffectSet extra, double nu, double t) {
  Scene s = glass_scene(kRolling | extra);
  s.particle_particle.rolling_damping_ratio = s.particle_wall.rolling_damping_ratio = nu;
  const double d = 3e-3, v0 = 5e-3, m = kDensity * M_PI * d * d / 4.0;
  add_wall(s, "floor", -0.5, -1e-3, 0.5, -1e-3, 2e-3);
  add_disk(s, 0.0, 0.5 * d - m * 9.81 / s.particle_wall.kn, d, v0, 0.0, -v0 / (0.5 * d));
  set_dt_fraction(s, 20.0);
  System sys(s);
  run_for(sys, t - 0.02);
  double vmax = 0.0;
  for (int k = 0; k < 200; ++k) {
    run_for(sys, 1e-4);
    vmax = std::max(vmax, std::hypot(sys.state.p.vx[0], sys.state.p.vy[0]));
  }
  return vmax;
}

TEST(Dashpots, RollingDampingStopsTheRocking) {
  const double undamped = rocking_speed(0, 0.0, 0.3);
  // the paper's law: it rocks on, undiminished (an independent check measured ~1.7 mm/s in its case)
  EXPECT_GT(undamped, 1e-4);
  EXPECT_GT(undamped, 0.8 * rocking_speed(0, 0.0, 0.15));
  // with a rolling dashpot the rocking decays (exponentially: the mode's rate
  // is ~ nu_r sqrt(k_r / I) / 3, the disk's rolling inertia being 3 I)
  const double damped_early = rocking_speed(effect::rolling_damping, 0.3, 0.15);
  const double damped = rocking_speed(effect::rolling_damping, 0.3, 0.3);
  EXPECT_LT(damped, 1e-2 * undamped);
  EXPECT_LT(damped, 0.1 * damped_early);
  std::printf("rocking speed at 0.3 s: %.3g m/s undamped, %.3g m/s with rolling damping nu_r = 0.3 (%.3g at 0.15 s)\n",
              undamped, damped, damped_early);
}

// A disk launched sliding without spin: once it rolls (t* = v0/(3 mu g)),
// the tangential spring rings and the speed oscillates about 2/3 v0. The
// spread of v over 2 ms from 2 t*: returned over v0.
double rolling_speed_ripple(EffectSet extra, double nu_t) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::walls | extra);
  s.particle_particle.tangential_damping_ratio = s.particle_wall.tangential_damping_ratio = nu_t;
  const double d = 3e-3, v0 = 0.1, m = kDensity * M_PI * d * d / 4.0;
  add_wall(s, "floor", -0.5, -1e-3, 0.5, -1e-3, 2e-3);
  add_disk(s, 0.0, 0.5 * d - m * 9.81 / s.particle_wall.kn, d, v0, 0.0, 0.0);
  set_dt_fraction(s, 50.0);
  System sys(s);
  run_for(sys, 2.0 * v0 / (3.0 * 0.5 * 9.81));
  double lo = 1e300, hi = -1e300, sum = 0.0;
  const int n = static_cast<int>(2e-3 / sys.config.dt);
  for (int k = 0; k < n; ++k) {
    sys.advance(1);
    lo = std::min(lo, sys.state.p.vx[0]);
    hi = std::max(hi, sys.state.p.vx[0]);
    sum += sys.state.p.vx[0];
  }
  EXPECT_NEAR(sum / n / v0, 2.0 / 3.0, 0.01);  // rolls at 2/3 v0 either way
  return (hi - lo) / v0;
}

TEST(Dashpots, TangentialDampingStopsTheRingingOfARollingDisk) {
  const double undamped = rolling_speed_ripple(0, 0.0);
  const double damped = rolling_speed_ripple(effect::tangential_damping, 0.3);
  EXPECT_GT(undamped, 1e-3);
  EXPECT_LT(damped, 1e-3 * undamped);
  std::printf("speed ripple of a rolling disk: %.3g v0 undamped, %.3g v0 with nu_t = 0.3\n", undamped, damped);
}

// While a contact slides, spring plus dashpot equal the cap, |F_t| = mu F_n.
TEST(Dashpots, SlidingForceIsTheCapWithADashpot) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::tangential_damping | effect::walls);
  s.particle_wall.tangential_damping_ratio = 0.5;
  const double d = 3e-3, m = kDensity * M_PI * d * d / 4.0;
  add_wall(s, "floor", -0.5, -1e-3, 0.5, -1e-3, 2e-3);
  add_disk(s, 0.0, 0.5 * d - m * 9.81 / s.particle_wall.kn, d, 0.1, 0.0, 0.0);
  set_dt_fraction(s, 50.0);
  System sys(s);
  run_for(sys, 5e-3);  // sliding until t* = 6.8 ms
  const WallList& w = sys.state.lists.walls;
  EXPECT_NEAR(std::abs(sys.state.p.fx[0]), s.particle_wall.friction * w.fn[0], 1e-12 * w.fn[0]);
  EXPECT_LT(sys.state.p.fx[0], 0.0);  // against the motion
}

}  // namespace
}  // namespace dem2d::test
