// Tangential friction and rolling resistance: analytic sliding-to-rolling
// transition, and the Coulomb and rolling caps in a sheared dense packing.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/contact_law.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// A disk launched sliding without spin on a flat wall: friction mu m g slows
// it and spins it up until v = omega r. With I = m d^2/8 = m r^2/2 that is
// v = v0 / (1 + I/(m r^2)) = 2/3 v0, reached at t* = v0 / (3 mu g).
TEST(Friction, SlidingDiskEndsRollingAtTwoThirds) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::walls);
  const double d = 3e-3, v0 = 0.1, mu = s.particle_wall.friction, g = 9.81;
  add_wall(s, "floor", -0.5, -1e-3, 0.5, -1e-3, 2e-3);
  const double m = kDensity * M_PI * d * d / 4.0;
  const double rest = m * g / s.particle_wall.kn;  // static overlap (m)
  add_disk(s, 0.0, 0.5 * d - rest, d, v0, 0.0, 0.0);
  set_dt_fraction(s, 50.0);
  System sys(s);

  const double t_star = v0 / (3.0 * mu * g);
  double t_stick = -1.0;
  while (sys.time() < 2.0 * t_star) {
    sys.advance(1);
    const WallList& w = sys.state.lists.walls;
    ASSERT_EQ(w.slots(), 1u);
    if (t_stick < 0.0 && w.fn[0] > 0.0 && std::abs(w.ft[0]) < mu * w.fn[0]) t_stick = sys.time();
  }
  ASSERT_GT(t_stick, 0.0);
  EXPECT_NEAR(t_stick / t_star, 1.0, 0.01);

  // once rolling, the tangential spring rings; average v over 2 ms (many periods)
  double v_sum = 0.0, w_sum = 0.0;
  const int n = static_cast<int>(2e-3 / sys.config.dt);
  for (int k = 0; k < n; ++k) {
    sys.advance(1);
    v_sum += sys.state.p.vx[0];
    w_sum += sys.state.p.omega[0];
  }
  EXPECT_NEAR(v_sum / n / v0, 2.0 / 3.0, 0.01 * 2.0 / 3.0);
  EXPECT_NEAR(-w_sum / n * 0.5 * d / (v_sum / n), 1.0, 0.01);  // rolls: v = -omega r
}

// A sheared, compressed packing: every contact of every step obeys
// |F_t| <= mu F_n and |M_r| <= mu_r F_n (to round-off), and both caps are
// actually reached somewhere, so the test can fail.
TEST(Friction, CoulombAndRollingCapsHoldInShearedPacking) {
  const EffectSet full = effect::gravity | effect::normal_damping | effect::friction |
                         effect::rolling_resistance | effect::walls;
  Scene s = boxed_bed(full, 150, 0.03);
  System bed(s);
  run_for(bed, 0.5);  // settle

  // a lid on the top grains, pressing down and moving sideways: shear + compression
  double top = 0.0;
  for (std::size_t i = 0; i < bed.size(); ++i) top = std::max(top, bed.state.p.y[i] + bed.state.p.radius[i]);
  Scene sh = with_state(s, bed);
  sh.effects |= effect::moving_bodies;
  add_wall(sh, "lid", 0.0, top + 0.9e-3, 0.03, top + 0.9e-3, 2e-3, 0.05, -0.05);
  System sys(sh);

  const ContactLaw pp = sys.config.law_pp, pw = sys.config.law_pw;
  std::size_t sliding = 0, rolling_capped = 0, checked = 0;
  auto check_list = [&](const auto& L, const ContactLaw& law) {
    for (std::size_t k = 0; k < L.slots(); ++k) {
      if (L.overlap[k] <= 0.0) continue;
      ++checked;
      const double cap_t = law.friction * L.fn[k], cap_r = law.rolling_friction * L.fn[k];
      ASSERT_LE(std::abs(L.ft[k]), cap_t * (1.0 + 1e-14)) << "step " << sys.state.step;
      ASSERT_LE(std::abs(L.mr[k]), cap_r * (1.0 + 1e-14)) << "step " << sys.state.step;
      sliding += is_sliding(L.fn[k], L.ft[k], law.friction);
      rolling_capped += L.fn[k] > 0.0 && std::abs(L.mr[k]) >= cap_r;
    }
  };
  const int steps = static_cast<int>(0.02 / sys.config.dt);
  for (int k = 0; k < steps; ++k) {
    sys.advance(1);
    check_list(sys.state.lists.pairs, pp);
    check_list(sys.state.lists.walls, pw);
  }
  EXPECT_GT(checked, 100000u);
  EXPECT_GT(sliding, 100u);
  EXPECT_GT(rolling_capped, 100u);
}

}  // namespace
}  // namespace dem2d::test
