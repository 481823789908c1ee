// Hard cases stay numerically stable: each ends with a finite state, bounded
// energy and no lost grain unless the case expects one.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/diagnostics.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

bool all_finite(const System& sys) {
  for (const auto* a : {&sys.state.p.x, &sys.state.p.y, &sys.state.p.vx, &sys.state.p.vy, &sys.state.p.omega, &sys.state.p.fx, &sys.state.p.fy, &sys.state.p.torque})
    for (const double v : *a)
      if (!std::isfinite(v)) return false;
  return true;
}

double total_energy(const System& sys) { return kinetic_energy(sys) + elastic_energy(sys) + gravity_energy(sys); }

// dt at 0.9 of the bound the scene parser enforces, the dense packing's
// stability limit (0.577 dt_c for this law, dt_c = sqrt(m_min/k_n)):
// a settled, frictional pile stays put and does not gain energy.
TEST(HardCases, TimeStepAtNineTenthsOfTheBound) {
  Scene s = boxed_bed(kFull, 150, 0.03);
  System bed(s);
  run_for(bed, 0.4);
  Scene hard = with_state(s, bed);
  hard.dt = 0.9 * hard.stability_limit().dt;
  System sys(hard);
  const double e0 = total_energy(sys);
  run_for(sys, 0.2);
  EXPECT_TRUE(all_finite(sys));
  EXPECT_LE(total_energy(sys), e0 + 1e-9);
  EXPECT_LT(max_overlap(sys), 0.02 * 2e-3);
  EXPECT_TRUE(sys.state.lost.empty());
}

// Two disks created half overlapped fly apart; the kinetic energy they end
// with cannot exceed the elastic energy they started with.
// Runs an overlapping pair for 10 ms: it must end finite, apart, and with no
// more kinetic energy than the elastic energy it started with (returned).
double expect_flies_apart(System& sys) {
  const double e0 = elastic_energy(sys);
  run_for(sys, 0.01);
  EXPECT_TRUE(all_finite(sys));
  EXPECT_EQ(contact_count(sys), 0u);
  EXPECT_LE(kinetic_energy(sys), e0);
  return e0;
}

TEST(HardCases, TwoDisksHalfOverlapped) {
  Scene s = glass_scene(effect::normal_damping | effect::friction | effect::rolling_resistance);
  add_disk(s, 0.0, 0.0, 3e-3);
  add_disk(s, 1.5e-3, 0.0, 3e-3);  // overlap 1.5 mm = 50 % of d
  set_dt_fraction(s, 20.0);
  System sys(s);
  const double e0 = expect_flies_apart(sys);
  EXPECT_GT(kinetic_energy(sys), 0.5 * e0);  // e = 0.9: most of it comes back
  EXPECT_LT(sys.state.p.vx[0], 0.0);
  EXPECT_GT(sys.state.p.vx[1], 0.0);
}

// Coincident centres: the normal is undefined; the pair is separated along x.
TEST(HardCases, CoincidentCentres) {
  Scene s = glass_scene(effect::normal_damping | effect::friction);
  add_disk(s, 0.0, 0.0, 3e-3);
  add_disk(s, 0.0, 0.0, 2e-3);
  set_dt_fraction(s, 20.0);
  System sys(s);
  expect_flies_apart(sys);
  EXPECT_LT(sys.state.p.vx[1] * sys.state.p.vx[0], 0.0);  // moving apart
  EXPECT_EQ(sys.state.p.vy[0], 0.0);
}

// A zero-length sphero-line is a point obstacle (its caps coincide): a disk
// dropped on it slightly off-centre rolls off and falls past it.
TEST(HardCases, ZeroLengthSpheroLine) {
  Scene s = glass_scene(kFull);
  add_wall(s, "point", 0.0, 0.0, 0.0, 0.0, 1e-3);
  add_disk(s, 2e-4, 3e-3, 3e-3);
  set_dt_fraction(s, 20.0);
  System sys(s);
  bool touched = false;
  for (int k = 0; k < 2000 && sys.state.p.y[0] > -0.01; ++k) {
    sys.advance(20);
    touched |= sys.state.lists.walls.slots() > 0 && sys.state.lists.walls.overlap[0] > 0.0;
  }
  EXPECT_TRUE(touched);
  EXPECT_TRUE(all_finite(sys));
  EXPECT_LT(sys.state.p.y[0], -0.01);  // it fell past
  EXPECT_GT(sys.state.p.x[0], 0.0);    // on the side it was offset to
}

// A disk on the floor between a wall and the round end of a bar driven
// towards the wall, the bar's axis 0.4 mm below the disk's centre: the cap
// pushes 9 degrees above horizontal.
Scene squeeze_scene(EffectSet effects) {
  Scene s = glass_scene(effects | effect::walls | effect::moving_bodies);
  const double d = 3e-3;
  add_wall(s, "floor", -0.02, -1e-3, 0.02, -1e-3);
  add_wall(s, "wall", 0.01 + 1e-3, -1e-3, 0.01 + 1e-3, 0.02);
  add_wall(s, "bar", -0.01, 0.5 * d - 4e-4, 0.01 - d - 1.5e-3, 0.5 * d - 4e-4, 2e-3, 0.02, 0.0);
  add_disk(s, 0.01 - 0.5 * d, 0.5 * d, d);
  set_dt_fraction(s, 20.0);
  return s;
}

// Without friction the wedge cannot hold: the disk is squeezed out upwards
// and the overlaps stay small.
TEST(HardCases, DiskSqueezedOutBetweenIntruderCapAndWall) {
  System sys(squeeze_scene(effect::gravity | effect::normal_damping));
  const double d = 3e-3;
  double worst = 0.0;
  while (sys.state.bodies.shape[2].vertex(1).x + 1e-3 < 0.01 - 0.3 * d) {  // until the gap is 0.3 d
    sys.advance(10);
    worst = std::max(worst, max_overlap(sys));
  }
  EXPECT_TRUE(all_finite(sys));
  EXPECT_GT(sys.state.p.y[0], 0.5 * d + 1e-3);  // pushed up and over the bar
  EXPECT_LT(worst, 0.02 * d);
  EXPECT_TRUE(sys.state.lost.empty());
}

// With mu = 0.5 (friction angle 26.6 degrees > 9) the wedge locks: the
// kinematic bar crushes the disk. The state stays finite and quiet, and the
// overlaps take up exactly the closure of the gap.
TEST(HardCases, DiskJammedBetweenIntruderCapAndWall) {
  System sys(squeeze_scene(effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance));
  const double d = 3e-3;
  while (sys.state.bodies.shape[2].vertex(1).x + 1e-3 < 0.01 - 0.5 * d) {  // until the gap is half a diameter
    sys.advance(10);
    ASSERT_TRUE(all_finite(sys)) << "t = " << sys.time();
    ASSERT_LT(kinetic_energy(sys), 1e-5) << "t = " << sys.time();  // J/m: never launched
  }
  EXPECT_NEAR(sys.state.p.y[0], 0.5 * d, 0.05 * d);  // still wedged in place
  // cap-disk + disk-wall overlaps ~ how far the cap has gone past touching
  double wedge = 0.0;
  for (std::size_t s = 0; s < sys.state.lists.walls.slots(); ++s)
    if (sys.state.lists.walls.body[s] != 0) wedge += sys.state.lists.walls.overlap[s];
  EXPECT_GT(wedge, 0.4 * d);
  EXPECT_TRUE(sys.state.lost.empty());
}

// Stiffness from 1e3 to 1e10 N/m with dt = dt_c/20: a small bed (three rows,
// so that even at 1e3 N/m, where grains overlap by a third of d, they cannot
// be pushed through the 2 mm walls) is stable at every stiffness and never
// gains energy.
TEST(HardCases, StiffnessFrom1e3To1e10) {
  for (double kn = 1e3; kn <= 1e10 * 1.0001; kn *= 10.0) {
    Scene s = boxed_bed(kFull, 20, 0.03, kn);
    System sys(s);
    const double e0 = total_energy(sys);
    sys.advance(20000);
    EXPECT_TRUE(all_finite(sys)) << "kn = " << kn;
    EXPECT_LE(total_energy(sys), e0 + 1e-12) << "kn = " << kn;
    EXPECT_TRUE(sys.state.lost.empty()) << "kn = " << kn;
    EXPECT_LT(max_overlap(sys), 0.5 * 2e-3) << "kn = " << kn;  // grains never pass through each other
  }
}

// A grain thrown out of the domain is removed and reported; the others carry on.
TEST(HardCases, DiskLeavingTheDomainIsReported) {
  Scene s = boxed_bed(kFull, 30, 0.02);
  s.particles[29].vy = 5.0;  // m/s upwards, out of the open top
  System sys(s);
  run_for(sys, 0.2);
  ASSERT_EQ(sys.state.lost.size(), 1u);
  EXPECT_EQ(sys.state.lost[0].id, 29);
  EXPECT_GT(sys.state.lost[0].y, s.domain.ymax);
  EXPECT_EQ(sys.state.p.active[29], 0);
  EXPECT_TRUE(all_finite(sys));
  for (std::size_t i = 0; i + 1 < sys.size(); ++i) EXPECT_EQ(sys.state.p.active[i], 1);
}

// A non-finite state is an error naming the grain, not a run that writes NaN.
// (An unstable time step does not get here: grains are thrown out of the
// domain first and reported as lost.)
TEST(HardCases, NonFiniteStateIsAnError) {
  Scene s = boxed_bed(kFull, 30, 0.02);
  s.particles[7].vx = std::nan("");
  try {
    System sys(s);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("particle 7 has a non-finite state"), std::string::npos) << e.what();
  }
  s.particles[7].vx = 0.0;
  System sys(s);
  sys.advance(10);
  sys.state.p.omega[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(sys.advance(10), std::runtime_error);
}

}  // namespace
}  // namespace dem2d::test
