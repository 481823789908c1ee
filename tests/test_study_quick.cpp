// The study's two stages on a small scene of the same kind (200 disks, a 40 mm
// cell, hopper, intruder pulled at 20 mm/s): fill, then pull-off from the
// fill's final state, as `make fill pulloff` does with the study's scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include "bed/bed_metrics.hpp"
#include "pulloff/drag_cycles.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_reader.hpp"
#include "quick_study.hpp"
#include "frame/drag_profile.hpp"
#include "pulloff/pulloff_metrics.hpp"
#include "run/progress.hpp"
#include "run/run.hpp"
#include "run/stop_criteria.hpp"
#include "scene/scene_toml.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;
const std::string kScenes = std::string(DEM2D_TESTS_DIR) + "/scenes/";

// A run of the fixture `quick_study` (tests/quick_study.hpp), as run_scene reported it.
struct Made {
  bool complete = false;
  std::string run_file, stop_reason;
  std::size_t lost = 0;
  std::int64_t final_step = 0;
};

Made made(const std::string& path) {
  if (!fs::exists(path)) return {false, path, quick_study_missing(path)};
  const h5::File f = h5::File::open_read(path);
  return {true, path, h5::read_attr_string(f, "/", "stop_reason"),
          static_cast<std::size_t>(h5::read_attr_int(f, "/", "lost_particles")), h5::read_attr_int(f, "/", "steps")};
}

struct QuickStudy : ::testing::Test {
  static inline fs::path dir;  // this process's own runs (resumed, cyclic) and scenes
  static inline Made fill, pull;

  // One thread: ctest runs tests side by side, and OpenMP threads waiting at
  // barriers on an oversubscribed machine slow everything down.
  static Scene scene(const std::string& file, const std::string& initial = "") {
    SceneSources extra;
    extra.initial_run = initial;
    Scene s = load_scene(kScenes + file, extra);
    s.threads = 1;
    return s;
  }
  static void SetUpTestSuite() {
    // per process: ctest runs each test of this suite in its own process, side by side
    dir = fs::temp_directory_path() / ("dem2d_quick_study_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fill = made(quick_study_run("fill"));
    pull = made(quick_study_run("pulloff"));
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  void SetUp() override {
    ASSERT_TRUE(fill.complete) << fill.stop_reason;
    ASSERT_TRUE(pull.complete) << pull.stop_reason;
  }
};

TEST_F(QuickStudy, FillEndsWithABedAtRest) {
  ASSERT_TRUE(fill.complete);
  EXPECT_NE(fill.stop_reason.find("kinetic energy below"), std::string::npos) << fill.stop_reason;
  EXPECT_EQ(fill.lost, 0u);
  const auto m = analysis::measure_run_file(fill.run_file, analysis::BedConfig{}, "")["fill"];
  EXPECT_GT(m["solid_fraction"].get<double>(), 0.78);
  EXPECT_LT(m["solid_fraction"].get<double>(), 0.88);
  // 200 grains of 7.3 mm^2 in a 40 mm cell at such a solid fraction: ~ 43 mm
  EXPECT_NEAR(m["bed_height_mm"].get<double>(), 43.0, 6.0);
  EXPECT_LT(m["max_overlap_over_d"].get<double>(), 0.01);
  EXPECT_EQ(m["grains_above_surface"].get<int>() <= 5, true);
}

TEST_F(QuickStudy, PullOffStartsFromTheFillAndEndsClear) {
  ASSERT_TRUE(pull.complete);
  EXPECT_NE(pull.stop_reason.find("free of the bed"), std::string::npos) << pull.stop_reason;
  EXPECT_EQ(pull.lost, 0u);
  const RunReader run(pull.run_file);
  EXPECT_EQ(run.particles(), 200u);
  EXPECT_EQ(h5::read_attr_string(run.file(), "/", "initial_run"), fill.run_file);
  // the first snapshot is the fill's last state (renumbered in spatial order)
  const RunReader fill_run(fill.run_file);
  const Snapshot a = fill_run.last_snapshot(), b = run.snapshot(0);
  auto sorted = [](const Snapshot& sn) {
    std::vector<std::pair<double, double>> v;
    for (const Vec2& q : sn.position) v.emplace_back(q.x, q.y);
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted(a), sorted(b));
  const double row = *std::max_element(b.diameter.begin(), b.diameter.end());
  for (std::size_t i = 1; i < b.size(); ++i)  // bottom-up rows of one largest diameter
    ASSERT_LE(std::floor(b.position[i - 1].y / row), std::floor(b.position[i].y / row)) << i;
}

// The progress lines' forecast of a pull-off's end (run/progress.hpp): a
// quarter of the way, the intruder's bottom rising at its speed to the bed's
// surface beside it, plus stop.free_time, foresees the end within 5 %.
TEST_F(QuickStudy, ProgressForecastsThePullOffsEnd) {
  const Scene s = scene("quick_pulloff.toml", fill.run_file);
  System sys(s);
  const double end = static_cast<double>(pull.final_step) * s.dt;
  const StopCriteria criteria(s, sys);
  const EndForecast at_start = criteria.forecast(sys);
  sys.advance(pull.final_step / 4);
  const EndForecast later = criteria.forecast(sys);
  EXPECT_NEAR(at_start.time, end, 0.1 * end);
  EXPECT_NEAR(later.time, end, 0.05 * end);
  EXPECT_EQ(later.what, "intruder clear of the bed + 0.1 s");
  EXPECT_FALSE(later.may_end_sooner);
  const DurationLimit duration(s);
  EXPECT_EQ(forecast_end(std::array<const Controller*, 2>{&criteria, &duration}, sys).time, later.time);
  // the fill's kinetic-energy criterion cannot be foreseen: the duration, as "at most"
  const Scene f = scene("quick_fill.toml");
  const System fill_sys(f);
  const StopCriteria energy(f, fill_sys);
  const DurationLimit fill_duration(f);
  const EndForecast e = forecast_end(std::array<const Controller*, 2>{&energy, &fill_duration}, fill_sys);
  EXPECT_NEAR(e.time, f.stop.duration, f.dt);
  EXPECT_TRUE(e.may_end_sooner);
  EXPECT_EQ(Progress::line(2.5, 1000, 1e-5, 1000.0, 200, e, 1000.0),
            "t = 2.5 s  step 1000  25.0 % of 10 s (the duration)  1e+03 steps/s  2e+05 particle-steps/s  "
            "ETA at most 0:12:30");
}

TEST_F(QuickStudy, DragIsPositiveWhileBuriedAndVanishesOnceClear) {
  const RunReader run(pull.run_file);
  const analysis::Study study = analysis::load_study(DEM2D_DATA_DIR "/study.toml");
  const analysis::DragProfile p = analysis::read_drag_profile(run);
  const double bed = analysis::measure_run_file(fill.run_file, analysis::BedConfig{}, "")["fill"]["bed_height_mm"]
                         .get<double>() * 1e-3;
  std::vector<double> buried;
  for (std::size_t k = 0; k < p.drag.size(); ++k) {
    ASSERT_TRUE(std::isfinite(p.drag[k])) << k;
    if (p.height[k] < bed - 3 * study.mean_diameter) buried.push_back(p.drag[k]);
  }
  ASSERT_GT(buried.size(), 100u);
  const auto positive = std::count_if(buried.begin(), buried.end(), [](double f) { return f > 0.0; });
  EXPECT_GT(static_cast<double>(positive), 0.95 * static_cast<double>(buried.size()));
  std::nth_element(buried.begin(), buried.begin() + static_cast<long>(buried.size() / 2), buried.end());
  EXPECT_GT(buried[buried.size() / 2], 1.0);  // N/m: the bed resists
  const double peak = *std::max_element(p.drag.begin(), p.drag.end());
  EXPECT_LT(std::abs(p.drag.back()), 0.02 * peak);  // clear: at most a few carried grains' weight
  EXPECT_GT(p.height.back(), bed);
}

// The static load is the bed's at rest (the fill's last row); the pull-off's
// first row already has the intruder moving: its dashpots add c V, so it is
// a little larger, by about as much as a row's interval of the pull.
TEST_F(QuickStudy, StaticLoadIsTheBedsAtRestNotThePullsFirstRow) {
  const RunReader run(pull.run_file), bed(fill.run_file);
  const analysis::Study study = analysis::load_study(DEM2D_DATA_DIR "/study.toml");
  const double at_rest = analysis::static_load(bed);
  const analysis::DragProfile p = analysis::read_drag_profile(run);
  EXPECT_GT(at_rest, 0.0);  // the grains above press on it
  EXPECT_GT(p.drag.front(), at_rest);
  EXPECT_LT(p.drag.front(), 1.2 * at_rest);
  const auto m = analysis::pulloff_metrics(run, p, study, &bed)["pulloff"];
  EXPECT_EQ(m["drag_static_N_per_m"].get<double>(), at_rest);
  EXPECT_TRUE(analysis::pulloff_metrics(run, p, study)["pulloff"]["drag_static_N_per_m"].is_null());
}

// Resumed at half the run, and at 26.5 % of it: there a contact that touched
// in the bed the run starts from and has opened since closes again soon after
// the checkpoint. The resumed run used to give it the history the new process
// had at its start (1.8e-9 m off at the next snapshot, growing to 3e-4 m);
// a resumed contact list now starts empty, as the uninterrupted one is.
TEST_F(QuickStudy, ResumedPullOffEqualsUninterrupted) {
  const Scene s = scene("quick_pulloff.toml", fill.run_file);
  for (const double at : {0.5, 0.265}) {
    RunOptions opt{(dir / ("pulloff_resumed_" + std::to_string(at))).string()};
    opt.interrupt_at_step = static_cast<std::int64_t>(at * static_cast<double>(pull.final_step));
    ASSERT_FALSE(run_scene(s, opt).complete);
    opt.interrupt_at_step = -1;
    const RunReport r = run_scene(s, opt);
    ASSERT_TRUE(r.complete);
    EXPECT_TRUE(r.resumed);
    EXPECT_EQ(r.final_step, pull.final_step) << "resumed at " << at;
    const h5::File fa = h5::File::open_read(pull.run_file), fb = h5::File::open_read(r.run_file);
    for (const char* name : {"series/body_force_mean", "snapshots/position", "snapshots/velocity", "contacts/ft"}) {
      const auto x = h5::read<double>(fa, name), y = h5::read<double>(fb, name);
      ASSERT_EQ(x.size(), y.size()) << name << " resumed at " << at;
      EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(double)), 0) << name << " resumed at " << at;
    }
  }
}

// Cyclic loading from the same bed (tests/scenes/quick_cyclic.toml): the
// intruder follows its schedule through the bed (a rise, a rest, three
// triangle cycles between 21 and 36 mm) and the drag cuts into its legs.
TEST_F(QuickStudy, CyclicRunFollowsItsScheduleAndCutsIntoCycles) {
  const RunReport cyc = run_scene(scene("quick_cyclic.toml", fill.run_file), {(dir / "cyclic").string()});
  ASSERT_TRUE(cyc.complete);
  EXPECT_EQ(cyc.lost, 0u);
  const RunReader run(cyc.run_file);
  const analysis::DragProfile p = analysis::read_drag_profile(run);
  const std::vector<analysis::DragLeg> legs = analysis::drag_legs(p);
  ASSERT_EQ(legs.size(), 7u);  // the rise, then up and down three times
  for (std::size_t k = 0; k < legs.size(); ++k) {
    const bool up = k == 0 || k % 2 == 1;
    EXPECT_EQ(legs[k].direction, up ? 1 : -1) << k;
    EXPECT_EQ(legs[k].cycle, static_cast<int>((k + 1) / 2)) << k;
    // every leg ends at a corner of the schedule, within one row's travel (0.03 mm)
    EXPECT_NEAR(p.height[legs[k].end - 1], up ? (k == 0 ? 21e-3 : 36e-3) : 21e-3, 0.03e-3) << k;
  }
  // buried, pulling up meets resistance (drag > 0), pushing down meets more, upward (drag < 0)
  const auto legs_json = analysis::cycle_metrics(p, legs)["legs"];
  for (std::size_t k = 1; k < legs.size(); ++k) {
    const double mean = legs_json[k]["drag_mean_N_per_m"].get<double>();
    if (legs[k].direction > 0)
      EXPECT_GT(mean, 0.0) << k;
    else
      EXPECT_LT(mean, -5.0 * legs_json[k - 1]["drag_mean_N_per_m"].get<double>()) << k;
  }
}

// A body placed into the settled bed (a punch across its middle) overlaps
// grains it never touched: refused like a generated grain's overlap, naming
// the deepest, unless allow_initial_overlap (the pull-off's own intruder,
// settled in with the bed, is its state and passes: the fixture loads it).
TEST_F(QuickStudy, BodyPlacedIntoTheBedIsRefused) {
  std::ifstream in(kScenes + "quick_pulloff.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text += "\n[[body]]\nname = \"punch\"\na = [0.004, 0.02]\nb = [0.036, 0.02]\nthickness = 0.003\n";
  const fs::path punch = dir / "punch.toml";
  std::ofstream(punch) << text;
  SceneSources extra;
  extra.initial_run = fill.run_file;
  try {
    load_scene(punch.string(), extra);
    FAIL() << "a punch through the bed was accepted";
  } catch (const std::exception& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("overlaps body 'punch' by "), std::string::npos) << m;
    EXPECT_NE(m.find("(the deepest of "), std::string::npos) << m;
    EXPECT_NE(m.find("a contact the initial run did not have"), std::string::npos) << m;
  }
  std::ofstream(punch) << "allow_initial_overlap = true\n" << text;
  EXPECT_NO_THROW(load_scene(punch.string(), extra));
}

// The study's own scenes load with every preset (the pull-off and the cyclic
// run from this bed): their keys, ranges and time steps are valid.
TEST_F(QuickStudy, StudyScenesLoadWithEveryPreset) {
  const std::string pipeline = std::string(DEM2D_TESTS_DIR) + "/../pipeline/";
  for (const char* preset : {"default", "fast", "paper"})
    for (const char* stage : {"fill", "pulloff", "cyclic"}) {
      SceneSources extra;
      extra.overlays = {pipeline + "presets/" + preset + ".toml"};
      if (std::string(stage) != "fill") extra.initial_run = fill.run_file;
      EXPECT_NO_THROW(load_scene(pipeline + stage + ".toml", extra)) << stage << " + " << preset;
    }
}

}  // namespace
}  // namespace dem2d::test
