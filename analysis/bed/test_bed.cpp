// bed_metrics (analysis/bed): the measures of the filled bed on states built in
// code with known answers (lattices of touching disks), its errors, and one
// run file written by the engine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include <unistd.h>

#include "bed/bed_metrics.hpp"
#include "common/output.hpp"
#include "core/version.hpp"
#include "runfile/run_reader.hpp"
#include "writer/run_file.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {

using test::TempDir;
namespace {

namespace fs = std::filesystem;

constexpr double kD = 3e-3;     // grain diameter (m)
constexpr double kWall = 2e-3;  // wall thickness (m)
const double kTriangular = std::numbers::pi / (2.0 * std::sqrt(3.0));  // 0.9069
const double kSquare = std::numbers::pi / 4.0;

// An empty cell: inner faces x = 0, x = width, y = 0; side walls `height` tall.
Snapshot box(double width, double height) {
  Snapshot s;
  const double h = 0.5 * kWall;
  s.bodies = {Body::segment("floor", -kWall, -h, width + kWall, -h, kWall, "floor"),
              Body::segment("left", -h, -h, -h, height, kWall, "left_wall"),
              Body::segment("right", width + h, -h, width + h, height, kWall, "right_wall")};
  return s;
}

void add_grain(Snapshot& s, double x, double y, double d, Vec2 v = {}, double omega = 0.0) {
  s.position.push_back({x, y});
  s.velocity.push_back(v);
  s.omega.push_back(omega);
  s.diameter.push_back(d);
  s.mass.push_back(2500.0 * std::numbers::pi * d * d / 4.0);
  s.active.push_back(1);
}

// `rows` rows of touching disks of diameter kD on the floor, across the whole
// width (a multiple of kD). Triangular: rows sqrt(3)/2 kD apart, odd rows
// shifted by kD/2 (one disk fewer); square: rows kD apart. Returns the top of
// the last row (m).
double fill_lattice(Snapshot& s, double width, int rows, bool triangular) {
  const double pitch = triangular ? 0.5 * std::sqrt(3.0) * kD : kD;
  for (int r = 0; r < rows; ++r) {
    const double shift = triangular && r % 2 ? 0.5 * kD : 0.0;
    for (double x = 0.5 * kD + shift; x + 0.5 * kD <= width * (1 + 1e-12); x += kD)
      add_grain(s, x, 0.5 * kD + r * pitch, kD);
  }
  return kD + (rows - 1) * pitch;
}

// The contacts of touching grains (distance <= the sum of radii, to round-off)
// and of grains touching the cell's walls, each with fn = 1 N/m.
void add_touching_contacts(Snapshot& s, const Cell& cell) {
  constexpr double kTol = 1e-9;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto gi = static_cast<std::int32_t>(i);
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      const double reach = 0.5 * (s.diameter[i] + s.diameter[j]);
      const double dist = std::hypot(s.position[i].x - s.position[j].x, s.position[i].y - s.position[j].y);
      if (dist <= reach * (1 + kTol)) s.contacts.add(gi, static_cast<std::int32_t>(j), 1.0, reach - dist + 1e-9);
    }
    const double r = 0.5 * s.diameter[i];
    const Vec2 p = s.position[i];
    if (p.y - r <= cell.floor + kTol * kD) s.contacts.add(gi, -1, 1.0, 1e-9);  // bodies 0, 1, 2: floor, left, right
    if (p.x - r <= cell.left + kTol * kD) s.contacts.add(gi, -2, 1.0, 1e-9);
    if (p.x + r >= cell.right - kTol * kD) s.contacts.add(gi, -3, 1.0, 1e-9);
  }
}

// ---- solid fraction ----------------------------------------------------------

TEST(BedMetrics, TriangularLatticeFillingTheBoxHasPiOverTwoRootThree) {
  const double width = 30 * kD;
  Snapshot s = box(width, width);
  fill_lattice(s, width, 33, true);  // 28.7 kD high
  const auto f = fill_metrics(s, BedConfig{});
  EXPECT_NEAR(f["solid_fraction"].get<double>(), kTriangular, 0.005 * kTriangular);
  EXPECT_FALSE(f["bulk_region_excluded_intruder"].get<bool>());
  EXPECT_NEAR(f["sampling_spacing_mm"].get<double>(), kD * 1e3 / 50, 1e-12);
  EXPECT_GT(f["sampling_points"].get<std::int64_t>(), 1'500'000);
  std::printf("triangular lattice: phi = %.5f (exact %.5f)\n", f["solid_fraction"].get<double>(), kTriangular);
}

TEST(BedMetrics, SquareLatticeFillingTheBoxHasPiOverFour) {
  const double width = 30 * kD;
  Snapshot s = box(width, width);
  fill_lattice(s, width, 30, false);
  const auto f = fill_metrics(s, BedConfig{});
  EXPECT_NEAR(f["solid_fraction"].get<double>(), kSquare, 0.005 * kSquare);
  std::printf("square lattice: phi = %.5f (exact %.5f)\n", f["solid_fraction"].get<double>(), kSquare);
}

// The hole around the intruder lies inside its exclusion zone, so the bulk
// solid fraction is the lattice's; without the exclusion the hole lowers it.
TEST(BedMetrics, HoleAroundTheIntruderIsExcluded) {
  const double width = 30 * kD;
  Snapshot full = box(width, width);
  fill_lattice(full, width, 33, true);
  Snapshot s = box(width, width);
  s.bodies.push_back(Body::segment("bar", 0.5 * width - 5e-3, 15 * kD, 0.5 * width + 5e-3, 15 * kD, kWall, "intruder"));
  const Rounded gap{make_shape({{0.5 * width - 5e-3, 15 * kD}, {0.5 * width + 5e-3, 15 * kD}}), 0.5 * kWall + kD};
  for (std::size_t i = 0; i < full.size(); ++i)
    if (!gap.contains(full.position[i].x, full.position[i].y)) add_grain(s, full.position[i].x, full.position[i].y, kD);
  ASSERT_LT(s.size() + 10, full.size());

  const auto f = fill_metrics(s, BedConfig{});
  EXPECT_NEAR(f["solid_fraction"].get<double>(), kTriangular, 0.005 * kTriangular);
  EXPECT_TRUE(f["bulk_region_excluded_intruder"].get<bool>());
  EXPECT_NEAR(f["intruder_exclusion_radius_mm"].get<double>(), (0.5 * kWall + 2 * kD) * 1e3, 1e-9);
  EXPECT_GT(f["sampling_points_excluded"].get<std::int64_t>(), 0);

  Snapshot blind = s;  // the same bar, not declared the intruder
  blind.bodies.back().role = "";
  const double phi_with_hole = fill_metrics(blind, BedConfig{})["solid_fraction"].get<double>();
  EXPECT_LT(phi_with_hole, kTriangular - 0.005) << "the hole must matter when it is not excluded";
  std::printf("lattice with a hole: phi = %.5f excluding the intruder, %.5f not excluding it\n",
              f["solid_fraction"].get<double>(), phi_with_hole);
}

// The sampling itself, on one disk inside a region: the covered
// fraction is the disk's area over the region's, to the grid's resolution.
TEST(BedMetrics, SamplingMeasuresAreas) {
  Snapshot s = box(0.1, 0.1);
  add_grain(s, 0.03, 0.04, 0.01);
  add_grain(s, 0.5, 0.5, 0.01);  // far away: not in the cell list
  const Region region{{0.02, 0.06, 0.02, 0.06}, std::nullopt};
  const Coverage c = sample_coverage(s, region, 1e-4);
  EXPECT_EQ(c.points, 400 * 400);
  EXPECT_NEAR(c.fraction * 0.04 * 0.04, std::numbers::pi * 0.005 * 0.005, 1e-3 * std::numbers::pi * 0.005 * 0.005);
  Region holed = region;
  holed.hole = Rounded{make_shape({{0.03, 0.04}, {0.03, 0.04}}), 0.005};  // removes exactly the disk
  const Coverage h = sample_coverage(s, holed, 1e-4);
  EXPECT_EQ(h.covered, 0);
  EXPECT_EQ(h.points + h.excluded, 400 * 400);
}

// ---- free surface ------------------------------------------------------------

TEST(BedMetrics, HalfFilledBoxBedHeightIsTheTopOfTheLayer) {
  const double width = 30 * kD;
  for (const bool triangular : {true, false}) {
    Snapshot s = box(width, 2 * 21 * kD);
    const double top = fill_lattice(s, width, 21, triangular);  // odd: the top row spans every column
    const auto f = fill_metrics(s, BedConfig{});
    EXPECT_NEAR(f["bed_height_mm"].get<double>(), top * 1e3, 0.01 * kD * 1e3) << "triangular " << triangular;
    EXPECT_NEAR(f["bed_surface_min_mm"].get<double>(), top * 1e3, 0.01 * kD * 1e3);
    EXPECT_NEAR(f["bed_surface_max_mm"].get<double>(), top * 1e3, 0.01 * kD * 1e3);
    // the grains' area spread at the lattice's solid fraction over the width: the same height, to a fraction of d
    EXPECT_NEAR(f["bed_height_from_area_mm"].get<double>(), top * 1e3, 0.5 * kD * 1e3);
    EXPECT_EQ(f["surface_columns"].get<int>(), 30);
    EXPECT_EQ(f["surface_empty_columns"].get<int>(), 0);
    EXPECT_EQ(f["grains_above_surface"].get<int>(), 0);
    EXPECT_NEAR(f["bulk_region_mm"][3].get<double>(), (top - 2 * kD) * 1e3, 1e-9);
  }
}

// The floor's inner face is the origin of heights; a grain in flight shows in
// the maximum and in grains_above_surface.
TEST(BedMetrics, BedHeightIsMeasuredFromTheFloorsInnerFace) {
  const double width = 30 * kD, lift = 7e-3;
  Snapshot s = box(width, 60 * kD);
  const double top = fill_lattice(s, width, 21, true);
  for (Vec2& p : s.position) p.y += lift;
  for (Body& b : s.bodies)
    for (Vec2& v : b.vertices) v.y += lift;
  add_grain(s, 10.5 * kD, lift + top + 2 * kD, kD);  // one grain in flight above column 10
  const auto f = fill_metrics(s, BedConfig{});
  EXPECT_NEAR(f["bed_surface_max_mm"].get<double>(), (top + 2.5 * kD) * 1e3, 1e-9);
  EXPECT_NEAR(f["bed_surface_min_mm"].get<double>(), top * 1e3, 1e-9);
  EXPECT_NEAR(f["bed_height_mm"].get<double>(), (top + 2.5 * kD / 30) * 1e3, 1e-9);
  EXPECT_NEAR(f["cell_mm"]["floor"].get<double>(), lift * 1e3, 1e-9);
  EXPECT_EQ(f["grains_above_surface"].get<int>(), 1);
}

// ---- coordination, overlap, energy ---------------------------------------------

TEST(BedMetrics, TriangularLatticeInteriorHasSixContacts) {
  const double width = 20 * kD;
  Snapshot s = box(width, width);
  fill_lattice(s, width, 21, true);
  const Cell cell = find_cell(s);
  add_touching_contacts(s, cell);
  const auto f = fill_metrics(s, BedConfig{});
  EXPECT_DOUBLE_EQ(f["coordination_number_bulk"].get<double>(), 6.0);
  EXPECT_GT(f["bulk_grains"].get<std::int64_t>(), 50);
  EXPECT_LT(f["coordination_number"].get<double>(), 6.0);  // the surface and wall grains have fewer
  EXPECT_GT(f["coordination_number"].get<double>(), 5.0);
  EXPECT_EQ(f["rattlers"].get<std::int64_t>(), 0);

  // A grain with one contact (and one without force) is a rattler; zero-force contacts do not count.
  add_grain(s, 0.5 * width, 0.5 * width, kD);
  const auto loose = static_cast<std::int32_t>(s.size() - 1);
  s.contacts.add(0, loose, 1.0, 1e-9);
  s.contacts.add(1, loose, 0.0, 1e-9);
  const Coordination z = coordination(s, bulk_region(cell, 0.5 * width, 2 * kD));
  EXPECT_EQ(z.rattlers, 1);
  EXPECT_EQ(z.contacts, static_cast<std::int64_t>(s.contacts.size()) - 1);

  // With cohesion: a touching contact under tension counts (fn < 0), one
  // attracting across a gap (overlap < 0) does not
  s.contacts.add(2, loose, -0.3, 1e-9);
  s.contacts.add(3, loose, -0.2, -2e-5);
  const Coordination c = coordination(s, bulk_region(cell, 0.5 * width, 2 * kD));
  EXPECT_EQ(c.contacts, z.contacts + 1);
  EXPECT_EQ(c.rattlers, 0);  // two contacts now
}

TEST(BedMetrics, MaxOverlapIsRelativeToTheSmallerDiameter) {
  Snapshot s = box(0.05, 0.05);
  add_grain(s, 0.010, 0.002, 2e-3);  // 0
  add_grain(s, 0.013, 0.002, 4e-3);  // 1
  add_grain(s, 0.020, 0.002, 4e-3);  // 2
  add_grain(s, 0.024, 0.002, 4e-3);  // 3
  s.contacts.add(0, 1, 1.0, 0.03e-3);   // 0.03/2 = 0.015
  s.contacts.add(2, 3, 1.0, 0.05e-3);   // 0.05/4 = 0.0125
  s.contacts.add(0, -1, 1.0, 0.02e-3);  // 0.02/2 = 0.010
  s.contacts.add(2, -1, 1.0, 0.07e-3);  // 0.07/4 = 0.0175, the largest
  MaxOverlap o = max_overlap(s);
  EXPECT_DOUBLE_EQ(o.over_d, 0.07e-3 / 4e-3);
  EXPECT_EQ(o.i, 2);
  EXPECT_EQ(o.j, -1);
  const auto f = fill_metrics(s, BedConfig{.margin_d = 0.1});
  EXPECT_EQ(f["max_overlap_contact"]["partner"], "floor");

  s.contacts.overlap[3] = 0.05e-3;  // now 0.0125: the small grain's pair is the largest although 1 overlap is bigger
  o = max_overlap(s);
  EXPECT_DOUBLE_EQ(o.over_d, 0.03e-3 / 2e-3);
  EXPECT_EQ(o.i, 0);
  EXPECT_EQ(o.j, 1);
}

TEST(BedMetrics, KineticEnergyCountsTranslationAndRotationOfActiveGrains) {
  Snapshot s = box(0.05, 0.05);
  add_grain(s, 0.01, 0.01, 3e-3, {0.3, -0.4}, 20.0);
  add_grain(s, 0.02, 0.01, 3e-3, {1.0, 0.0}, 0.0);
  s.active[1] = 0;
  const double m = s.mass[0];
  EXPECT_DOUBLE_EQ(kinetic_energy(s), 0.5 * m * 0.25 + 0.5 * (m * 9e-6 / 8) * 400.0);
}

// ---- bad input -----------------------------------------------------------------

TEST(BedMetrics, MissingWallIsAnErrorNamingIt) {
  Snapshot s = box(0.05, 0.05);
  add_grain(s, 0.01, 0.01, kD);
  s.bodies.erase(s.bodies.begin() + 1);  // no left wall
  try {
    fill_metrics(s, BedConfig{});
    FAIL() << "expected StageError";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("no body has the role 'left_wall'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("floor (floor), right (right_wall)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("role = \"left_wall\""), std::string::npos) << e.what();
  }
  s.bodies.clear();
  EXPECT_THROW(fill_metrics(s, BedConfig{}), StageError);
}

TEST(BedMetrics, EmptySnapshotIsAnError) {
  Snapshot s = box(0.05, 0.05);
  EXPECT_THROW(fill_metrics(s, BedConfig{}), StageError);
  add_grain(s, 0.01, 0.01, kD);
  s.active[0] = 0;  // all lost
  try {
    fill_metrics(s, BedConfig{});
    FAIL() << "expected StageError";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("no active grains"), std::string::npos) << e.what();
  }
  s.active[0] = 1;  // one grain: a bed too shallow for a bulk region
  EXPECT_THROW(fill_metrics(s, BedConfig{}), StageError);
}

// ---- the config file ---------------------------------------------------------


TEST(BedMetricsConfig, DefaultFileHoldsTheDefaults) {
  EXPECT_EQ(load_bed_config(DEM2D_DATA_DIR "/bed_metrics.toml"), BedConfig{});
}

TEST(BedMetricsConfig, KeysAreReadAndBadOnesRejectedWithTheirPlace) {
  TempDir dir;
  const BedConfig c = load_bed_config(dir.file("a.toml", "margin_d = 3\n"));
  EXPECT_EQ(c.margin_d, 3.0);
  const auto error = [&](const std::string& text) {
    try {
      load_bed_config(dir.file("b.toml", text));
    } catch (const BedError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("margin = 2\n").find("b.toml:1:1: unknown key 'margin'"), std::string::npos) << error("margin = 2\n");
  // bodies are found by their roles in the run file, not named here
  EXPECT_NE(error("\n[bodies]\nleft = \"left\"\n").find("b.toml:2:2: unknown key 'bodies'"), std::string::npos);
  EXPECT_NE(error("sampling_per_d = 0\n").find("sampling_per_d = 0: must be in [1, 200]"), std::string::npos);
  // NaN and huge values (1e9 sample points per d hung the stage) are refused
  EXPECT_NE(error("sampling_per_d = 1e9\n").find("must be in [1, 200]"), std::string::npos);
  EXPECT_NE(error("margin_d = nan\n").find("margin_d = nan: must be finite and in [0, 1000]"), std::string::npos)
      << error("margin_d = nan\n");
  EXPECT_NE(error("column_width_d = \"wide\"\n").find("wrong type"), std::string::npos);
  EXPECT_NE(error("margin_d = = 2\n").find("b.toml:1:"), std::string::npos);
  EXPECT_THROW(load_bed_config(dir.file("missing.toml")), BedError);
}

// ---- run files ---------------------------------------------------------------

RunInfo run_info(const Scene& scene) {
  RunInfo info;
  info.scene = &scene;
  info.code_version = code_version();
  return info;
}

// A few dozen grains poured into a box (walls left, right, floor) and settled
// for 0.5 s: the reader returns what the System held, and the tool's numbers
// are those of a settled bed.
TEST(BedMetricsRunFile, SettledBedInARunFile) {
  TempDir dir;
  Scene scene = test::boxed_bed(test::kFull, 60, 0.024);
  std::mt19937_64 rng(3);  // sideways kicks, or the grains fall in columns and stay stacked
  for (ParticleInit& p : scene.particles) p.vx = std::uniform_real_distribution<double>(-0.2, 0.2)(rng);
  System sys(scene);
  RunRecorder rec(sys, dir.file(""));
  // 100 snapshots, 5 ms apart: /snapshots/position (96 KB) is then chunked and
  // compressed, and each snapshot is read as a hyperslab of it.
  constexpr int kSnapshots = 100;
  std::vector<double> times, y_of_grain_k;
  for (int k = 0; k < kSnapshots; ++k) {
    if (k > 0) test::run_for(sys, 0.005);
    rec.record_snapshot(sys);
    times.push_back(sys.time());
    y_of_grain_k.push_back(sys.state.p.y[static_cast<std::size_t>(k) % sys.size()]);
  }
  const std::string run = dir.file("run.h5");
  rec.finish(sys, run_info(scene), run, "test");

  const RunReader reader(run);
  ASSERT_EQ(reader.snapshots(), static_cast<std::size_t>(kSnapshots));
  EXPECT_EQ(reader.snapshot_times(), times);
  for (std::size_t k = 0; k < kSnapshots; ++k)
    EXPECT_EQ(reader.snapshot(k).position[k % sys.size()].y, y_of_grain_k[k]) << "snapshot " << k;
  const Snapshot last = reader.last_snapshot();
  ASSERT_EQ(last.size(), sys.size());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    EXPECT_EQ(last.position[i].x, sys.state.p.x[i]);
    EXPECT_EQ(last.velocity[i].y, sys.state.p.vy[i]);
    EXPECT_EQ(last.diameter[i], 2 * sys.state.p.radius[i]);
  }
  EXPECT_EQ(last.time, sys.time());
  EXPECT_GT(last.contacts.size(), sys.size());
  EXPECT_EQ(reader.snapshot(0).position[5].y, scene.particles[5].y);
  EXPECT_EQ(reader.snapshot(0).velocity[5].x, scene.particles[5].vx);

  const std::string out = dir.file("metrics/fill.json");
  write_file_atomic(out, measure_run_file(run, BedConfig{}).dump(2));
  const auto j = nlohmann::json::parse(std::ifstream(out));
  const auto& f = j.at("fill");
  double top = 0.0, bottom = 1.0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    top = std::max(top, sys.state.p.y[i] + sys.state.p.radius[i]);
    bottom = std::min(bottom, sys.state.p.y[i] - sys.state.p.radius[i]);
  }
  for (const char* key : {"solid_fraction", "bed_height_mm", "bed_height_from_area_mm", "bed_surface_min_mm",
                          "bed_surface_max_mm", "coordination_number", "coordination_number_bulk", "rattlers", "max_overlap_over_d",
                          "kinetic_energy_J_per_m", "particles", "lost_particles", "bulk_region_mm",
                          "bulk_region_excluded_intruder", "sampling_spacing_mm", "sampling_points"})
    EXPECT_TRUE(f.contains(key)) << key;
  const double phi = f["solid_fraction"].get<double>(), height = f["bed_height_mm"].get<double>() * 1e-3;
  EXPECT_GT(phi, 0.5);
  EXPECT_LT(phi, 0.95);
  EXPECT_GT(height, bottom + 2 * test::kMeanD);
  EXPECT_LE(height, top);
  EXPECT_LE(f["bed_surface_max_mm"].get<double>() * 1e-3, top + 1e-12);
  EXPECT_EQ(f["particles"].get<int>(), 60);
  EXPECT_EQ(f["lost_particles"].get<int>(), 0);
  EXPECT_EQ(f["surface_empty_columns"].get<int>(), 0);
  EXPECT_GT(f["coordination_number"].get<double>(), 2.0);
  EXPECT_LT(f["coordination_number"].get<double>(), 6.0);
  EXPECT_LT(f["max_overlap_over_d"].get<double>(), 0.05);
  EXPECT_GE(f["kinetic_energy_J_per_m"].get<double>(), 0.0);
  EXPECT_EQ(f["snapshot"]["index"].get<int>(), kSnapshots - 1);
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  std::printf("settled bed of 60 grains: phi = %.4f, H = %.2f mm (grains %.2f..%.2f mm), Z = %.3f, KE = %.3g J/m\n",
              phi, height * 1e3, bottom * 1e3, top * 1e3, f["coordination_number"].get<double>(),
              f["kinetic_energy_J_per_m"].get<double>());
}

TEST(BedMetricsRunFile, BadFilesAreErrorsNamingTheFile) {
  TempDir dir;
  const auto message = [](const std::string& path) {
    try {
      measure_run_file(path, BedConfig{});
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = dir.file("missing.h5");
  EXPECT_EQ(message(missing), missing + ": no such file");
  const std::string text = dir.file("text.h5", "not HDF5\n");
  EXPECT_NE(message(text).find(text + ": cannot open as HDF5"), std::string::npos) << message(text);

  // A complete run file without snapshots.
  const std::string empty = dir.file("empty.h5");
  {
    const Scene scene = test::boxed_bed(effect::gravity | effect::walls, 10, 0.02);
    System sys(scene);
    RunRecorder rec(sys, dir.file(""));
    rec.record_series(sys);
    rec.finish(sys, run_info(scene), empty, "test");
  }
  EXPECT_NE(message(empty).find(empty + ": the run file has no snapshots"), std::string::npos) << message(empty);

  // A run file whose walls have other names: found by their roles; without
  // the role, an error.
  const std::string unnamed = dir.file("unnamed.h5");
  {
    Scene scene = test::boxed_bed(effect::gravity | effect::walls, 10, 0.02);
    scene.bodies[1].name = "west";
    System sys(scene);
    RunRecorder rec(sys, dir.file(""));
    rec.record_snapshot(sys);
    rec.finish(sys, run_info(scene), dir.file("west.h5"), "test");
    scene.bodies[1].role = "";
    System unroled(scene);
    RunRecorder rec2(unroled, dir.file(""));
    rec2.record_snapshot(unroled);
    rec2.finish(unroled, run_info(scene), unnamed, "test");
  }
  EXPECT_EQ(RunReader(dir.file("west.h5")).body_with_role("left_wall"), 1u);
  EXPECT_EQ(message(dir.file("west.h5")).find("role"), std::string::npos) << message(dir.file("west.h5"));
  EXPECT_NE(message(unnamed).find(unnamed + ": no body has the role 'left_wall'"), std::string::npos) << message(unnamed);
}

}  // namespace
}  // namespace dem2d::analysis
