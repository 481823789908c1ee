// The generic kernel (every term compiled in, the scene's effects tested at
// run time) against the kernels specialised for a set: the same arithmetic
// for the effects a scene names and none for the others, so the same state
// bit for bit; and a set no line of sim/engine/kernel_sets.inc declares runs.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include "engine/kernel_sets.hpp"
#include "engine/system.hpp"
#include "scene_builder.hpp"

namespace dem2d {
namespace {

using test::add_wall;
using test::boxed_bed;

constexpr EffectSet kStudy = effect::gravity | effect::normal_damping | effect::friction |
                             effect::rolling_resistance | effect::walls | effect::moving_bodies;

// 60 grains in a 2 cm box, thrown about (+-0.3 m/s, so that sets without
// gravity collide too), a bar pulled up through them, a paddle turning about
// a pivot where the set has rotating bodies; cohesive where it has cohesion.
Scene stirred(EffectSet effects) {
  Scene s = boxed_bed(effects, 60, 0.02);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> v(-0.3, 0.3);
  for (ParticleInit& p : s.particles) p.vx = v(rng), p.vy = v(rng);
  if (has(effects, effect::moving_bodies)) add_wall(s, "intruder", 0.006, 0.008, 0.014, 0.008, 2e-3, 0.0, 0.05);
  if (has(effects, effect::rotating_bodies)) {
    add_wall(s, "paddle", 0.004, 0.02, 0.012, 0.02, 1e-3);
    s.bodies.back().pivot = Point{0.008, 0.02};
    s.bodies.back().motion = {{MotionKind::constant, 1.0, 0.0, 0.0, 20.0}};  // 20 rad/s
  }
  if (has(effects, effect::cohesion))
    for (ContactLaw* law : {&s.particle_particle, &s.particle_wall}) {
      law->cohesion_force = 2.0;     // N/m: several grain weights
      law->cohesion_range = 1e-4;    // m
    }
  s.output.energy_balance = true;  // the ledger reads the same contacts on both kernels
  return s;
}

System advanced(Scene s, bool generic, std::int64_t steps) {
  s.generic_kernel = generic;
  System sys(s);
  sys.advance(steps);
  return sys;
}

template <class V>
bool same_bits(const V& a, const V& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

void expect_same_state(const System& a, const System& b) {
  const Particles &p = a.state.p, &q = b.state.p;
  EXPECT_TRUE(same_bits(p.x, q.x) && same_bits(p.y, q.y)) << "positions";
  EXPECT_TRUE(same_bits(p.vx, q.vx) && same_bits(p.vy, q.vy)) << "velocities";
  EXPECT_TRUE(same_bits(p.omega, q.omega) && same_bits(p.theta, q.theta)) << "spins";
  EXPECT_TRUE(same_bits(p.fx, q.fx) && same_bits(p.fy, q.fy) && same_bits(p.torque, q.torque)) << "forces";
  const PairList &l = a.state.lists.pairs, &m = b.state.lists.pairs;
  EXPECT_TRUE(same_bits(l.ft, m.ft) && same_bits(l.mr, m.mr) && same_bits(l.fn, m.fn)) << "pair springs";
  const WallList &w = a.state.lists.walls, &u = b.state.lists.walls;
  EXPECT_TRUE(same_bits(w.ft, u.ft) && same_bits(w.mr, u.mr) && same_bits(w.fn, u.fn)) << "wall springs";
  EXPECT_TRUE(same_bits(a.state.bodies.fy, b.state.bodies.fy)) << "body forces";
  const auto ea = accumulators(a.state.energy), eb = accumulators(b.state.energy);
  for (std::size_t k = 0; k < ea.size(); ++k) EXPECT_TRUE(same_bits(*ea[k].second, *eb[k].second)) << ea[k].first;
}

// Declared sets that switch every effect both on and off: each on its
// specialised kernel and on the generic one, 4000 steps (~200 collisions a
// grain), the same bits.
TEST(GenericKernel, SameBitsAsEverySpecialisedKernel) {
  const EffectSet sets[] = {
      kStudy,
      kStudy | effect::tangential_damping | effect::rolling_damping,
      (kStudy & ~effect::moving_bodies) | effect::cohesion,
      kStudy | effect::rotating_bodies,
      effect::gravity | effect::normal_damping | effect::walls | effect::moving_bodies,
      effect::walls,
  };
  ASSERT_TRUE(kernels_specialised(kStudy));
  for (const EffectSet e : sets) {
    SCOPED_TRACE(effect_names(e));
    if (!kernels_specialised(e)) continue;  // a build with fewer sets (the ASan+UBSan build's two)
    const System specialised = advanced(stirred(e), false, 4000), generic = advanced(stirred(e), true, 4000);
    ASSERT_GT(specialised.state.lists.pairs.slots(), 0u);
    expect_same_state(specialised, generic);
  }
}

// Sets no line declares (a LAMMPS user's paddle without rolling resistance or
// damping, a cohesive drum, cohesive grains without friction) run on the
// generic kernel; dropping an effect that the scene's coefficients already
// switch off (e = 1: no normal damping) changes nothing.
TEST(GenericKernel, UndeclaredSetsRun) {
  const EffectSet paddle = effect::gravity | effect::friction | effect::walls | effect::moving_bodies;
  const EffectSet drum = kStudy | effect::rotating_bodies | effect::cohesion;
  const EffectSet sticky = effect::gravity | effect::normal_damping | effect::walls | effect::cohesion;
  for (const EffectSet e : {paddle, drum, sticky}) {
    SCOPED_TRACE(effect_names(e));
    ASSERT_FALSE(kernels_specialised(e));
    const System sys = advanced(stirred(e), false, 4000);
    EXPECT_EQ(sys.state.step, 4000);
    EXPECT_TRUE(sys.failure.empty()) << sys.failure;
    EXPECT_TRUE(sys.state.lost.empty());
  }
  // the study's set with e = 1 against the same set without normal_damping (undeclared)
  Scene elastic = stirred(kStudy);
  elastic.particle_particle.restitution = elastic.particle_wall.restitution = 1.0;
  Scene undamped = elastic;
  undamped.effects &= ~effect::normal_damping;
  ASSERT_FALSE(kernels_specialised(undamped.effects));
  const System a = advanced(elastic, false, 4000), b = advanced(undamped, false, 4000);
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max({worst, std::abs(a.state.p.x[i] - b.state.p.x[i]), std::abs(a.state.p.y[i] - b.state.p.y[i])});
  EXPECT_LT(worst, 1e-12) << "m: the zero dashpot and the absent one part";
}

}  // namespace
}  // namespace dem2d
