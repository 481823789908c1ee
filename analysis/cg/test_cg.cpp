// Tests of the stage `cg`: the kernel and the fields it gives (mass, uniform
// and sheared velocities, one grain, no grain, walls), bad parameters, the
// cone fit on a synthetic v* field with a known cone, the cone statistics
// leaving out edges that narrow upwards, the wall-mobility step fit, the events contract, the config file, and the stage on the quick
// pull-off run (the quick study's, tests/quick_study.hpp: a failure if it is absent).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "cg/cg_field.hpp"
#include "cg/cg_measure.hpp"
#include "cg/cg_report.hpp"
#include "cg/cg_stage.hpp"
#include "cg/wall_loss.hpp"
#include "runfile/h5.hpp"
#include "quick_study.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

constexpr double kRho = 2500.0;  // grain density (kg/m^3)

// Grains in SoA form, kept alive for the spans of a Grains view.
struct Bed {
  std::vector<Vec2> position, velocity;
  std::vector<double> mass, diameter;
  std::vector<std::uint8_t> active;
  void add(double x, double y, double d, Vec2 v = {}) {
    position.push_back({x, y});
    velocity.push_back(v);
    diameter.push_back(d);
    mass.push_back(kRho * std::numbers::pi * d * d / 4.0);
    active.push_back(1);
  }
  Grains grains() const { return {position, mass, diameter, active, {velocity}}; }
};

// A triangular lattice of touching disks of diameter d filling [x0, x1] x [y0, y1].
Bed lattice(double x0, double x1, double y0, double y1, double d) {
  Bed b;
  const double row = d * std::sqrt(3.0) / 2.0;
  int r = 0;
  for (double y = y0 + d / 2; y <= y1 - d / 2; y += row, ++r)
    for (double x = x0 + d / 2 + (r % 2) * d / 2; x <= x1 - d / 2; x += d) b.add(x, y, d);
  return b;
}

TEST(CgKernel, IntegratesToOneOverTheTruncatedDisk) {
  const Kernel k = make_kernel(0.0045, 4.0);
  EXPECT_NEAR(k.volume(), 2 * std::numbers::pi * k.w * k.w * (1 - std::exp(-8.0)), 1e-18);
  // radial quadrature of G over r <= 4w
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * k.radius() / n;
    sum += k(r) * 2 * std::numbers::pi * r * k.radius() / n;
  }
  EXPECT_NEAR(sum, 1.0, 1e-9);
  EXPECT_EQ(k(k.radius() * 1.0001), 0.0);
}

TEST(CgField, SingleGrainMatchesTheAnalyticKernel) {
  const Grid g = make_grid(0.0, 0.05, 0.0, 0.05, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  Bed b;
  b.add(0.0251, 0.0237, 0.003, {0.002, -0.001});
  const Fields f = coarse_grain(g, k, b.grains());
  const double area = std::numbers::pi * 0.003 * 0.003 / 4.0;
  int inside = 0;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const std::size_t n = g.at(i, j);
      const double G = k(std::hypot(g.x(i) - 0.0251, g.y(j) - 0.0237));
      ASSERT_NEAR(f.rho[n], b.mass[0] * G, 1e-12 * b.mass[0] * k(0.0));
      ASSERT_NEAR(f.phi[n], area * G, 1e-12 * area * k(0.0));
      inside += G > 0.0;
    }
  EXPECT_GT(inside, 6000);  // pi (18 mm / 0.4 mm)^2 = 6362 nodes
  // one grain: V = its velocity wherever it reaches, NaN elsewhere
  const Velocity v = velocity(f, 0, 0.0);
  for (std::size_t n = 0; n < g.size(); ++n) {
    if (f.rho[n] > 0.0) {
      ASSERT_NEAR(v.vx[n], 0.002, 1e-15);
      ASSERT_NEAR(v.vy[n], -0.001, 1e-15);
    } else {
      ASSERT_TRUE(std::isnan(v.vx[n]));
    }
  }
}

TEST(CgField, TotalMassRecoveredAwayFromBoundaries) {
  // random grains at least the cut-off radius inside the grid: sum rho dx^2 = sum m
  const Grid g = make_grid(0.0, 0.1, 0.0, 0.1, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(0.019, 0.081), dia(0.002, 0.004);
  Bed b;
  for (int i = 0; i < 300; ++i) b.add(pos(rng), pos(rng), dia(rng));
  const Fields f = coarse_grain(g, k, b.grains());
  double mass = 0.0, integral = 0.0, area = 0.0, phi_integral = 0.0;
  for (std::size_t i = 0; i < b.mass.size(); ++i) mass += b.mass[i], area += std::numbers::pi * b.diameter[i] * b.diameter[i] / 4;
  for (std::size_t n = 0; n < g.size(); ++n) integral += f.rho[n] * g.dx * g.dx, phi_integral += f.phi[n] * g.dx * g.dx;
  EXPECT_NEAR(integral / mass, 1.0, 1e-3);
  EXPECT_NEAR(phi_integral / area, 1.0, 1e-3);
}

TEST(CgField, UniformVelocityReproducedEverywhereAndDensityHalvedAtWalls) {
  // a lattice filling a 60 x 60 mm box: V exact at every node; at the walls the
  // kernel reaches outside the grains, so rho drops to about half the bulk value
  const Grid g = make_grid(0.0, 0.06, 0.0, 0.06, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  Bed b = lattice(0.0, 0.06, 0.0, 0.06, 0.003);
  for (Vec2& v : b.velocity) v = {-0.0007, 0.0012};
  const Fields f = coarse_grain(g, k, b.grains());
  const Velocity v = velocity(f, 0, 0.0);
  for (std::size_t n = 0; n < g.size(); ++n) {
    ASSERT_NEAR(v.vx[n], -0.0007, 1e-15);
    ASSERT_NEAR(v.vy[n], 0.0012, 1e-15);
  }
  const double bulk = f.phi[g.at(g.nx / 2, g.ny / 2)];
  EXPECT_NEAR(bulk, std::numbers::pi / (2 * std::sqrt(3.0)), 0.01);  // triangular packing
  const double wall = f.phi[g.at(0, g.ny / 2)];
  EXPECT_GT(wall / bulk, 0.4);
  EXPECT_LT(wall / bulk, 0.6);
}

TEST(CgField, LinearShearReproducedInTheBulk) {
  // v_x = gamma (y - y_mid) on a lattice: at nodes a cut-off radius from the
  // edges, V_x = gamma (mass-weighted mean y in the kernel - y_mid) = gamma (y - y_mid)
  // up to the lattice's granularity
  const Grid g = make_grid(0.0, 0.08, 0.0, 0.08, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  Bed b = lattice(0.0, 0.08, 0.0, 0.08, 0.003);
  const double gamma = 0.5;  // 1/s
  for (std::size_t i = 0; i < b.position.size(); ++i) b.velocity[i] = {gamma * (b.position[i].y - 0.04), 0.0};
  const Fields f = coarse_grain(g, k, b.grains());
  const Velocity v = velocity(f, 0, 0.0);
  double worst = 0.0;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      if (std::min({g.x(i), g.y(j), 0.08 - g.x(i), 0.08 - g.y(j)}) < k.radius()) continue;
      worst = std::max(worst, std::abs(v.vx[g.at(i, j)] - gamma * (g.y(j) - 0.04)));
      ASSERT_NEAR(v.vy[g.at(i, j)], 0.0, 1e-15);
    }
  EXPECT_LT(worst, 0.01 * gamma * 0.003);  // < 1 % of the velocity difference across one grain
}

// Averaging in a moving point's frame: a patch of grains carried up by the
// point keeps its field (what moves with the point stays), and velocity noise
// independent between the snapshots falls as 1/sqrt(snapshots).
TEST(CgField, FrameAverageKeepsWhatMovesWithThePointAndAveragesNoise) {
  const Grid g = make_grid(0.0, 0.06, 0.0, 0.06, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  const double V = 0.0012;
  const Bed patch = lattice(0.02, 0.035, 0.02, 0.035, 0.003);  // the kernel's cut-off (18 mm) inside the grid
  for (const double step : {0.0008, 0.0007}) {  // 2 node spacings; 1.75 (between the nodes)
    std::vector<Fields> f;
    std::vector<Vec2> at;
    for (int s = 0; s < 4; ++s) {
      Bed b = patch;
      for (Vec2& p : b.position) p.y += s * step;
      for (Vec2& v : b.velocity) v = {0.0, V};
      f.push_back(coarse_grain(g, k, b.grains()));
      at.push_back({0.03, 0.02 + s * step});
    }
    const Fields avg = frame_average(g, {&f[0], &f[1], &f[2], &f[3]}, at);
    double peak = 0.0, worst = 0.0;
    for (std::size_t n = 0; n < g.size(); ++n) peak = std::max(peak, f[3].rho[n]);
    for (std::size_t n = 0; n < g.size(); ++n) worst = std::max(worst, std::abs(avg.rho[n] - f[3].rho[n]));
    // whole node spacings: the same field up to rounding; between nodes the
    // bilinear error of a field smooth over w = 11 dx
    EXPECT_LT(worst / peak, step == 0.0008 ? 1e-6 : 3e-3) << step;
    const Velocity v = velocity(avg, 0, 0.05);
    int inside = 0;
    for (std::size_t n = 0; n < g.size(); ++n)
      if (avg.phi[n] > 0.3) {
        ++inside;
        EXPECT_NEAR(v.vy[n], V, 1e-9 * V);
        EXPECT_NEAR(v.vx[n], 0.0, 1e-9 * V);
      }
    EXPECT_GT(inside, 500);
  }
  // a bed at rest with independent velocity noise on every grain in each snapshot
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, V);
  std::vector<Fields> f;
  std::vector<Vec2> at;
  for (int s = 0; s < 4; ++s) {
    Bed b = lattice(0.0, 0.06, 0.0, 0.06, 0.003);
    for (Vec2& v : b.velocity) v = {noise(rng), noise(rng)};
    f.push_back(coarse_grain(g, k, b.grains()));
    at.push_back({0.03, 0.02 + s * 0.0007});
  }
  const Fields avg = frame_average(g, {&f[0], &f[1], &f[2], &f[3]}, at);
  auto rms = [&](const Fields& x) {
    const Velocity v = velocity(x, 0, 0.0);
    double ss = 0.0;
    int n = 0;
    for (std::size_t j = g.ny / 4; j < 3 * g.ny / 4; ++j)
      for (std::size_t i = g.nx / 4; i < 3 * g.nx / 4; ++i) ss += v.vx[g.at(i, j)] * v.vx[g.at(i, j)], ++n;
    return std::sqrt(ss / n);
  };
  double single = 0.0;
  for (const Fields& x : f) single += rms(x) * rms(x) / 4.0;
  EXPECT_NEAR(rms(avg) / std::sqrt(single), 0.5, 0.1);
}

TEST(CgField, EmptyAndInactiveSnapshots) {
  const Grid g = make_grid(0.0, 0.02, 0.0, 0.02, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  Bed none;
  const Fields f0 = coarse_grain(g, k, none.grains());
  for (const double r : f0.rho) ASSERT_EQ(r, 0.0);
  Bed lost;
  lost.add(0.01, 0.01, 0.003, {1.0, 1.0});
  lost.active[0] = 0;
  const Fields f1 = coarse_grain(g, k, lost.grains());
  const Velocity v = velocity(f1, 0, 0.0);
  for (std::size_t n = 0; n < g.size(); ++n) {
    ASSERT_EQ(f1.rho[n], 0.0);
    ASSERT_TRUE(std::isnan(v.vx[n]));
  }
  // measurements on an empty field: nothing, no crash
  const std::vector<double> vstar = speed_ratio(v, 0.0, 0.0, 0.001);
  const ZoneAreas a = zone_areas(g, vstar, 0.25, 0.75);
  EXPECT_EQ(a.immobile + a.cone + a.dragged, 0.0);
  const Intruder in{0.01, 0.002, 0.005, 0.015, 0.003};
  const ConeFit c = fit_cone(g, zone_from_intruder(g, vstar, 0.25, in, 0.003), in, in.top, 0.006);
  EXPECT_TRUE(std::isnan(c.beta_deg(kVerticalEdgeDeg)));
  EXPECT_TRUE(std::isnan(region_mean(g, vstar, 0, 1, 0, 1)));
  // a grain far outside the grid contributes nothing
  Bed far;
  far.add(1.0, 1.0, 0.003);
  for (const double r : coarse_grain(g, k, far.grains()).rho) ASSERT_EQ(r, 0.0);
}

TEST(CgField, BadParametersGiveClearErrors) {
  const auto message = [](auto f) {
    try {
      f();
    } catch (const std::runtime_error& e) {  // CgError, or StageError from the shared kernel and grid
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] { make_kernel(0.0, 4.0); }), "kernel width w = 0 mm: must be > 0");
  EXPECT_EQ(message([] { make_kernel(-0.001, 4.0); }), "kernel width w = -1 mm: must be > 0");
  EXPECT_NE(message([] { make_kernel(0.001, 0.0); }).find("cut-off"), std::string::npos);
  EXPECT_EQ(message([] { make_grid(0, 0.1, 0, 0.1, 0.0); }), "grid spacing 0 mm: must be > 0");
  EXPECT_EQ(message([] { make_grid(0, 0.1, 0, 0.05, 0.2); }),
            "grid spacing 200 mm is larger than the domain (100 mm x 50 mm): no node");
  CgConfig c;
  c.w_over_d = -1.0;
  EXPECT_EQ(message([&] { validate(c, "cfg"); }), "cfg: kernel.w_over_d = -1: must be > 0 (kernel width w in mean diameters)");
}

TEST(CgGrid, PaperResolution) {
  const Grid g = make_grid(0.0, 0.1, 0.0, 0.168, 0.0004);
  EXPECT_EQ(g.nx, 250u);
  EXPECT_EQ(g.ny, 420u);
  EXPECT_NEAR(g.x(0), 0.0002, 1e-15);
  EXPECT_NEAR(g.x(249), 0.0998, 1e-15);
}

// A v* field with a known cone: 1 between lines rising from the intruder's
// tips at `beta` to the horizontal (up to y_max), 0 outside.
std::vector<double> cone_field(const Grid& g, const Intruder& in, double beta_left_deg, double beta_right_deg,
                               double y_max) {
  std::vector<double> v(g.size(), 0.0);
  const double cl = 1 / std::tan(beta_left_deg * std::numbers::pi / 180);
  const double cr = 1 / std::tan(beta_right_deg * std::numbers::pi / 180);
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double h = g.y(j) - in.top;
      if (h >= 0 && g.y(j) <= y_max && g.x(i) >= in.left - cl * h && g.x(i) <= in.right + cr * h) v[g.at(i, j)] = 1.0;
    }
  return v;
}

TEST(CgCone, FitRecoversAKnownCone) {
  const Grid g = make_grid(0.0, 0.1, 0.0, 0.168, 0.0004);
  const Intruder in{0.05, 0.02, 0.045, 0.055, 0.021};
  for (const double beta : {45.0, 60.0, 75.0}) {
    const std::vector<double> vstar = cone_field(g, in, beta, beta, 0.14);
    const std::vector<std::uint8_t> zone = zone_from_intruder(g, vstar, 0.25, in, 0.003);
    const ConeFit c = fit_cone(g, zone, in, in.top, 0.006);
    EXPECT_NEAR(c.left.beta_deg, beta, 0.5) << beta;
    EXPECT_NEAR(c.right.beta_deg, beta, 0.5) << beta;
    EXPECT_NEAR(c.beta_deg(kVerticalEdgeDeg), beta, 0.5);
    // the edge meets the wall where the line from the tip does: 45 mm x tan(beta) above the top
    const double meet = in.top + 0.045 * std::tan(beta * std::numbers::pi / 180);
    if (meet < 0.14) {
      EXPECT_TRUE(c.left.meets_wall && c.right.meets_wall);
      EXPECT_NEAR(c.wall_y(kVerticalEdgeDeg), meet, 0.002) << beta;
    }
    EXPECT_NEAR(c.left.x_at_y0, in.left, 0.001);
    EXPECT_NEAR(c.right.x_at_y0, in.right, 0.001);
  }
  // asymmetric cone, truncated by the surface before reaching the walls
  const std::vector<double> vstar = cone_field(g, in, 50.0, 70.0, 0.06);
  const ConeFit c = fit_cone(g, zone_from_intruder(g, vstar, 0.25, in, 0.003), in, in.top, 0.006);
  EXPECT_NEAR(c.left.beta_deg, 50.0, 0.5);
  EXPECT_NEAR(c.right.beta_deg, 70.0, 0.5);
  EXPECT_FALSE(c.left.meets_wall || c.right.meets_wall);
  // a zone not connected to the intruder is ignored; a narrowing column gives beta > 90
  std::vector<double> column(g.size(), 0.0);
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double h = g.y(j) - in.top;
      if (h >= 0 && h < 0.03 && std::abs(g.x(i) - in.xc) <= 0.005 - 0.05 * h) column[g.at(i, j)] = 1.0;
      if (g.x(i) < 0.01 && g.y(j) > 0.1) column[g.at(i, j)] = 1.0;  // elsewhere
    }
  const ConeFit n = fit_cone(g, zone_from_intruder(g, column, 0.25, in, 0.003), in, in.top, 0.006);
  EXPECT_GT(n.left.beta_deg, 90.0);
  EXPECT_FALSE(n.left.meets_wall);
  // narrowing edges are left out of the snapshot's beta (none left: NaN), kept by the cut-off 180
  EXPECT_TRUE(n.left.excluded(kVerticalEdgeDeg) && n.right.excluded(kVerticalEdgeDeg));
  EXPECT_TRUE(std::isnan(n.beta_deg(kVerticalEdgeDeg)));
  EXPECT_NEAR(n.beta_deg(180.0), 0.5 * (n.left.beta_deg + n.right.beta_deg), 1e-12);
  // a vertical edge is exactly 90 degrees and kept: it does not narrow
  const ConeFit v = fit_cone(g, zone_from_intruder(g, cone_field(g, in, 90.0, 90.0, 0.06), 0.25, in, 0.003), in,
                             in.top, 0.006);
  EXPECT_EQ(v.left.beta_deg, 90.0);
  EXPECT_EQ(v.right.beta_deg, 90.0);
  EXPECT_EQ(v.beta_deg(kVerticalEdgeDeg), 90.0);
  // a span shorter than min_span gives no angle
  const ConeFit s = fit_cone(g, zone_from_intruder(g, column, 0.25, in, 0.003), in, in.top, 0.2);
  EXPECT_TRUE(std::isnan(s.beta_deg(180.0)));
}

// The stage's record of snapshots with the given cones (beta of the left and
// right edge), each fitted on its synthetic v* field as the stage does; no run
// file. Selection: all snapshots (no events); walls never mobile.
StageRecord cone_record(const std::vector<std::pair<double, double>>& cones) {
  const Intruder in{0.05, 0.02, 0.045, 0.055, 0.021};
  StageRecord r;
  Setup& su = r.setup;
  su.grid = make_grid(0.0, 0.1, 0.0, 0.168, 0.0004);
  su.kernel = make_kernel(0.0045, 4.0);
  su.cell.left = 0.0, su.cell.right = 0.1;
  su.d = 0.003, su.v_ref = 0.0012, su.start = in;
  su.levels = {0.25}, su.starts = {0.0}, su.bands = {0.003}, su.heights = {0.03};
  r.primary = kPiv, r.has_piv = true;
  for (const auto& [left, right] : cones) {
    SnapshotMeasure m;
    m.height = in.yc, m.surface = 0.14, m.intruder = in;
    m.phi_follow = m.phi_fixed = {0.8};
    SourceMeasure& s = m.src[kPiv];
    s.valid = true;
    s.cone = {fit_cone(su.grid, zone_from_intruder(su.grid, cone_field(su.grid, in, left, right, 0.14), 0.25, in, 0.003),
                       in, in.top, 0.006)};
    s.wall_left = s.wall_right = {0.0};
    r.times.push_back(static_cast<double>(r.ms.size()));
    r.heights.push_back(m.height);
    r.piv_ok.push_back(1);
    r.ms.push_back(m);
  }
  return r;
}

TEST(CgCone, NarrowingEdgesAreLeftOutOfBeta) {
  // 8 snapshots: 5 cones widening at 60 degrees on both sides, 2 with the right
  // edge narrowing at 100 degrees, 1 narrowing on both sides: 16 edges, 4 narrow
  std::vector<std::pair<double, double>> cones(5, {60.0, 60.0});
  cones.insert(cones.end(), 2, {60.0, 100.0});
  cones.push_back({100.0, 100.0});
  const auto m = cg_metrics(cone_record(cones));
  // beta: the widening edges only, over the 7 snapshots that have one
  EXPECT_NEAR(m["cone_angle_deg"].get<double>(), 60.0, 0.5);
  EXPECT_LT(m["cone_angle_sd_deg"].get<double>(), 0.5);
  EXPECT_EQ(m["cone_angle_snapshots"], 7);
  EXPECT_NEAR(m["cone_angle_left_deg"].get<double>(), 60.0, 0.5);
  EXPECT_NEAR(m["cone_angle_right_deg"].get<double>(), 60.0, 0.5);
  EXPECT_NEAR(m["cone_angle_all_snapshots_deg"].get<double>(), 60.0, 0.5);
  // the narrowing edges: counted, with their own statistics
  EXPECT_EQ(m["cone_fitted_edges"], 16);
  EXPECT_EQ(m["cone_narrowing_edges"], 4);
  EXPECT_DOUBLE_EQ(m["cone_narrowing_edge_fraction"].get<double>(), 0.25);
  EXPECT_NEAR(m["cone_angle_narrowing_mean_deg"].get<double>(), 100.0, 0.5);
  EXPECT_LT(m["cone_angle_narrowing_sd_deg"].get<double>(), 0.5);
  EXPECT_EQ(m["cone_snapshots_with_narrowing_edge"], 3);
  EXPECT_DOUBLE_EQ(m["cone_narrowing_snapshot_fraction"].get<double>(), 3.0 / 8.0);
  EXPECT_EQ(m["cone_snapshots_only_narrowing"], 1);
  EXPECT_DOUBLE_EQ(m["cone_excluded_snapshot_fraction"].get<double>(), 1.0 / 8.0);
  // the old definition, every edge: (5 x 60 + 2 x 80 + 100) / 8 = 70 degrees
  EXPECT_NEAR(m["cone_angle_including_narrowing_deg"].get<double>(), 70.0, 0.5);
  // what follows from beta: the paper's H_c = 45 mm x tan 60 = 77.9 mm, the chord
  // to where the 60-degree edges meet the walls, lines through the tips
  EXPECT_NEAR(m["wall_mobility_length_from_beta_mm"].get<double>(), 45.0 * std::tan(std::numbers::pi / 3), 0.5);
  EXPECT_NEAR(m["cone_angle_from_wall_meet_deg"].get<double>(), 60.0, 0.5);
  EXPECT_NEAR(m["cone_edge_offset_at_intruder_mm"].get<double>(), 0.0, 0.4);  // one node
  // the sensitivity to the cut-off: every edge (180), then 90, 85, 80: the same 60 degrees
  const auto& rows = m["sensitivity"]["cone_angle_edge_cutoff"];
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["max_edge_angle_deg"], 180.0);
  EXPECT_EQ(rows[0]["excluded_edge_fraction"], 0.0);
  EXPECT_NEAR(rows[0]["cone_angle_deg"].get<double>(), 70.0, 0.5);
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(rows[k]["excluded_edge_fraction"].get<double>(), 0.25);
    EXPECT_NEAR(rows[k]["cone_angle_deg"].get<double>(), 60.0, 0.5);
  }
  EXPECT_DOUBLE_EQ(m["by_height_band"][0]["narrowing_edge_fraction"].get<double>(), 0.25);
  EXPECT_NEAR(m["by_height_band"][0]["cone_angle_deg"].get<double>(), 60.0, 0.5);
}

// beta is a value only when the snapshots decide it: too few snapshots, or a
// mean whose 95 % interval is wider than +-5 deg, give null and say why; the
// mean is still given as measured.
TEST(CgCone, BetaFromTooFewOrTooScatteredSnapshotsIsUndetermined) {
  const auto few = cg_metrics(cone_record(std::vector<std::pair<double, double>>(3, {60.0, 60.0})));
  EXPECT_TRUE(few["cone_angle_deg"].is_null());
  EXPECT_NE(few["cone_angle_outcome"].get<std::string>().find("3 loading snapshot(s), fewer than cone.min_snapshots = 5"),
            std::string::npos) << few["cone_angle_outcome"];
  EXPECT_NEAR(few["cone_angle_measured_deg"].get<double>(), 60.0, 0.5);
  EXPECT_TRUE(few["cone_opening_angle_deg"].is_null());
  std::vector<std::pair<double, double>> scattered;
  for (int k = 0; k < 6; ++k) scattered.push_back(k % 2 ? std::pair{45.0, 45.0} : std::pair{85.0, 85.0});
  const auto wide = cg_metrics(cone_record(scattered));
  EXPECT_TRUE(wide["cone_angle_deg"].is_null());
  EXPECT_NE(wide["cone_angle_outcome"].get<std::string>().find("wider than cone.max_interval_deg = 5"), std::string::npos)
      << wide["cone_angle_outcome"];
  const double lo = wide["cone_angle_interval_deg"][0].get<double>(), hi = wide["cone_angle_interval_deg"][1].get<double>();
  EXPECT_GT(hi - lo, 2.0 * 5.0);
  EXPECT_NEAR(0.5 * (lo + hi), wide["cone_angle_measured_deg"].get<double>(), 1e-9);
  const auto steady = cg_metrics(cone_record(std::vector<std::pair<double, double>>(5, {60.0, 60.0})));
  EXPECT_EQ(steady["cone_angle_outcome"], "found");
  EXPECT_NEAR(steady["cone_angle_deg"].get<double>(), 60.0, 0.5);
}

TEST(CgCone, ZonesAndRedExtent) {
  const Grid g = make_grid(0.0, 0.01, 0.0, 0.01, 0.001);  // 10 x 10 nodes of 1 mm^2
  std::vector<double> vstar(g.size(), 0.1);
  for (std::size_t j = 5; j < 8; ++j) vstar[g.at(5, j)] = 1.0;  // a red column over the intruder
  vstar[g.at(0, 0)] = 0.5;
  vstar[g.at(9, 9)] = std::numeric_limits<double>::quiet_NaN();
  const ZoneAreas a = zone_areas(g, vstar, 0.25, 0.75);
  EXPECT_NEAR(a.dragged, 3e-6, 1e-15);
  EXPECT_NEAR(a.cone, 1e-6, 1e-15);
  EXPECT_NEAR(a.immobile, 95e-6, 1e-15);
  const Intruder in{0.0055, 0.004, 0.004, 0.007, 0.0045};
  const ZoneExtent e = zone_extent(g, zone_from_intruder(g, vstar, 0.75, in, 0.001), in);
  EXPECT_NEAR(e.area, 3e-6, 1e-15);
  EXPECT_NEAR(e.height, g.y(7) - in.top, 1e-15);
}

// At a wall the kernel's mean is the velocity of the grains' weighted centroid,
// ~0.8 w inside the wall; a local-linear fit has no such shift for a linear field.
TEST(CgWall, LocalLinearProfileHasNoBoundaryShift) {
  const Grid g = make_grid(0.0, 0.08, 0.0, 0.08, 0.0004);
  const Kernel k = make_kernel(0.0045, 4.0);
  Bed b = lattice(0.0, 0.08, 0.0, 0.08, 0.003);
  const double gamma = 0.5;  // v_y = gamma x: zero at the wall x = 0
  for (std::size_t i = 0; i < b.position.size(); ++i) b.velocity[i] = {0.0, gamma * b.position[i].x};
  const Grains grains = b.grains();
  const double x = 0.0015, v_ref = gamma * 0.003;  // v* = x / 3 mm
  const std::vector<double> p = local_linear_profile(g, k, grains, 0, x, v_ref, std::vector<std::uint8_t>(g.ny, 1));
  const Velocity mean = velocity(coarse_grain(g, k, grains), 0, 0.0);
  const std::size_t i = static_cast<std::size_t>(std::lround((x - g.x0) / g.dx)), j = g.ny / 2;
  EXPECT_NEAR(p[j], x * gamma / v_ref, 1e-9);             // the field at the column: 0.5
  EXPECT_GT(mean.vy[g.at(i, j)] / v_ref, p[j] + 0.5);     // the kernel's mean reads >= 1 d further in
  // invalid rows and a column without grains are NaN
  std::vector<std::uint8_t> valid(g.ny, 1);
  valid[j] = 0;
  EXPECT_TRUE(std::isnan(local_linear_profile(g, k, grains, 0, x, v_ref, valid)[j]));
  EXPECT_TRUE(std::isnan(local_linear_profile(g, k, grains, 0, 0.5, v_ref, std::vector<std::uint8_t>(g.ny, 1))[j]));
}

TEST(CgWall, ProfileMobileLengthAndStepFit) {
  const Grid g = make_grid(0.0, 0.01, 0.0, 0.01, 0.001);
  std::vector<double> vstar(g.size(), 0.0);
  for (std::size_t j = 6; j < 10; ++j) vstar[g.at(0, j)] = 0.5, vstar[g.at(1, j)] = 0.3;
  const std::vector<double> p = wall_profile(g, vstar, 0.0, 0.002);  // columns x = 0.5, 1.5 mm
  EXPECT_NEAR(p[7], 0.4, 1e-12);
  EXPECT_NEAR(p[2], 0.0, 1e-12);
  EXPECT_NEAR(mobile_length(g, p, 0.0, 0.25), 0.004, 1e-12);
  EXPECT_NEAR(mobile_length(g, p, 0.008, 0.25), 0.002, 1e-12);
  // mobile below 62 mm, one outlier each side
  std::vector<double> h;
  std::vector<bool> mob;
  for (int k = 0; k < 100; ++k) h.push_back(0.0015 * k), mob.push_back(0.0015 * k < 0.062);
  mob[10] = false, mob[80] = true;
  const StepFit s = step_down(h, mob);
  EXPECT_NEAR(s.height, 0.06225, 1e-9);  // between 61.5 and 63 mm
  EXPECT_EQ(s.misclassified, 2);
  EXPECT_TRUE(std::isnan(step_down(h, std::vector<bool>(100, true)).height));  // never lost
  EXPECT_TRUE(std::isnan(step_down(h, std::vector<bool>(100, false)).height));
}

TEST(CgEvents, PreRuptureSnapshotsAndFileErrors) {
  const std::vector<double> t = {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75};
  std::vector<RuptureEvent> e(3);
  const double load[] = {0.1, 0.4, 0.7}, peak[] = {0.3, 0.6, 0.72}, drop[] = {0.35, 0.65, 0.8};
  for (std::size_t k = 0; k < 3; ++k) e[k].load_start_time = load[k], e[k].peak_time = peak[k], e[k].drop_end_time = drop[k];
  EXPECT_EQ(pre_rupture_snapshots(t, e, 0.0), (std::vector<std::int64_t>{2, 4, -1}));
  EXPECT_EQ(pre_rupture_snapshots(t, e, 0.05), (std::vector<std::int64_t>{2, 4, -1}));
  EXPECT_EQ(pre_rupture_snapshots(t, e, 0.15), (std::vector<std::int64_t>{2, -1, -1}));  // window inside loading

  test::TempDir dir;
  const std::string path = (dir.path() / "events.h5").string();
  {
    const h5::File f = h5::File::create(path);
    h5::write(f, "/events/peak_time", std::vector<double>{1.0});
    h5::write(f, "/events/load_start_time", std::vector<double>{0.5});
    h5::write(f, "/events/peak_height", std::vector<double>{0.001});
  }
  try {
    read_events(path);
    FAIL() << "no error";
  } catch (const StageError& x) {
    EXPECT_EQ(std::string(x.what()), path + ": dataset /events/drop_end_time is missing (the spectrum stage's events file)");
  }
  EXPECT_THROW(read_events((dir.path() / "none.h5").string()), StageError);
}

TEST(CgConfigFile, DefaultsAndErrors) {
  EXPECT_EQ(load_cg_config(DEM2D_DATA_DIR "/cg.toml"), CgConfig{});
  test::TempDir dir;
  const auto error = [&](const std::string& text) {
    const std::string p = dir.file("c.toml", text);
    try {
      load_cg_config(p);
    } catch (const CgError& e) {
      return std::string(e.what()).substr(p.size());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("[kernel]\nw_over_d = 0.0\n"),
            ":2:12: kernel.w_over_d = 0: must be in (0, 100] (kernel width w in mean diameters)");
  EXPECT_EQ(error("[kernel]\nwidth = 2\n"), ":2:1: unknown key 'width' in [kernel] (allowed: w_over_d, cutoff_over_w)");
  EXPECT_EQ(error("[colour]\n"), ":1:2: unknown key 'colour' at the top level (allowed: kernel, grid, velocity, zones, "
                                 "cone, wall, noise, dilatancy, output, sensitivity)");
  EXPECT_EQ(error("[velocity]\nuse = \"fast\"\n"),
            ":2:7: velocity.use = \"fast\": must be one of \"piv\", \"instantaneous\" (the velocity the zones use)");
  EXPECT_EQ(error("[grid]\nspacing_mm = \"a\"\n"), ":2:14: grid.spacing_mm = \"a\": wrong type, expected a number");
  EXPECT_EQ(error("[output]\nbands_mm = [0, 10, 5]\n"), ":2:12: output.bands_mm = 5: must increase");
  EXPECT_EQ(error("[grid]\naverage_snapshots = 0\n"),
            ":2:21: grid.average_snapshots = 0: must be an integer in [1, 1000000] (snapshots averaged per field)");
  EXPECT_EQ(error("[cone]\nframe_snapshots = 101\n"),
            ":2:19: cone.frame_snapshots = 101: must be an integer in [1, 100] (snapshots averaged in the intruder's frame)");
  EXPECT_EQ(error("[sensitivity]\nmax_edge_angles_deg = [90, 200]\n"),
            ":2:28: sensitivity.max_edge_angles_deg[1] = 200: must be in (0, 180] (degrees from the horizontal; 180: "
            "every edge)");
  // NaN, inf and 1e300 window sizes (which hung the stage) are refused where they are written
  EXPECT_EQ(error("[output]\ntip_window_width_mm = inf\n"),
            ":2:23: output.tip_window_width_mm = inf: must be finite and in (0, 100000] (mm)");
  EXPECT_EQ(error("[grid]\nspacing_mm = nan\n"),
            ":2:14: grid.spacing_mm = nan: must be finite and in (0, 100000] (node spacing in mm)");
  EXPECT_EQ(error("[output]\ntip_window_height_mm = 1e300\n"),
            ":2:24: output.tip_window_height_mm = 1e+300: must be in (0, 100000] (mm)");
}

// The stage on the quick pull-off run (200 grains, 40 mm cell, 20 mm/s, PIV window 3 ms).
TEST(CgStage, QuickPulloffRun) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  test::TempDir dir;
  // events: loading phases of 0.06 s ending at peaks every 0.075 s
  const std::string events = (dir.path() / "events.h5").string();
  {
    std::vector<double> load, peak, height, drop;
    for (int e = 0; e < 20; ++e) {
      peak.push_back(0.1 + 0.075 * e), load.push_back(peak.back() - 0.06);
      height.push_back(0.001 + 0.02 * peak.back()), drop.push_back(peak.back() + 0.01);
    }
    const h5::File f = h5::File::create(events);
    h5::write(f, "/events/peak_time", peak);
    h5::write(f, "/events/load_start_time", load);
    h5::write(f, "/events/peak_height", height);
    h5::write(f, "/events/drop_end_time", drop);
  }
  {  // the reader's PIV data: none before the first snapshot, then displacements over 3 ms
    const RunReader reader(run);
    EXPECT_NEAR(reader.displacement_window(), 0.003, 1e-5);
    EXPECT_TRUE(std::isnan(reader.displacement(0)[0].x));
    const std::vector<Vec2> d = reader.displacement(10);
    ASSERT_EQ(d.size(), reader.particles());
    EXPECT_TRUE(std::isfinite(d[0].x) && std::isfinite(d[0].y));
  }
  CgInput in;
  in.run_path = run;
  in.events_path = events;
  in.threads = 1;
  const CgResult one = compute_cg(in);
  const auto& m = one.metrics["cg"];
  EXPECT_EQ(m["velocity_source"], "piv");
  EXPECT_EQ(m["loading_selection"], "pre_rupture");
  EXPECT_EQ(m["grid"]["nx"], 100);  // 40 mm / 0.4 mm
  EXPECT_NEAR(m["intruder_speed_mm_s"].get<double>(), 20.0, 1e-9);
  EXPECT_GT(m["grid"]["phi_ref"].get<double>(), 0.7);
  EXPECT_LT(m["grid"]["phi_ref"].get<double>(), 0.9);
  EXPECT_GT(m["events_with_snapshot"].get<int>(), 10);
  EXPECT_GT(m["cone_angle_snapshots"].get<int>(), 0);
  const double beta = m["cone_angle_deg"].get<double>();
  EXPECT_GT(beta, 0.0);
  EXPECT_LE(beta, kVerticalEdgeDeg);  // widening edges only
  // every snapshot with a fitted edge either has a beta or only narrowing edges
  EXPECT_EQ(m["cone_angle_snapshots"].get<int>() + m["cone_snapshots_only_narrowing"].get<int>(),
            m["cone_fitted_snapshots"].get<int>());
  EXPECT_EQ(m["cone_angle_including_narrowing_deg"], m["sensitivity"]["cone_angle_edge_cutoff"][0]["cone_angle_deg"]);
  EXPECT_TRUE(m["dilatancy_delta_phi"].is_number());
  EXPECT_GT(m["snapshots_with_piv"].get<int>(), 100);
  // results do not depend on the thread count
  in.threads = 2;
  const CgResult two = compute_cg(in);
  auto a = one.metrics, b = two.metrics;
  for (auto* x : {&a, &b}) (*x)["cg"].erase("cost");
  EXPECT_EQ(a.dump(), b.dump());
  const auto& d1 = one.h5.datasets();
  const auto& d2 = two.h5.datasets();
  ASSERT_EQ(d1.size(), d2.size());
  for (std::size_t k = 0; k < d1.size(); ++k) {
    const auto bits = [](const H5Output::Dataset& d) {
      return std::visit([](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
      }, d.data);
    };
    EXPECT_EQ(bits(d1[k]), bits(d2[k])) << d1[k].name;
    EXPECT_FALSE(d1[k].units.empty() || d1[k].description.empty()) << d1[k].name;
  }
  // outputs
  write_cg(one, dir.path().string());
  const h5::File f = h5::File::open_read((dir.path() / "cg.h5").string());
  EXPECT_EQ(h5::read_attr_string(f, "/", "format"), "dem2d-cg-2");
  const std::size_t S = h5::shape(f, "snapshots/time")[0];
  EXPECT_EQ(h5::shape(f, "profiles/centre_vy_piv"), (std::vector<hsize_t>{S, m["grid"]["ny"].get<hsize_t>()}));
  EXPECT_EQ(h5::shape(f, "fields/phi")[1], m["grid"]["ny"].get<hsize_t>());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "metrics.json"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "cg.h5.tmp"));
  // averaged in the intruder's frame: its noise level no higher than one
  // snapshot's, and the results again independent of the thread count
  in.config.frame_snapshots = 4;
  in.threads = 1;
  auto f1 = compute_cg(in).metrics;
  in.threads = 2;
  auto f2 = compute_cg(in).metrics;
  for (auto* x : {&f1, &f2}) (*x)["cg"].erase("cost");
  EXPECT_EQ(f1.dump(), f2.dump());
  EXPECT_LE(f1["cg"]["cone_level"].get<double>(), m["cone_level"].get<double>());
  EXPECT_NE(f1["cg"]["zone_area_cone_mm2"], m["zone_area_cone_mm2"]);  // the zones are measured on the averages
  in.config.frame_snapshots = 1;
  // without events: all snapshots, said so
  in.events_path = "";
  EXPECT_EQ(compute_cg(in).metrics["cg"]["loading_selection"], "all_snapshots");
}

TEST(CgStage, BadInputsNameTheFile) {
  CgInput in;
  in.run_path = "/nonexistent/run.h5";
  try {
    compute_cg(in);
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/run.h5: no such file");
  }
}

}  // namespace
}  // namespace dem2d::analysis
