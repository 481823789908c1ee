// Tests of the stage `stress` with known answers: the kernel's branch
// integral against quadrature and its defining identity; the stress of a
// uniform strained lattice (exact: sigma = (1/A) sum over a grain's three
// contact directions of F (x) l), with tangential forces; the kinetic
// stress of grains moving in opposite directions; the fields' exact balance
// around a body among random contacts; a stack at rest on a floor, whose
// weight the stress carries to the floor (and a box too small to hold the
// floor's kernel, which misses part of it); the stage on the quick pull-off:
// the identity within its quadrature error, the drag from the stress, the
// maps, the result the same on 1 and 2 threads, the command's exit codes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <random>

#include "planted/stress_scenes.hpp"
#include "runfile/h5.hpp"
#include "quick_study.hpp"
#include "stress/stress_balance.hpp"
#include "stress/stress_field.hpp"
#include "stress/stress_stage.hpp"
#include "stage_command.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

constexpr double kD = 0.003;     // grain diameter (m)

// int_0^1 G(r - a - s (b - a)) ds by the midpoint rule on n points
double quadrature(const Kernel& k, Vec2 r, Vec2 a, Vec2 b, int n = 20000) {
  double sum = 0.0;
  for (int q = 0; q < n; ++q) {
    const double s = (q + 0.5) / n;
    sum += k(std::hypot(r.x - a.x - s * (b.x - a.x), r.y - a.y - s * (b.y - a.y)));
  }
  return sum / n;
}

TEST(StressKernel, BranchIntegralIsTheKernelAlongTheSegment) {
  const Kernel k = make_kernel(0.0045, 4.0);
  const double v_w = k.volume();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.025, 0.025);
  int clipped = 0;
  for (int t = 0; t < 200; ++t) {
    const Vec2 a{u(rng), u(rng)}, b{a.x + 0.5 * u(rng), a.y + 0.5 * u(rng)}, r{0.5 * u(rng), 0.5 * u(rng)};
    const double exact = quadrature(k, r, a, b), got = k.along(r, a, b, v_w);
    EXPECT_NEAR(got, exact, 1e-5 * k(0.0)) << t;
    if ((std::hypot(r.x - a.x, r.y - a.y) > k.radius()) != (std::hypot(r.x - b.x, r.y - b.y) > k.radius())) ++clipped;
  }
  EXPECT_GE(clipped, 20);  // segments that the cut-off truncates were among them
  // a point: the kernel itself; beyond the cut-off: nothing
  EXPECT_DOUBLE_EQ(k.along({0.001, 0.002}, {0.0, 0.0}, {0.0, 0.0}, v_w), k(std::hypot(0.001, 0.002)));
  EXPECT_EQ(k.along({0.05, 0.0}, {0.0, 0.0}, {0.001, 0.0}, v_w), 0.0);
}

TEST(StressKernel, BranchIntegralsGradientAlongTheBranchIsTheDifferenceOfItsEnds) {
  // (b - a) . grad_r int G(r - a - s(b - a)) ds = G(r - a) - G(r - b): what makes div sigma balance the forces
  const Kernel k = make_kernel(0.0045, 4.0);
  const double v_w = k.volume(), h = 1e-7;
  const Vec2 a{0.001, -0.002}, b{0.0035, 0.0};
  for (const Vec2 r : {Vec2{0.0, 0.0}, Vec2{0.004, 0.003}, Vec2{-0.006, 0.001}, Vec2{0.01, -0.008}}) {
    const Vec2 u{b.x - a.x, b.y - a.y};
    const double dx = (k.along({r.x + h, r.y}, a, b, v_w) - k.along({r.x - h, r.y}, a, b, v_w)) / (2 * h);
    const double dy = (k.along({r.x, r.y + h}, a, b, v_w) - k.along({r.x, r.y - h}, a, b, v_w)) / (2 * h);
    const double ends = k(std::hypot(r.x - a.x, r.y - a.y)) - k(std::hypot(r.x - b.x, r.y - b.y));
    EXPECT_NEAR(u.x * dx + u.y * dy, ends, 1e-6 * k(0.0));
  }
}

// the field at nodes around the lattice's middle, 18 mm (c w) from its edges, against its exact stress
void expect_lattice_stress(const planted::StrainedLattice& L) {
  const Grid g = make_grid(L.centre.x - 0.01, L.centre.x + 0.01, L.centre.y - 0.008, L.centre.y + 0.008, 0.001);
  const Kernel k = make_kernel(1.5 * kD, 4.0);
  const StressFields f = coarse_grain_stress(g, k, L.s);
  const double scale = std::max(std::abs(L.sigma[kXX]), std::abs(L.sigma[kYY]));
  for (std::size_t n : {std::size_t{0}, g.size() / 2, g.size() - 1})
    for (Component c : {kXX, kXY, kYX, kYY}) EXPECT_NEAR(f.contact[c][n], L.sigma[c], 1e-4 * scale) << c;
}

TEST(StressField, UniformCompressedLatticeGivesItsExactPressure) {
  const double fn = 2.0;  // N/m
  const planted::StrainedLattice L = planted::strained_lattice(kD, 0.999, 0.999, {fn, fn, fn}, {0.0, 0.0, 0.0});
  // isotropic: sqrt(3) fn / a, a the spacing
  EXPECT_NEAR(L.sigma[kXX], std::sqrt(3.0) * fn / (0.999 * kD), 1e-9);
  EXPECT_NEAR(L.sigma[kXY], 0.0, 1e-9);
  expect_lattice_stress(L);
}

TEST(StressField, StrainedLatticeWithFrictionGivesItsExactTensor) {
  const planted::StrainedLattice L = planted::strained_lattice(kD, 0.998, 0.995, {1.0, 3.0, 2.5}, {0.4, -0.2, 0.7});
  EXPECT_GT(std::abs(L.sigma[kXY] - L.sigma[kYX]), 0.05 * std::abs(L.sigma[kYY]));  // not symmetric
  expect_lattice_stress(L);
}

TEST(StressField, KineticStressOfGrainsMovingApartIsRhoUSquared) {
  // a lattice whose grains move at +u or -u along x, alternating: V = 0, sigma_k,xx = rho u^2
  const double u = 0.01, row = kD * std::sqrt(3.0) / 2;
  const Snapshot s = planted::counter_moving_lattice(kD, u);
  const Grid g = make_grid(0.04, 0.08, 0.03, 0.07, 0.001);
  const StressFields f = coarse_grain_stress(g, make_kernel(1.5 * kD, 4.0), s);
  const double rho = s.mass[0] / (kD * row);  // per lattice cell of one grain
  for (std::size_t n : {std::size_t{0}, g.size() / 2}) {
    EXPECT_NEAR(f.kinetic[kXX][n], rho * u * u, 1e-3 * rho * u * u);
    EXPECT_NEAR(f.kinetic[kYY][n], 0.0, 1e-9);
    EXPECT_NEAR(f.rho[n], rho, 1e-4 * rho);
  }
}

TEST(StressBalance, TheStressAroundABodyAndTheNetForcesInsideGiveItsForce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Vec2 truth;
    const Snapshot s = planted::random_contacts(seed, kD, &truth);
    const Grid g = make_grid(-0.06, 0.06, -0.06, 0.06, 0.0005);
    const StressFields f = coarse_grain_stress(g, make_kernel(1.5 * kD, 4.0), s);
    // any box that holds the body's contacts with their kernels (18 mm), whatever it cuts of the grains
    for (double half : {0.025, 0.03, 0.045}) {
      const BodyForce F = body_force(g, f, node_box(g, -half, half, -half, half), {0.0, -9.81});
      const double scale = std::hypot(truth.x, truth.y) + 1.0;
      EXPECT_NEAR(F.exact.x, truth.x, 2e-3 * scale) << seed << " " << half;
      EXPECT_NEAR(F.exact.y, truth.y, 2e-3 * scale) << seed << " " << half;
    }
  }
}

TEST(StressBalance, AStackAtRestCarriesItsWeightToTheFloor) {
  // ten grains stacked on a floor segment at y = 0: contact k carries the weight of the grains above it
  const double g = 9.81;
  double weight = 0.0;
  const Snapshot s = planted::stack_on_floor(10, kD, g, &weight);
  const Grid grid = make_grid(-0.04, 0.04, -0.03, 0.05, 0.0005);
  const StressFields f = coarse_grain_stress(grid, make_kernel(1.5 * kD, 4.0), s);
  // boxes around the floor's contact and its kernel (18 mm), cutting the stack at 6.3 and 8 grains up
  for (double top : {0.019, 0.024}) {
    const BodyForce F = body_force(grid, f, node_box(grid, -0.03, 0.03, -0.025, top), {0.0, -g});
    EXPECT_NEAR(F.quasi_static.y, -weight, 1e-3 * weight) << top;
    EXPECT_NEAR(F.quasi_static.x, 0.0, 1e-3 * weight);
    EXPECT_NEAR(F.inertia.y, 0.0, 1e-3 * weight);
    EXPECT_NEAR(F.exact.y, -weight, 1e-3 * weight);
  }
  // a box that cuts the floor's kernel misses part of the force
  const BodyForce cut = body_force(grid, f, node_box(grid, -0.03, 0.03, -0.025, 0.0045), {0.0, -g});
  EXPECT_GT(std::abs(cut.exact.y + weight), 0.05 * weight);
}


TEST(StressStage, QuickRun) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  StressConfig c;
  c.every = 3;
  const Study study = load_study(DEM2D_DATA_DIR "/study.toml");
  const StressResult r = run_stress(run, "test", c, study, 1);
  const auto& m = r.metrics["stress"];
  const auto& check = m["force_check"];
  EXPECT_GT(check["snapshots_used"].get<int>(), 40);
  // the fields balance the recorded contact forces to the grid's quadrature (1.6e-3 at 1 mm)
  EXPECT_LT(check["exact_residual"].get<double>(), 4e-3);
  // the quick run rings (20 mm/s): its snapshots' inertia is large, the mean close
  EXPECT_GT(check["inertia_share"].get<double>(), 0.1);
  EXPECT_LT(check["mean_relative_error"].get<double>(), 0.15);
  EXPECT_NE(check["verdict"].get<std::string>(), "fails");
  // the bed at rest: a pressure below the hydrostatic one at the intruder (Janssen: the walls carry part)
  const double p = m["rest_pressure_at_intruder_pa"].get<double>();
  EXPECT_GT(p, 50.0);
  EXPECT_LT(p, 2500.0 * 9.81 * 0.06);
  const double K = m["rest_lateral_ratio_at_intruder"].get<double>();
  EXPECT_GT(K, 0.2);
  EXPECT_LT(K, 1.5);

  const test::TempDir dir;
  const std::string out = (dir.path() / "stress.h5").string();
  r.h5.write(out);
  const h5::File h = h5::File::open_read(out);
  const auto snap = h5::read<std::int64_t>(h, "maps/snapshot");
  EXPECT_EQ(snap.size(), 6u);
  EXPECT_EQ(snap.front(), 0);
  const auto x = h5::read<double>(h, "grid/x"), y = h5::read<double>(h, "grid/y");
  EXPECT_EQ(h5::read<float>(h, "maps/pressure").size(), snap.size() * x.size() * y.size());
  EXPECT_EQ(h5::read<float>(h, "maps/sigma").size(), 4 * snap.size() * x.size() * y.size());

  // the same on two threads, bit for bit
  const StressResult r2 = run_stress(run, "test", c, study, 2);
  EXPECT_EQ(r2.metrics.dump(), r.metrics.dump());
}

TEST(StressCommand, ExitCodes) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  test::expect_stage_command_contract(DEM2D_STRESS_EXE, run, "[grid]\nspacing_mm = 0\n");
}

}  // namespace
}  // namespace dem2d::analysis
