// Long runs (seconds each in an optimised build; not run under sanitizers).
#include <gtest/gtest.h>

#include <cmath>

#include "engine/diagnostics.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// The paper's stiffness and time step (k_n = 1.92e8 N/m, dt = 1e-7 s, about
// dt_c/64): a pile poured and settled with them stays at rest. Over the 0.1 s
// after settling no grain drifts by more than 1e-4 d, and the kinetic energy
// falls window after window until it reaches the round-off floor. (The
// envelope: the largest of 100 samples in each window, since the energy of a
// ringing bed swaps between kinetic and elastic within a window.)
// (Pouring at a softer stiffness and switching would not do: the same
// overlaps store 100x the energy at the stiffer law and blow the pile apart.)
TEST(LongRuns, SettledPileAtPaperStiffnessStaysAtRest) {
  Scene s = boxed_bed(kFull, 40, 0.02, 1.92e8);
  s.dt = 1e-7;
  ASSERT_LT(s.dt, s.critical_dt() / 60.0);
  System sys(s);
  run_for(sys, 0.25);  // fall and settle: 2.5e6 steps

  const AlignedVector<double> x0 = sys.state.p.x, y0 = sys.state.p.y;
  constexpr double kRoundOffFloor = 1e-17;  // J/m: grains of ~10 g/m at ~1e-8 m/s
  auto envelope = [&sys] {
    double ke = 0.0;
    for (int k = 0; k < 100; ++k) {
      run_for(sys, 1e-4);
      ke = std::max(ke, kinetic_energy(sys));
    }
    return ke;
  };
  const double ke_start = envelope();
  double ke_prev = ke_start;
  for (int w = 0; w < 9; ++w) {
    const double ke = envelope();
    if (ke_prev > kRoundOffFloor) {
      EXPECT_LT(ke, ke_prev) << "window " << w;
    }
    ke_prev = ke;
  }
  double drift = 0.0;
  for (std::size_t i = 0; i < sys.size(); ++i) drift = std::max(drift, std::hypot(sys.state.p.x[i] - x0[i], sys.state.p.y[i] - y0[i]));
  EXPECT_LT(drift, 1e-4 * kMeanD);
  EXPECT_LT(ke_prev, 1e-4 * ke_start + kRoundOffFloor);
  EXPECT_LT(max_overlap(sys), 1e-3 * kMeanD);  // paper stiffness: overlaps ~ 1e-8 m
  std::printf("pile at paper stiffness: drift %.3g m, kinetic energy %.3g -> %.3g J/m, max overlap %.3g m\n",
              drift, ke_start, ke_prev, max_overlap(sys));
}

// 1e6 steps of a dense frictional packing, poured and then left: no NaN, no
// lost grain, energy bounded by its initial value.
TEST(LongRuns, MillionStepsOfDensePackingStayFinite) {
  Scene s = boxed_bed(kFull, 100, 0.025);
  System sys(s);
  const double e0 = kinetic_energy(sys) + elastic_energy(sys) + gravity_energy(sys);
  for (int k = 0; k < 100; ++k) {
    sys.advance(10000);
    ASSERT_TRUE(std::isfinite(kinetic_energy(sys))) << "step " << sys.state.step;
  }
  EXPECT_EQ(sys.state.step, 1000000);
  EXPECT_TRUE(sys.state.lost.empty());
  EXPECT_LE(kinetic_energy(sys) + elastic_energy(sys) + gravity_energy(sys), e0);
  for (std::size_t i = 0; i < sys.size(); ++i) {
    ASSERT_TRUE(std::isfinite(sys.state.p.x[i]) && std::isfinite(sys.state.p.vx[i]) && std::isfinite(sys.state.p.omega[i]));
  }
}

}  // namespace
}  // namespace dem2d::test
