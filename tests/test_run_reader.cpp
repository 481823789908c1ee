// The run-file reader checks every dataset it hands out, once, for every
// consumer: a run file with one value or one dataset wrong (NaN, a wrong
// shape, a wrong type, times out of order, a contact that is none) is an
// error naming the file and the dataset, never a crash or a number computed
// from garbage. Each case corrupts one dataset of a valid run file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/number_text.hpp"
#include "core/version.hpp"
#include "frame/drag_profile.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_parameters.hpp"
#include "runfile/run_reader.hpp"
#include "writer/run_file.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 30 grains settling in a box around an intruder at rest, 4 snapshots and
// series rows 0.05 s apart: a valid run file with contacts.
std::string valid_run(const TempDir& dir) {
  Scene scene = boxed_bed(effect::gravity | effect::normal_damping | effect::friction, 30, 0.03);
  add_wall(scene, "intruder", 0.01, 0.02, 0.02, 0.02, 2e-3);
  System sys(scene);
  RunRecorder rec(sys, dir.file(""));
  for (int k = 0; k < 4; ++k) {
    if (k > 0) run_for(sys, 0.05);
    rec.record_series(sys);
    rec.record_snapshot(sys);
  }
  RunInfo info;
  info.scene = &scene;
  info.code_version = code_version();
  const std::string path = dir.file("valid.h5");
  rec.finish(sys, info, path, "test");
  return path;
}

// A copy of `src` named `tag`.h5 whose dataset `name` holds `data` with shape `dims`.
template <class T>
std::string with_dataset(const TempDir& dir, const std::string& src, const std::string& tag, const std::string& name,
                         const std::vector<T>& data, std::vector<hsize_t> dims) {
  const std::string path = dir.file(tag + ".h5");
  fs::copy_file(src, path, fs::copy_options::overwrite_existing);
  const h5::File f = h5::File::open_write(path);
  H5Ldelete(f.id(), name.c_str(), H5P_DEFAULT);
  h5::write(f, name, data, std::move(dims));
  return path;
}

// A copy of `src` with element `index` of dataset `name` set to `value`.
template <class T>
std::string with_value(const TempDir& dir, const std::string& src, const std::string& tag, const std::string& name,
                       std::size_t index, T value) {
  std::vector<hsize_t> dims;
  std::vector<T> data = h5::read<T>(h5::File::open_read(src), name, &dims);
  data.at(index) = value;
  return with_dataset(dir, src, tag, name, data, dims);
}

// The message of what `f` throws ("no error" if nothing).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

#define EXPECT_ERROR(call, path, text)                                       \
  do {                                                                       \
    const std::string msg_ = error_of([&] { call; });                            \
    EXPECT_EQ(msg_.rfind(path + ": ", 0), 0u) << msg_;                            \
    EXPECT_NE(msg_.find(text), std::string::npos) << "expected '" << text << "' in: " << msg_; \
  } while (0)

class RunReaderChecks : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    valid_ = valid_run(*dir_);
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
  static std::string valid_;
};
TempDir* RunReaderChecks::dir_ = nullptr;
std::string RunReaderChecks::valid_;

TEST_F(RunReaderChecks, ValidRunIsReadWhole) {
  const RunReader run(valid_);
  ASSERT_EQ(run.snapshots(), 4u);
  ASSERT_EQ(run.series_rows(), 4u);
  EXPECT_EQ(run.series("body_force_mean").size(), 4u * run.bodies() * 2);
  EXPECT_EQ(run.body_velocities().size(), run.bodies());
  std::size_t contacts = 0;
  for (std::size_t k = 0; k < run.snapshots(); ++k) contacts += run.snapshot(k).contacts.size();
  EXPECT_GT(contacts, 10u);
}

// The bodies' outlines have one row per /series/time (and per snapshot): a dataset a row short is refused
// by the reader, naming it, not read at its own length (a stage indexing it by time crashed)
TEST_F(RunReaderChecks, BodyOutlinesARowShortAreRefused) {
  const RunReader valid(valid_);
  std::vector<hsize_t> dims;
  std::vector<double> v = h5::read<double>(h5::File::open_read(valid_), "series/body_vertices", &dims);
  ASSERT_EQ(dims[0], valid.series_rows());
  EXPECT_EQ(valid.body_rows("series", 0).size(), valid.series_rows());
  dims[0] -= 1;
  v.resize(v.size() / (dims[0] + 1) * dims[0]);
  const std::string short_series = with_dataset(*dir_, valid_, "short_outlines", "series/body_vertices", v, dims);
  const RunReader run(short_series);
  EXPECT_ERROR(run.body_rows("series", 0), short_series, "series/body_vertices");
  EXPECT_ERROR(run.body_rows("elsewhere", 0), short_series, "elsewhere");
}

// A damaged displacement window is refused, not read as "none" (a stage then measured other velocities
// without a word): NaN, negative, infinite
TEST_F(RunReaderChecks, ADamagedDisplacementWindowIsRefused) {
  EXPECT_EQ(RunReader(valid_).displacement_window(), 0.0);  // written without displacements
  for (const double w : {kNaN, -1.0, std::numeric_limits<double>::infinity()}) {
    const std::string path = dir_->file("window.h5");
    fs::copy_file(valid_, path, fs::copy_options::overwrite_existing);
    h5::write_attr(h5::File::open_write(path), "/", "displacement_window", w);
    const RunReader run(path);
    EXPECT_ERROR(run.displacement_window(), path, "displacement_window");
  }
}

// An attribute of one value damaged into an array: refused naming it (it was read into a single value,
// past its end: a stack overflow that ASan reports), in C++ as in Python.
TEST_F(RunReaderChecks, AnArrayWhereOneValueBelongsIsRefusedNotReadPastItsEnd) {
  const std::string path = dir_->file("array_attr.h5");
  fs::copy_file(valid_, path, fs::copy_options::overwrite_existing);
  {
    const h5::File f = h5::File::open_write(path);
    if (H5Aexists(f.id(), "displacement_window") > 0) H5Adelete(f.id(), "displacement_window");
    const hsize_t n = 64;
    const std::vector<double> values(n, 0.05);
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t a = H5Acreate2(f.id(), "displacement_window", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Awrite(a, H5T_NATIVE_DOUBLE, values.data()), 0);
    H5Aclose(a), H5Sclose(space);
  }
  EXPECT_ERROR(RunReader(path).displacement_window(), path, "displacement_window holds 64 values, expected one");
}

// The run's end, which the spectrum stage's exit height is read from: a NaN,
// one before the last record, one after the last snapshot (the final state
// ends every run file) or none is the file's damage, named as such (a NaN was
// blamed on the run's stop criterion; 1e300 put the exit height outside the
// series, silently).
TEST_F(RunReaderChecks, TheRunsEndIsAFiniteTimeAfterItsLastRecord) {
  const double end = RunReader(valid_).end_time();
  EXPECT_GE(end, RunReader(valid_).series_times().back());
  const std::string path = dir_->file("end_time.h5");
  for (const double bad : {kNaN, -1.0, 0.5 * end}) {
    fs::copy_file(valid_, path, fs::copy_options::overwrite_existing);
    h5::write_attr(h5::File::open_write(path), "/", "end_time", bad);
    EXPECT_ERROR(RunReader(path).end_time(), path, "end_time = " + shortest(bad) + ": must be a finite time (s) at or after");
    EXPECT_ERROR(RunReader(path).check_rest(), path, "end_time = ");
  }
  for (const double bad : {std::nextafter(end, 2.0 * end), 2.0 * end, 1e300}) {
    fs::copy_file(valid_, path, fs::copy_options::overwrite_existing);
    h5::write_attr(h5::File::open_write(path), "/", "end_time", bad);
    EXPECT_ERROR(RunReader(path).end_time(), path, "end_time = " + shortest(bad) + ": must be the time of the run's last snapshot");
  }
  {
    const h5::File f = h5::File::open_write(path);
    H5Adelete(f.id(), "end_time");
  }
  EXPECT_ERROR(RunReader(path).end_time(), path, "root attribute end_time is missing");
}

// /parameters hands back what the run ran with; a file without it is
// refused (naming the version that wrote it), a value out of the scene's
// range is named.
TEST_F(RunReaderChecks, ParametersAreTheScenesAndOldFilesAreRefused) {
  Scene scene = boxed_bed(effect::gravity | effect::normal_damping | effect::friction, 30, 0.03);
  add_wall(scene, "intruder", 0.01, 0.02, 0.02, 0.02, 2e-3);
  const RunParameters p = RunReader(valid_).parameters();
  EXPECT_EQ(p.effects, scene.effects);
  EXPECT_EQ(p.dt, scene.dt);
  EXPECT_EQ(p.gy, scene.gy);
  EXPECT_EQ(p.density, scene.density);
  EXPECT_EQ(p.grain_grain.kn, scene.particle_particle.kn);
  EXPECT_EQ(p.grain_body.friction, scene.particle_wall.friction);
  EXPECT_EQ(p.grain_grain.rolling_friction, 0.0);  // its effect is off: not in the file
  EXPECT_EQ(p.stop.duration, scene.stop.duration);
  ASSERT_EQ(p.bodies.size(), scene.bodies.size());
  EXPECT_EQ(p.bodies[3].name, "intruder");
  EXPECT_EQ(p.bodies[3].vertices[1].x, 0.02);
  EXPECT_EQ(p.find_role("floor"), 0);
  EXPECT_EQ(h5::read_attr_string(h5::File::open_read(valid_), "/parameters/contact/grain_grain/kn", "units"), "N/m");

  const std::string old = dir_->file("old.h5");
  fs::copy_file(valid_, old, fs::copy_options::overwrite_existing);
  H5Ldelete(h5::File::open_write(old).id(), "parameters", H5P_DEFAULT);
  EXPECT_ERROR(RunReader{old}, old, "before run files carried their parameters");
  EXPECT_ERROR(RunReader{old}, old, code_version());

  const std::string kn = "parameters/contact/grain_grain/kn";
  const std::string array = with_dataset<double>(*dir_, valid_, "array_kn", kn, {1e6}, {1});
  EXPECT_ERROR(RunReader(array).parameters(), array, "/" + kn + ": not a scalar");
  const std::string bad = dir_->file("bad_kn.h5");
  fs::copy_file(valid_, bad, fs::copy_options::overwrite_existing);
  {
    const h5::File f = h5::File::open_write(bad);
    H5Ldelete(f.id(), kn.c_str(), H5P_DEFAULT);
    h5::write_scalar(f, kn, -1.0);
  }
  EXPECT_ERROR(RunReader(bad).parameters(), bad, "/" + kn + ": -1: must be normal stiffness in N/m, > 0");
}

TEST_F(RunReaderChecks, NonFiniteValuesAreRefusedWhereTheyAreRead) {
  const std::string pos = with_value(*dir_, valid_, "nan_position", "snapshots/position", 2 * (30 + 3) + 1, kNaN);
  const RunReader run(pos);  // snapshot values are checked when read
  EXPECT_NO_THROW(run.snapshot(0));
  EXPECT_ERROR(run.snapshot(1), pos, "/snapshots/position at snapshot 1: grain 3 holds NaN");
  // a finite position far outside the domain (the engine keeps no active grain there): refused, naming it
  const std::string far = with_value(*dir_, valid_, "far_position", "snapshots/position", 2 * (30 + 3), 1e300);
  EXPECT_NO_THROW(RunReader{far}.snapshot(0));
  EXPECT_ERROR(RunReader{far}.snapshot(1), far,
               "/snapshots/position at snapshot 1: grain 3 at (1e+300, ");
  const std::string d = with_value(*dir_, valid_, "nan_diameter", "particles/diameter", 7, kNaN);
  EXPECT_ERROR(RunReader{d}, d, "dataset /particles/diameter: row 7 holds NaN");
  const std::string t = with_value(*dir_, valid_, "inf_thickness", "bodies/thickness", 1, HUGE_VAL);
  EXPECT_ERROR(RunReader{t}, t, "dataset /bodies/thickness: row 1 holds an infinite value");
  const std::string ends = with_value(*dir_, valid_, "nan_body", "series/body_vertices", 3, kNaN);
  EXPECT_ERROR(RunReader{ends}.body_rows("series", 0), ends, "/series/body_vertices: row 0 holds NaN");
  const std::string v = with_value(*dir_, valid_, "nan_velocity", "bodies/velocity", 1, kNaN);
  EXPECT_ERROR(RunReader{v}.body_velocities(), v, "/bodies/velocity: row 0 holds NaN");
  const std::string force = with_value(*dir_, valid_, "nan_force", "series/body_force_mean", 5, kNaN);
  EXPECT_ERROR(RunReader{force}.series("body_force_mean"), force, "/series/body_force_mean: row 0 holds NaN");
}

TEST_F(RunReaderChecks, GrainsWithoutSizeOrMassAreRefused) {
  const std::string neg = with_value(*dir_, valid_, "negative_diameter", "particles/diameter", 2, -3e-3);
  EXPECT_ERROR(RunReader{neg}, neg, "grain 2 has diameter -0.003");
  const std::string m = with_value(*dir_, valid_, "zero_mass", "particles/mass", 0, 0.0);
  EXPECT_ERROR(RunReader{m}, m, "both must be > 0");
}

TEST_F(RunReaderChecks, ShapesAreCheckedAgainstEachOther) {
  const RunReader run(valid_);
  const auto B = run.bodies();
  const std::string short_force = with_dataset(*dir_, valid_, "short_force", "series/body_force_mean",
                                               std::vector<double>(3 * B * 2, 1.0), {3, B, 2});
  EXPECT_ERROR(RunReader{short_force}.series("body_force_mean"), short_force,
               "dataset /series/body_force_mean has shape [3, " + std::to_string(B) + ", 2], expected [4, " +
                   std::to_string(B) + ", 2]");
  const std::string empty = with_dataset(*dir_, valid_, "empty_overlap", "series/max_overlap", std::vector<double>{}, {0});
  EXPECT_ERROR(RunReader{empty}.series("max_overlap"), empty, "dataset /series/max_overlap has shape [0], expected [4]");
  const std::string mass = with_dataset(*dir_, valid_, "short_mass", "particles/mass", std::vector<double>(29, 1.0), {29});
  EXPECT_ERROR(RunReader{mass}, mass, "dataset /particles/mass has shape [29], expected [30]");
  EXPECT_ERROR(run.series("no_such_column"), valid_, "dataset /series/no_such_column is missing");
}

// What no stage reads is checked too: no damaged file passes for a good one.
TEST_F(RunReaderChecks, RecordsNoStageReadsAreChecked) {
  const std::string ids = with_dataset(*dir_, valid_, "empty_ids", "particles/id", std::vector<std::int32_t>{}, {0});
  EXPECT_ERROR(RunReader{ids}, ids, "dataset /particles/id has shape [0], expected [30]");
  std::vector<std::int32_t> swapped(30);
  for (std::int32_t i = 0; i < 30; ++i) swapped[static_cast<std::size_t>(i)] = i;
  std::swap(swapped[3], swapped[4]);
  const std::string order = with_dataset(*dir_, valid_, "swapped_ids", "particles/id", swapped, {30});
  EXPECT_ERROR(RunReader{order}, order, "dataset /particles/id: row 3 holds 4");
  const std::string theta = with_dataset(*dir_, valid_, "short_theta", "snapshots/theta", std::vector<double>(30, 0.0), {1, 30});
  EXPECT_ERROR(RunReader{theta}, theta, "dataset /snapshots/theta has shape [1, 30], expected [4, 30]");
}

TEST_F(RunReaderChecks, IntegersStandingInForCoordinatesAreRefused) {
  const std::string ints = with_dataset(*dir_, valid_, "int_position", "snapshots/position",
                                        std::vector<std::int64_t>(4 * 30 * 2, 0), {4, 30, 2});
  EXPECT_ERROR(RunReader{ints}, ints, "dataset /snapshots/position holds i8, expected f8");
}

TEST_F(RunReaderChecks, TimesMustStrictlyIncrease) {
  const RunReader run(valid_);
  const std::string snap = with_value(*dir_, valid_, "repeated_time", "snapshots/time", 2, run.snapshot_times()[1]);
  EXPECT_ERROR(RunReader{snap}, snap, "dataset /snapshots/time is not strictly increasing: row 2");
  const std::string series = with_value(*dir_, valid_, "reversed_series", "series/time", 0, 1.0);
  EXPECT_ERROR(RunReader{series}, series, "dataset /series/time is not strictly increasing: row 1");
}

TEST_F(RunReaderChecks, ContactsMustNameTwoDifferentExistingPartners) {
  const RunReader run(valid_);
  const Snapshot s = run.snapshot(3);
  const auto row = static_cast<std::size_t>(run.snapshot(0).contacts.size() + run.snapshot(1).contacts.size() +
                                            run.snapshot(2).contacts.size());
  ASSERT_GT(s.contacts.size(), 0u);
  const std::string self = with_value(*dir_, valid_, "self_contact", "contacts/j", row, s.contacts.i[0]);
  EXPECT_ERROR(RunReader{self}.snapshot(3), self, "contact row " + std::to_string(row));
  EXPECT_ERROR(RunReader{self}.snapshot(3), self, "is not a contact");
  const std::string body = with_value(*dir_, valid_, "no_body", "contacts/j", row, std::int32_t{-100});
  EXPECT_ERROR(RunReader{body}.snapshot(3), body, "is not a contact");
  const std::string fn = with_value(*dir_, valid_, "nan_fn", "contacts/fn", row, kNaN);
  EXPECT_ERROR(RunReader{fn}.snapshot(3), fn, "dataset /contacts/fn: row " + std::to_string(row) + " holds NaN");
}

// The stage that needs a moving intruder refuses a run where it stays put
// (pulloff_metrics given the fill's run file reported "travel 0.0 mm").
TEST_F(RunReaderChecks, DragProfileNeedsAMovingIntruder) {
  EXPECT_ERROR(analysis::read_drag_profile(RunReader{valid_}), valid_,
               "the intruder 'intruder' stays at");
}

}  // namespace
}  // namespace dem2d::test
