// The energy ledger (engine/energy_ledger.hpp): on a frictional, damped run
// with every effect, moving and removed bodies and a lost grain, its terms
// add up to a constant to round-off; each dissipation term is what the
// physics says it is; the integration error vanishes as dt^2; the ledger is
// the same for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "engine/diagnostics.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// 120 grains poured into a box (every effect but cohesion, which the ledger does not count yet, and
// turning bodies: ClosesInATurningDrum; the dashpots at nu = 0.2), a
// paddle stirring them, a support removed while loaded, one grain thrown out
// of the domain.
Scene stirred(int threads) {
  Scene s = boxed_bed(kFullMoving, 120, 0.025);
  for (ContactLaw* l : {&s.particle_particle, &s.particle_wall}) l->tangential_damping_ratio = l->rolling_damping_ratio = 0.2;
  add_wall(s, "paddle", -0.004, 0.006, 0.0, 0.006, 2e-3, 0.1, 0.0);
  add_wall(s, "support", 0.0126, 0.0, 0.0126, 0.012, 0.2e-3);
  s.bodies.back().remove_at = 0.08;  // (removed by the test, as the run driver does)
  s.particles[119].vy = 3.0;         // m/s: leaves through the open top
  s.output.energy_balance = true;
  s.threads = threads;
  return s;
}

// The ledger every 2 ms for 0.15 s (the support removed at 0.08 s).
std::vector<EnergyBalance> ledger_of(const Scene& s) {
  System sys(s);
  std::vector<EnergyBalance> out{energy::balance(sys)};
  for (int k = 1; k <= 75; ++k) {
    run_for(sys, 2e-3);
    if (k == 40) sys.remove_body(sys.body_index("support"));
    out.push_back(energy::balance(sys));
  }
  EXPECT_EQ(sys.state.lost.size(), 1u);
  return out;
}

TEST(EnergyLedger, ClosesToRoundOffOnAFrictionalDampedRun) {
  const std::vector<EnergyBalance> rows = ledger_of(stirred(1));
  double scale = 0.0, worst = 0.0;
  for (const EnergyBalance& b : rows)
    for (const auto& [name, v] : b.terms()) scale = std::max(scale, std::abs(v));
  for (const EnergyBalance& b : rows) worst = std::max(worst, std::abs(b.total() - rows.front().total()));
  const EnergyBalance& end = rows.back();
  std::printf("ledger at 0.15 s (J/m):");
  for (const auto& [name, v] : end.terms()) std::printf(" %.*s %.4g", static_cast<int>(name.size()), name.data(), v);
  std::printf("; total moved %.3g (largest term %.3g)\n", worst, scale);
  EXPECT_LT(worst, 1e-12 * scale);
  // every term is at work, so the closure is not vacuous
  for (const auto& [name, v] : end.terms()) EXPECT_GT(std::abs(v), 0.0) << name;
  EXPECT_GT(end.body_work, 0.0);  // the paddle pushes
  for (const double d : end.dissipated) EXPECT_GT(d, 0.0);  // (every column of the law's terms)
  EXPECT_EQ(end.dissipated.size(), 5u);
  // the support held grains when it went: their contacts' energy left with it
  EXPECT_GT(end.removed, 0.5 * 0.5 * kDensity * M_PI * 9e-6 / 4.0 * 9.0);  // > half the thrown grain's 1/2 m v^2
  // what the integrator adds or loses is small against what the contacts
  // dissipate (first order in dt with dashpots, which see the half-step
  // velocity: measured 1.2e-3 at dt_c/20, 6e-4 at dt_c/40, 3e-4 at dt_c/80)
  double dissipated = 0.0;
  for (const double d : end.dissipated) dissipated += d;
  EXPECT_LT(std::abs(end.integration_error), 3e-3 * dissipated);
}

// 60 grains in a drum of 12 walls turning at 5 rad/s about its axis: the walls'
// work is the contact forces against the walls' surface velocity, omega x r at
// each contact point; the ledger closes to round-off and the drum feeds it.
TEST(EnergyLedger, ClosesInATurningDrum) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance |
                        effect::walls | effect::moving_bodies | effect::rotating_bodies);
  const int walls = 12;
  const double apothem = 0.016, corner = apothem / std::cos(M_PI / walls);
  for (int k = 0; k < walls; ++k) {
    const double a = 2.0 * M_PI * k / walls - M_PI / walls, b = a + 2.0 * M_PI / walls;
    add_wall(s, "drum_" + std::to_string(k), corner * std::cos(a), corner * std::sin(a), corner * std::cos(b),
             corner * std::sin(b));
    s.bodies.back().pivot = Point{0.0, 0.0};
    s.bodies.back().motion.resize(1);
    s.bodies.back().motion[0] = {MotionKind::constant, std::numeric_limits<double>::infinity(), 0.0, 0.0, 5.0};
  }
  for (int row = 0; row < 14 && s.particles.size() < 60; ++row)  // 2.1 mm apart, clear of the walls (faces at 15 mm)
    for (int col = -7; col <= 7 && s.particles.size() < 60; ++col) {
      const double x = 2.1e-3 * col, y = -0.0135 + 2.1e-3 * row;
      if (std::hypot(x, y) < 0.0135) add_disk(s, x, y, 2e-3 - 1e-5 * static_cast<double>(s.particles.size() % 7));
    }
  ASSERT_EQ(s.particles.size(), 60u);
  s.output.energy_balance = true;
  set_dt_fraction(s, 20.0);
  System sys(s);
  std::vector<EnergyBalance> rows{energy::balance(sys)};
  for (int k = 0; k < 50; ++k) {
    run_for(sys, 4e-3);
    rows.push_back(energy::balance(sys));
  }
  double scale = 0.0, worst = 0.0;
  for (const EnergyBalance& b : rows)
    for (const auto& [name, v] : b.terms()) scale = std::max(scale, std::abs(v));
  for (const EnergyBalance& b : rows) worst = std::max(worst, std::abs(b.total() - rows.front().total()));
  const EnergyBalance& end = rows.back();
  std::printf("drum ledger at 0.2 s (1 rad turned, J/m): kinetic %.4g, gravity %.4g, walls' work %.4g, sliding %.4g, "
              "integration error %.3g; total moved %.3g (largest term %.3g)\n",
              end.kinetic, end.gravity, end.body_work, end.dissipated_in("sliding"), end.integration_error, worst, scale);
  EXPECT_LT(worst, 1e-12 * scale);
  EXPECT_GT(end.body_work, 0.2 * scale);  // the turning walls drag the bed up: a term that counts
  EXPECT_LT(std::abs(end.integration_error), 3e-3 * end.dissipated_in("sliding"));
}

TEST(EnergyLedger, BitwiseTheSameForAnyThreadCount) {
  const std::vector<EnergyBalance> one = ledger_of(stirred(1)), three = ledger_of(stirred(3));
  ASSERT_EQ(one.size(), three.size());
  for (std::size_t k = 0; k < one.size(); ++k)
    EXPECT_EQ(std::memcmp(&one[k], &three[k], sizeof(EnergyBalance)), 0) << "row " << k;
}

// A head-on collision at relative speed 2v dissipates 1/2 m_eff (2v)^2 (1 - e^2).
TEST(EnergyLedger, HeadOnCollisionDissipatesWhatTheRestitutionSays) {
  for (const double e : {0.9, 0.5, 0.1}) {
    Scene s = glass_scene(effect::normal_damping);
    s.particle_particle.restitution = e;
    add_disk(s, -1.6e-3, 0.0, 3e-3, 0.1, 0.0);
    add_disk(s, 1.6e-3, 0.0, 3e-3, -0.1, 0.0);
    s.output.energy_balance = true;
    set_dt_fraction(s, 200.0);
    System sys(s);
    run_for(sys, 2e-3);
    ASSERT_EQ(contact_count(sys), 0u);
    const EnergyBalance b = energy::balance(sys);
    const double meff = 0.5 * sys.state.p.mass[0], expected = 0.5 * meff * 0.04 * (1.0 - e * e);
    EXPECT_NEAR(b.dissipated_in("normal_damping"), expected, 0.01 * expected) << "e = " << e;
    // first order: the dashpot sees the half-step velocity (measured 0.2 % at
    // e = 0.5, 0.9 % at e = 0.1, dt = dt_c/200)
    EXPECT_LT(std::abs(b.integration_error), 2e-2 * expected) << "e = " << e;
  }
}

// A disk launched sliding without spin ends rolling at 2/3 v0: friction has
// then dissipated 1/2 m v0^2 - 3/4 m (2/3 v0)^2 = m v0^2 / 6.
TEST(EnergyLedger, SlideToRollDissipatesASixthOfMV0Squared) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::walls);
  const double d = 3e-3, v0 = 0.1, m = kDensity * M_PI * d * d / 4.0;
  add_wall(s, "floor", -0.5, -1e-3, 0.5, -1e-3, 2e-3);
  add_disk(s, 0.0, 0.5 * d - m * 9.81 / s.particle_wall.kn, d, v0, 0.0, 0.0);
  s.output.energy_balance = true;
  set_dt_fraction(s, 50.0);
  System sys(s);
  run_for(sys, 2.0 * v0 / (3.0 * 0.5 * 9.81));
  const EnergyBalance b = energy::balance(sys);
  EXPECT_NEAR(b.dissipated_in("sliding"), m * v0 * v0 / 6.0, 0.01 * m * v0 * v0 / 6.0);
  EXPECT_LT(std::abs(b.dissipated_in("normal_damping")), 1e-3 * b.dissipated_in("sliding"));
  EXPECT_LT(std::abs(b.integration_error), 1e-3 * b.dissipated_in("sliding"));
}

// An elastic gas (undamped, frictionless, dense and vibrating): its only
// loss is the integrator's, which falls as dt^2.
double elastic_gas_error(double divisor) {
  Scene s = glass_scene(effect::walls);
  crystal_in_box(s, 16, 12, 2.985e-3, 2.995e-3, 3.005e-3, 0.05);
  s.output.energy_balance = true;
  set_dt_fraction(s, divisor);
  System sys(s);
  double worst = 0.0, e0 = 0.0;
  for (int k = 0; k < 100; ++k) {
    run_for(sys, 2e-4);
    const EnergyBalance b = energy::balance(sys);
    worst = std::max(worst, std::abs(b.integration_error));
    e0 = std::max(e0, b.kinetic);
  }
  return worst / e0;
}

// The largest error over a run picks an oscillation's phase: one ratio of
// two dt scatters (2.9 to 4.9 over three seeds); the slope over four dt is 2.
TEST(EnergyLedger, IntegrationErrorOfAnElasticGasIsSecondOrder) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  const double divisors[] = {20.0, 40.0, 80.0, 160.0};
  for (const double divisor : divisors) {
    const double x = std::log(1.0 / divisor), y = std::log(elastic_gas_error(divisor));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = 4.0, order = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  const double coarse = elastic_gas_error(20.0);
  std::printf("elastic gas: integration error %.3g of the kinetic energy at dt_c/20, order %.2f over dt_c/20-/160\n",
              coarse, order);
  EXPECT_NEAR(order, 2.0, 0.15);
  EXPECT_LT(coarse, 1e-3);
}

}  // namespace
}  // namespace dem2d::test
