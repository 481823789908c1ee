// The term contract (sim/contact/law_terms.hpp), proven on a term the engine
// does not have: this program's engine is built with InnerPull added to the
// law's list (inner_pull.hpp) and no other edit. The stability limit, the
// energy ledger and the run file's friction load must be right for it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "contact/stability.hpp"
#include "engine/energy_ledger.hpp"
#include "io/run_file.hpp"
#include "io/run_reader.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

constexpr double kKn = 1.92e6;   // N/m
constexpr double kKa = 0.5 * kKn;  // N/m: the pull halves the normal stiffness

ContactLaw pulled(ContactLaw law) {
  law.inner_pull = kKa;
  return law;
}

// Undamped normal springs of stiffness k on the hexagonal crystal:
// dt <= 2 / sqrt(6 k / m) (contact/stability.hpp).
TEST(ExtraTerm, StabilityLimitFollowsItsStiffness) {
  ContactLaw law;
  law.kn = kKn;
  const double d = 3e-3, m = kDensity * M_PI * d * d / 4.0;
  const StabilityLimit plain = stability_limit(law, 0, kDensity, d);
  EXPECT_NEAR(plain.dt, 2.0 / std::sqrt(6.0 * kKn / m), 1e-6 * plain.dt);
  const StabilityLimit soft = stability_limit(pulled(law), effect::inner_pull, kDensity, d);
  EXPECT_NEAR(soft.dt, 2.0 / std::sqrt(6.0 * (kKn - kKa) / m), 1e-6 * soft.dt);
  EXPECT_NEAR(soft.dt / plain.dt, std::sqrt(2.0), 1e-6);
  // without its effect the term is not there, whatever its parameter
  EXPECT_EQ(stability_limit(pulled(law), 0, kDensity, d).dt, plain.dt);
}

// Two grains meet head-on without damping: what the contact stores is
// 1/2 (k_n - k_a) overlap^2, so kinetic plus stored energy is conserved and
// the ledger's integration error stays small. Were the term's energy left
// out, the stored energy would be counted twice as large and the error would
// reach the whole kinetic energy at the deepest overlap.
TEST(ExtraTerm, EnergyLedgerCountsItsEnergy) {
  Scene s = glass_scene(effect::inner_pull, kKn);
  s.particle_particle = pulled(s.particle_particle);
  const double d = 3e-3, v = 0.1;  // m, m/s
  add_disk(s, -0.51 * d, 0.0, d, v);
  add_disk(s, 0.51 * d, 0.0, d, -v);
  s.output.energy_balance = true;
  set_dt_fraction(s, 50.0);
  System sys(s);
  const double kinetic0 = energy::balance(sys).kinetic;
  double deepest = 0.0, stored_at_deepest = 0.0, worst_error = 0.0, worst_damping = 0.0;
  for (int k = 0; k < 400; ++k) {
    sys.advance(1);
    const EnergyBalance b = energy::balance(sys);
    worst_error = std::max(worst_error, std::abs(b.integration_error));
    worst_damping = std::max(worst_damping, std::abs(b.normal_damping));
    const double overlap = d - (sys.state.p.x[1] - sys.state.p.x[0]);
    if (overlap > deepest) deepest = overlap, stored_at_deepest = b.elastic_normal;
  }
  const double m_eff = 0.5 * kDensity * M_PI * d * d / 4.0;
  EXPECT_NEAR(deepest, 2.0 * v * std::sqrt(m_eff / (kKn - kKa)), 0.01 * deepest);  // the softened spring
  EXPECT_NEAR(stored_at_deepest, 0.5 * (kKn - kKa) * deepest * deepest, 1e-12 * kinetic0);
  EXPECT_NEAR(stored_at_deepest, kinetic0, 0.01 * kinetic0);
  EXPECT_LT(worst_error, 1e-3 * kinetic0);
  EXPECT_LT(worst_damping, 1e-12 * kinetic0);  // no dashpot: the ledger finds none
  EXPECT_NEAR(energy::balance(sys).kinetic, kinetic0, 1e-3 * kinetic0);  // they parted elastically
}

// A grain resting on a floor that moves sideways slides on it: its friction
// sits on the cap mu times the load k_n overlap, not mu F_n = mu (k_n - k_a)
// overlap. The run file's mu_star = |F_t| / (mu load) is then 1 and the
// contact is flagged sliding; with F_n as the load mu_star would read 2.
TEST(ExtraTerm, RunFileFrictionLoadIncludesItsPull) {
  Scene s = glass_scene(effect::gravity | effect::friction | effect::walls | effect::moving_bodies | effect::inner_pull, kKn);
  s.particle_wall = pulled(s.particle_wall);
  const double d = 3e-3, m = kDensity * M_PI * d * d / 4.0;
  const double rest = m * 9.81 / (kKn - kKa);  // overlap at rest (m)
  add_disk(s, 0.0, 0.5 * d - rest, d);
  add_wall(s, "floor", -0.05, -1e-3, 0.05, -1e-3, 2e-3, 0.05);  // face at y = 0, moving at 5 cm/s
  set_dt_fraction(s, 50.0);
  System sys(s);
  const TempDir dir("extra_term");
  RunRecorder rec(sys, dir.path().string());
  for (int k = 0; k < 5; ++k) {
    run_for(sys, 2e-4);
    rec.record_snapshot(sys);
  }
  const std::string out = (dir.path() / "run.h5").string();
  RunInfo info;
  info.scene = &s;
  rec.finish(sys, info, out, "duration");
  const RunReader run(out);
  const std::vector<double> mu_star = read_rows<double>(run.file(), "contacts/mu_star", 0, 5);
  for (std::size_t k = 0; k < run.snapshots(); ++k) {
    const Contacts c = run.snapshot(k).contacts;
    ASSERT_EQ(c.size(), 1u) << "snapshot " << k;
    const double load = c.fn[0] + kKa * c.overlap[0];
    EXPECT_NEAR(std::abs(c.ft[0]), 0.5 * load, 1e-9 * load) << "snapshot " << k << ": on the cap mu k_n overlap";
    EXPECT_NEAR(mu_star[k], 1.0, 1e-9) << "snapshot " << k;
    EXPECT_EQ(c.sliding[0], 1) << "snapshot " << k;
  }
}

}  // namespace
}  // namespace dem2d::test
