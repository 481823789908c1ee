// The run file: records match the System, segmenting and resuming do not change
// the data, the layout of docs/run_file.md, the XDMF companion.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "core/version.hpp"
#include "engine/diagnostics.hpp"
#include "runfile/h5.hpp"
#include "writer/run_file.hpp"
#include "writer/run_file_describe.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

namespace fs = std::filesystem;


// Four grains in a row on a floor with one on top, a piston coming in from the
// right, and one grain thrown out of the domain (lost, then inactive).
Scene run_scene() {
  // cohesion: test_cohesion.cpp; turning bodies: test_motion.cpp
  Scene s = glass_scene(kFullMoving);
  const double d = 3e-3, y = 0.5 * d - 1e-5;
  add_wall(s, "floor", -0.02, -1e-3, 0.02, -1e-3);  // flat face at y = 0
  for (int k = 0; k < 4; ++k) add_disk(s, k * (d - 1e-5), y, d);
  add_disk(s, 1.5 * (d - 1e-5), y + 0.866 * d - 1e-5, d);
  add_wall(s, "piston", 3 * d + 0.5 * d + 1e-3 + 0.3e-3, 0.0, 3 * d + 0.5 * d + 1.3e-3, 0.01, 2e-3, -0.5, 0.0);
  add_disk(s, 0.995, 0.5, d, 20.0, 0.0);
  s.text = "# scene built in code\n";
  s.path = "test.toml";
  set_dt_fraction(s, 20.0);
  return s;
}

struct Contact {
  std::int32_t i, j;
  double fn, ft, overlap, mr;
};

// What the System showed when each record was taken.
struct SeriesRow {
  double time, ke, max_overlap;
  std::int64_t step, contacts;
  std::vector<double> force, force_mean, torque, torque_mean, ends;
};
struct Snapshot {
  double time;
  std::int64_t step;
  Particles p;
  std::vector<double> ends;
  std::vector<Contact> contacts;
};
struct Expected {
  std::vector<SeriesRow> series;
  std::vector<Snapshot> snapshots;
  std::int64_t contacts = 0;
};

std::vector<double> body_vertices(const System& sys) {
  std::vector<double> e;
  for (std::size_t b = 0; b < sys.state.bodies.size(); ++b)
    for (int k = 0; k < sys.state.bodies.shape[b].n; ++k)
      e.insert(e.end(), {sys.state.bodies.shape[b].vertex(k).x, sys.state.bodies.shape[b].vertex(k).y});
  return e;
}

std::vector<Contact> touching(const System& sys) {
  std::vector<Contact> out;
  const PairList& P = sys.state.lists.pairs;
  for (std::size_t i = 0; i + 1 < P.start.size(); ++i)
    for (auto s = static_cast<std::size_t>(P.start[i]); s < static_cast<std::size_t>(P.start[i + 1]); ++s)
      if (P.overlap[s] > 0.0)
        out.push_back({static_cast<std::int32_t>(i), P.partner[s], P.fn[s], P.ft[s], P.overlap[s], P.mr[s]});
  const WallList& W = sys.state.lists.walls;
  for (std::size_t i = 0; i + 1 < W.start.size(); ++i)
    for (auto s = static_cast<std::size_t>(W.start[i]); s < static_cast<std::size_t>(W.start[i + 1]); ++s)
      if (W.overlap[s] > 0.0)
        out.push_back({static_cast<std::int32_t>(i), -1 - W.body[s], W.fn[s], W.ft[s], W.overlap[s], W.mr[s]});
  return out;
}

SeriesRow series_row(const System& sys) {
  SeriesRow r{sys.time(), kinetic_energy(sys), 0.0, sys.state.step, 0, {}, {}, {}, {}, body_vertices(sys)};
  const auto n = static_cast<double>(sys.state.body_sum_steps);
  for (std::size_t b = 0; b < sys.state.bodies.size(); ++b) {
    const bool mean = sys.state.body_sum_steps > 0;
    r.force.insert(r.force.end(), {sys.state.bodies.fx[b], sys.state.bodies.fy[b]});
    r.force_mean.insert(r.force_mean.end(), {mean ? sys.state.body_fx_sum[b] / n : sys.state.bodies.fx[b],
                                             mean ? sys.state.body_fy_sum[b] / n : sys.state.bodies.fy[b]});
    r.torque.push_back(sys.state.bodies.torque[b]);
    r.torque_mean.push_back(mean ? sys.state.body_torque_sum[b] / n : sys.state.bodies.torque[b]);
  }
  for (const Contact& c : touching(sys)) {
    r.max_overlap = std::max(r.max_overlap, c.overlap);
    ++r.contacts;
  }
  return r;
}

// Records rows [from, to) of the standard schedule: `steps` steps apart, a
// snapshot every second row, a segment flushed every `flush_every` rows (0: never).
constexpr int kRows = 12, kSteps = 40;
void record(System& sys, RunRecorder& rec, Expected& ex, int from, int to, int flush_every,
            const fs::path& out) {
  for (int k = from; k < to; ++k) {
    if (k > 0) sys.advance(kSteps);
    if (k % 2 == 0) {
      ex.snapshots.push_back({sys.time(), sys.state.step, sys.state.p, body_vertices(sys), touching(sys)});
      ex.contacts += static_cast<std::int64_t>(ex.snapshots.back().contacts.size());
      rec.record_snapshot(sys);
    }
    ex.series.push_back(series_row(sys));
    rec.record_series(sys);
    EXPECT_EQ(sys.state.body_sum_steps, 0);
    if (flush_every > 0 && (k + 1) % flush_every == 0) rec.flush_segment();
    EXPECT_FALSE(fs::exists(out)) << "the run file must not exist before finish";
  }
}

constexpr const char* kSceneText = "# scene built in code\n";

RunInfo run_info(const Scene& scene) {
  RunInfo info;
  info.scene = &scene;
  info.scene_text = kSceneText;
  info.scene_path = "test.toml";
  info.code_version = code_version();
  return info;
}

// The whole standard run into dir/run.h5.
Expected run(const fs::path& dir, int flush_every, int* segments = nullptr) {
  const Scene scene = run_scene();
  System sys(scene);
  RunRecorder rec(sys, dir.string());
  Expected ex;
  const fs::path out = dir / "run.h5";
  record(sys, rec, ex, 0, kRows, flush_every, out);
  if (segments) *segments = rec.segments();
  rec.finish(sys, run_info(scene), out.string(), "duration");
  return ex;
}

// ---- the layout ---------------------------------------------------------------

struct Entry {
  std::string name, dtype;
  std::vector<hsize_t> shape;
};

// K: the most core vertices of a body (2: the sphero-lines of these tests; 1 without bodies)
std::vector<Entry> layout(hsize_t T, hsize_t S, hsize_t C, hsize_t L, hsize_t N, hsize_t B, hsize_t K = 2) {
  return {
      {"particles/id", "i4", {N}},           {"particles/diameter", "f8", {N}},
      {"particles/mass", "f8", {N}},
      {"particles/inertia", "f8", {N}},      {"bodies/name", "str", {B}},
      {"bodies/thickness", "f8", {B}},       {"bodies/velocity", "f8", {B, 2}},
      {"bodies/shape", "str", {B}},          {"bodies/vertex_count", "i4", {B}},
      {"series/time", "f8", {T}},            {"series/step", "i8", {T}},
      {"series/body_force", "f8", {T, B, 2}}, {"series/body_force_mean", "f8", {T, B, 2}},
      {"series/body_torque", "f8", {T, B}},  {"series/body_torque_mean", "f8", {T, B}},
      {"series/body_vertices", "f8", {T, B, K, 2}}, {"series/kinetic_energy", "f8", {T}},
      {"series/max_overlap", "f8", {T}},     {"series/contacts", "i8", {T}},
      {"snapshots/time", "f8", {S}},         {"snapshots/step", "i8", {S}},
      {"snapshots/position", "f8", {S, N, 2}}, {"snapshots/velocity", "f8", {S, N, 2}},
      {"snapshots/omega", "f8", {S, N}},     {"snapshots/theta", "f8", {S, N}},
      {"snapshots/active", "u1", {S, N}},    {"snapshots/body_vertices", "f8", {S, B, K, 2}},
      {"snapshots/contact_start", "i8", {S + 1}},
      {"contacts/i", "i4", {C}},             {"contacts/j", "i4", {C}},
      {"contacts/fn", "f8", {C}},            {"contacts/ft", "f8", {C}},
      {"contacts/overlap", "f8", {C}},       {"contacts/nx", "f8", {C}},
      {"contacts/ny", "f8", {C}},            {"contacts/mr", "f8", {C}},
      {"contacts/sliding", "u1", {C}},
      {"lost/id", "i4", {L}},                {"lost/step", "i8", {L}},
      {"lost/x", "f8", {L}},                 {"lost/y", "f8", {L}},
  };
}

void expect_layout(const h5::File& f, const std::vector<Entry>& entries) {
  for (const Entry& e : entries) {
    ASSERT_TRUE(h5::exists(f, e.name)) << e.name;
    EXPECT_EQ(h5::shape(f, e.name), e.shape) << e.name;
    EXPECT_EQ(h5::dtype(f, e.name), e.dtype) << e.name;
  }
}

// A dataset's bytes, whatever its numeric type (strings as their concatenation).
std::string bytes(const h5::File& f, const Entry& e) {
  const auto raw = [](const auto& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  };
  if (e.dtype == "f8") return raw(h5::read<double>(f, e.name));
  if (e.dtype == "i8") return raw(h5::read<std::int64_t>(f, e.name));
  if (e.dtype == "i4") return raw(h5::read<std::int32_t>(f, e.name));
  if (e.dtype == "u1") return raw(h5::read<std::uint8_t>(f, e.name));
  std::string out;
  for (const std::string& s : h5::read_strings(f, e.name)) out += s + '\0';
  return out;
}

std::vector<Entry> file_layout(const h5::File& f) {
  const auto dim = [&](const char* name) { return h5::shape(f, name).at(0); };
  return layout(dim("series/time"), dim("snapshots/time"), dim("contacts/i"), dim("lost/id"),
                dim("particles/diameter"), dim("bodies/name"), h5::shape(f, "series/body_vertices").at(2));
}

std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.ends_with(".tmp") || name.starts_with("segment_")) out.push_back(name);
  }
  return out;
}

// ---- a minimal XML reader: elements, attributes, text, the declaration --------

struct XmlNode {
  std::string tag, text;
  std::map<std::string, std::string> attr;
  std::vector<XmlNode> children;
};

class XmlReader {
 public:
  explicit XmlReader(std::string s) : s_(std::move(s)) {}
  XmlNode document() {
    skip_space();
    if (s_.compare(pos_, 5, "<?xml") == 0) pos_ = s_.find("?>", pos_) + 2;
    skip_space();
    XmlNode root = element();
    skip_space();
    if (pos_ != s_.size()) fail("text after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("XML: " + what + " at offset " + std::to_string(pos_));
  }
  void skip_space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void expect(char c) {
    if (pos_ >= s_.size() || s_[pos_] != c) fail(std::string("expected '") + c + "'");
    ++pos_;
  }
  std::string name() {
    const std::size_t b = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    if (b == pos_) fail("expected a name");
    return s_.substr(b, pos_ - b);
  }
  XmlNode element() {
    XmlNode n;
    expect('<');
    n.tag = name();
    while (true) {
      skip_space();
      if (pos_ < s_.size() && s_[pos_] == '/') {
        ++pos_;
        expect('>');
        return n;
      }
      if (pos_ < s_.size() && s_[pos_] == '>') break;
      const std::string key = name();
      expect('=');
      expect('"');
      const std::size_t end = s_.find('"', pos_);
      if (end == std::string::npos) fail("unterminated attribute");
      if (!n.attr.emplace(key, s_.substr(pos_, end - pos_)).second) fail("duplicate attribute " + key);
      pos_ = end + 1;
    }
    ++pos_;
    while (true) {
      if (pos_ >= s_.size()) fail("unclosed <" + n.tag + ">");
      if (s_.compare(pos_, 2, "</") == 0) {
        pos_ += 2;
        if (name() != n.tag) fail("mismatched closing tag for <" + n.tag + ">");
        expect('>');
        const std::size_t b = n.text.find_first_not_of(" \n"), e = n.text.find_last_not_of(" \n");
        n.text = b == std::string::npos ? "" : n.text.substr(b, e - b + 1);
        return n;
      }
      if (s_[pos_] == '<') {
        n.children.push_back(element());
      } else {
        if (s_[pos_] == '&') fail("entities are not expected");
        n.text += s_[pos_++];
      }
    }
  }
  std::string s_;
  std::size_t pos_ = 0;
};

std::vector<hsize_t> numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<hsize_t> v;
  for (hsize_t x; in >> x;) v.push_back(x);
  return v;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts{""};
  for (const char c : s) {
    if (c == sep)
      parts.emplace_back();
    else
      parts.back().push_back(c);
  }
  return parts;
}

hsize_t product(const std::vector<hsize_t>& v) {
  hsize_t p = 1;
  for (const hsize_t x : v) p *= x;
  return p;
}

// A DataItem refers to an existing dataset of the declared type: whole
// ("file:/dataset", with the declared dimensions) or a hyperslab within its
// bounds ("file:/dataset|start:stride:count:dataspace", as many values as declared).
// Returns the hyperslab's start ({} for a whole dataset).
std::vector<hsize_t> expect_data_item(const XmlNode& item, const h5::File& f, const std::string& h5_name) {
  EXPECT_EQ(item.tag, "DataItem");
  EXPECT_EQ(item.attr.at("Format"), "HDF");
  const std::vector<hsize_t> dims = numbers(item.attr.at("Dimensions"));
  const std::vector<std::string> parts = split(item.text, '|');
  const std::size_t colon = parts[0].find(':');
  EXPECT_EQ(parts[0].substr(0, colon), h5_name);
  const std::string dataset = parts[0].substr(colon + 1);
  if (!h5::exists(f, dataset)) {
    ADD_FAILURE() << "no dataset " << dataset;
    return {};
  }
  const std::vector<hsize_t> shape = h5::shape(f, dataset);
  const std::map<std::string, std::string> types{{"f8", "Float8"}, {"u1", "UChar1"}, {"i4", "Int4"}};
  EXPECT_EQ(item.attr.at("NumberType") + item.attr.at("Precision"), types.at(h5::dtype(f, dataset))) << dataset;
  if (parts.size() == 1) {
    EXPECT_EQ(shape, dims) << dataset;
    return {};
  }
  const std::vector<std::string> sel = split(parts.at(1), ':');
  EXPECT_EQ(sel.size(), 4u) << item.text;
  const std::vector<hsize_t> start = numbers(sel.at(0)), stride = numbers(sel.at(1)), count = numbers(sel.at(2));
  EXPECT_EQ(numbers(sel.at(3)), shape) << dataset;
  EXPECT_EQ(product(count), product(dims)) << item.text;
  EXPECT_TRUE(start.size() == shape.size() && stride.size() == shape.size() && count.size() == shape.size());
  for (std::size_t a = 0; a < shape.size(); ++a)
    EXPECT_TRUE(count[a] == 0 || start[a] + (count[a] - 1) * stride[a] < shape[a]) << item.text;
  return start;
}

void expect_xdmf(const fs::path& xdmf, const fs::path& run_file) {
  std::ifstream in(xdmf);
  ASSERT_TRUE(in) << xdmf;
  std::stringstream text;
  text << in.rdbuf();
  XmlNode root;
  ASSERT_NO_THROW(root = XmlReader(text.str()).document());
  ASSERT_EQ(root.tag, "Xdmf");
  const XmlNode& collection = root.children.at(0).children.at(0);
  EXPECT_EQ(collection.attr.at("CollectionType"), "Temporal");
  const h5::File f = h5::File::open_read(run_file.string());
  const std::vector<double> times = h5::read<double>(f, "snapshots/time");
  const hsize_t n = h5::shape(f, "particles/diameter").at(0);
  ASSERT_EQ(collection.children.size(), times.size());
  const std::string h5_name = run_file.filename().string();
  for (std::size_t k = 0; k < times.size(); ++k) {
    // snapshot k: a spatial collection of its time and the grids particles, bodies, contacts
    const XmlNode& snapshot = collection.children[k];
    EXPECT_EQ(snapshot.attr.at("CollectionType"), "Spatial");
    const XmlNode *time = nullptr, *particles = nullptr;
    for (const XmlNode& c : snapshot.children) {
      if (c.tag == "Time") time = &c;
      if (c.tag == "Grid" && c.attr.at("Name") == "particles") particles = &c;
    }
    ASSERT_TRUE(time != nullptr && particles != nullptr) << "snapshot " << k;
    EXPECT_EQ(std::stod(time->attr.at("Value")), times[k]);
    const XmlNode& grid = *particles;
    std::map<std::string, const XmlNode*> parts;
    std::vector<std::string> attributes;
    for (const XmlNode& c : grid.children) {
      parts[c.tag] = &c;
      if (c.tag == "Attribute") attributes.push_back(c.attr.at("Name"));
    }
    const XmlNode& topology = *parts.at("Topology");
    EXPECT_EQ(topology.attr.at("TopologyType"), "Polyvertex");
    EXPECT_EQ(numbers(topology.attr.at("NumberOfElements")), std::vector<hsize_t>{n});
    EXPECT_EQ(topology.children.at(0).text, h5_name + ":/particles/id");
    expect_data_item(topology.children.at(0), f, h5_name);
    EXPECT_EQ(parts.at("Geometry")->attr.at("GeometryType"), "XY");
    const XmlNode& geometry = parts.at("Geometry")->children.at(0);
    EXPECT_EQ(numbers(geometry.attr.at("Dimensions")), (std::vector<hsize_t>{n, 2}));
    EXPECT_EQ(expect_data_item(geometry, f, h5_name), (std::vector<hsize_t>{k, 0, 0}));
    EXPECT_EQ(attributes, (std::vector<std::string>{"diameter", "velocity", "omega", "theta", "active"}));
    for (const XmlNode& c : grid.children) {
      if (c.tag != "Attribute") continue;
      const XmlNode& data = c.children.at(0);
      const hsize_t components = c.attr.at("AttributeType") == "Vector" ? 2 : 1;
      EXPECT_EQ(product(numbers(data.attr.at("Dimensions"))), n * components) << c.attr.at("Name");
      const std::vector<hsize_t> start = expect_data_item(data, f, h5_name);
      if (c.attr.at("Name") != "diameter") {
        EXPECT_EQ(start.at(0), k) << c.attr.at("Name");
      }
    }
  }
}

// ---- the tests ----------------------------------------------------------------

TEST(RunFile, RecordsMatchTheSystem) {
  TempDir dir;
  int segments = 0;
  const Expected ex = run(dir.path(), 3, &segments);
  EXPECT_EQ(segments, kRows / 3);
  EXPECT_TRUE(leftovers(dir.path()).empty()) << leftovers(dir.path()).front();
  ASSERT_TRUE(fs::exists(dir.path() / "run.xdmf"));

  const h5::File f = h5::File::open_read((dir.path() / "run.h5").string());
  const System sys0(run_scene());
  const hsize_t T = kRows, S = (kRows + 1) / 2, N = sys0.size(), B = 2;
  const auto C = static_cast<hsize_t>(ex.contacts);
  ASSERT_GT(C, 0u);
  expect_layout(f, layout(T, S, C, 1, N, B));

  // header
  EXPECT_EQ(h5::read_attr_string(f, "/", "format"), "dem2d-run-2");
  EXPECT_EQ(h5::read_attr_string(f, "/", "scene_text"), kSceneText);
  EXPECT_EQ(h5::read_attr_string(f, "/", "scene_path"), "test.toml");
  EXPECT_EQ(h5::read_attr_string(f, "/", "code_version"), code_version());
  EXPECT_EQ(h5::read_attr_string(f, "/", "stop_reason"), "duration");
  EXPECT_EQ(h5::read_attr_string(f, "/", "effects"),
            "gravity,normal_damping,friction,rolling_resistance,walls,moving_bodies,tangential_damping,rolling_damping");
  EXPECT_EQ(h5::read_attr_int(f, "/", "threads"), 1);
  EXPECT_EQ(h5::read_attr_int(f, "/", "steps"), (kRows - 1) * kSteps);
  EXPECT_EQ(h5::read_attr_int(f, "/", "n_particles"), 6);
  EXPECT_EQ(h5::read_attr_int(f, "/", "n_bodies"), 2);
  EXPECT_EQ(h5::read_attr_int(f, "/", "lost_particles"), 1);
  EXPECT_EQ(h5::read_attr_double(f, "/", "dt"), sys0.config.dt);
  EXPECT_EQ(h5::read_attr_double(f, "/", "end_time"), static_cast<double>((kRows - 1) * kSteps) * sys0.config.dt);
  EXPECT_EQ(h5::read<std::int32_t>(f, "particles/id"), (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(h5::read<double>(f, "particles/diameter")[0], 3e-3);
  EXPECT_EQ(h5::read<double>(f, "particles/mass"), std::vector<double>(sys0.state.p.mass.begin(), sys0.state.p.mass.end()));
  EXPECT_DOUBLE_EQ(h5::read<double>(f, "particles/inertia")[0], sys0.state.p.mass[0] * 9e-6 / 8.0);
  EXPECT_EQ(h5::read_strings(f, "bodies/name"), (std::vector<std::string>{"floor", "piston"}));
  EXPECT_EQ(h5::read<double>(f, "bodies/thickness"), (std::vector<double>{2e-3, 2e-3}));
  EXPECT_EQ(h5::read<double>(f, "bodies/velocity"), (std::vector<double>{0.0, 0.0, -0.5, 0.0}));
  EXPECT_EQ(h5::read<std::int32_t>(f, "lost/id"), std::vector<std::int32_t>{5});
  EXPECT_GT(h5::read<std::int64_t>(f, "lost/step")[0], 0);
  EXPECT_GT(h5::read<double>(f, "lost/x")[0], 1.0);

  // series
  const auto time = h5::read<double>(f, "series/time"), ke = h5::read<double>(f, "series/kinetic_energy"),
             max_overlap = h5::read<double>(f, "series/max_overlap"),
             force = h5::read<double>(f, "series/body_force"),
             force_mean = h5::read<double>(f, "series/body_force_mean"),
             torque = h5::read<double>(f, "series/body_torque"),
             torque_mean = h5::read<double>(f, "series/body_torque_mean"),
             ends = h5::read<double>(f, "series/body_vertices");
  const auto step = h5::read<std::int64_t>(f, "series/step"), contacts = h5::read<std::int64_t>(f, "series/contacts");
  bool mean_differs = false;
  for (std::size_t t = 0; t < T; ++t) {
    const SeriesRow& r = ex.series[t];
    EXPECT_EQ(time[t], r.time);
    EXPECT_EQ(step[t], r.step);
    EXPECT_DOUBLE_EQ(ke[t], r.ke);
    EXPECT_EQ(max_overlap[t], r.max_overlap);
    EXPECT_EQ(contacts[t], r.contacts);
    for (std::size_t k = 0; k < 2 * B; ++k) {
      EXPECT_EQ(force[t * 2 * B + k], r.force[k]);
      EXPECT_EQ(force_mean[t * 2 * B + k], r.force_mean[k]);
      mean_differs |= r.force[k] != r.force_mean[k];
    }
    for (std::size_t b = 0; b < B; ++b) {
      EXPECT_EQ(torque[t * B + b], r.torque[b]);
      EXPECT_EQ(torque_mean[t * B + b], r.torque_mean[b]);
    }
    for (std::size_t k = 0; k < 4 * B; ++k) EXPECT_EQ(ends[t * 4 * B + k], r.ends[k]);
  }
  EXPECT_TRUE(mean_differs) << "the means should differ from the instantaneous forces somewhere";
  EXPECT_EQ(force_mean[0], force[0]) << "first row: no steps summed, mean = instantaneous";
  EXPECT_NE(ends[4], ends[4 * B * (T - 1) + 4]) << "the piston moves";

  // snapshots and their contacts
  const auto pos = h5::read<double>(f, "snapshots/position"), vel = h5::read<double>(f, "snapshots/velocity"),
             omega = h5::read<double>(f, "snapshots/omega"), theta = h5::read<double>(f, "snapshots/theta"),
             snap_ends = h5::read<double>(f, "snapshots/body_vertices"), snap_time = h5::read<double>(f, "snapshots/time");
  const auto active = h5::read<std::uint8_t>(f, "snapshots/active");
  const auto start = h5::read<std::int64_t>(f, "snapshots/contact_start"),
             snap_step = h5::read<std::int64_t>(f, "snapshots/step");
  const auto ci = h5::read<std::int32_t>(f, "contacts/i"), cj = h5::read<std::int32_t>(f, "contacts/j");
  const auto fn = h5::read<double>(f, "contacts/fn"), ft = h5::read<double>(f, "contacts/ft"),
             ov = h5::read<double>(f, "contacts/overlap"), nx = h5::read<double>(f, "contacts/nx"),
             ny = h5::read<double>(f, "contacts/ny"), mr = h5::read<double>(f, "contacts/mr");
  const auto sliding = h5::read<std::uint8_t>(f, "contacts/sliding");
  ASSERT_EQ(start.front(), 0);
  ASSERT_EQ(start.back(), static_cast<std::int64_t>(C));
  int wall_contacts = 0, inactive = 0;
  for (std::size_t k = 0; k < S; ++k) {
    const Snapshot& s = ex.snapshots[k];
    EXPECT_EQ(snap_time[k], s.time);
    EXPECT_EQ(snap_step[k], s.step);
    for (std::size_t i = 0; i < N; ++i) {
      const std::size_t a = k * N + i;
      EXPECT_EQ(pos[2 * a], s.p.x[i]);
      EXPECT_EQ(pos[2 * a + 1], s.p.y[i]);
      EXPECT_EQ(vel[2 * a], s.p.vx[i]);
      EXPECT_EQ(vel[2 * a + 1], s.p.vy[i]);
      EXPECT_EQ(omega[a], s.p.omega[i]);
      EXPECT_EQ(theta[a], s.p.theta[i]);
      EXPECT_EQ(active[a], s.p.active[i]);
      inactive += active[a] == 0;
    }
    for (std::size_t q = 0; q < 4 * B; ++q) EXPECT_EQ(snap_ends[k * 4 * B + q], s.ends[q]);
    ASSERT_EQ(start[k + 1] - start[k], static_cast<std::int64_t>(s.contacts.size())) << "snapshot " << k;
    for (std::size_t c = 0; c < s.contacts.size(); ++c) {
      const Contact& e = s.contacts[c];
      const auto r = static_cast<std::size_t>(start[k]) + c;
      EXPECT_EQ(ci[r], e.i);
      EXPECT_EQ(cj[r], e.j);
      EXPECT_EQ(fn[r], e.fn);
      EXPECT_EQ(ft[r], e.ft);
      EXPECT_EQ(ov[r], e.overlap);
      EXPECT_EQ(mr[r], e.mr);
      EXPECT_GT(ov[r], 0.0);
      EXPECT_EQ(sliding[r], is_sliding(fn[r], ft[r], 0.5) ? 1 : 0);
      EXPECT_NEAR(std::hypot(nx[r], ny[r]), 1.0, 1e-12);
      // the normal points from the partner to grain i: stepping back from i's
      // centre along -n by the centre distance reaches the partner's surface point
      const auto i = static_cast<std::size_t>(e.i);
      const double ri = 0.5 * 3e-3;
      if (e.j >= 0) {
        const auto j = static_cast<std::size_t>(e.j);
        const double gap = 2 * ri - e.overlap;  // centre distance
        EXPECT_NEAR(s.p.x[i] - gap * nx[r], s.p.x[j], 1e-12);
        EXPECT_NEAR(s.p.y[i] - gap * ny[r], s.p.y[j], 1e-12);
      } else {
        ++wall_contacts;
        const auto b = static_cast<std::size_t>(-1 - e.j);
        const double dist = ri + 1e-3 - e.overlap;  // centre to the segment
        const double px = s.p.x[i] - dist * nx[r], py = s.p.y[i] - dist * ny[r];
        const double* q = &s.ends[4 * b];  // the closest point lies on the segment
        const double cross = (q[2] - q[0]) * (py - q[1]) - (q[3] - q[1]) * (px - q[0]);
        EXPECT_NEAR(cross / std::hypot(q[2] - q[0], q[3] - q[1]), 0.0, 1e-12);
      }
    }
  }
  EXPECT_GT(wall_contacts, 0);
  EXPECT_GT(inactive, 0) << "the thrown grain is flagged once lost";
  expect_xdmf(dir.path() / "run.xdmf", dir.path() / "run.h5");
}

TEST(RunFile, SegmentsDoNotChangeTheData) {
  TempDir dir;
  int many = 0, one = 0;
  run(dir.sub("many"), 2, &many);
  run(dir.sub("one"), 0, &one);
  EXPECT_EQ(many, kRows / 2);
  EXPECT_EQ(one, 0);  // finish flushed the only segment
  const h5::File a = h5::File::open_read((dir.path() / "many/run.h5").string());
  const h5::File b = h5::File::open_read((dir.path() / "one/run.h5").string());
  for (const Entry& e : file_layout(a)) EXPECT_EQ(bytes(a, e), bytes(b, e)) << e.name;
  for (const char* attr : {"steps", "n_particles", "lost_particles"})
    EXPECT_EQ(h5::read_attr_int(a, "/", attr), h5::read_attr_int(b, "/", attr)) << attr;
}

// A run killed after its checkpoint resumes from it: the segments written after
// the checkpoint are dropped and the run file equals an uninterrupted run's.
TEST(RunFile, ResumeDropsLaterSegments) {
  TempDir dir;
  run(dir.sub("whole"), 3);

  const fs::path work = dir.sub("resumed"), out = work / "run.h5";
  const Scene scene = run_scene();
  System sys(scene);
  Expected ex;
  RunRecorder rec(sys, work.string());
  record(sys, rec, ex, 0, 6, 3, out);
  const System checkpoint = sys;
  const int segments = rec.segments();
  const std::int64_t rows = rec.series_rows(), snaps = rec.snapshot_count();
  ASSERT_EQ(segments, 2);
  record(sys, rec, ex, 6, 10, 3, out);  // one more segment, some rows buffered, then killed
  ASSERT_TRUE(fs::exists(work / "segment_000002.h5"));

  std::ofstream(work / "segment_000003.h5.tmp") << "killed while writing";
  std::ofstream(work / "checkpoint.h5") << "not the recorder's";

  System resumed = checkpoint;
  RunRecorder again(resumed, work.string());
  again.restore_counts(segments, rows, snaps);
  EXPECT_FALSE(fs::exists(work / "segment_000002.h5"));
  EXPECT_FALSE(fs::exists(work / "segment_000003.h5.tmp"));
  EXPECT_TRUE(fs::exists(work / "segment_000001.h5"));
  EXPECT_TRUE(fs::exists(work / "checkpoint.h5"));
  EXPECT_EQ(again.series_rows(), 6);
  record(resumed, again, ex, 6, kRows, 3, out);
  again.finish(resumed, run_info(scene), out.string(), "duration");
  EXPECT_TRUE(leftovers(dir.path()).empty());

  const h5::File a = h5::File::open_read((dir.path() / "whole/run.h5").string());
  const h5::File b = h5::File::open_read(out.string());
  for (const Entry& e : file_layout(a)) EXPECT_EQ(bytes(a, e), bytes(b, e)) << e.name;
}

TEST(RunFile, EmptyRunHasEveryDataset) {
  TempDir dir;
  Scene s = glass_scene(effect::normal_damping);
  add_disk(s, 0.0, 0.0, 3e-3);
  add_disk(s, 0.01, 0.0, 3e-3);
  set_dt_fraction(s, 20.0);
  System sys(s);
  RunRecorder rec(sys, dir.path().string());
  rec.flush_segment();  // nothing buffered: no segment
  EXPECT_EQ(rec.segments(), 0);
  const fs::path out = dir.path() / "empty.h5";
  rec.finish(sys, run_info(s), out.string(), "energy");
  EXPECT_TRUE(leftovers(dir.path()).empty());
  const h5::File f = h5::File::open_read(out.string());
  expect_layout(f, layout(0, 0, 0, 0, 2, 0, 1));
  EXPECT_EQ(h5::read<std::int64_t>(f, "snapshots/contact_start"), std::vector<std::int64_t>{0});
  EXPECT_EQ(h5::read_attr_string(f, "/", "effects"), "normal_damping");
  expect_xdmf(dir.path() / "empty.xdmf", out);
}

// tests/check_run_file.py on a run file, when /usr/bin/python3 has h5py and numpy.
TEST(RunFile, PythonCheckAcceptsTheRunFile) {
  const std::string python = "/usr/bin/python3";
  ASSERT_EQ(std::system((python + " -c 'import h5py, numpy' 2>/dev/null").c_str()), 0)
      << "the tests need " << python << " with h5py and numpy (make test installs python3-h5py, python3-numpy)";
  TempDir dir;
  run(dir.path(), 5);
  const fs::path schema = dir.path() / "schema.json";
  std::ofstream(schema) << run_file_schema_json();
  const std::string cmd = python + " " + DEM2D_TESTS_DIR + "/check_run_file.py --schema " + schema.string() + " " +
                          (dir.path() / "run.h5").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

}  // namespace
}  // namespace dem2d::test
