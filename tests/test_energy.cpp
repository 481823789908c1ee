// Energy: velocity Verlet with undamped, frictionless linear springs
// conserves the total energy of a dense packing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/diagnostics.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// A jammed packing: a closed frictionless box filled by a triangular lattice
// compressed by ~0.5 % of d (about 1750 contacts for 590 grains), no
// gravity, random velocities of up to 5 cm/s, so the grains vibrate in
// persistent contacts. 1e5 steps at dt = dt_c/20. The drift is the change of
// the mean energy between the first and the last 1000 steps; velocity
// Verlet's bounded O(dt^2) oscillation around its shadow energy is the
// largest instantaneous deviation, bounded separately.
TEST(Energy, UndampedFrictionlessDensePackingConserves) {
  Scene s = glass_scene(effect::walls);
  crystal_in_box(s, 30, 20, 2.985e-3, 2.995e-3, 3.005e-3, 0.05);  // lattice pitch < d: compressed
  set_dt_fraction(s, 20.0);
  System sys(s);
  ASSERT_GT(contact_count(sys), 2 * s.particles.size());  // dense: > 2 contacts per grain

  auto energy = [&] { return kinetic_energy(sys) + elastic_energy(sys); };
  const double e0 = energy();
  auto window_mean = [&] {
    double sum = 0.0;
    for (int k = 0; k < 1000; ++k) {
      sys.advance(1);
      sum += energy();
    }
    return sum / 1000.0;
  };
  const double first = window_mean();
  double max_dev = 0.0;
  for (int k = 0; k < 98; ++k) {
    sys.advance(1000);
    max_dev = std::max(max_dev, std::abs(energy() - e0) / e0);
  }
  const double last = window_mean();
  const double drift = std::abs(last - first) / e0;
  EXPECT_EQ(sys.state.step, 100000);
  EXPECT_LT(drift, 1e-4);
  EXPECT_LT(max_dev, 1e-3);
  EXPECT_GT(kinetic_energy(sys), 0.02 * e0);  // it really is vibrating
  std::printf("energy: drift %.3e, max deviation %.3e (relative), %zu contacts\n", drift, max_dev,
              contact_count(sys));
}

}  // namespace
}  // namespace dem2d::test
