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

#include "io/h5.hpp"
#include "quick_study.hpp"
#include "stress/stress_balance.hpp"
#include "stress/stress_field.hpp"
#include "stress/stress_stage.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

constexpr double kRho = 2500.0;  // grain density (kg/m^3)
constexpr double kD = 0.003;     // grain diameter (m)

void add_grain(Snapshot& s, Vec2 x, double d = kD, Vec2 v = {}) {
  s.position.push_back(x);
  s.velocity.push_back(v);
  s.omega.push_back(0.0);
  s.active.push_back(1);
  s.diameter.push_back(d);
  s.mass.push_back(kRho * std::numbers::pi * d * d / 4.0);
}

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

// A triangular lattice of grains of diameter d whose neighbours along the
// three directions 0, 60 and 120 deg are l_k apart (a strained lattice),
// with contact forces fn_k, ft_k along each: the stress inside is
// sigma = (1/A) sum_k (fn_k n_k + ft_k t_k) (x) l_k n_k, A the area per grain.
struct Lattice {
  Snapshot s;
  double area = 0.0;
  std::array<double, 4> sigma{};
};
Lattice strained_lattice(double stretch_x, double stretch_y, std::array<double, 3> fn, std::array<double, 3> ft,
                         int n = 40) {
  Lattice L;
  const Vec2 e1{kD * stretch_x, 0.0}, e2{0.5 * kD * stretch_x, kD * std::sqrt(3.0) / 2 * stretch_y};
  const std::array<Vec2, 3> e{e1, e2, Vec2{e2.x - e1.x, e2.y - e1.y}};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) add_grain(L.s, {i * e1.x + j * e2.x, i * e1.y + j * e2.y});
  L.area = e1.x * e2.y - e1.y * e2.x;
  const auto at = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int dir = 0; dir < 3; ++dir) {
        const int i2 = i + (dir == 0 ? 1 : dir == 1 ? 0 : -1), j2 = j + (dir == 0 ? 0 : 1);
        if (i2 < 0 || i2 >= n || j2 >= n) continue;
        // partner j > i: the normal from the partner (the upper or right one) to i
        const double len = std::hypot(e[dir].x, e[dir].y);
        L.s.contacts.add(at(i, j), at(i2, j2), fn[dir], kD - len, -e[dir].x / len, -e[dir].y / len, ft[dir]);
      }
  for (int dir = 0; dir < 3; ++dir) {
    const double len = std::hypot(e[dir].x, e[dir].y), nx = -e[dir].x / len, ny = -e[dir].y / len;
    const double Fx = fn[dir] * nx - ft[dir] * ny, Fy = fn[dir] * ny + ft[dir] * nx;
    const double lx = nx * len, ly = ny * len;  // x_i - x_j
    L.sigma[kXX] += Fx * lx / L.area, L.sigma[kXY] += Fx * ly / L.area;
    L.sigma[kYX] += Fy * lx / L.area, L.sigma[kYY] += Fy * ly / L.area;
  }
  return L;
}

void expect_lattice_stress(const Lattice& L) {
  const Grid g = make_grid(0.08, 0.10, 0.045, 0.06, 0.001);  // at the 40 x 40 lattice's centre, 18 mm (c w) from its edges
  const Kernel k = make_kernel(1.5 * kD, 4.0);
  const StressFields f = coarse_grain_stress(g, k, L.s);
  const double scale = std::max(std::abs(L.sigma[kXX]), std::abs(L.sigma[kYY]));
  for (std::size_t n : {std::size_t{0}, g.size() / 2, g.size() - 1})
    for (Component c : {kXX, kXY, kYX, kYY}) EXPECT_NEAR(f.contact[c][n], L.sigma[c], 1e-4 * scale) << c;
}

TEST(StressField, UniformCompressedLatticeGivesItsExactPressure) {
  const double fn = 2.0;  // N/m
  const Lattice L = strained_lattice(0.999, 0.999, {fn, fn, fn}, {0.0, 0.0, 0.0});
  // isotropic: sqrt(3) fn / a, a the spacing
  EXPECT_NEAR(L.sigma[kXX], std::sqrt(3.0) * fn / (0.999 * kD), 1e-9);
  EXPECT_NEAR(L.sigma[kXY], 0.0, 1e-9);
  expect_lattice_stress(L);
}

TEST(StressField, StrainedLatticeWithFrictionGivesItsExactTensor) {
  const Lattice L = strained_lattice(0.998, 0.995, {1.0, 3.0, 2.5}, {0.4, -0.2, 0.7});
  EXPECT_GT(std::abs(L.sigma[kXY] - L.sigma[kYX]), 0.05 * std::abs(L.sigma[kYY]));  // not symmetric
  expect_lattice_stress(L);
}

TEST(StressField, KineticStressOfGrainsMovingApartIsRhoUSquared) {
  // a lattice whose grains move at +u or -u along x, alternating: V = 0, sigma_k,xx = rho u^2
  Snapshot s;
  const double u = 0.01, row = kD * std::sqrt(3.0) / 2;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) add_grain(s, {i * kD + (j % 2) * kD / 2, j * row}, kD, {(i + j) % 2 ? u : -u, 0.0});
  const Grid g = make_grid(0.04, 0.08, 0.03, 0.07, 0.001);
  const StressFields f = coarse_grain_stress(g, make_kernel(1.5 * kD, 4.0), s);
  const double rho = s.mass[0] / (kD * row);
  for (std::size_t n : {std::size_t{0}, g.size() / 2}) {
    EXPECT_NEAR(f.kinetic[kXX][n], rho * u * u, 1e-3 * rho * u * u);
    EXPECT_NEAR(f.kinetic[kYY][n], 0.0, 1e-9);
    EXPECT_NEAR(f.rho[n], rho, 1e-4 * rho);
  }
}

// random grains around a body at the origin; random forces between grains and on the body
Snapshot random_contacts(unsigned seed, Vec2* body_force) {
  Snapshot s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) add_grain(s, {0.012 * u(rng), 0.012 * u(rng)}, kD * (1.0 + 0.1 * u(rng)));
  s.bodies.push_back(Body::segment("intruder", -0.004, 0.0, 0.004, 0.0, 0.002, "intruder"));
  *body_force = {0.0, 0.0};
  for (int c = 0; c < 150; ++c) {
    int i = static_cast<int>((u(rng) + 1.0) * 29.99);
    int j = static_cast<int>((u(rng) + 1.0) * 29.99);
    if (j == i) continue;
    if (j < i) std::swap(i, j);
    const Vec2 d{s.position[i].x - s.position[j].x, s.position[i].y - s.position[j].y};
    const double len = std::hypot(d.x, d.y);
    s.contacts.add(i, j, 1.0 + u(rng), 1e-5, d.x / len, d.y / len, 0.3 * u(rng));
  }
  for (int c = 0; c < 12; ++c) {  // on the body: grain i at its surface, the normal from the segment
    const int i = static_cast<int>((u(rng) + 1.0) * 29.99);
    const double ang = std::numbers::pi * (u(rng) + 1.0);
    const Vec2 n{std::cos(ang), std::sin(ang)};
    s.position[i] = {0.003 * u(rng) + n.x * 0.0025, n.y * 0.0025};
    const double fn = 1.0 + u(rng), ft = 0.3 * u(rng);
    s.contacts.add(i, -1, fn, 1e-5, n.x, n.y, ft);
    body_force->x -= fn * n.x - ft * n.y, body_force->y -= fn * n.y + ft * n.x;
  }
  return s;
}

TEST(StressBalance, TheStressAroundABodyAndTheNetForcesInsideGiveItsForce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Vec2 truth;
    const Snapshot s = random_contacts(seed, &truth);
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
  Snapshot s;
  s.bodies.push_back(Body::segment("floor", -0.05, 0.0, 0.05, 0.0, 0.0, "floor"));
  const double g = 9.81;
  const int n = 10;
  for (int i = 0; i < n; ++i) add_grain(s, {0.0, kD / 2 + i * kD});
  const double mg = s.mass[0] * g, weight = n * mg;
  for (int i = 0; i + 1 < n; ++i) s.contacts.add(i, i + 1, (n - 1 - i) * mg, 0.0, 0.0, -1.0);
  s.contacts.add(0, -1, weight, 0.0, 0.0, 1.0);
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
  const auto& check = m["drag_check"];
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
  const auto command = [](const std::string& args) {
    const int status = std::system((std::string(DEM2D_STRESS_EXE) + " " + args + " 2>/dev/null").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  const test::TempDir dir;
  const std::string out = (dir.path() / "out").string(), cfg = (dir.path() / "bad.toml").string();
  {
    std::ofstream f(cfg);
    f << "[grid]\nspacing_mm = 0\n";
  }
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  EXPECT_EQ(command(run + " --out " + out + " --config " + cfg), 2);
  EXPECT_FALSE(std::filesystem::exists(out + "/metrics.json"));
  EXPECT_EQ(command(dir.path().string() + "/none.h5 --out " + out), 2);
}

}  // namespace
}  // namespace dem2d::analysis
