// Tests of the stage `piv` with known answers: the swirl strength of a
// solid-body rotation (its angular velocity) and of a shear and an expansion
// (none), a shear with a small counter-shear (swirl, not dominant); the stage on the quick pull-off: frame pairs measured, PIV and the
// coarse-grained field close on the same nodes (the typical node, the cone's
// angle), the maps written, the result the same on 1 and 2 threads; the
// frame pairs a snapshot interval apart; the refusals (a run without displacements, a window larger
// than the image, a frame interval the snapshots cannot give) and
// the command's exit codes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cg/cg_config.hpp"
#include "common/stage_error.hpp"
#include "piv/piv_measure.hpp"
#include "piv/piv_stage.hpp"
#include "runfile/h5.hpp"
#include "quick_study.hpp"
#include "stage_command.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

Grid square_grid(std::size_t n, double dx) {
  Grid g;
  g.nx = g.ny = n, g.dx = dx;
  return g;
}

TEST(PivSwirl, SolidBodyRotationHasItsAngularVelocityShearAndExpansionNone) {
  const Grid g = square_grid(12, 0.002);
  const double omega = 3.0, xc = 0.01, yc = 0.012;
  std::vector<double> vx(g.size()), vy(g.size()), sx(g.size()), sy(g.size()), ex(g.size()), ey(g.size());
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const std::size_t n = g.at(i, j);
      vx[n] = -omega * (g.y(j) - yc) + 0.5, vy[n] = omega * (g.x(i) - xc) - 0.2;  // plus a uniform drift
      sx[n] = 7.0 * g.y(j), sy[n] = 0.0;                                          // simple shear
      ex[n] = 2.0 * g.x(i), ey[n] = 2.0 * g.y(j);                                 // expansion
    }
  const auto rot = swirl_strength(g, vx, vy, 0.5), shear = swirl_strength(g, sx, sy, 0.0), exp = swirl_strength(g, ex, ey, 0.0);
  EXPECT_TRUE(std::isnan(rot[g.at(0, 5)]));  // the edge has no central difference
  for (std::size_t j = 1; j + 1 < g.ny; ++j)
    for (std::size_t i = 1; i + 1 < g.nx; ++i) {
      EXPECT_NEAR(rot[g.at(i, j)], omega, 1e-9);
      EXPECT_EQ(shear[g.at(i, j)], 0.0);
      EXPECT_EQ(exp[g.at(i, j)], 0.0);
    }
  // a shear with a small counter-shear: complex eigenvalues, lambda_ci = sqrt(7 x 0.2), a share 0.17 of the norm
  for (std::size_t n = 0; n < g.size(); ++n) sy[n] = -0.2 * g.x(n % g.nx);
  EXPECT_NEAR(swirl_strength(g, sx, sy, 0.0)[g.at(5, 5)], std::sqrt(7.0 * 0.2), 1e-9);
  EXPECT_EQ(swirl_strength(g, sx, sy, 0.5)[g.at(5, 5)], 0.0);
  // a node next to one without velocity has none
  vx[g.at(5, 5)] = kNaN;
  EXPECT_TRUE(std::isnan(swirl_strength(g, vx, vy, 0.5)[g.at(6, 5)]));
}

// The cg stage's settings are found beside the piv settings (compare.cg_config, relative to that
// file): a copy elsewhere without them is refused naming the copy, the key and the file looked for
// (it said only "cg.toml: no such file").
TEST(PivConfig, TheCgSettingsAreLookedForBesideTheFileAndTheirAbsenceNamesTheKey) {
  const PivConfig c = load_piv_config(DEM2D_DATA_DIR "/piv.toml");
  EXPECT_EQ(cg_config_path(DEM2D_DATA_DIR "/piv.toml", c), DEM2D_DATA_DIR "/cg.toml");
  const test::TempDir dir;
  const std::string copy = dir.file("my_piv.toml");
  try {
    cg_config_path(copy, c);
    ADD_FAILURE() << "a missing cg settings file was accepted";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find(copy + ": compare.cg_config = \"cg.toml\": " + dir.file("cg.toml") +
                                         ": no such file"),
              std::string::npos)
        << e.what();
  }
}

PivInput quick_input() {
  PivInput in;
  in.config = load_piv_config(DEM2D_DATA_DIR "/piv.toml");
  in.config_path = DEM2D_DATA_DIR "/piv.toml";
  in.cg_config_path = cg_config_path(in.config_path, in.config);
  in.cg = load_cg_config(in.cg_config_path);
  in.config.every = 12;
  in.config.png_frames = 0;
  in.threads = 1;
  return in;
}

TEST(PivStage, QuickRun) {
  PivInput in = quick_input();
  in.run_path = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(in.run_path)) << test::quick_study_missing(in.run_path);
  const PivResult r = run_piv(in);
  const auto& m = r.metrics["piv"];
  EXPECT_GE(m["pairs"].get<int>(), 10);
  // the region of interest holds the bed: ~860 vectors a pair, 1.4 % replaced by the median test
  EXPECT_GT(m["vectors_per_pair"].get<double>(), 500.0);
  EXPECT_LT(m["replaced_fraction"].get<double>(), 0.05);
  // PIV of the rendered face against the coarse-grained displacements on the same nodes: the typical node
  // within 0.054 V (the rms, 0.57, is led by the few nodes of the quick run's fast avalanches)
  EXPECT_LT(m["median_abs_vstar_difference"].get<double>(), 0.1);
  const auto& beta = m["cone_angle_deg"]["difference"];
  ASSERT_GE(beta["snapshots"].get<int>(), 3);
  EXPECT_LT(std::abs(beta["mean"].get<double>()), 5.0);  // measured -0.46 deg
  EXPECT_NE(m["vortices"]["piv"]["verdict"].get<std::string>(), "fails");
  EXPECT_EQ(m["vortices"]["piv"]["sensitivity"].size(), 9u);
  const test::TempDir dir;
  write_piv(r, dir.path().string());
  const h5::File h = h5::File::open_read((dir.path() / "piv.h5").string());
  const auto snap = h5::read<std::int64_t>(h, "maps/snapshot");
  EXPECT_GE(snap.size(), 5u);
  EXPECT_EQ(h5::read<float>(h, "maps/vstar_piv").size(), h5::read<float>(h, "maps/vstar_cg").size());
  EXPECT_EQ(h5::read<double>(h, "pairs/time").size(), m["pairs"].get<std::size_t>());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "metrics.json"));
  in.threads = 2;
  const PivResult r2 = run_piv(in);
  auto a = r.metrics, b = r2.metrics;
  a["piv"].erase("cost"), b["piv"].erase("cost");
  EXPECT_EQ(a.dump(), b.dump());
}

TEST(PivStage, QuickStudyRunsItCannotMeasureAreRefused) {
  PivInput in = quick_input();
  in.run_path = test::quick_study_run("fill");
  ASSERT_TRUE(std::filesystem::exists(in.run_path)) << test::quick_study_missing(in.run_path);
  try {
    run_piv(in);
    ADD_FAILURE() << "a fill (no displacements) was measured";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("displacement_window"), std::string::npos) << e.what();
  }
  in.run_path = test::quick_study_run("pulloff");
  in.config.piv.windows = {2048, 32};
  try {
    run_piv(in);
    ADD_FAILURE() << "a window larger than the image was accepted";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("windows_px = 2048"), std::string::npos) << e.what();
  }
  // settings under which no pair gives vectors (every 10^6-th snapshot: the first, before any displacement,
  // and the final state, which has none): the settings named with the run, and every reason a pair was
  // skipped with its count (it named the run only, and the first pair's reason)
  in.config = quick_input().config;
  in.config.every = 1000000;
  try {
    run_piv(in);
    ADD_FAILURE() << "settings that leave no pair were accepted";
  } catch (const StageError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(in.config_path + " with " + in.run_path + ": no snapshot gives a frame pair", 0), 0u) << msg;
    EXPECT_NE(msg.find("(2 skipped: 2 x a grain without a displacement"), std::string::npos) << msg;  // (the first and the final state)
  }
}

TEST(PivStage, QuickRunFrameIntervalsTheSnapshotsGiveAndOnesTheyCannot) {
  PivInput in = quick_input();
  in.run_path = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(in.run_path)) << test::quick_study_missing(in.run_path);
  const RunFileSource run(in.run_path);
  const std::vector<double>& t = run.snapshot_times();
  ASSERT_GE(t.size(), 20u);
  const double spacing = t[10] - t[9];
  // frame A from the snapshot before: the interval is the snapshots', the fields still agree on the same nodes
  in.config.frame_interval_s = spacing;
  const auto m = run_piv(in).metrics["piv"];
  EXPECT_EQ(m["frame_interval_from"].get<std::string>(), "1 snapshot interval");
  EXPECT_NEAR(m["frame_interval_s"].get<double>(), spacing, 1e-6 * spacing);
  EXPECT_GE(m["pairs"].get<int>(), 10);
  EXPECT_LT(m["median_abs_vstar_difference"].get<double>(), 0.1);
  // neither the window nor a whole number of snapshot intervals: refused, naming the file and the setting
  for (double bad : {0.7 * spacing, 1.5 * spacing, 1e4}) {
    in.config.frame_interval_s = bad;
    try {
      run_piv(in);
      ADD_FAILURE() << "a frame interval of " << bad << " s was accepted";
    } catch (const StageError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(in.config_path + ": snapshots.frame_interval_s"), std::string::npos) << what;
      EXPECT_NE(what.find("cannot give it"), std::string::npos) << what;
    }
  }
}

TEST(PivCommand, ExitCodes) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  test::expect_stage_command_contract(DEM2D_PIV_EXE, run, "[piv]\nwindows_px = [32, 64]\n");
}

}  // namespace
}  // namespace dem2d::analysis
