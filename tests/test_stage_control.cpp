// What the study's stages need beyond the contact physics: bodies taken away
// during a run (the hopper gate), body velocities that change (taps), the
// hopper jam controller, and the stop criteria (bed at rest, body clear).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "engine/diagnostics.hpp"
#include "run/progress.hpp"
#include "run/run.hpp"
#include "run/thread_choice.hpp"
#include "runfile/h5.hpp"
#include "scene/scene_toml.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;

// Moving a body at v for n steps and back at -v for n steps returns it to
// where it was (to round-off), and the motion is exact in between.
TEST(Bodies, VelocityChangesAreExactAndContinuous) {
  Scene s = glass_scene(kFull | effect::moving_bodies);
  add_disk(s, 0.0, 0.1, 3e-3);
  add_wall(s, "paddle", -0.01, 0.0, 0.01, 0.0, 2e-3, 0.0, 0.0);
  set_dt_fraction(s, 20.0);
  System sys(s);
  sys.set_body_velocity(0, 0.0, 0.5);
  sys.advance(1000);
  EXPECT_NEAR(sys.state.bodies.shape[0].y0(), 0.5 * 1000 * sys.config.dt, 1e-15);
  const double top = sys.state.bodies.shape[0].y0();
  sys.set_body_velocity(0, 0.0, -0.5);
  sys.advance(1);
  EXPECT_NEAR(sys.state.bodies.shape[0].y0(), top - 0.5 * sys.config.dt, 1e-15);  // no jump at the change
  sys.advance(999);
  EXPECT_NEAR(sys.state.bodies.shape[0].y0(), 0.0, 1e-15);
  EXPECT_NEAR(sys.state.bodies.shape[0].vertex(1).y, 0.0, 1e-15);
  EXPECT_NEAR(sys.state.bodies.shape[0].x0(), -0.01, 1e-15);
}

// A static body cannot be given a velocity without the moving_bodies effect.
TEST(Bodies, VelocityNeedsTheMovingBodiesEffect) {
  Scene s = glass_scene(kFull);
  add_disk(s, 0.0, 0.1, 3e-3);
  add_wall(s, "floor", -0.01, 0.0, 0.01, 0.0);
  set_dt_fraction(s, 20.0);
  System sys(s);
  EXPECT_THROW(sys.set_body_velocity(0, 0.0, 1.0), std::invalid_argument);
}

// Grains resting on a gate stay until the gate is taken away, then fall.
TEST(Bodies, RemovedGateLetsGrainsFall) {
  Scene s = glass_scene(kFull);
  add_wall(s, "gate", -0.01, 0.0, 0.01, 0.0, 2e-3);
  add_wall(s, "floor", -0.01, -0.05, 0.01, -0.05, 2e-3);
  add_disk(s, 0.0, 2.5e-3, 3e-3);
  s.bodies[0].remove_at = 0.05;
  s.stop.duration = 0.2;
  s.output.snapshot_interval = 0.01;
  set_dt_fraction(s, 20.0);
  TempDir dir("gate");
  const RunReport r = run_scene(s, {dir.path().string()});
  ASSERT_TRUE(r.complete);
  const h5::File f = h5::File::open_read(r.run_file);
  const auto pos = h5::read<double>(f, "snapshots/position");  // [S, 1, 2]
  for (int k = 1; k <= 4; ++k) EXPECT_NEAR(pos[2 * k + 1], 2.5e-3, 1e-5) << "t = " << 0.01 * k;  // resting
  double lowest = 0.0;
  for (std::size_t k = 6; k < pos.size() / 2; ++k) lowest = std::min(lowest, pos[2 * k + 1]);
  EXPECT_LT(lowest, -0.04);  // fell through to the floor (and bounces there)
}

// output.displacement_window: each snapshot holds the displacement over the
// window before it (x(t) - x(t - window)): exact for a disk in free flight,
// NaN where there was no reference (the first snapshot, the final state).
// A window as long as the interval (allowed) starts at the snapshot before.
class Output : public ::testing::TestWithParam<double> {};

TEST_P(Output, DisplacementOverTheWindow) {
  Scene s = glass_scene(effect::normal_damping);
  add_disk(s, 0.0, 0.0, 3e-3, 0.1, -0.05);
  set_dt_fraction(s, 20.0);
  s.stop.duration = 0.0505;
  s.output.snapshot_interval = 0.01;
  s.output.displacement_window = GetParam();
  TempDir dir;
  const RunReport r = run_scene(s, {dir.path().string()});
  const h5::File f = h5::File::open_read(r.run_file);
  const auto d = h5::read<double>(f, "snapshots/displacement");  // [S, 1, 2]
  const auto t = h5::read<double>(f, "snapshots/time");
  ASSERT_EQ(t.size(), 7u);  // 0, 0.01, ..., 0.05 and the final state
  const double w = h5::read_attr_double(f, "/", "displacement_window");
  EXPECT_NEAR(w, GetParam(), s.dt);
  EXPECT_TRUE(std::isnan(d[0]) && std::isnan(d[1]));
  for (std::size_t k = 1; k + 1 < t.size(); ++k) {
    EXPECT_NEAR(d[2 * k], 0.1 * w, 1e-15) << k;
    EXPECT_NEAR(d[2 * k + 1], -0.05 * w, 1e-15) << k;
  }
  EXPECT_TRUE(std::isnan(d[2 * (t.size() - 1)]));
}

INSTANTIATE_TEST_SUITE_P(Windows, Output, ::testing::Values(0.002, 0.01));

// A small hopper whose outlet (2 d) jams: jams are detected and tapped, and
// the run always ends (emptied, or stopped saying the outlet stays jammed).
Scene jamming_hopper() {
  Scene s = glass_scene(kFull | effect::moving_bodies);
  const double d = 3e-3, half = d;  // outlet 2 d wide at y = 0
  const double slope = std::tan(50.0 * M_PI / 180.0);
  const double top = 0.05;
  add_wall(s, "hopper_left", -half - 1e-3, 0.0, -half - 1e-3 - top / slope, top, 2e-3);
  add_wall(s, "hopper_right", half + 1e-3, 0.0, half + 1e-3 + top / slope, top, 2e-3);
  add_wall(s, "gate", -half - 2e-3, -1e-3, half + 2e-3, -1e-3, 2e-3);
  add_wall(s, "floor", -0.05, -0.06, 0.05, -0.06, 2e-3);
  for (int row = 0; row < 6; ++row) {  // rows as wide as the funnel allows, 1 mm clear of the walls
    const double y = 2e-3 + (row + 0.5) * 1.05 * d;
    const double inner = half + 1e-3 + y / slope - 1e-3 / std::sin(50.0 * M_PI / 180.0);
    const int m = static_cast<int>((inner - 0.5 * d - 1e-3) / (1.05 * d));
    for (int k = -m; k <= m; ++k) add_disk(s, k * 1.05 * d, y, d);
  }
  s.bodies[2].remove_at = 0.02;
  s.domain = {-0.1, -0.1, 0.1, 0.1};
  s.jam = {true, 0.0, 0.02, 0.05, 0.005, {"hopper_left", "hopper_right"}, 0.0, 0.2, 0.01, 30};
  s.stop.duration = 3.0;
  s.stop.kinetic_energy_below = 1e-7;
  s.stop.all_below = 0.0;
  s.stop.check_interval = 0.01;
  s.output.snapshot_interval = 0.1;
  s.text = "jamming hopper (built in code)";
  set_dt_fraction(s, 20.0);
  return s;
}

TEST(Jam, DetectedTappedAndNeverHangs) {
  TempDir dir("jam");
  const RunReport r = run_scene(jamming_hopper(), {dir.path().string()});
  ASSERT_TRUE(r.complete);
  EXPECT_GE(r.jams, 1u);
  const h5::File f = h5::File::open_read(r.run_file);
  EXPECT_EQ(h5::read_attr_int(f, "/", "jams"), static_cast<std::int64_t>(r.jams));
  EXPECT_EQ(h5::read<double>(f, "events/jam_time").size(), r.jams);
  const bool emptied = r.stop_reason.find("kinetic energy") != std::string::npos;
  const bool gave_up = r.stop_reason.find("jammed") != std::string::npos;
  EXPECT_TRUE(emptied || gave_up) << r.stop_reason;
  if (gave_up) {
    EXPECT_EQ(r.jams, 31u);
  }
  // the hopper walls are back where they were
  const auto ends = h5::read<double>(f, "snapshots/body_vertices");
  EXPECT_NEAR(ends[ends.size() - 16 + 1], 0.0, 1e-12);  // hopper_left's C1.y
}

TEST(Jam, RestartDuringTapsIsBitwiseIdentical) {
  const Scene s = jamming_hopper();
  TempDir whole("jam_whole"), parts("jam_parts");
  const RunReport full = run_scene(s, {whole.path().string()});
  ASSERT_GE(full.jams, 1u);
  // interrupt in the middle of the first tap: 2 ms after its detection
  const h5::File ff = h5::File::open_read(full.run_file);
  const double first_jam = h5::read<double>(ff, "events/jam_time")[0];
  RunOptions opt{parts.path().string()};
  opt.interrupt_at_step = std::llround((first_jam + 0.002) / s.dt);
  ASSERT_FALSE(run_scene(s, opt).complete);
  opt.interrupt_at_step = -1;
  const RunReport rest = run_scene(s, opt);
  ASSERT_TRUE(rest.complete);
  EXPECT_EQ(rest.jams, full.jams);
  const h5::File fr = h5::File::open_read(rest.run_file);
  for (const char* name : {"snapshots/position", "snapshots/velocity", "events/jam_time", "snapshots/body_vertices"}) {
    const auto a = h5::read<double>(ff, name), b = h5::read<double>(fr, name);
    ASSERT_EQ(a.size(), b.size()) << name;
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << name;
  }
}

// stop.body_free: a bar pulled up out of a small bed: the run stops once it is clear.
TEST(Stop, BodyFreeEndsThePullOnceClear) {
  Scene s = boxed_bed(kFull, 30, 0.02);
  System bed(s);
  run_for(bed, 0.3);
  Scene pull = with_state(s, bed);
  pull.effects |= effect::moving_bodies;
  pull.particles.clear();
  for (std::size_t i = 0; i < bed.size(); ++i)
    if (bed.state.p.y[i] > 6e-3)  // leave room for the bar at the bottom
      pull.particles.push_back({bed.state.p.x[i], bed.state.p.y[i], 2 * bed.state.p.radius[i], 0.0, 0.0, 0.0});
  // a round bar (zero-length sphero-line): no grain can stay balanced on it
  add_wall(pull, "intruder", 0.01, 3e-3, 0.01, 3e-3, 4e-3, 0.0, 0.1);
  pull.stop.duration = 2.0;
  pull.stop.body_free = "intruder";
  pull.stop.free_time = 0.05;
  pull.stop.check_interval = 0.005;
  TempDir dir("free");
  const RunReport r = run_scene(pull, {dir.path().string()});
  ASSERT_TRUE(r.complete);
  EXPECT_NE(r.stop_reason.find("free of the bed"), std::string::npos) << r.stop_reason;
  EXPECT_LT(static_cast<double>(r.final_step) * pull.dt, 1.5);
}

// The scene keys of all this, and their errors.
TEST(StageScene, KeysParseAndAreValidated) {
  const std::string base = R"(
[effects]
gravity = true
walls = true
moving_bodies = true
[gravity]
g = [0.0, -9.81]
[material]
density = 2500.0
[contact]
kn = 1e6
[time]
duration = 1.0
dt_over_critical = 0.05
[domain]
xmin = -0.1
xmax = 0.1
ymin = -0.1
ymax = 0.1
[[particle]]
x = 0.0
y = 0.01
d = 3e-3
[[body]]
name = "gate"
a = [-0.01, 0.0]
b = [0.01, 0.0]
thickness = 2e-3
remove_at = 0.1
[[body]]
name = "wall"
a = [-0.02, 0.0]
b = [-0.02, 0.05]
thickness = 2e-3
)";
  const std::string jam = R"(
[jam]
outlet_height = 0.0
start_time = 0.1
no_flow_time = 0.2
bodies = ["wall"]
tap_velocity = [0.0, 0.1]
tap_duration = 0.01
[stop]
kinetic_energy_below = 1e-6
all_below = 0.0
body_free = "gate"
free_time = 0.5
check_interval = 0.01
)";
  const Scene s = parse_scene(base + jam, "stage.toml");
  EXPECT_DOUBLE_EQ(s.bodies[0].remove_at, 0.1);
  EXPECT_TRUE(s.jam.enabled);
  EXPECT_EQ(s.jam.bodies, std::vector<std::string>{"wall"});
  EXPECT_DOUBLE_EQ(s.jam.check_interval, 0.02);  // default: no_flow_time / 10
  EXPECT_EQ(s.jam.max_taps, 20);
  EXPECT_EQ(s.stop.body_free, "gate");
  EXPECT_DOUBLE_EQ(s.stop.all_below, 0.0);

  auto error_of = [&](const std::string& text) {
    try {
      parse_scene(text, "stage.toml");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(base + R"(
[jam]
outlet_height = 0.0
no_flow_time = 0.2
bodies = ["nope"]
tap_velocity = [0.0, 0.1]
tap_duration = 0.01
)").find("jam.bodies = [\"nope\"]: 'nope' names no [[body]]"), std::string::npos);
  EXPECT_NE(error_of(base + "[stop]\nall_below = 0.1\n").find("stop.all_below = 0.1: given but no kinetic energy criterion"),
            std::string::npos);
  EXPECT_NE(error_of(base + "[stop]\nkinetic_energy_below = 1e-6\nkinetic_energy_per_grain_below = 1e-9\ncheck_interval = 0.01\n")
                .find("stop.kinetic_energy_per_grain_below = 1e-09: stop.kinetic_energy_below is also given"),
            std::string::npos);
  const Scene per_grain =
      parse_scene(base + jam.substr(0, jam.find("[stop]")) + "[stop]\nkinetic_energy_per_grain_below = 1e-9\ncheck_interval = 0.01\n",
                  "stage.toml");
  EXPECT_EQ(per_grain.stop.kinetic_energy_per_grain_below, 1e-9);
  EXPECT_EQ(per_grain.stop.kinetic_energy_below, -1.0);
  EXPECT_NE(error_of(base + "[stop]\nbody_free = \"gate\"\ncheck_interval = 0.1\n").find("missing key stop.free_time"),
            std::string::npos);
  std::string no_move = base + jam;
  no_move.replace(no_move.find("moving_bodies = true"), 20, "moving_bodies = false");
  EXPECT_NE(error_of(no_move).find("[jam] taps hopper walls, which needs effects.moving_bodies = true"),
            std::string::npos);
}

}  // namespace
}  // namespace dem2d::test

namespace dem2d::test {
namespace {

// The per-grain criterion ends beds of different sizes at the same state of
// rest: a total threshold would have to be rescaled with the grain count.
TEST(Stop, KineticEnergyPerGrainIsTheSameRestForAnySize) {
  for (const int n : {40, 160}) {
    Scene s = boxed_bed(effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance, n, 0.03);
    s.stop.duration = 2.0;
    s.stop.kinetic_energy_per_grain_below = 1e-8;  // J/m per grain: ~1 mm/s
    s.stop.check_interval = 0.01;
    s.output.series_interval = 0.01;
    s.text = "settling box (built in code)";
    TempDir dir("per_grain");
    const RunReport r = run_scene(s, {dir.path().string()});
    ASSERT_TRUE(r.complete);
    EXPECT_EQ(r.stop_reason, "kinetic energy below 1e-08 J/m per grain") << n << " grains";
    const h5::File f = h5::File::open_read(r.run_file);
    const std::vector<double> ke = h5::read<double>(f, "series/kinetic_energy");
    ASSERT_FALSE(ke.empty());
    EXPECT_LT(ke.back(), 1e-8 * n);
    EXPECT_LT(r.final_step, std::llround(2.0 / s.dt));  // ended early, at rest
  }
}

// The ETA's rate is averaged over a window: 100 s at 1000 steps/s, then 20 s
// of a machine so busy the run makes 10 steps/s. The rate since the last line
// falls 100-fold (the ETA jumped from 0:10:37 to 2:41:50 and back); the
// window's falls by the stall's share of it, 17 %. Once the window has passed
// the stall, the rate is the steady one again.
TEST(Progress, EtaRateIsAveragedOverItsWindow) {
  RateWindow w(120.0);
  EXPECT_EQ(w.rate(), 0.0);
  std::int64_t step = 0;
  double t = 0.0;
  for (; t < 100.0; t += 1.0, step += 1000) w.add(t, step);
  EXPECT_DOUBLE_EQ(w.rate(), 1000.0);
  for (; t < 120.0; t += 1.0, step += 10) w.add(t, step);
  EXPECT_NEAR(w.rate(), 1000.0, 0.18 * 1000.0);
  EXPECT_GT(w.rate(), 800.0);
  for (int k = 0; k < 240; ++k, t += 1.0, step += 1000) w.add(t, step);
  EXPECT_NEAR(w.rate(), 1000.0, 1e-9);
}

// The default thread count (run/thread_choice.hpp): one thread for a small
// scene (the 200-grain box ran 0.75 s on one thread, 0.85 s on two, on an
// idle machine), two for the study's 1600 grains when two cores are free, no
// more than the cores free now (a core held by another program made every
// step wait for the thread that shared it), and the reason said.
TEST(Threads, DefaultFromTheSceneAndTheFreeCores) {
  EXPECT_EQ(choose_threads(200, 2, 2.0).threads, 1);
  EXPECT_NE(choose_threads(200, 2, 2.0).why.find("200 grains"), std::string::npos) << choose_threads(200, 2, 2.0).why;
  EXPECT_EQ(choose_threads(1600, 2, 2.0).threads, 2);
  EXPECT_EQ(choose_threads(1600, 2, 1.9).threads, 2);
  const ThreadChoice busy = choose_threads(1600, 2, 1.0);
  EXPECT_EQ(busy.threads, 1);
  EXPECT_NE(busy.why.find("1 of the 2 cores are free"), std::string::npos) << busy.why;
  EXPECT_EQ(choose_threads(1600, 2, 0.0).threads, 1);  // never none
  EXPECT_EQ(choose_threads(100000, 8, 3.2).threads, 3);
  EXPECT_EQ(choose_threads(100000, 8, 8.0).threads, 8);
  EXPECT_NE(choose_threads(100000, 8, 8.0).why.find("all 8 cores"), std::string::npos);
  const double free = free_cores_now(2, 0.05);
  EXPECT_GE(free, 0.0);
  EXPECT_LE(free, 2.0);
}

}  // namespace
}  // namespace dem2d::test
