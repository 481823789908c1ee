// A finished run is a result, and a checkpoint is a state to go on from.
//  - The same command again into a finished folder does nothing; another
//    scene (or starting state, or dem2d version) is refused unless
//    --overwrite, which says what it leaves stale.
//  - A checkpoint taken as the starting state (--initial, LAMMPS's
//    read_restart and new settings) carries the grains and their contact
//    history over exactly, goes on as the uninterrupted run does, and the
//    run file says where it came from.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "core/version.hpp"
#include "run/checkpoint.hpp"
#include "run/output_dir.hpp"
#include "run/run.hpp"
#include "runfile/h5.hpp"
#include "scene/initial_state.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Scene small_box() {
  Scene s = boxed_bed(effect::gravity | effect::normal_damping | effect::friction, 40, 0.02);
  s.text = "small box (built in code)";
  s.stop.duration = 0.01;
  s.output.series_interval = 1e-3;
  s.output.snapshot_interval = 5e-3;
  return s;
}

TEST(FinishedRun, TheSameCommandAgainHasNothingToDo) {
  const Scene s = small_box();
  TempDir dir("done");
  const RunReport first = run_scene(s, {dir.path().string()});
  ASSERT_TRUE(first.complete);
  const std::string bytes = text_of(first.run_file), log = text_of(dir.path() / "run.log");
  const RunReport again = run_scene(s, {dir.path().string()});
  EXPECT_TRUE(again.complete);
  EXPECT_TRUE(again.already_complete);
  EXPECT_EQ(again.steps, 0);
  EXPECT_EQ(again.run_file, first.run_file);
  EXPECT_NE(again.stop_reason.find(code_version()), std::string::npos) << again.stop_reason;
  EXPECT_TRUE(text_of(first.run_file) == bytes) << "the finished run was written again";
  EXPECT_EQ(text_of(dir.path() / "run.log"), log);
  // --fresh discards an unfinished run's work, not a finished result
  RunOptions fresh{dir.path().string()};
  fresh.fresh = true;
  EXPECT_TRUE(run_scene(s, fresh).already_complete);
}

// What differs is named, and nothing is written; --overwrite replaces the
// run and names what lies beside it, now stale.
TEST(FinishedRun, AnotherRunIsRefusedUnlessOverwrite) {
  Scene s = small_box();
  TempDir dir("other");
  ASSERT_TRUE(run_scene(s, {dir.path().string()}).complete);
  std::ofstream(dir.path() / "metrics.json") << "{}";  // an analysis made from the run
  const std::string bytes = text_of(dir.path() / "run.h5");
  const auto refused = [&](const Scene& other, const std::string& why) {
    try {
      run_scene(other, {dir.path().string()});
      ADD_FAILURE() << "a different run replaced the finished one (" << why << ")";
    } catch (const OutputDirError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--overwrite"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(text_of(dir.path() / "run.h5") == bytes);
  };
  Scene edited = s;
  edited.text += " (edited)";
  refused(edited, "another scene");
  Scene restarted = s;  // the same text from another starting state (the initial run made again)
  restarted.initial_run = (dir.path().parent_path() / "elsewhere" / "run.h5").string();
  restarted.initial_digest = "0123456789abcdef";
  refused(restarted, "another state");

  RunOptions overwrite{dir.path().string()};
  overwrite.overwrite = true;
  const RunReport r = run_scene(edited, overwrite);
  ASSERT_TRUE(r.complete);
  EXPECT_FALSE(r.already_complete);
  const std::string log = text_of(dir.path() / "run.log");
  EXPECT_NE(log.find("replacing the finished run " + r.run_file), std::string::npos) << log;
  EXPECT_NE(log.find("it ran another scene"), std::string::npos) << log;
  EXPECT_NE(log.find("beside it: metrics.json"), std::string::npos) << log;
  EXPECT_EQ(h5::read_attr_string(h5::File::open_read(r.run_file), "/", "scene_text"), edited.text);
}

// Every grain's (x, y, d, vx, vy, omega), sorted: the state independent of numbering.
using Grain = std::array<double, 6>;
std::vector<Grain> grains_of(const System& sys) {
  std::vector<Grain> g;
  const Particles& p = sys.state.p;
  for (std::size_t i = 0; i < sys.size(); ++i)
    if (p.active[i]) g.push_back({p.x[i], p.y[i], 2.0 * p.radius[i], p.vx[i], p.vy[i], p.omega[i]});
  std::sort(g.begin(), g.end());
  return g;
}

// The tangential springs of the acting contacts (pairs and walls), sorted.
std::vector<double> springs_of(const System& sys) {
  std::vector<double> ft;
  for (std::size_t s = 0; s < sys.state.lists.pairs.ft.size(); ++s)
    if (sys.state.lists.pairs.overlap[s] > 0.0) ft.push_back(sys.state.lists.pairs.ft[s]);
  for (std::size_t s = 0; s < sys.state.lists.walls.ft.size(); ++s)
    if (sys.state.lists.walls.overlap[s] > 0.0) ft.push_back(sys.state.lists.walls.ft[s]);
  std::sort(ft.begin(), ft.end());
  return ft;
}

TEST(RestartFromCheckpoint, GoesOnAsTheUninterruptedRunWithTheNewSettings) {
  Scene s = small_box();
  for (std::size_t k = 0; k < s.particles.size(); ++k) {  // thrown in: a jumbled bed with loaded springs
    s.particles[k].vx = 0.3 * std::sin(1.7 * static_cast<double>(k));
    s.particles[k].omega = 50.0 * std::cos(0.9 * static_cast<double>(k));
  }
  const std::int64_t at = 60000, more = 2000;  // steps of 3.2 us: the bed landed, still settling
  System whole(s);
  whole.advance(at);
  TempDir dir("restart");
  const std::string ckpt = dir.file("checkpoint.h5");
  write_checkpoint(ckpt, whole, {}, 0.0, s.text);
  const std::vector<double> springs = springs_of(whole);
  ASSERT_GE(springs.size(), 40u);  // a loaded bed: its contact history matters

  Scene go_on = s;  // the same settings, the grains from the checkpoint
  go_on.particles.clear();
  load_initial_state(ckpt, go_on);
  EXPECT_EQ(go_on.initial_source, "checkpoint at step " + std::to_string(at));
  EXPECT_EQ(go_on.initial_digest.size(), 16u);
  // the state carries over bit for bit: every grain, every spring
  std::vector<double> carried;
  for (const InitialContact& c : go_on.initial_contacts) carried.push_back(c.ft);
  std::sort(carried.begin(), carried.end());
  EXPECT_EQ(carried, springs);
  System from(go_on);
  EXPECT_EQ(grains_of(from), grains_of(whole));

  // and goes on as the uninterrupted run. Not bit for bit: the grains are
  // renumbered (another summation order), and the first force evaluation
  // caps the springs of sliding contacts at the Coulomb limit of the state
  // as stored (its damping from the full-step velocities, where the
  // uninterrupted run had the half-step ones). Measured after 2000 steps:
  // 1.05e-9 m; with the contact history dropped, 3.1e-6 m.
  whole.advance(more);
  from.advance(more);
  const std::vector<Grain> a = grains_of(whole), b = grains_of(from);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max({worst, std::abs(a[k][0] - b[k][0]), std::abs(a[k][1] - b[k][1])});
  EXPECT_LT(worst, 1e-8) << "m: the continuation left the uninterrupted run";

  // with a changed setting, through run_scene: the run file says where it started
  Scene slippery = go_on;
  slippery.particle_particle.friction = 0.1;
  slippery.text += " + friction 0.1";
  const RunReport r = run_scene(slippery, {dir.sub("slippery").string()});
  ASSERT_TRUE(r.complete);
  const h5::File f = h5::File::open_read(r.run_file);
  EXPECT_EQ(h5::read_attr_string(f, "/", "initial_run"), ckpt);
  EXPECT_EQ(h5::read_attr_string(f, "/", "initial_source"), "checkpoint at step " + std::to_string(at));
  EXPECT_EQ(h5::read_attr_string(f, "/", "initial_digest"), go_on.initial_digest);
}

// A checkpoint of another format (an older dem2d's) is refused by name, not misread.
TEST(RestartFromCheckpoint, AnotherFormatIsRefused) {
  const Scene s = small_box();
  System sys(s);
  TempDir dir("format");
  const std::string ckpt = dir.file("checkpoint.h5");
  write_checkpoint(ckpt, sys, {}, 0.0, s.text);
  {
    const h5::File f = h5::File::open_write(ckpt);
    h5::write_attr(f, "/", "format", std::string("dem2d-checkpoint-3"));
  }
  Scene go_on = s;
  go_on.particles.clear();
  try {
    load_initial_state(ckpt, go_on);
    FAIL() << "an old checkpoint was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("dem2d-checkpoint-3"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(ckpt, 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace dem2d::test
