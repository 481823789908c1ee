// Checkpoint / restart: a run interrupted and resumed (also with another
// thread count) writes a run file bitwise identical to an uninterrupted one.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "run/checkpoint.hpp"
#include "run/run.hpp"
#include "runfile/h5.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;

// Grains poured into a box, stirred by a paddle moving across, a support
// removed while loaded, one grain thrown out of the domain, the energy
// ledger on: history, moving and removed bodies, lost grains and the ledger
// all cross the restart.
Scene stirred_box() {
  Scene s = boxed_bed(effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance |
                          effect::moving_bodies,
                      80, 0.025);
  add_wall(s, "paddle", -0.004, 0.004, 0.0, 0.004, 2e-3, 0.1, 0.0);
  add_wall(s, "support", 0.0126, 0.0, 0.0126, 0.012, 0.2e-3);
  s.particles[79].vy = 3.0;  // m/s: leaves through the open top
  s.text = "stirred box (built in code)";
  s.stop.duration = 0.12;
  s.output.series_interval = 1e-3;
  s.output.snapshot_interval = 0.01;
  s.output.displacement_window = 0.005;  // reference positions 0.005 s before each snapshot
  s.output.energy_balance = true;
  return s;
}


// Every dataset of two run files, compared byte for byte.
void expect_same_datasets(const std::string& a, const std::string& b, bool ledger = true) {
  const h5::File fa = h5::File::open_read(a), fb = h5::File::open_read(b);
  const char* numeric[] = {"particles/diameter", "particles/mass", "series/time", "series/body_force",
                           "series/body_force_mean", "series/body_torque", "series/body_vertices",
                           "series/kinetic_energy", "series/max_overlap", "snapshots/time",
                           "snapshots/position", "snapshots/velocity", "snapshots/displacement",
                           "snapshots/omega", "snapshots/theta",
                           "snapshots/body_vertices", "contacts/fn", "contacts/ft", "contacts/overlap",
                           "contacts/nx", "contacts/ny", "contacts/mr", "lost/x", "lost/y"};
  std::vector<std::string> names(std::begin(numeric), std::end(numeric));
  if (ledger)
    for (const auto& [term, v] : EnergyBalance{}.terms()) names.push_back("series/energy/" + std::string(term));
  for (const std::string& name : names) {
    const auto va = h5::read<double>(fa, name), vb = h5::read<double>(fb, name);
    ASSERT_EQ(va.size(), vb.size()) << name;
    EXPECT_EQ(std::memcmp(va.data(), vb.data(), va.size() * sizeof(double)), 0) << name;
  }
  for (const char* name : {"contacts/i", "contacts/j", "lost/id"})
    EXPECT_EQ(h5::read<std::int32_t>(fa, name), h5::read<std::int32_t>(fb, name)) << name;
  for (const char* name : {"series/step", "snapshots/step", "snapshots/contact_start", "lost/step"})
    EXPECT_EQ(h5::read<std::int64_t>(fa, name), h5::read<std::int64_t>(fb, name)) << name;
  EXPECT_EQ(h5::read<std::uint8_t>(fa, "contacts/sliding"), h5::read<std::uint8_t>(fb, "contacts/sliding"));
  EXPECT_EQ(h5::read<std::uint8_t>(fa, "snapshots/active"), h5::read<std::uint8_t>(fb, "snapshots/active"));
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A full disk while a checkpoint is written (here a file-size limit,
// RLIMIT_FSIZE, in a child process): the write is an error, the last good
// checkpoint stays byte for byte, and no temporary file is left. HDF5 writes
// part of a file only when it closes it; a close whose failure went unnoticed
// renamed an unreadable checkpoint over the good one, and the run could not
// resume.
TEST(Checkpoint, FullDiskNeverReplacesTheLastGoodCheckpoint) {
  TempDir dir;
  System sys(boxed_bed(effect::gravity | effect::walls, 400, 0.1));
  const std::string path = dir.file("checkpoint.h5");
  write_checkpoint(path, sys, {}, 1.0, "scene");
  const std::string good = bytes_of(path);
  ASSERT_GT(good.size(), 20000u);  // far above the limit below
  sys.state.step = 1234;                  // what the failed checkpoint would have said
  const pid_t child = fork();
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails with EFBIG instead of killing
    const rlimit limit{8192, 8192};
    setrlimit(RLIMIT_FSIZE, &limit);
    int code = 1;  // no error
    try {
      write_checkpoint(path, sys, {}, 2.0, "scene");
    } catch (const std::exception&) {
      code = 0;
    }
    _exit(code);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the writer died (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
  EXPECT_EQ(WEXITSTATUS(status), 0) << "a checkpoint written to a full disk raised no error";
  EXPECT_TRUE(bytes_of(path) == good) << "the last good checkpoint was replaced";
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(h5::read_attr_int(h5::File::open_read(path), "/", "step"), 0);
}

TEST(Checkpoint, ResumedRunIsBitwiseIdenticalToUninterrupted) {
  // interrupted twice, the second leg with two threads; both interruptions
  // fall between a snapshot's reference positions and the snapshot itself
  Scene s = stirred_box();
  const auto every = std::llround(s.output.snapshot_interval / s.dt), window = std::llround(s.output.displacement_window / s.dt);
  const std::int64_t first = 3 * every - window / 2, second = 8 * every - window / 3;
  // the support goes at the first interruption's step: that checkpoint holds
  // a body removed but still in the lists (its contacts act in that step)
  s.bodies.back().remove_at = static_cast<double>(first) * s.dt;
  TempDir whole("whole"), parts("parts");
  const RunReport full = run_scene(s, {whole.path().string()});
  ASSERT_TRUE(full.complete);
  ASSERT_EQ(full.lost, 1u);

  RunOptions opt{parts.path().string()};
  opt.interrupt_at_step = first;
  RunReport r = run_scene(s, opt);
  ASSERT_FALSE(r.complete);
  EXPECT_EQ(r.final_step, first);
  EXPECT_FALSE(fs::exists(parts.path() / "run.h5"));  // nothing that looks complete
  Scene two = s;
  two.threads = 2;
  opt.interrupt_at_step = second;
  r = run_scene(two, opt);
  ASSERT_FALSE(r.complete);
  EXPECT_TRUE(r.resumed);
  opt.interrupt_at_step = -1;
  r = run_scene(s, opt);
  ASSERT_TRUE(r.complete);
  EXPECT_TRUE(r.resumed);
  EXPECT_EQ(r.final_step, full.final_step);
  EXPECT_FALSE(fs::exists(parts.path() / ".run.work"));  // cleaned up
  // the log says how it went: started, interrupted, resumed (twice), finished
  std::ifstream log(parts.path() / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count(" started '"), 1u) << text;
  EXPECT_EQ(count(" interrupted at step " + std::to_string(first)), 1u) << text;
  EXPECT_EQ(count(" resumed '"), 2u) << text;
  EXPECT_EQ(count(" finished at step " + std::to_string(full.final_step)), 1u) << text;

  expect_same_datasets(full.run_file, r.run_file);
  // the support was loaded when it went: the ledger took its contacts' energy out
  const h5::File f = h5::File::open_read(full.run_file);
  const std::vector<double> removed = h5::read<double>(f, "series/energy/removed");
  EXPECT_GT(removed.back(), 0.0);
}

// With cohesion, contacts attracting across a gap (no spring history, but a
// force) cross the restart too, and the run file lists them (overlap < 0).
TEST(Checkpoint, CohesiveRunResumesBitwise) {
  Scene s = stirred_box();
  s.effects |= effect::cohesion;
  s.output.energy_balance = false;  // (the ledger does not count cohesion yet)
  for (ContactLaw* law : {&s.particle_particle, &s.particle_wall}) {
    law->cohesion_force = 0.2;    // N/m
    law->cohesion_range = 2e-4;   // m
  }
  const std::int64_t every = std::llround(s.output.snapshot_interval / s.dt);
  TempDir whole("whole"), parts("parts");
  const RunReport full = run_scene(s, {whole.path().string()});
  ASSERT_TRUE(full.complete);
  RunOptions opt{parts.path().string()};
  opt.interrupt_at_step = 5 * every;  // at a snapshot's step
  ASSERT_FALSE(run_scene(s, opt).complete);
  opt.interrupt_at_step = -1;
  const RunReport r = run_scene(s, opt);
  ASSERT_TRUE(r.complete && r.resumed);
  expect_same_datasets(full.run_file, r.run_file, false);
  const h5::File f = h5::File::open_read(full.run_file);
  const std::vector<double> overlap = h5::read<double>(f, "contacts/overlap"), fn = h5::read<double>(f, "contacts/fn");
  std::size_t gap = 0;
  for (std::size_t k = 0; k < overlap.size(); ++k)
    if (overlap[k] < 0.0) {
      ++gap;
      EXPECT_LT(fn[k], 0.0);                  // attraction only
      EXPECT_GT(overlap[k], -2e-4);           // within the range
    }
  EXPECT_GT(gap, 0u);
}

// A paddle turning about a pivot in the bed (the drum's kernels): its angle
// and angular velocity come back from the schedule, the bed's contacts with
// it from the checkpoint; the resumed run is the uninterrupted one bit for bit.
TEST(Checkpoint, TurningBodyResumesBitwise) {
  Scene s = stirred_box();
  s.effects |= effect::walls | effect::rotating_bodies;
  s.output.energy_balance = false;  // (the drum's kernels, without the ledger's dashpot terms)
  BodySpec& paddle = s.bodies[s.bodies.size() - 2];
  paddle.vx = 0.0;
  paddle.pivot = Point{0.006, 0.006};
  paddle.motion = {{MotionKind::ramp, 0.05, 0.0, 0.0, 20.0}, {MotionKind::constant, 0.07, 0.02, 0.0, 20.0}};
  const std::int64_t every = std::llround(s.output.snapshot_interval / s.dt);
  TempDir whole("whole"), parts("parts");
  const RunReport full = run_scene(s, {whole.path().string()});
  ASSERT_TRUE(full.complete);
  RunOptions opt{parts.path().string()};
  opt.interrupt_at_step = 7 * every;  // turning at 20 rad/s
  ASSERT_FALSE(run_scene(s, opt).complete);
  opt.interrupt_at_step = -1;
  const RunReport r = run_scene(s, opt);
  ASSERT_TRUE(r.complete && r.resumed);
  expect_same_datasets(full.run_file, r.run_file, false);
}

// Bytes changed inside a dataset of an unfinished run (a disk error, a
// hand edit) read back as other numbers, which HDF5 cannot notice: the
// checkpoint and each segment carry a checksum of their content, and the
// resume stops, naming the file and --fresh, instead of continuing from them.
TEST(Checkpoint, ChangedBytesInTheWorkDirectoryStopTheResume) {
  Scene s = stirred_box();
  const std::int64_t every = std::llround(s.output.snapshot_interval / s.dt);
  for (const auto& [file, dataset] : {std::pair{"checkpoint.h5", "particles/x"},
                                      std::pair{"segment_000000.h5", "snapshots/position"}}) {
    TempDir dir("damaged");
    RunOptions opt{dir.path().string()};
    opt.interrupt_at_step = 3 * every + 1;
    ASSERT_FALSE(run_scene(s, opt).complete);
    const std::string path = (dir.path() / ".run.work" / file).string();
    haddr_t offset = HADDR_UNDEF;
    {
      const h5::File f = h5::File::open_read(path);
      h5::Handle d(H5Dopen2(f.id(), dataset, H5P_DEFAULT), H5Dclose);
      offset = H5Dget_offset(d);
    }
    ASSERT_NE(offset, HADDR_UNDEF) << dataset;
    {
      std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
      io.seekp(static_cast<std::streamoff>(offset + 8));
      io.write("\x13\x13\x13\x13", 4);  // one coordinate changed, still a finite number
    }
    opt.interrupt_at_step = -1;
    try {
      run_scene(s, opt);
      FAIL() << "resumed from a damaged " << file;
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path + ": its content does not match its checksum"), std::string::npos) << m;
      EXPECT_NE(m.find("--fresh"), std::string::npos) << m;
    }
    EXPECT_FALSE(fs::exists(dir.path() / "run.h5"));
    opt.fresh = true;
    EXPECT_TRUE(run_scene(s, opt).complete);
  }
}

TEST(Checkpoint, RefusesToResumeAnotherScene) {
  Scene s = stirred_box();
  TempDir dir("other");
  RunOptions opt{dir.path().string()};
  opt.interrupt_at_step = 100;
  ASSERT_FALSE(run_scene(s, opt).complete);
  s.text += " (edited)";
  opt.interrupt_at_step = -1;
  try {
    run_scene(s, opt);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("different scene"), std::string::npos) << e.what();
  }
  opt.fresh = true;  // discards the checkpoint
  EXPECT_TRUE(run_scene(s, opt).complete);
}

// A run killed before its first checkpoint (or with checkpoint_interval = 0)
// leaves segments and no checkpoint: the rerun starts from step 0 and its
// first line says so, instead of starting over silently.
TEST(Checkpoint, RestartFromZeroSaysSo) {
  const Scene s = stirred_box();
  TempDir dir("killed");
  fs::create_directories(dir.path() / ".run.work");
  std::ofstream(dir.path() / ".run.work" / "segment_000000.h5") << "the segment of a killed run";
  const RunReport r = run_scene(s, {dir.path().string()});
  ASSERT_TRUE(r.complete);
  EXPECT_FALSE(r.resumed);
  std::ifstream log(dir.path() / "run.log");
  const std::string first_line = [&] {
    std::string line;
    std::getline(log, line);
    return line;
  }();
  EXPECT_NE(first_line.find(" started '"), std::string::npos) << first_line;
  EXPECT_NE(first_line.find("left no checkpoint (killed before its first, or checkpoint_interval = 0): started "
                            "again from step 0"),
            std::string::npos)
      << first_line;
  // a folder without an unfinished run says nothing of the kind
  TempDir clean("clean");
  run_scene(s, {clean.path().string()});
  std::ifstream log2(clean.path() / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log2)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("left no checkpoint"), std::string::npos) << text;
}

}  // namespace
}  // namespace dem2d::test
