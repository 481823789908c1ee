// Reading dem2d run files (docs/run_file.md), for the analysis stages and for
// runs that start from an earlier run's final state: one snapshot at a time,
// read as hyperslabs, so that a run with thousands of snapshots costs only
// what is read.
//
// Every dataset handed out is checked first, once, for every consumer: its
// shape against the others', its element type, and finite values (NaN only
// where the format allows it: /snapshots/displacement); times strictly
// increase, contacts name existing grains and bodies, diameters and masses
// are > 0. Every error is a std::runtime_error whose message starts with the
// file's path, names the dataset and says what is wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/box.hpp"
#include "runfile/h5.hpp"
#include "shape/shape.hpp"

namespace dem2d {

struct RunParameters;  // runfile/run_parameters.hpp

struct Vec2 {
  double x = 0.0, y = 0.0;
};

// A body at one moment: a convex sphero-polygon (sim/shape/shape.hpp), the
// core outline `vertices` rounded by thickness / 2. A sphero-line (the paper's
// walls and intruder) has two vertices, its ends C1 and C2.
struct Body {
  std::string name;
  std::string shape = "segment";  // the scene's shape kind
  std::vector<Vec2> vertices;     // core outline (m); counter-clockwise if 3 or more
  double thickness = 0.0;         // rounding diameter (m)
  std::string role;               // core/body_roles.hpp ("" none)

  // A sphero-line C1C2 (for bodies built in code, e.g. in tests).
  static Body segment(std::string name, double ax, double ay, double bx, double by, double thickness,
                      std::string role = "") {
    return {std::move(name), "segment", {{ax, ay}, {bx, by}}, thickness, std::move(role)};
  }

  double radius() const { return 0.5 * thickness; }
  Vec2 centre() const;  // mean of the core's vertices (m)
  // Bounding box, rounding included (m).
  double xmin() const;
  double xmax() const;
  double ymin() const;
  double ymax() const;
  Shape core() const;  // the outline as the engine's shape (shape/shape.hpp)
};

// The touching contacts of one snapshot, one column per quantity (/contacts).
struct Contacts {
  std::vector<std::int32_t> i;      // grain
  std::vector<std::int32_t> j;      // partner: grain j (> i) if j >= 0, else body -1 - j
  std::vector<double> fn, ft;       // normal (> 0 repulsive; < 0 only with cohesion) and tangential force on i (N/m)
  std::vector<double> overlap;      // (m), > 0 touching; < 0 (a gap) only with cohesion
  std::vector<double> nx, ny;       // unit normal from the partner to i
  std::vector<double> mr;           // rolling moment on i (N)
  std::vector<std::uint8_t> sliding;  // 1: on the Coulomb cone

  std::size_t size() const { return i.size(); }
  // Appends one contact (for contacts built in code, e.g. in tests).
  void add(std::int32_t gi, std::int32_t partner, double normal_force, double overlap_m, double n_x = 0.0,
           double n_y = 0.0, double tangential_force = 0.0, bool is_sliding = false, double rolling_moment = 0.0);
};

// The state at one snapshot plus the run's constants. SI units, per unit depth.
struct Snapshot {
  std::size_t index = 0;  // snapshot number k in the run file
  double time = 0.0;      // (s)
  std::int64_t step = 0;

  std::vector<Vec2> position;        // centre (m)         [N]
  std::vector<Vec2> velocity;        // (m/s)              [N]
  std::vector<double> omega;         // (rad/s), counter-clockwise positive [N]
  std::vector<std::uint8_t> active;  // 0 once the grain has left the domain [N]
  std::vector<double> diameter;      // (m)                [N]
  std::vector<double> mass;          // (kg/m)             [N]
  std::vector<Body> bodies;          // their outlines at this snapshot [B]
  Contacts contacts;

  std::size_t size() const { return position.size(); }
  std::size_t active_count() const;
  // Index of the body with this role (core/body_roles.hpp), or -1.
  int find_role(std::string_view role) const;
  // The error message when find_role finds none (no_body_with_role below).
  std::string no_body_with_role(std::string_view role) const;
};

// "no body has the role 'R' (the bodies: NAME (ROLE), ...); the scene declares
// it: [[body]] role = "R"": names[b], roles[b] for every body.
std::string no_body_with_role(std::string_view role, const std::vector<std::string>& names,
                              const std::vector<std::string>& roles);

class RunReader {
 public:
  // Opens the run file and checks its format, the constants (/particles,
  // /bodies), the times, and the shapes and types of the snapshot and contact
  // datasets; a snapshot's values are checked when it is read.
  explicit RunReader(const std::string& path);

  const std::string& path() const { return file_.path(); }
  // For what this class does not wrap (/series, root attributes): sim/runfile/h5.hpp.
  const h5::File& file() const { return file_; }

  // The run's parameters (/parameters: the law per pair, the bodies and
  // their schedules, the time step, effects, stop criteria), read when asked.
  RunParameters parameters() const;
  // Which criterion ended the run: "duration", "body_free", "kinetic_energy",
  // "max_taps" ("" for files written by a program, not a run).
  std::string stopped_by() const;

  std::size_t particles() const { return diameter_.size(); }
  std::size_t snapshots() const { return times_.size(); }
  const std::vector<double>& snapshot_times() const { return times_; }      // (s) [S]
  const std::vector<std::int64_t>& snapshot_steps() const { return steps_; }  // [S]
  const std::vector<double>& diameters() const { return diameter_; }  // (m) [N], > 0
  const std::vector<double>& masses() const { return mass_; }         // (kg/m) [N], > 0

  // /series: one row per series interval (docs/run_file.md). Its times (s)
  // [T], strictly increasing; empty if the run wrote no series.
  std::size_t series_rows() const { return series_times_.size(); }
  const std::vector<double>& series_times() const { return series_times_; }
  // Dataset /series/<name>, checked to be float64 of the schema's shape
  // (runfile/run_file_schema.cpp; [T] for a column without a row there: the energy
  // ledger's terms) with finite values, flattened row-major; e.g.
  // series("body_force_mean"): [T, B, 2].
  std::vector<double> series(const std::string& name) const;
  // What reading the snapshots does not check: every dataset under /series
  // (energy/ included) has T rows and finite floats; /contacts/line and
  // /bodies/velocity hold finite values. (dem2d inspect: the whole file.)
  void check_rest() const;
  // /bodies/velocity: each body's prescribed velocity at the end of the run (m/s) [B].
  std::vector<Vec2> body_velocities() const;

  // Snapshot k (0 <= k < snapshots()), reading only that record.
  Snapshot snapshot(std::size_t k) const;
  // The last snapshot (the final state of the run); an error if there is none.
  Snapshot last_snapshot() const;

  // PIV-like data (docs/run_file.md): the window of /snapshots/displacement (s;
  // root attribute displacement_window, 0 if the file has none) and the grains'
  // displacements over that window before snapshot k (m) [N]. All NaN where
  // not recorded, including files written before displacements existed.
  double displacement_window() const;
  std::vector<Vec2> displacement(std::size_t k) const;
  // The run's end (s, root attribute end_time): finite, at or after its last snapshot and series row.
  double end_time() const;

  std::size_t bodies() const { return body_names_.size(); }
  const std::vector<std::string>& body_names() const { return body_names_; }
  // Roles (core/body_roles.hpp; "" none).
  const std::vector<std::string>& body_roles() const { return body_roles_; }
  // Index of the body with this role; an error naming the run's bodies and
  // roles if none.
  std::size_t body_with_role(std::string_view role) const;
  // Body b at every row of /series (group "series") or /snapshots ("snapshots").
  std::vector<Body> body_rows(const std::string& group, std::size_t b) const;

 private:
  [[noreturn]] void fail(const std::string& what) const;
  // dataset `name` exists with this shape and element type ("f8", "i4", ...)
  void check_dataset(const std::string& name, const std::vector<hsize_t>& dims, const std::string& dtype) const;
  // ... with the shape and type of the run file's schema (runfile/run_file_schema.hpp), its sizes from sizes_
  void check_dataset(const std::string& name) const;
  std::vector<hsize_t> schema_dims(const std::string& name) const;
  // every value finite; the error names the row (`row_word` row0 + k / per_row)
  void check_finite(const std::string& name, const std::vector<double>& v, std::size_t per_row,
                    const char* row_word, std::size_t row0) const;
  void check_records(hsize_t N);
  void check_increasing(const std::string& name, const std::vector<double>& t) const;
  // the whole dataset, checked (shape, type, finite values for floats)
  template <class T>
  std::vector<T> checked(const std::string& name, const std::vector<hsize_t>& dims) const;
  template <class T>
  std::vector<T> checked(const std::string& name) const { return checked<T>(name, schema_dims(name)); }

  h5::File file_;
  // group's body outline dataset, [rows, B, K, 2]
  std::string vertices_dataset(const std::string& group) const;
  // body b at `row` of such a dataset, read as `flat`
  Body body_of(const std::vector<double>& flat, std::size_t row, std::size_t b) const;

  std::vector<double> diameter_, mass_, thickness_;
  std::vector<std::string> body_names_, body_roles_, body_shapes_;
  std::vector<std::int32_t> vertex_count_;
  hsize_t max_vertices_ = 1;
  Box domain_;  // /parameters/domain: where every active grain lies
  std::map<char, std::uint64_t> sizes_;  // the file's sizes by the schema's symbols (N, B, K, S, C, T, L, J), once known
  std::vector<double> times_, series_times_;
  std::vector<std::int64_t> steps_, contact_start_;
};

// Rows [first, first + count) along the first dimension of dataset `name`,
// all other dimensions whole, flattened in row-major order. T: double,
// std::int32_t, std::int64_t or std::uint8_t.
template <class T>
std::vector<T> read_rows(const h5::File& f, const std::string& name, hsize_t first, hsize_t count);

}  // namespace dem2d
