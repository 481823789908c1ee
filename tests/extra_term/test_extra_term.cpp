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
#include "runfile/run_reader.hpp"
#include "writer/run_file.hpp"
#include "writer/run_file_describe.hpp"
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
    worst_damping = std::max(worst_damping, std::abs(b.dissipated_in("normal_damping")));
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

// Its dashpot c_a dissipates into its own column of the ledger. Without the
// normal dashpot the contact is a linear spring k' = k_n - k_a with a
// dashpot c_a that may pull, so two grains meeting head-on part when the
// overlap is back at 0, after half a damped period: restitution
// e = exp(-zeta pi / sqrt(1 - zeta^2)), zeta = c_a / (2 sqrt(m_eff k')).
// What the collision took, (1 - e^2) of the kinetic energy, is in
// inner_pull_damping, none of it in normal_damping, up to the ledger's
// integration error, which for dashpots is first order in dt
// (docs/energy.md); and the run file and the schema have the column.
// The run file of `sys` (scene s) with a snapshot after each of `snapshots` advances of `every` seconds.
std::string record_run(System& sys, Scene& s, const TempDir& dir, int snapshots, double every) {
  RunRecorder rec(sys, dir.path().string());
  for (int k = 0; k < snapshots; ++k) {
    run_for(sys, every);
    rec.record_snapshot(sys);
  }
  const std::string out = (dir.path() / "run.h5").string();
  RunInfo info;
  info.scene = &s;
  rec.finish(sys, info, out, "duration");
  return out;
}

struct Collision {
  double e, kinetic0, lost, column, normal, drift, error;
};

Collision collide(double zeta, double dt_divisor) {
  const double d = 3e-3, v = 0.1;  // m, m/s
  const double m_eff = 0.5 * kDensity * M_PI * d * d / 4.0;
  Scene s = glass_scene(effect::inner_pull, kKn);
  s.particle_particle = pulled(s.particle_particle);
  s.particle_particle.inner_pull_damping = 2.0 * zeta * std::sqrt(m_eff * (kKn - kKa));
  add_disk(s, -0.51 * d, 0.0, d, v);
  add_disk(s, 0.51 * d, 0.0, d, -v);
  s.output.energy_balance = true;
  set_dt_fraction(s, dt_divisor);
  System sys(s);
  const EnergyBalance start = energy::balance(sys);
  Collision c{};
  bool touched = false;
  for (int n = 0; n < 100000 && !(touched && sys.state.p.x[1] - sys.state.p.x[0] > d); ++n) {  // until they part
    sys.advance(1);
    touched = touched || sys.state.p.x[1] - sys.state.p.x[0] < d;
    c.drift = std::max(c.drift, std::abs(energy::balance(sys).total() - start.total()));
  }
  const EnergyBalance end = energy::balance(sys);
  c.e = (sys.state.p.vx[1] - sys.state.p.vx[0]) / (2.0 * v);
  c.kinetic0 = start.kinetic;
  c.lost = start.kinetic - end.kinetic;
  c.column = end.dissipated_in("inner_pull_damping");
  c.normal = end.dissipated_in("normal_damping");
  c.error = end.integration_error;
  return c;
}

TEST(ExtraTerm, ItsDashpotDissipatesIntoItsOwnColumn) {
  const double zeta = 0.2, e = std::exp(-zeta * M_PI / std::sqrt(1.0 - zeta * zeta));
  const Collision coarse = collide(zeta, 50.0), fine = collide(zeta, 100.0);
  for (const Collision& c : {coarse, fine}) {
    EXPECT_NEAR(c.e, e, 5e-3 * e);  // they parted at e (to first order in dt: where in a step they part)
    EXPECT_NEAR(c.lost, (1.0 - e * e) * c.kinetic0, 4e-3 * c.kinetic0);
    EXPECT_LT(std::abs(c.normal), 1e-12 * c.kinetic0);  // none of it in the normal dashpot's column
    EXPECT_LT(c.drift, 1e-12 * c.kinetic0);             // the balance closes at every step
    EXPECT_NEAR(c.column + c.error, c.lost, 1e-12 * c.kinetic0);
    EXPECT_LT(std::abs(c.error), 5e-3 * c.lost);
  }
  EXPECT_NEAR(fine.error / coarse.error, 0.5, 0.1);  // first order: the column converges to what was lost
}

TEST(ExtraTerm, RunFileAndSchemaHaveItsColumn) {
  Scene s = glass_scene(effect::inner_pull, kKn);
  s.particle_particle = pulled(s.particle_particle);
  add_disk(s, 0.0, 0.0, 3e-3);
  s.output.energy_balance = true;
  set_dt_fraction(s, 50.0);
  System sys(s);
  const TempDir dir("extra_term_column");
  const RunReader run(record_run(sys, s, dir, 1, s.dt));
  EXPECT_EQ(run.series("energy/inner_pull_damping").size(), run.series_rows());
  EXPECT_NE(run_file_schema_json().find("\"series/energy/inner_pull_damping\""), std::string::npos);
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
  const RunReader run(record_run(sys, s, dir, 5, 2e-4));
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
