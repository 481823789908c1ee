#include "runfile/run_reader.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <limits>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "core/body_roles.hpp"
#include "core/number_text.hpp"
#include "runfile/run_file_schema.hpp"
#include "runfile/run_format.hpp"
#include "runfile/run_parameters.hpp"

namespace dem2d {

void Contacts::add(std::int32_t gi, std::int32_t partner, double normal_force, double overlap_m, double n_x,
                   double n_y, double tangential_force, bool is_sliding, double rolling_moment) {
  i.push_back(gi);
  j.push_back(partner);
  fn.push_back(normal_force);
  ft.push_back(tangential_force);
  overlap.push_back(overlap_m);
  nx.push_back(n_x);
  ny.push_back(n_y);
  mr.push_back(rolling_moment);
  sliding.push_back(is_sliding ? 1 : 0);
}

std::size_t Snapshot::active_count() const {
  return static_cast<std::size_t>(std::count_if(active.begin(), active.end(), [](std::uint8_t a) { return a != 0; }));
}

Vec2 Body::centre() const {
  Vec2 c;
  for (const Vec2& v : vertices) {
    c.x += v.x;
    c.y += v.y;
  }
  const auto n = static_cast<double>(vertices.size());
  return {c.x / n, c.y / n};
}

namespace {
// The largest (sign +1) or, negated, smallest (sign -1) coordinate c of the
// body's vertices, pushed out by the rounding.
double extreme(const Body& b, double Vec2::*c, double sign) {
  double m = -std::numeric_limits<double>::infinity();
  for (const Vec2& v : b.vertices) m = std::max(m, sign * (v.*c));
  return sign * (m + b.radius());
}
}  // namespace

double Body::xmin() const { return extreme(*this, &Vec2::x, -1.0); }
double Body::xmax() const { return extreme(*this, &Vec2::x, 1.0); }
double Body::ymin() const { return extreme(*this, &Vec2::y, -1.0); }
double Body::ymax() const { return extreme(*this, &Vec2::y, 1.0); }

Shape Body::core() const {
  std::vector<Point> v;
  for (const Vec2& q : vertices) v.push_back({q.x, q.y});
  return make_shape(v);
}

int Snapshot::find_role(std::string_view role) const {
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].role == role) return static_cast<int>(b);
  return -1;
}

std::string Snapshot::no_body_with_role(std::string_view role) const {
  std::vector<std::string> names, roles;
  for (const Body& b : bodies) names.push_back(b.name), roles.push_back(b.role);
  return dem2d::no_body_with_role(role, names, roles);
}

std::string no_body_with_role(std::string_view role, const std::vector<std::string>& names,
                              const std::vector<std::string>& roles) {
  std::string list;
  for (std::size_t b = 0; b < names.size(); ++b)
    list += (list.empty() ? "" : ", ") + names[b] + (roles[b].empty() ? "" : " (" + roles[b] + ")");
  const std::string r(role);
  return "no body has the role '" + r + "' (the bodies: " + (list.empty() ? "none" : list) +
         "); the scene declares it: [[body]] role = \"" + r + "\"";
}

template <class T>
std::vector<T> read_rows(const h5::File& f, const std::string& name, hsize_t first, hsize_t count) {
  const auto fail = [&](const std::string& what) { throw std::runtime_error(f.path() + ": " + name + ": " + what); };
  std::vector<hsize_t> dims = h5::shape(f, name);
  if (dims.empty() || first + count > dims[0])
    fail("rows " + std::to_string(first) + ".." + std::to_string(first + count) + " out of range");
  std::vector<hsize_t> start(dims.size(), 0);
  start[0] = first;
  dims[0] = count;
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  std::vector<T> out(total);
  if (total == 0) return out;
  h5::Handle ds(H5Dopen2(f.id(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds.id() < 0) fail("cannot open the dataset");
  h5::Handle file_space(H5Dget_space(ds), H5Sclose);
  h5::Handle mem_space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  if (H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr) < 0 ||
      H5Dread(ds, h5::native_type<T>(), mem_space, file_space, H5P_DEFAULT, out.data()) < 0)
    fail("cannot read rows " + std::to_string(first) + ".." + std::to_string(first + count));
  return out;
}

template std::vector<double> read_rows<double>(const h5::File&, const std::string&, hsize_t, hsize_t);
template std::vector<std::int32_t> read_rows<std::int32_t>(const h5::File&, const std::string&, hsize_t, hsize_t);
template std::vector<std::int64_t> read_rows<std::int64_t>(const h5::File&, const std::string&, hsize_t, hsize_t);
template std::vector<std::uint8_t> read_rows<std::uint8_t>(const h5::File&, const std::string&, hsize_t, hsize_t);

namespace {

h5::File open_run_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file");
  return h5::File::open_read(path);
}

std::string show(const std::vector<hsize_t>& dims) {
  std::string s = "[";
  for (std::size_t k = 0; k < dims.size(); ++k) s += (k ? ", " : "") + std::to_string(dims[k]);
  return s + "]";
}

// The element kind a dataset must have: floats (f4, f8) are read as double,
// integers only as the exact type written (an integer dataset standing in
// for coordinates is not a run file's).
bool dtype_ok(const std::string& got, const std::string& want) {
  return got == want || (want == "f8" && got == "f4");
}

template <class T>
const char* native_dtype() {
  if constexpr (std::is_same_v<T, double>) return "f8";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "i4";
  else if constexpr (std::is_same_v<T, std::int64_t>) return "i8";
  else return "u1";
}

}  // namespace

void RunReader::check_dataset(const std::string& name, const std::vector<hsize_t>& dims,
                              const std::string& dtype) const {
  if (!h5::exists(file_, name)) fail("dataset /" + name + " is missing (truncated or not a run file?)");
  const std::vector<hsize_t> got = h5::shape(file_, name);
  if (got != dims) fail("dataset /" + name + " has shape " + show(got) + ", expected " + show(dims));
  const std::string type = h5::dtype(file_, name);
  if (!dtype_ok(type, dtype)) fail("dataset /" + name + " holds " + type + ", expected " + dtype);
}

std::vector<hsize_t> RunReader::schema_dims(const std::string& name) const {
  const DatasetSchema* d = find_dataset(name);
  if (d == nullptr) throw std::logic_error("run-file schema: no dataset " + name);
  const std::vector<std::uint64_t> dims = schema_shape(*d, sizes_);
  return {dims.begin(), dims.end()};
}

void RunReader::check_dataset(const std::string& name) const {
  check_dataset(name, schema_dims(name), std::string(find_dataset(name)->type));
}

void RunReader::check_finite(const std::string& name, const std::vector<double>& v, std::size_t per_row,
                             const char* row_word, std::size_t row0) const {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k]))
      fail("dataset /" + name + ": " + row_word + " " + std::to_string(row0 + k / per_row) + " holds " +
           (std::isnan(v[k]) ? "NaN" : "an infinite value") + " (element " + std::to_string(k % per_row) +
           "): a run file holds finite numbers only");
}

template <class T>
std::vector<T> RunReader::checked(const std::string& name, const std::vector<hsize_t>& dims) const {
  if (const DatasetSchema* d = find_dataset(name); d != nullptr && d->type != native_dtype<T>())
    throw std::logic_error("run-file schema: /" + name + " is " + std::string(d->type) + ", read as " + native_dtype<T>());
  check_dataset(name, dims, native_dtype<T>());
  std::vector<T> v = h5::read<T>(file_, name);
  if constexpr (std::is_floating_point_v<T>) {
    std::size_t per_row = 1;
    for (std::size_t k = 1; k < dims.size(); ++k) per_row *= dims[k];
    check_finite(name, v, per_row, "row", 0);
  }
  return v;
}

void RunReader::fail(const std::string& what) const { throw std::runtime_error(path() + ": " + what); }

RunReader::RunReader(const std::string& path) : file_(open_run_file(path)) {
  const std::string format =
      h5::has_attr(file_, "/", "format") ? h5::read_attr_string(file_, "/", "format") : "(none)";
  if (format != kRunFileFormat)
    fail("not a dem2d run file: format attribute is " + format + ", expected " + kRunFileFormat);
  if (!has_parameters(file_)) {
    const std::string by = h5::has_attr(file_, "/", "code_version") ? h5::read_attr_string(file_, "/", "code_version")
                                                                    : "an unknown version";
    fail("written by dem2d " + by + ", before run files carried their parameters (/parameters), which the "
         "analyses read: run its scene again with this dem2d (make rebuilds the run files of the study; "
         "dem2d run SCENE --out DIR for another)");
  }
  const auto need = [&](const std::string& name) {
    if (!h5::exists(file_, name)) fail("dataset /" + name + " is missing (truncated or not a run file?)");
  };
  // the length of a 1-D dataset that sets a count (N, S, T)
  const auto length = [&](const std::string& name) {
    need(name);
    const std::vector<hsize_t> dims = h5::shape(file_, name);
    if (dims.size() != 1) fail("dataset /" + name + " has shape " + show(dims) + ", expected one dimension");
    return dims[0];
  };
  domain_ = read_parameters(file_).domain;  // (every value of /parameters checked)
  need("bodies/name");
  const hsize_t N = length("particles/diameter");
  sizes_['N'] = N;
  diameter_ = checked<double>("particles/diameter");
  mass_ = checked<double>("particles/mass");
  for (std::size_t i = 0; i < N; ++i)
    if (!(diameter_[i] > 0.0) || !(mass_[i] > 0.0))
      fail("grain " + std::to_string(i) + " has diameter " + shortest(diameter_[i]) + " m and mass " +
           shortest(mass_[i]) + " kg/m in /particles: both must be > 0");
  body_names_ = h5::read_strings(file_, "bodies/name");
  const hsize_t B = body_names_.size();
  sizes_['B'] = B;
  thickness_ = checked<double>("bodies/thickness");
  for (std::size_t b = 0; b < B; ++b)
    if (thickness_[b] < 0.0) fail("dataset /bodies/thickness: body " + std::to_string(b) + " has a negative thickness");
  need("bodies/role");
  body_roles_ = h5::read_strings(file_, "bodies/role");
  if (body_roles_.size() != B) fail("/bodies/role must have one entry per body (" + std::to_string(B) + ")");
  need("bodies/shape");
  body_shapes_ = h5::read_strings(file_, "bodies/shape");
  if (body_shapes_.size() != B) fail("/bodies/shape must have one entry per body (" + std::to_string(B) + ")");
  vertex_count_ = checked<std::int32_t>("bodies/vertex_count");
  for (const std::int32_t n : vertex_count_) {
    if (n < 1 || n > Shape::kMaxVertices)
      fail("/bodies/vertex_count has " + std::to_string(n) + ", expected 1.." + std::to_string(Shape::kMaxVertices));
    max_vertices_ = std::max<hsize_t>(max_vertices_, static_cast<hsize_t>(n));
  }
  sizes_['K'] = max_vertices_;
  for (const auto& [attr, count, what] : {std::tuple<const char*, hsize_t, const char*>{"n_particles", N, " grains (/particles)"},
                                          {"n_bodies", B, " bodies (/bodies)"}}) {
    if (!h5::has_attr(file_, "/", attr)) continue;
    const std::int64_t said = h5::read_attr_int(file_, "/", attr);
    if (said != static_cast<std::int64_t>(count))
      fail("root attribute " + std::string(attr) + " is " + std::to_string(said) + ", but the file holds " +
           std::to_string(count) + what);
  }
  const hsize_t S = length("snapshots/time");
  sizes_['S'] = S;
  times_ = checked<double>("snapshots/time");
  steps_ = checked<std::int64_t>("snapshots/step");
  contact_start_ = checked<std::int64_t>("snapshots/contact_start");
  check_increasing("snapshots/time", times_);
  for (std::size_t k = 1; k < S; ++k)
    if (steps_[k] <= steps_[k - 1]) fail("dataset /snapshots/step is not strictly increasing (row " + std::to_string(k) + ")");
  if (contact_start_.front() != 0 || !std::is_sorted(contact_start_.begin(), contact_start_.end()))
    fail("/snapshots/contact_start is not a non-decreasing index starting at 0");
  sizes_['C'] = static_cast<hsize_t>(contact_start_.back());
  for (const DatasetSchema& d : run_file_datasets())  // every snapshot and contact dataset a run file holds
    if (d.required() && (d.path.starts_with("snapshots/") || d.path.starts_with("contacts/")))
      check_dataset(std::string(d.path));
  if (h5::exists(file_, "series/time")) {
    sizes_['T'] = length("series/time");
    series_times_ = checked<double>("series/time");
    check_increasing("series/time", series_times_);
  } else {
    sizes_['T'] = 0;  // (no rows)
  }
  check_records(N);
}

// What no stage reads but a run file holds (grain ids, the lost grains, jam
// times, rotation angles): checked too, so that no damaged file passes for
// a good one. Files written before these existed lack them.
void RunReader::check_records(hsize_t N) {
  const auto has = [&](std::string_view name) { return h5::exists(file_, std::string(name)); };
  const auto rows = [&](const char* name) {  // a 1-D record's length (the shape check refuses any other rank)
    const std::vector<hsize_t> dims = h5::shape(file_, name);
    return dims.empty() ? hsize_t{0} : dims[0];
  };
  if (has("particles/id")) {
    const std::vector<std::int32_t> id = checked<std::int32_t>("particles/id");
    for (std::size_t i = 0; i < id.size(); ++i)
      if (id[i] != static_cast<std::int32_t>(i)) fail("dataset /particles/id: row " + std::to_string(i) + " holds " + std::to_string(id[i]));
  }
  if (has("lost/id")) sizes_['L'] = rows("lost/id");
  if (has("events/jam_time")) sizes_['J'] = rows("events/jam_time");
  const auto sized = [&](const DatasetSchema& d) {  // (lost/x without lost/id: not read)
    return std::ranges::all_of(d.shape, [&](char c) { return !std::isupper(static_cast<unsigned char>(c)) || sizes_.contains(c); });
  };
  for (const DatasetSchema& d : run_file_datasets())  // the others' shapes and types (series: check_rest)
    if (d.optional && !d.path.starts_with("series/") && has(d.path) && sized(d))
      check_dataset(std::string(d.path));
  if (has("particles/inertia")) {  // > 0; +infinity for a grain that does not rotate
    for (const double v : h5::read<double>(file_, "particles/inertia"))
      if (!(v > 0.0)) fail("dataset /particles/inertia holds " + shortest(v) + ": moments of inertia are > 0");
  }
  if (has("lost/id")) {
    for (const std::int32_t i : checked<std::int32_t>("lost/id"))
      if (i < 0 || static_cast<hsize_t>(i) >= N) fail("dataset /lost/id holds " + std::to_string(i) + ", not a grain");
    checked<std::int64_t>("lost/step");
    checked<double>("lost/x");
    checked<double>("lost/y");
  }
  if (has("events/jam_time")) {
    check_increasing("events/jam_time", checked<double>("events/jam_time"));
  }
}

void RunReader::check_increasing(const std::string& name, const std::vector<double>& t) const {
  for (std::size_t k = 1; k < t.size(); ++k)
    if (!(t[k] > t[k - 1]))
      fail("dataset /" + name + " is not strictly increasing: row " + std::to_string(k) + " is " +
           shortest(t[k]) + " s after " + shortest(t[k - 1]) + " s");
}

std::vector<double> RunReader::series(const std::string& name) const {
  const std::string path = "series/" + name;
  return checked<double>(path, find_dataset(path) ? schema_dims(path) : std::vector<hsize_t>{series_rows()});
}

void RunReader::check_rest() const {
  if (h5::exists(file_, "bodies/velocity")) body_velocities();
  displacement_window();
  end_time();
  if (h5::exists(file_, "contacts/line"))  // (its shape: checked on opening)
    check_finite("contacts/line", h5::read<double>(file_, "contacts/line"), 4, "row", 0);
  if (!h5::exists(file_, "series")) return;
  for (const DatasetSchema& d : run_file_datasets())
    if (d.required() && d.path.starts_with("series/") && !h5::exists(file_, std::string(d.path)))
      fail("dataset /" + std::string(d.path) + " is missing");
  for (const std::string& member : h5::datasets_under(file_, "series")) {
    const std::string name = "series/" + member;
    const std::vector<hsize_t> dims = h5::shape(file_, name);
    if (dims.empty() || dims[0] != series_rows())
      fail("dataset /" + name + " has shape " + show(dims) + ", expected " + std::to_string(series_rows()) +
           " rows (one per /series/time)");
    const DatasetSchema* d = find_dataset(name);
    if (d && d->type != "f8") check_dataset(name);  // (the counts)
    else if (d) series(member);                      // floats, finite
    else checked<double>(name, dims);                // a column the schema has no row for (the energy
                                                     // ledger's terms: writer/run_file_describe.hpp): floats
  }
}

std::vector<Vec2> RunReader::body_velocities() const {
  const std::vector<double> v = checked<double>("bodies/velocity");
  std::vector<Vec2> out(bodies());
  for (std::size_t b = 0; b < bodies(); ++b) out[b] = {v[2 * b], v[2 * b + 1]};
  return out;
}

std::string RunReader::vertices_dataset(const std::string& group) const { return group + "/body_vertices"; }

Body RunReader::body_of(const std::vector<double>& flat, std::size_t row, std::size_t b) const {
  Body body;
  body.name = body_names_[b];
  body.shape = body_shapes_[b];
  body.thickness = thickness_[b];
  body.role = body_roles_[b];
  const double* v = &flat[((row * bodies() + b) * max_vertices_) * 2];
  for (std::int32_t q = 0; q < vertex_count_[b]; ++q) body.vertices.push_back({v[2 * q], v[2 * q + 1]});
  return body;
}

std::size_t RunReader::body_with_role(std::string_view role) const {
  for (std::size_t b = 0; b < bodies(); ++b)
    if (body_roles_[b] == role) return b;
  fail(no_body_with_role(role, body_names_, body_roles_));
}

std::vector<Body> RunReader::body_rows(const std::string& group, std::size_t b) const {
  const std::string name = vertices_dataset(group);
  if (!h5::exists(file_, name)) fail("dataset /" + name + " is missing");
  // one row per /series/time or per snapshot: a stage indexes the outlines by those rows, so a dataset
  // of any other length is refused here (it was taken at its own length, and a row short crashed a stage)
  if (group != "series" && group != "snapshots") fail("no body outlines under /" + group);
  const hsize_t rows = group == "series" ? series_rows() : snapshots();
  const std::vector<double> flat = checked<double>(name);
  std::vector<Body> out;
  out.reserve(rows);
  for (hsize_t r = 0; r < rows; ++r) out.push_back(body_of(flat, r, b));
  return out;
}

Snapshot RunReader::snapshot(std::size_t k) const {
  if (k >= snapshots())
    fail("snapshot " + std::to_string(k) + " requested, the file has " + std::to_string(snapshots()));
  const std::size_t n = particles();
  Snapshot s;
  s.index = k;
  s.time = times_[k];
  s.step = steps_[k];
  s.diameter = diameter_;
  s.mass = mass_;
  const auto rows = [&](const std::string& name, hsize_t first, hsize_t count, std::size_t per_row,
                        const char* row_word) {
    std::vector<double> v = read_rows<double>(file_, name, first, count);
    check_finite(name, v, per_row, row_word, static_cast<std::size_t>(first));
    return v;
  };
  const auto vec2 = [&](const std::string& name) {
    std::vector<double> flat = read_rows<double>(file_, name, k, 1);
    check_finite(name + " at snapshot " + std::to_string(k), flat, 2, "grain", 0);
    std::vector<Vec2> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = {flat[2 * i], flat[2 * i + 1]};
    return out;
  };
  s.position = vec2("snapshots/position");
  s.active = read_rows<std::uint8_t>(file_, "snapshots/active", k, 1);
  for (std::size_t i = 0; i < n; ++i)  // (the engine removes a grain whose centre leaves the domain, every step)
    if (s.active[i] && !domain_.contains(s.position[i].x, s.position[i].y))
      fail("dataset /snapshots/position at snapshot " + std::to_string(k) + ": grain " + std::to_string(i) + " at (" +
           shortest(s.position[i].x) + ", " + shortest(s.position[i].y) + ") m is active outside the domain " +
           "(/parameters/domain): a run keeps only grains inside it");
  s.velocity = vec2("snapshots/velocity");
  s.omega = read_rows<double>(file_, "snapshots/omega", k, 1);
  check_finite("snapshots/omega at snapshot " + std::to_string(k), s.omega, 1, "grain", 0);
  if (h5::exists(file_, "snapshots/theta"))  // (files written before rotation angles lack it)
    check_finite("snapshots/theta at snapshot " + std::to_string(k), read_rows<double>(file_, "snapshots/theta", k, 1),
                 1, "grain", 0);
  const std::vector<double> outlines = read_rows<double>(file_, vertices_dataset("snapshots"), k, 1);
  check_finite(vertices_dataset("snapshots") + " at snapshot " + std::to_string(k), outlines,
               2 * max_vertices_, "body", 0);
  for (std::size_t b = 0; b < bodies(); ++b) s.bodies.push_back(body_of(outlines, 0, b));

  const auto first = static_cast<hsize_t>(contact_start_[k]);
  const auto count = static_cast<hsize_t>(contact_start_[k + 1] - contact_start_[k]);
  Contacts& c = s.contacts;
  c.i = read_rows<std::int32_t>(file_, "contacts/i", first, count);
  c.j = read_rows<std::int32_t>(file_, "contacts/j", first, count);
  c.fn = rows("contacts/fn", first, count, 1, "row");
  c.ft = rows("contacts/ft", first, count, 1, "row");
  c.overlap = rows("contacts/overlap", first, count, 1, "row");
  c.nx = rows("contacts/nx", first, count, 1, "row");
  c.ny = rows("contacts/ny", first, count, 1, "row");
  c.mr = rows("contacts/mr", first, count, 1, "row");
  c.sliding = read_rows<std::uint8_t>(file_, "contacts/sliding", first, count);
  const auto in = [](std::int64_t v, std::size_t size) { return v >= 0 && static_cast<std::size_t>(v) < size; };
  for (std::size_t r = 0; r < c.size(); ++r)
    if (!in(c.i[r], n) || (c.j[r] >= 0 ? !in(c.j[r], n) || c.j[r] <= c.i[r]
                                       : !in(-1 - static_cast<std::int64_t>(c.j[r]), bodies())) ||
        c.sliding[r] > 1)
      fail("snapshot " + std::to_string(k) + ": contact row " + std::to_string(first + r) + " (i = " +
           std::to_string(c.i[r]) + ", j = " + std::to_string(c.j[r]) + ", sliding = " + std::to_string(c.sliding[r]) +
           ") is not a contact: /contacts/i must name a grain, /contacts/j a grain j > i or a body (-1 - b), "
           "/contacts/sliding 0 or 1");
  return s;
}

double RunReader::displacement_window() const {
  const double w = h5::has_attr(file_, "/", "displacement_window") ? h5::read_attr_double(file_, "/", "displacement_window")
                                                                  : 0.0;
  // a damaged window must not pass for "none": a stage would measure other velocities without a word
  if (!(std::isfinite(w) && w >= 0.0))
    fail("root attribute displacement_window = " + shortest(w) + ": must be a finite number of seconds >= 0 (0: none)");
  return w;
}

double RunReader::end_time() const {
  if (!h5::has_attr(file_, "/", "end_time")) fail("root attribute end_time is missing");
  const double t = h5::read_attr_double(file_, "/", "end_time");
  double last = 0.0;
  if (!times_.empty()) last = std::max(last, times_.back());
  if (!series_times_.empty()) last = std::max(last, series_times_.back());
  if (!(std::isfinite(t) && t >= last))
    fail("root attribute end_time = " + shortest(t) + ": must be a finite time (s) at or after the run's last "
         "snapshot and series row (" + shortest(last) + " s)");
  // the run's final state always ends the file (its last snapshot): a later end is damage (the spectrum stage's
  // exit height, read at end_time - free_time, fell silently outside the series)
  if (!times_.empty() && t != times_.back())
    fail("root attribute end_time = " + shortest(t) + ": must be the time of the run's last snapshot (" +
         shortest(times_.back()) + " s), the state every run file ends with");
  return t;
}

std::vector<Vec2> RunReader::displacement(std::size_t k) const {
  if (k >= snapshots())
    fail("snapshot " + std::to_string(k) + " requested, the file has " + std::to_string(snapshots()));
  const std::size_t n = particles();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec2> out(n, Vec2{nan, nan});
  const std::string name = "snapshots/displacement";
  if (!h5::exists(file_, name)) return out;
  check_dataset(name);  // (NaN is allowed: not recorded)
  const std::vector<double> flat = read_rows<double>(file_, name, k, 1);
  for (std::size_t i = 0; i < n; ++i) out[i] = {flat[2 * i], flat[2 * i + 1]};
  return out;
}

Snapshot RunReader::last_snapshot() const {
  if (snapshots() == 0) fail("the run file has no snapshots (/snapshots/time is empty)");
  return snapshot(snapshots() - 1);
}

RunParameters RunReader::parameters() const { return read_parameters(file_); }

std::string RunReader::stopped_by() const {
  if (!h5::has_attr(file_, "/", "stopped_by")) fail("root attribute stopped_by is missing");
  return h5::read_attr_string(file_, "/", "stopped_by");
}

}  // namespace dem2d
