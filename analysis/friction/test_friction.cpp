// Stage `friction`: hand-made contact sets with known mu*, the scene's
// coefficients, the settings file, and the stage on the quick run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <tuple>
#include <filesystem>

#include "friction/friction.hpp"
#include "runfile/h5.hpp"
#include "quick_study.hpp"
#include "stage_command.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

constexpr std::int32_t kLeft = -1, kRight = -2, kFloor = -3, kIntruder = -4;

// The laws of a run with Coulomb coefficients mu_grain, mu_wall and, with
// cohesion, pull-off forces f_c (the range 1 m: the pull is f_c in contact).
FrictionLaws laws(double mu_grain, double mu_wall, double fc_grain = 0.0, double fc_wall = 0.0) {
  RunParameters run;
  run.effects = effect::friction | effect::walls | (fc_grain > 0.0 ? effect::cohesion : 0);
  run.dt = 1e-6;
  for (auto [law, mu, fc] : {std::tuple{&run.grain_grain, mu_grain, fc_grain}, {&run.grain_body, mu_wall, fc_wall}}) {
    law->kn = 1e6;
    law->friction = mu;
    law->cohesion_force = fc;
    law->cohesion_range = 1.0;
  }
  return friction_laws(run, std::nullopt, std::nullopt, "run.h5");
}

TEST(FrictionMuStar, RatioOfTangentialToCoulombForce) {
  Contacts c;
  c.add(0, 1, 10.0, 1e-6, 1, 0, -2.5);        // grain-grain: 2.5 / (0.5 x 10) = 0.5
  c.add(0, kLeft, 4.0, 1e-6, 1, 0, 1.0);      // wall, mu_wall 0.25: 1 / (0.25 x 4) = 1
  c.add(1, kFloor, 0.0, 1e-6, 0, 1, 0.0);     // no load: excluded
  c.add(1, kIntruder, 2.0, 1e-6, 0, 1, 0.1);  // 0.1 / 0.5 = 0.2
  const std::vector<Partner> p = {Partner::grain, Partner::left, Partner::floor, Partner::intruder};
  const std::vector<double> m = mu_star(c, p, laws(0.5, 0.25));
  EXPECT_DOUBLE_EQ(m[0], 0.5);
  EXPECT_DOUBLE_EQ(m[1], 1.0);
  EXPECT_TRUE(std::isnan(m[2]));
  EXPECT_DOUBLE_EQ(m[3], 0.2);
}

// With cohesion the cap's load is fn + f_c for touching contacts (a pair held
// by cohesion alone, fn = 0, still has friction mu f_c), and a contact
// attracting across a gap has no friction.
TEST(FrictionMuStar, CohesionAddsThePullOffForceToTheLoad) {
  Contacts c;
  c.add(0, 1, 0.0, 1e-7, 1, 0, 0.1);        // at cohesive equilibrium: 0.1 / (0.5 x (0 + 0.5)) = 0.4
  c.add(0, 2, -0.2, 1e-8, 1, 0, 0.06);      // pulled: 0.06 / (0.5 x 0.3) = 0.4
  c.add(1, 2, -0.3, -2e-5, 1, 0, 0.0);      // across a gap: excluded
  c.add(1, kLeft, 0.0, 1e-7, 1, 0, 0.05);   // wall, f_c 0.25, mu_wall 0.25: 0.05 / (0.25 x 0.25) = 0.8
  c.add(2, 3, -0.6, 1e-9, 1, 0, 0.0);       // pulled beyond f_c (cannot hold in the engine): no load
  const std::vector<Partner> p = {Partner::grain, Partner::grain, Partner::grain, Partner::left, Partner::grain};
  const std::vector<double> m = mu_star(c, p, laws(0.5, 0.25, 0.5, 0.25));
  EXPECT_DOUBLE_EQ(m[0], 0.4);
  EXPECT_DOUBLE_EQ(m[1], 0.4);
  EXPECT_TRUE(std::isnan(m[2]));
  EXPECT_DOUBLE_EQ(m[3], 0.8);
  EXPECT_TRUE(std::isnan(m[4]));
}

TEST(FrictionSummary, SlipFractionZeroForcesAndGroups) {
  Contacts c;
  std::vector<Partner> p;
  const auto add = [&](std::int32_t j, Partner kind, double fn, double ft, bool sliding = false) {
    c.add(0, j, fn, 1e-6, 1, 0, ft, sliding);
    p.push_back(kind);
  };
  add(1, Partner::grain, 10, 5.0, true);   // mu* 1 (sliding)
  add(2, Partner::grain, 10, 4.96);        // 0.992
  add(3, Partner::grain, 10, 2.0);         // 0.4
  add(4, Partner::grain, 10, 0.0);         // 0
  add(kLeft, Partner::left, 10, 3.0);      // 0.6
  add(kRight, Partner::right, 10, -1.0);   // 0.2
  add(kFloor, Partner::floor, 10, 1.0);    // 0.2
  add(kIntruder, Partner::intruder, 10, 4.0);  // 0.8
  add(5, Partner::grain, 0.0, 0.0);        // excluded
  add(kLeft, Partner::left, 0.0, 0.0);     // excluded
  const std::vector<double> ms = mu_star(c, p, laws(0.5, 0.5));
  const SnapshotFriction s = summarise_friction(c, p, ms, {0.99, 0.995, 0.5});
  EXPECT_EQ(s.rows, 10);
  EXPECT_EQ(s.zero_fn, 2);
  EXPECT_EQ(s.all.count, 8);
  EXPECT_DOUBLE_EQ(s.slip_fraction(0), 2.0 / 8.0);
  EXPECT_DOUBLE_EQ(s.slip_fraction(1), 1.0 / 8.0);
  EXPECT_DOUBLE_EQ(s.slip_fraction(2), 4.0 / 8.0);
  EXPECT_EQ(s.sliding_flag, 1);
  EXPECT_EQ(s.bulk.count, 4);
  EXPECT_NEAR(s.bulk.mean(), (1.0 + 0.992 + 0.4 + 0.0) / 4.0, 1e-12);
  EXPECT_EQ(s.wall.count, 2);
  EXPECT_NEAR(s.wall.mean(), 0.4, 1e-12);
  EXPECT_NEAR(s.floor.mean(), 0.2, 1e-12);
  EXPECT_NEAR(s.intruder.mean(), 0.8, 1e-12);

  const SnapshotFriction none = summarise_friction(Contacts{}, {}, {}, {0.99});
  EXPECT_TRUE(std::isnan(none.slip_fraction(0)));
  EXPECT_TRUE(std::isnan(none.bulk.mean()));
}

// The Coulomb coefficients are the run's; a config's replace them; a run
// without friction needs the config's.
TEST(FrictionLaws, FromTheRunsParameters) {
  FrictionLaws mu = laws(0.5, 0.3);
  EXPECT_EQ(mu.grain.mu, 0.5);
  EXPECT_EQ(mu.wall.mu, 0.3);
  RunParameters run;
  run.effects = effect::gravity;
  run.grain_grain.kn = run.grain_body.kn = 1.0;
  mu = friction_laws(run, 0.4, 0.2, "run.h5");
  EXPECT_EQ(mu.grain.mu, 0.4);
  EXPECT_EQ(mu.wall.mu, 0.2);
  try {
    friction_laws(run, std::nullopt, std::nullopt, "x/run.h5");
    FAIL();
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("x/run.h5: the run has no friction"), std::string::npos);
  }
}

TEST(FrictionConfig, DataFileHoldsTheDefaultsAndBadKeysAreNamed) {
  EXPECT_EQ(to_json(load_friction_config(DEM2D_DATA_DIR "/friction.toml")), to_json(FrictionConfig{}));
  const test::TempDir dir;
  const FrictionConfig c = load_friction_config(dir.file("c.toml", "mu_grain = 0.4\nmu_wall = 0.2\ncritical_height_mm = 70\n"));
  EXPECT_EQ(*c.mu_grain, 0.4);
  EXPECT_EQ(*c.critical_height_mm, 70.0);
  const auto error = [&](const std::string& text) {
    try {
      load_friction_config(dir.file("e.toml", text));
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("slip_treshold = 0.9\n").find("e.toml:1:1: unknown key 'slip_treshold'"), std::string::npos);
  EXPECT_NE(error("slip_threshold = 1.5\n").find("slip_threshold = 1.5: must be in [0, 1]"), std::string::npos);
  EXPECT_NE(error("mu_grain = 0.4\n").find("give both mu_grain and mu_wall"), std::string::npos);
  EXPECT_NE(error("sensitivity_slip_threshold = [0.9, \"x\"]\n").find("sensitivity_slip_threshold[1] = \"x\": wrong type, expected a number"), std::string::npos);
}

TEST(FrictionStage, QuickRun) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  const FrictionResult r = run_friction(run, "test", FrictionConfig{}, load_study(DEM2D_DATA_DIR "/study.toml"));
  const auto& m = r.metrics["friction"];
  EXPECT_EQ(m["mu_grain"].get<double>(), 0.5);
  const double slip = m["slip_fraction"].get<double>();
  EXPECT_GE(slip, 0.0);
  EXPECT_LE(slip, 1.0);
  for (const char* key : {"mean_mu_star_lower", "mean_mu_star_upper", "mean_mu_star_lower_wall"}) {
    ASSERT_TRUE(m[key].is_number()) << key;
    EXPECT_GT(m[key].get<double>(), 0.0) << key;
    EXPECT_LT(m[key].get<double>(), 1.0) << key;
  }
  // H_c of the 40 mm cell: (40 - 10)/2 tan 60 deg.
  EXPECT_NEAR(m["critical_height_mm"].get<double>(), 15.0 * std::sqrt(3.0), 1e-9);
  // The engine's sliding flag is |ft| >= mu fn: the same contacts as mu* >= 1 up to rounding.
  EXPECT_NEAR(m["sliding_flag_fraction_pooled"].get<double>(), m["slip_fraction_pooled"].get<double>(), 0.02);
  const auto& table = m["sensitivity"]["slip_fraction"];
  ASSERT_EQ(table.size(), 3u);
  EXPECT_GE(table[0]["slip_fraction"].get<double>(), table[2]["slip_fraction"].get<double>());

  const test::TempDir dir;
  const std::string out = (dir.path() / "friction.h5").string();
  r.h5.write(out);
  const h5::File h = h5::File::open_read(out);
  const auto fig = h5::read<std::int64_t>(h, "figure/snapshot");
  const auto start = h5::read<std::int64_t>(h, "figure/start");
  ASSERT_EQ(start.size(), fig.size() + 1);
  const auto mu = h5::read<double>(h, "figure/mu_star");
  EXPECT_EQ(static_cast<std::int64_t>(mu.size()), start.back());
  for (const double v : mu) ASSERT_LE(v, 1.0 + 1e-9);
}

TEST(FrictionCommand, ExitCodes) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  test::expect_stage_command_contract(DEM2D_FRICTION_EXE, run, "x = 1\n", {"friction.h5", "metrics.json"});
}

}  // namespace
}  // namespace dem2d::analysis
